#pragma once

#include <cstdint>
#include <string>

#include "domain/GrainPacking.hpp"

namespace ringdem {

/// One inlet (`inflow[]` in the case file): batches of grains packed in the inlet box at the
/// solid fraction that gives the discharge, each batch when the one before has moved out
/// (engine/InflowSource).
struct InflowSpec {
  std::string name;
  GrainFill batch;        ///< the inlet box, sizes, solid fraction, velocity, seed, ...
  double interval = 0.0;  ///< s between batches: the box's depth along the velocity / speed
  double start_time = 0.0;
  double end_time = 0.0;
  std::int64_t gid_base = 0;  ///< gids of batch b: gid_base + b * (the batch's gid range)
};

}  // namespace ringdem

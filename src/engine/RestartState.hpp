#pragma once

#include <cstdint>

#include "domain/ContactHistory.hpp"

namespace ringdem {

/// What a checkpoint restores besides the particle, bond and body fields (io/Checkpoint).
struct RestartState {
  double time = 0.0;
  std::int64_t steps = 0;
  double dt = 0.0;
  std::int64_t rebuilds = 0;
  ContactHistory history;  ///< every tangential spring once (any rank may hold any entry)
  /// Step and time from which dt is the time step (0 unless a restart changed it): the step
  /// that reaches a given time is counted from there (Simulation::steps_until).
  std::int64_t dt_origin_step = 0;
  double dt_origin_time = 0.0;
};

}  // namespace ringdem

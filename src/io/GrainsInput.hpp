#pragma once

/// The loader's side of the grain sources (engine/GrainSource.hpp, InflowSource.hpp): the
/// radius distribution a `particles.grains[]` entry or an inlet describes, its grain count, the
/// checks that relate its keys to each other, and how an inlet delivers its discharge. The
/// inlets' and outflow boxes' own checks are DebrisValidation's.

#include <string>

#include "domain/GrainSizeDistribution.hpp"
#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// The distribution of a validated entry.
GrainSizeDistribution grain_size_distribution(const GrainSizesConfig& sizes);

/// The expected grain count: solid volume over mean grain volume (0 for an invalid entry).
double expected_grain_count(const GrainsConfig& grains);

/// The smallest and largest radius an entry can create (0 when it lists no size class).
double smallest_grain_radius(const GrainSizesConfig& sizes);
double largest_grain_radius(const GrainSizesConfig& sizes);

/// Cross-key checks of the entry at path `p`: the box, the keys that the distribution uses
/// and those it does not, the size classes, a box wide enough for the largest grain. Returns
/// the expected grain count (0 when the entry has errors).
double validate_grains(const GrainsConfig& grains, const std::string& p, schema::Context& ctx);

/// How an inlet delivers its discharge: a batch fills the inlet box every `interval` (the
/// box's depth along the velocity's main axis over the speed along it), at the solid fraction
/// discharge x interval / box volume.
struct InflowBatch {
  double interval = 0.0;
  double solid_fraction = 0.0;
};
InflowBatch inflow_batch(const InflowConfig& inflow);

/// The inlet's box and sizes as a grains entry (what validate_grains checks).
GrainsConfig inflow_fill(const InflowConfig& inflow);

}  // namespace ringdem

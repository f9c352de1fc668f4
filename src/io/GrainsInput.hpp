#pragma once

/// The loader's side of the debris sources and sink (engine/GrainSource.hpp, InflowSource.hpp,
/// OutflowSink.hpp): the radius distribution a `particles.grains[]` entry describes, its grain
/// count, the checks that relate its keys to each other, and those of the inlets and of the
/// outflow boxes' groups.

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

/// Cross-key checks of the inlet at path `p`: its box and sizes as for grains, a velocity, a
/// solid fraction that random sequential addition reaches, an end after the start; a warning
/// when it opens only after the run has ended (`run_duration`, CaseMagnitudes.hpp).
void validate_inflow(const InflowConfig& inflow, const std::string& p, double run_duration,
                     schema::Context& ctx);

/// Cross-key checks of outflow box i (after its groups are known to exist):
/// - its box_max above its box_min;
/// - its groups against what it can take, free particles in no ring: a group of ring particles
///   only (a net's, its shackles') is an error, as the box would do nothing with it;
/// - the grain sources (`particles.grains`, `inflow`) of the groups it takes against its box:
///   a source box wholly outside it is an error (every grain would be taken out at its first
///   step), one that reaches out of it a warning (some would).
void validate_outflow(const CaseConfig& c, std::size_t i, schema::Context& ctx);

}  // namespace ringdem

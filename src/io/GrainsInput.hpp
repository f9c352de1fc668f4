#pragma once

/// The loader's side of the debris grain source (engine/GrainSource.hpp): the radius
/// distribution a `particles.grains[]` entry describes, its grain count, and the checks that
/// relate its keys to each other.

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

}  // namespace ringdem

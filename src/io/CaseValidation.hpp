#pragma once

/// Checks of a parsed case that relate keys to each other, which the per-key schema cannot
/// express: references to materials, bonds, rigid bodies and particle groups, constraints
/// between keys of one entry, ring-net geometry and the scenario drivers' needs.

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// Runs every cross-key check on `config` (already filled by the schema tables) and reports
/// problems to `ctx`. It also resolves the values that depend on other keys: contact_radius
/// defaults, normalised directions, net rows/columns from width/length and bond moduli from
/// `derive_from`.
void cross_validate_case(CaseConfig& config, schema::Context& ctx);

}  // namespace ringdem

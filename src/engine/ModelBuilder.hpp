#pragma once

#include <string>
#include <vector>

#include "engine/Model.hpp"
#include "io/CaseConfig.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/MaterialTable.hpp"

namespace ringdem {

/// Generates particles, bonds and rigid bodies of a case, gids 0..N-1 in generator order.
Model build_model(const CaseConfig& config);

/// Adds a bond between two existing particles (by index) with the given type, its reference
/// frame from the current orientations and its strengths drawn by (seed, gid pair).
void add_bond(Model& model, std::size_t index_a, std::size_t index_b, int bond_type,
              std::uint64_t seed);

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <vector>

#include "physics/BondTimoshenko.hpp"

namespace ringdem {

/// All bonds a rank holds, structure of arrays, keyed by the ordered gid pair
/// (gid_a < gid_b). Bonds reference particles by gid; the local indices are resolved after
/// every rebuild of the particle index.
class BondStore {
 public:
  // --- persistent state (migrates, checkpoints) ---
  std::vector<std::int64_t> gid_a, gid_b;
  std::vector<std::int32_t> type;  ///< bond type (case-file table)
  std::vector<BondTimoshenko::Section> section;
  std::vector<BondTimoshenko::Reference> reference;
  std::vector<BondTimoshenko::Strength> strength;
  std::vector<std::uint8_t> broken;  ///< 0 intact, 1 broken
  std::vector<BondTimoshenko::Failure> failure;
  std::vector<double> break_time;  ///< simulated time of failure, -1 while intact

  // --- per-step results (output only) ---
  std::vector<double> axial_force, bending_moment, utilisation, energy;

  // --- local indices of the two ends, resolved by resolve_indices() ---
  std::vector<std::uint32_t> index_a, index_b;

  std::size_t size() const { return gid_a.size(); }

  /// Adds a bond between a and b in canonical order (swaps so that gid_a < gid_b).
  void add(std::int64_t gid_first, std::int64_t gid_second, std::int32_t bond_type,
           const BondTimoshenko::Section& s, const BondTimoshenko::Reference& ref_low_high,
           const BondTimoshenko::Strength& st);

  std::size_t count_broken() const;
};

}  // namespace ringdem

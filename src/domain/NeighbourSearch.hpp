#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "domain/CellGrid.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Candidate contact pairs (i, j) as particle indices, i holding the lower gid; from
/// NeighbourSearch in ascending order of the ends' sort keys (ParticleStore::sorts_before):
/// by the end that comes first, then by the other. The pairs of one first end are
/// consecutive.
struct PairCandidates {
  std::vector<std::uint32_t> i, j;
  std::size_t size() const { return i.size(); }
  void clear() {
    i.clear();
    j.clear();
  }
};

/// Pairs that must not get a contact (intact bonds), as gid lists per particle index.
struct PairExclusions {
  std::vector<std::uint32_t> offset;  ///< size n_total + 1
  std::vector<std::int64_t> partner_gid;
  bool excluded(std::uint32_t index, std::int64_t other_gid) const {
    if (offset.empty()) return false;
    for (std::uint32_t k = offset[index]; k < offset[index + 1]; ++k)
      if (partner_gid[k] == other_gid) return true;
    return false;
  }
};

/// Cell-grid neighbour search with a Verlet skin, one grid per level of particle size
/// (CellGrid: dense or hashed). A pair is a candidate when the centre distance is below
/// r_i + r_j + skin, at least one of the two is owned, and it is not excluded.
class NeighbourSearch {
 public:
  void build(const ParticleStore& p, double skin, const PairExclusions& exclusions,
             PairCandidates& out);
  /// The size levels of the last build, and whether a level's grid was dense (else hashed).
  std::size_t n_levels() const { return active_.size(); }
  bool used_dense_grid(std::size_t level = 0) const { return active_.at(level)->grid.dense(); }
  /// Boxes of up to `cells` cells take the dense grid (CellGrid::kDenseCellFloor by default;
  /// tests set 0 to reach the hashed cells with few particles).
  void set_dense_cell_floor(std::size_t cells) { dense_cell_floor_ = cells; }

 private:
  struct Level {
    std::vector<std::uint32_t> members;
    double r_max = 0.0;  ///< largest radius of the level
    CellGrid grid;
  };
  std::vector<Level> levels_;          ///< by level number: radii in [r_min 2^l, r_min 2^(l+1))
  std::vector<const Level*> active_;   ///< the levels with members, finest first
  std::vector<std::uint32_t> by_key_;  ///< all particles in key order (scratch)
  std::size_t last_pairs_ = 0;         ///< pairs of the last build (the next one's reserve)
  std::size_t dense_cell_floor_ = CellGrid::kDenseCellFloor;
};

/// O(N^2) reference with the same criterion, for tests.
PairCandidates brute_force_pairs(const ParticleStore& p, double skin,
                                 const PairExclusions& exclusions);

}  // namespace ringdem

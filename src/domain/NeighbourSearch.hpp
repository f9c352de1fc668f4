#pragma once

#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Candidate contact pairs (i, j) as particle indices, i holding the lower gid; from
/// NeighbourSearch in ascending (gid of i, gid of j) order.
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

/// Cell-grid neighbour search with a Verlet skin. A pair is a candidate when the centre
/// distance is below r_i + r_j + skin, at least one of the two is owned, and it is not
/// excluded. The cells are a dense grid when the particles fill their bounding box, hashed
/// when they are sparse in it, so a sparse or very large domain costs nothing extra.
class NeighbourSearch {
 public:
  void build(const ParticleStore& p, double skin, const PairExclusions& exclusions,
             PairCandidates& out);
  /// Whether the last build used the dense grid (else hashed cells).
  bool used_dense_grid() const { return dense_; }

 private:
  // Dense grid: particle indices by cell (counting sort), cell ranges, the grid's dimensions.
  bool dense_ = false;
  std::int64_t dims_[3] = {0, 0, 0};
  std::vector<std::uint32_t> cell_start_, fill_, cell_of_particle_, in_cells_;
  // Hashed cells: (cell key, particle index) sorted, and each key's range.
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed_;
  std::vector<std::uint32_t> by_gid_;
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> cells_;
};

/// O(N^2) reference with the same criterion, for tests.
PairCandidates brute_force_pairs(const ParticleStore& p, double skin,
                                 const PairExclusions& exclusions);

}  // namespace ringdem

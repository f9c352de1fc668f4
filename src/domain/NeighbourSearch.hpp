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
/// excluded. Cells are hashed, so a sparse or very large domain costs nothing extra.
class NeighbourSearch {
 public:
  void build(const ParticleStore& p, double skin, const PairExclusions& exclusions,
             PairCandidates& out);

 private:
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed_;
  std::vector<std::uint32_t> by_gid_;
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> cells_;
};

/// O(N^2) reference with the same criterion, for tests.
PairCandidates brute_force_pairs(const ParticleStore& p, double skin,
                                 const PairExclusions& exclusions);

}  // namespace ringdem

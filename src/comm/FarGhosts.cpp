#include "comm/FarGhosts.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/CellKeys.hpp"

namespace ringdem {

using cell_keys::floor_div;
using cell_keys::for_each_neighbour;
using cell_keys::pack;
using cell_keys::unpack;

FarGhosts::FarGhosts(FarGhostRule rule, double block_size) : rule_(std::move(rule)) {
  if (!(rule_.reach > 0.0) || !(block_size > 0.0))
    throw std::invalid_argument("far ghosts: reach and block size must be positive");
  if (!rule_.anchor || !rule_.partner)
    throw std::invalid_argument("far ghosts: the rule needs both tests");
  zone_blocks_ =
      std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(rule_.reach / block_size)));
}

std::uint64_t FarGhosts::zone_of_block(std::uint64_t block) const {
  std::int64_t i, j, k;
  unpack(block, i, j, k);
  return pack(floor_div(i, zone_blocks_), floor_div(j, zone_blocks_), floor_div(k, zone_blocks_));
}

void FarGhosts::index(const Communicator& comm, const ParticleStore& p,
                      const std::function<std::uint64_t(const Vec3&)>& block_of) {
  rank_ = comm.rank();
  std::vector<AnchorBlock> mine;
  std::vector<std::uint64_t> zones;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const bool anchor = rule_.anchor(p, k);
    if (!anchor && !rule_.partner(p, k)) continue;
    const std::uint64_t block = block_of(p.position[k]);
    if (anchor) mine.push_back({block, rank_});
    zones.push_back(zone_of_block(block));
  }
  const auto unique = [](auto& v, auto less, auto equal) {
    std::sort(v.begin(), v.end(), less);
    v.erase(std::unique(v.begin(), v.end(), equal), v.end());
  };
  unique(
      mine, [](const AnchorBlock& a, const AnchorBlock& b) { return a.block < b.block; },
      [](const AnchorBlock& a, const AnchorBlock& b) { return a.block == b.block; });
  unique(zones, std::less<>{}, std::equal_to<>{});
  struct OwnedZone {
    std::uint64_t zone;
    std::int32_t rank;
  };
  std::vector<OwnedZone> owned_zones;
  owned_zones.reserve(zones.size());
  for (const std::uint64_t z : zones)
    owned_zones.push_back({z, rank_});
  const std::vector<AnchorBlock> anchors = comm.allgather(mine);
  const std::vector<OwnedZone> occupied = comm.allgather(owned_zones);

  // Each entry listed under the 27 zones around its own: a particle then looks up its own
  // zone only.
  anchors_near_.clear();
  owners_near_.clear();
  for (const AnchorBlock& a : anchors)
    for_each_neighbour(zone_of_block(a.block),
                       [&](std::uint64_t zone) { anchors_near_[zone].push_back(a); });
  for (const OwnedZone& z : occupied)
    if (z.rank != rank_)
      for_each_neighbour(z.zone, [&](std::uint64_t zone) { owners_near_[zone].push_back(z.rank); });
  for (auto& [zone, ranks] : owners_near_) {
    std::sort(ranks.begin(), ranks.end());
    ranks.erase(std::unique(ranks.begin(), ranks.end()), ranks.end());
  }
}

void FarGhosts::append_targets(const ParticleStore& p, std::size_t k, std::uint64_t block,
                               std::vector<int>& ranks) const {
  const bool anchor = rule_.anchor(p, k);
  if (!anchor && !rule_.partner(p, k)) return;
  const std::uint64_t zone = zone_of_block(block);
  if (anchor) {  // (the owners of anchors near it are among these)
    const auto it = owners_near_.find(zone);
    if (it != owners_near_.end()) ranks.insert(ranks.end(), it->second.begin(), it->second.end());
    return;
  }
  const auto it = anchors_near_.find(zone);
  if (it == anchors_near_.end()) return;
  std::int64_t i, j, l;
  unpack(block, i, j, l);
  for (const AnchorBlock& a : it->second) {
    if (a.rank == rank_) continue;
    std::int64_t ai, aj, al;
    unpack(a.block, ai, aj, al);
    if (std::abs(ai - i) <= zone_blocks_ && std::abs(aj - j) <= zone_blocks_ &&
        std::abs(al - l) <= zone_blocks_)
      ranks.push_back(a.rank);
  }
}

}  // namespace ringdem

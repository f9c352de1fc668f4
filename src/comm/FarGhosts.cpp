#include "comm/FarGhosts.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <unordered_set>

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
  std::vector<AnchorBox> boxes;  // this rank's, one per zone
  std::vector<std::uint64_t> zones;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const bool anchor = rule_.anchor(p, k);
    if (!anchor && !rule_.partner(p, k)) continue;
    const std::uint64_t block = block_of(p.position[k]);
    const std::uint64_t zone = zone_of_block(block);
    zones.push_back(zone);
    if (!anchor) continue;
    std::int64_t b[3];
    unpack(block, b[0], b[1], b[2]);
    // Anchors are few and come in runs of one ring: the last box is most often theirs.
    auto box = std::find_if(boxes.rbegin(), boxes.rend(),
                            [zone](const AnchorBox& x) { return x.zone == zone; });
    if (box == boxes.rend()) {
      boxes.push_back({zone, {b[0], b[1], b[2]}, {b[0], b[1], b[2]}, rank_});
      continue;
    }
    for (int a = 0; a < 3; ++a) {
      box->low[a] = std::min(box->low[a], b[a]);
      box->high[a] = std::max(box->high[a], b[a]);
    }
  }
  const std::vector<AnchorBox> all_boxes = comm.allgather(boxes);
  std::unordered_set<std::uint64_t> anchor_zones;
  for (const AnchorBox& box : all_boxes)
    anchor_zones.insert(box.zone);
  // The zones this rank owns anchors or partners in, those next to an anchor's zone only
  // (only anchors look them up; all of them would grow with the whole model on every rank).
  std::sort(zones.begin(), zones.end());
  zones.erase(std::unique(zones.begin(), zones.end()), zones.end());
  struct OwnedZone {
    std::uint64_t zone;
    std::int32_t rank;
  };
  std::vector<OwnedZone> owned_zones;
  for (const std::uint64_t z : zones) {
    bool near_anchor = false;
    for_each_neighbour(
        z, [&](std::uint64_t n) { near_anchor = near_anchor || anchor_zones.count(n); });
    if (near_anchor) owned_zones.push_back({z, rank_});
  }
  const std::vector<OwnedZone> occupied = comm.allgather(owned_zones);

  // Each entry listed under the zones around its own: a particle then looks up its own zone
  // only. This rank's own entries are left out (nothing to send to itself).
  anchors_near_.clear();
  owners_near_.clear();
  for (const AnchorBox& box : all_boxes)
    if (box.rank != rank_)
      for_each_neighbour(box.zone, [&](std::uint64_t zone) { anchors_near_[zone].push_back(box); });
  for (const OwnedZone& z : occupied)
    if (z.rank != rank_)
      for_each_neighbour(z.zone, [&](std::uint64_t zone) {
        if (anchor_zones.count(zone)) owners_near_[zone].push_back(z.rank);
      });
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
  std::int64_t b[3];
  unpack(block, b[0], b[1], b[2]);
  for (const AnchorBox& box : it->second) {
    bool within = true;  // the box's nearest block at most D blocks away along each axis
    for (int a = 0; a < 3; ++a)
      within = within && b[a] >= box.low[a] - zone_blocks_ && b[a] <= box.high[a] + zone_blocks_;
    if (within) ranks.push_back(box.rank);
  }
}

}  // namespace ringdem

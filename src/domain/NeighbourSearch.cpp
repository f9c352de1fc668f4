#include "domain/NeighbourSearch.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace ringdem {

namespace {

/// `owned_in_order`: the owned particles are stored in ascending key order, so that of two
/// owned ones the one at the lower index sorts first, without reading their keys.
inline bool is_candidate(const ParticleStore& p, std::size_t n_local, bool owned_in_order,
                         double skin, const PairExclusions& ex, std::uint32_t a, std::uint32_t b) {
  // Each pair once, from the end first in key order.
  if (owned_in_order && a < n_local && b < n_local) {
    if (b <= a) return false;
  } else if (!p.sorts_before(a, b)) {
    return false;
  }
  if (a >= n_local && b >= n_local) return false;
  const double cut = p.radius[a] + p.radius[b] + skin;
  if (norm2(p.position[b] - p.position[a]) >= cut * cut) return false;
  // Two held particles (fixed or prescribed, which no force moves) do not touch: their force
  // would only be reported (contact energy, loads), as the start's overlap check has it.
  if (p.motion[a] != Motion::kFree && p.motion[b] != Motion::kFree) return false;
  return !ex.excluded(a, p.gid[b]);
}

/// Appends the pair (a, b) with the lower gid first, whatever the keys: the contact law's sign,
/// the springs' keys and the rows a checkpoint holds do not depend on the order.
inline void push_oriented(const ParticleStore& p, std::uint32_t a, std::uint32_t b,
                          PairCandidates& out) {
  const bool a_first = p.gid[a] < p.gid[b];
  out.i.push_back(a_first ? a : b);
  out.j.push_back(a_first ? b : a);
}

}  // namespace

void NeighbourSearch::build(const ParticleStore& p, double skin, const PairExclusions& ex,
                            PairCandidates& out) {
  out.clear();
  const std::size_t n = p.n_total();
  if (n == 0) return;
  // Levels of particle size: radii in [r_min 2^l, r_min 2^(l+1)) form level l, binned by
  // cells of 2 r_max(l) + skin. A particle looks for partners in every level within its
  // radius + that level's largest radius + skin: a grain scans 27 cells of each level, and a
  // boulder many small cells of the grains' level, instead of every cell being sized by the
  // boulder (where a single-level grid puts all grains near it in one cell).
  double r_min = std::numeric_limits<double>::max();
  for (std::size_t k = 0; k < n; ++k)
    r_min = std::min(r_min, p.radius[k]);
  constexpr std::size_t kMaxLevels = 16;
  levels_.resize(kMaxLevels);
  for (Level& level : levels_) {
    level.members.clear();
    level.r_max = 0.0;
  }
  // Each level's members counted first and reserved: pushed one by one, a level's list grew
  // by doubling to up to twice its members, 4 bytes a grain of a 10^6-grain bed's peak, which
  // a rebuild reaches while the keyed springs are held (docs/performance.md, forty-fifth round).
  std::vector<std::uint8_t> level_of(n);
  std::array<std::size_t, kMaxLevels> members{};
  for (std::uint32_t k = 0; k < n; ++k) {
    const auto l =
        std::min(kMaxLevels - 1, static_cast<std::size_t>(std::log2(p.radius[k] / r_min)));
    level_of[k] = static_cast<std::uint8_t>(l);
    ++members[l];
    levels_[l].r_max = std::max(levels_[l].r_max, p.radius[k]);
  }
  for (std::size_t l = 0; l < kMaxLevels; ++l)
    levels_[l].members.reserve(members[l]);
  for (std::uint32_t k = 0; k < n; ++k)
    levels_[level_of[k]].members.push_back(k);
  std::vector<std::uint8_t>().swap(level_of);
  active_.clear();
  for (std::size_t l = 0; l < kMaxLevels; ++l)
    if (!levels_[l].members.empty()) {
      levels_[l].grid.build(p.position, levels_[l].members, 2.0 * levels_[l].r_max + skin,
                            dense_cell_floor_);
      active_.push_back(&levels_[l]);
    }

  // The pairs in ascending order of (key of the first end, key of the second), the key being
  // (sort_bin, gid) (ParticleStore::sorts_before): a term that adds each pair's loads to both
  // ends in list order then gives every particle its contacts in ascending partner key,
  // whatever the storage order or the rank count (PairContactTerm). The owned range and the
  // ghost range are each usually sorted already; the check is linear.
  const std::size_t n_local = p.n_local();
  const auto by_key = [&p](std::uint32_t x, std::uint32_t y) { return p.sorts_before(x, y); };
  by_key_.resize(n);
  for (std::uint32_t k = 0; k < n; ++k)
    by_key_[k] = k;
  const auto middle = by_key_.begin() + static_cast<std::ptrdiff_t>(n_local);
  // Owned particles are usually stored in key order (DomainDecomposition::migrate): then the
  // candidate test compares their indices instead of reading both keys of every particle in
  // the stencil, half of which sort before the searching one (the test's loads of the key were
  // the search's largest stall on the 10^6-grain bed).
  const bool owned_in_order = std::is_sorted(by_key_.begin(), middle, by_key);
  if (!owned_in_order) std::sort(by_key_.begin(), middle, by_key);
  if (!std::is_sorted(middle, by_key_.end(), by_key)) std::sort(middle, by_key_.end(), by_key);
  std::inplace_merge(by_key_.begin(), middle, by_key_.end(), by_key);

  // Room for about as many pairs as the last build found: growth by doubling alone leaves up
  // to half of the pairs' memory unused (4.2 million slots for 3 million pairs).
  out.i.reserve(last_pairs_ + last_pairs_ / 16);
  out.j.reserve(last_pairs_ + last_pairs_ / 16);
  std::vector<std::uint32_t> partners;
  for (const std::uint32_t a : by_key_) {
    partners.clear();
    for (const Level* level : active_)
      level->grid.for_each_near(p.position[a], p.radius[a] + level->r_max + skin,
                                [&](std::uint32_t b) {
                                  if (is_candidate(p, n_local, owned_in_order, skin, ex, a, b))
                                    partners.push_back(b);
                                });
    std::sort(partners.begin(), partners.end(), by_key);
    for (const std::uint32_t b : partners)
      push_oriented(p, a, b, out);
  }
  last_pairs_ = out.i.size();
  if (out.i.capacity() > last_pairs_ + last_pairs_ / 4) {
    out.i.shrink_to_fit();
    out.j.shrink_to_fit();
  }
  // The bins and the order are scratch: given back, so that they do not sit beside the keyed
  // springs when the caller reads those back (22 bytes a grain of a rebuild's peak at 10^6
  // grains in contact; allocating them again costs a few milliseconds a rebuild there).
  for (Level& level : levels_) {
    std::vector<std::uint32_t>().swap(level.members);
    level.grid.release_memory();
  }
  std::vector<std::uint32_t>().swap(by_key_);
}

PairCandidates brute_force_pairs(const ParticleStore& p, double skin, const PairExclusions& ex) {
  PairCandidates out;
  const std::size_t n = p.n_total();
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = 0; b < n; ++b)
      if (a != b && is_candidate(p, p.n_local(), false, skin, ex, a, b))
        push_oriented(p, a, b, out);
  return out;
}

}  // namespace ringdem

#include "domain/NeighbourSearch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ringdem {

namespace {

constexpr std::int64_t kCellBias = 1 << 20;  // 21 bits per axis

inline std::uint64_t cell_key(std::int64_t cx, std::int64_t cy, std::int64_t cz) {
  return (static_cast<std::uint64_t>(cx + kCellBias) << 42) |
         (static_cast<std::uint64_t>(cy + kCellBias) << 21) |
         static_cast<std::uint64_t>(cz + kCellBias);
}

inline bool is_candidate(const ParticleStore& p, std::size_t n_local, double skin,
                         const PairExclusions& ex, std::uint32_t a, std::uint32_t b) {
  if (p.gid[a] >= p.gid[b]) return false;  // each pair once, lower gid first
  if (a >= n_local && b >= n_local) return false;
  const double cut = p.radius[a] + p.radius[b] + skin;
  if (norm2(p.position[b] - p.position[a]) >= cut * cut) return false;
  return !ex.excluded(a, p.gid[b]);
}

}  // namespace

void NeighbourSearch::build(const ParticleStore& p, double skin, const PairExclusions& ex,
                            PairCandidates& out) {
  out.clear();
  const std::size_t n = p.n_total();
  if (n == 0) return;
  double r_max = 0.0;
  Vec3 lo{std::numeric_limits<double>::max(), std::numeric_limits<double>::max(),
          std::numeric_limits<double>::max()};
  for (std::size_t k = 0; k < n; ++k) {
    r_max = std::max(r_max, p.radius[k]);
    lo = {std::min(lo.x, p.position[k].x), std::min(lo.y, p.position[k].y),
          std::min(lo.z, p.position[k].z)};
  }
  const double h = 2.0 * r_max + skin;
  const double inv_h = 1.0 / h;

  keyed_.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    const Vec3 rel = (p.position[k] - lo) * inv_h;
    keyed_[k] = {cell_key(static_cast<std::int64_t>(rel.x), static_cast<std::int64_t>(rel.y),
                          static_cast<std::int64_t>(rel.z)),
                 static_cast<std::uint32_t>(k)};
  }
  std::sort(keyed_.begin(), keyed_.end());
  cells_.clear();
  cells_.reserve(n);
  for (std::uint32_t s = 0; s < n;) {
    std::uint32_t e = s + 1;
    while (e < n && keyed_[e].first == keyed_[s].first)
      ++e;
    cells_.emplace(keyed_[s].first, std::make_pair(s, e));
    s = e;
  }

  // The pairs in ascending (gid of a, gid of b) order: a term that adds each pair's loads to
  // both ends in list order then gives every particle its contacts in ascending partner gid,
  // whatever the storage order or the rank count (PairContactTerm). The owned range and the
  // ghost range are each usually sorted already; the check is linear.
  const std::size_t n_local = p.n_local();
  const auto by_gid = [&p](std::uint32_t x, std::uint32_t y) { return p.gid[x] < p.gid[y]; };
  by_gid_.resize(n);
  for (std::uint32_t k = 0; k < n; ++k)
    by_gid_[k] = k;
  const auto middle = by_gid_.begin() + static_cast<std::ptrdiff_t>(n_local);
  if (!std::is_sorted(by_gid_.begin(), middle, by_gid)) std::sort(by_gid_.begin(), middle, by_gid);
  if (!std::is_sorted(middle, by_gid_.end(), by_gid)) std::sort(middle, by_gid_.end(), by_gid);
  std::inplace_merge(by_gid_.begin(), middle, by_gid_.end(), by_gid);

  std::vector<std::uint32_t> partners;
  for (const std::uint32_t a : by_gid_) {
    const Vec3 rel = (p.position[a] - lo) * inv_h;
    const auto cx = static_cast<std::int64_t>(rel.x);
    const auto cy = static_cast<std::int64_t>(rel.y);
    const auto cz = static_cast<std::int64_t>(rel.z);
    partners.clear();
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells_.find(cell_key(cx + dx, cy + dy, cz + dz));
          if (it == cells_.end()) continue;
          for (std::uint32_t s = it->second.first; s < it->second.second; ++s) {
            const std::uint32_t b = keyed_[s].second;
            if (is_candidate(p, n_local, skin, ex, a, b)) partners.push_back(b);
          }
        }
    std::sort(partners.begin(), partners.end(), by_gid);
    for (const std::uint32_t b : partners) {
      out.i.push_back(a);
      out.j.push_back(b);
    }
  }
}

PairCandidates brute_force_pairs(const ParticleStore& p, double skin, const PairExclusions& ex) {
  PairCandidates out;
  const std::size_t n = p.n_total();
  for (std::uint32_t a = 0; a < n; ++a)
    for (std::uint32_t b = 0; b < n; ++b)
      if (a != b && is_candidate(p, p.n_local(), skin, ex, a, b)) {
        out.i.push_back(a);
        out.j.push_back(b);
      }
  return out;
}

}  // namespace ringdem

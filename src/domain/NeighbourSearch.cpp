#include "domain/NeighbourSearch.hpp"

#include <algorithm>
#include <array>
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
  constexpr double kBig = std::numeric_limits<double>::max();
  Vec3 lo{kBig, kBig, kBig}, hi{-kBig, -kBig, -kBig};
  for (std::size_t k = 0; k < n; ++k) {
    r_max = std::max(r_max, p.radius[k]);
    const Vec3& x = p.position[k];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
  }
  const double h = 2.0 * r_max + skin;
  const double inv_h = 1.0 / h;
  const auto cell_of = [&](std::size_t k) {
    const Vec3 rel = (p.position[k] - lo) * inv_h;
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(rel.x),
                                       static_cast<std::int64_t>(rel.y),
                                       static_cast<std::int64_t>(rel.z)};
  };

  // A dense grid (counting sort, array lookups) when the particles fill their bounding box;
  // hashed cells when they are sparse in it (a net far from the boulder, a few grains far apart).
  const double extent[3] = {std::floor((hi.x - lo.x) * inv_h) + 1.0,
                            std::floor((hi.y - lo.y) * inv_h) + 1.0,
                            std::floor((hi.z - lo.z) * inv_h) + 1.0};
  dense_ = extent[0] * extent[1] * extent[2] <= 2.0 * static_cast<double>(n) + 64.0;
  if (dense_) {
    for (int d = 0; d < 3; ++d)
      dims_[d] = static_cast<std::int64_t>(extent[d]);
    const auto n_cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
    cell_start_.assign(n_cells + 1, 0);
    cell_of_particle_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const auto c = cell_of(k);
      cell_of_particle_[k] = static_cast<std::uint32_t>((c[0] * dims_[1] + c[1]) * dims_[2] + c[2]);
      ++cell_start_[cell_of_particle_[k] + 1];
    }
    for (std::size_t c = 0; c < n_cells; ++c)
      cell_start_[c + 1] += cell_start_[c];
    in_cells_.resize(n);
    fill_ = cell_start_;
    for (std::uint32_t k = 0; k < n; ++k)
      in_cells_[fill_[cell_of_particle_[k]]++] = k;
  } else {
    keyed_.resize(n);
    for (std::size_t k = 0; k < n; ++k) {
      const auto c = cell_of(k);
      keyed_[k] = {cell_key(c[0], c[1], c[2]), static_cast<std::uint32_t>(k)};
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
  }
  // Calls f(particle index) for every particle in cell (cx, cy, cz).
  const auto for_each_in_cell = [&](std::int64_t cx, std::int64_t cy, std::int64_t cz, auto&& f) {
    if (dense_) {
      if (cx < 0 || cy < 0 || cz < 0 || cx >= dims_[0] || cy >= dims_[1] || cz >= dims_[2]) return;
      const auto c = static_cast<std::size_t>((cx * dims_[1] + cy) * dims_[2] + cz);
      for (std::uint32_t s = cell_start_[c]; s < cell_start_[c + 1]; ++s)
        f(in_cells_[s]);
      return;
    }
    const auto it = cells_.find(cell_key(cx, cy, cz));
    if (it == cells_.end()) return;
    for (std::uint32_t s = it->second.first; s < it->second.second; ++s)
      f(keyed_[s].second);
  };

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
    const auto c = cell_of(a);
    partners.clear();
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz)
          for_each_in_cell(c[0] + dx, c[1] + dy, c[2] + dz, [&](std::uint32_t b) {
            if (is_candidate(p, n_local, skin, ex, a, b)) partners.push_back(b);
          });
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

#include "domain/GrainPacking.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>

#include <fmt/format.h>

namespace ringdem {

std::vector<double> draw_cell_radii(const GrainSizeDistribution& sizes, double target_volume,
                                    std::mt19937_64& rng) {
  std::vector<double> radii;
  double volume = 0.0;
  for (;;) {
    const double r = sizes.draw(rng);
    const double v = 4.0 / 3.0 * M_PI * r * r * r;
    if (volume + v > target_volume) break;
    volume += v;
    radii.push_back(r);
  }
  std::sort(radii.begin(), radii.end(), std::greater<>());
  return radii;
}

namespace {

/// The grains placed so far in a uniform grid over the box: each grain is listed in every
/// grid cell that its bounding box touches, so two overlapping spheres share a cell and a
/// candidate needs to look only at the cells of its own bounding box.
class PlacedGrid {
 public:
  PlacedGrid(const Vec3& lo, const Vec3& hi, double spacing) : lo_(lo) {
    const double extent[3] = {hi.x - lo.x, hi.y - lo.y, hi.z - lo.z};
    for (int a = 0; a < 3; ++a) {
      n_[a] = static_cast<int>(std::clamp(std::floor(extent[a] / spacing), 1.0, 128.0));
      inv_h_[a] = n_[a] / extent[a];
    }
    cells_.resize(static_cast<std::size_t>(n_[0]) * n_[1] * n_[2]);
  }

  template <class F>
  bool any_in_box(const Vec3& c, double r, F&& f) const {
    const auto range = cell_range(c, r);
    for (int i = range[0]; i <= range[3]; ++i)
      for (int j = range[1]; j <= range[4]; ++j)
        for (int k = range[2]; k <= range[5]; ++k)
          for (const std::uint32_t g : cells_[index(i, j, k)])
            if (f(g)) return true;
    return false;
  }

  void insert(const Vec3& c, double r, std::uint32_t g) {
    const auto range = cell_range(c, r);
    for (int i = range[0]; i <= range[3]; ++i)
      for (int j = range[1]; j <= range[4]; ++j)
        for (int k = range[2]; k <= range[5]; ++k)
          cells_[index(i, j, k)].push_back(g);
  }

 private:
  std::size_t index(int i, int j, int k) const {
    return (static_cast<std::size_t>(i) * n_[1] + j) * n_[2] + k;
  }
  int clamp_cell(double x, int a) const {
    return std::clamp(static_cast<int>(std::floor(x * inv_h_[a])), 0, n_[a] - 1);
  }
  std::array<int, 6> cell_range(const Vec3& c, double r) const {
    const Vec3 a = c - lo_;
    return {clamp_cell(a.x - r, 0), clamp_cell(a.y - r, 1), clamp_cell(a.z - r, 2),
            clamp_cell(a.x + r, 0), clamp_cell(a.y + r, 1), clamp_cell(a.z + r, 2)};
  }

  Vec3 lo_;
  int n_[3] = {1, 1, 1};
  double inv_h_[3] = {1.0, 1.0, 1.0};
  std::vector<std::vector<std::uint32_t>> cells_;
};

}  // namespace

std::vector<PackedGrain> place_grains(const std::vector<double>& radii, const Vec3& lo,
                                      const Vec3& hi, std::mt19937_64& rng, int max_attempts) {
  std::vector<PackedGrain> grains;
  if (radii.empty()) return grains;
  grains.reserve(radii.size());
  // Grid spacing: twice the mean radius, so that a typical grain touches a few cells and a
  // cell lists a few grains; the few larger grains are listed in more cells.
  double mean_radius = 0.0;
  for (const double r : radii)
    mean_radius += r;
  mean_radius /= static_cast<double>(radii.size());
  PlacedGrid grid(lo, hi, 2.0 * mean_radius);
  for (const double r : radii) {
    const Vec3 span = hi - lo - Vec3{2.0 * r, 2.0 * r, 2.0 * r};
    if (span.x < 0.0 || span.y < 0.0 || span.z < 0.0)
      throw GrainPackingError(fmt::format(
          "a grain of radius {:.6g} m does not fit in a packing cell of {:.6g} x {:.6g} x {:.6g} m",
          r, hi.x - lo.x, hi.y - lo.y, hi.z - lo.z));
    bool placed = false;
    for (int attempt = 0; attempt < max_attempts && !placed; ++attempt) {
      // Braced initialisation evaluates the draws left to right.
      const Vec3 u{unit_draw(rng), unit_draw(rng), unit_draw(rng)};
      const Vec3 c{lo.x + r + u.x * span.x, lo.y + r + u.y * span.y, lo.z + r + u.z * span.z};
      const bool overlaps = grid.any_in_box(c, r, [&](std::uint32_t g) {
        const double reach = r + grains[g].radius;
        return norm2(c - grains[g].centre) < reach * reach;
      });
      if (overlaps) continue;
      grid.insert(c, r, static_cast<std::uint32_t>(grains.size()));
      grains.push_back({c, r});
      placed = true;
    }
    if (!placed)
      throw GrainPackingError(fmt::format(
          "random sequential addition found no room for grain {} of {} (radius {:.6g} m) after "
          "{} attempts",
          grains.size() + 1, radii.size(), r, max_attempts));
  }
  return grains;
}

void order_by_space(std::vector<PackedGrain>& grains, const Vec3& lo, double bin) {
  struct Keyed {
    std::array<std::int64_t, 3> bin;  // x, y, z: compared lexicographically, z fastest
    PackedGrain grain;
  };
  std::vector<Keyed> keyed;
  keyed.reserve(grains.size());
  const auto bin_of = [&](double x, double origin) {
    return static_cast<std::int64_t>(std::floor((x - origin) / bin));
  };
  for (const PackedGrain& g : grains)
    keyed.push_back(
        {{bin_of(g.centre.x, lo.x), bin_of(g.centre.y, lo.y), bin_of(g.centre.z, lo.z)}, g});
  std::stable_sort(keyed.begin(), keyed.end(),
                   [](const Keyed& a, const Keyed& b) { return a.bin < b.bin; });
  for (std::size_t k = 0; k < grains.size(); ++k)
    grains[k] = keyed[k].grain;
}

}  // namespace ringdem

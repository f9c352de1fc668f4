#include "engine/GrainSource.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "domain/GrainPacking.hpp"

namespace ringdem {
namespace {

/// SplitMix64's finaliser: decorrelates the seeds of neighbouring cells.
std::uint64_t mix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ULL;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
  return x ^ (x >> 31);
}

}  // namespace

GrainSource::GrainSource(const Spec& spec) : spec_(spec) {
  const Vec3 extent = spec.box_max - spec.box_min;
  const double d_max = 2.0 * spec.sizes.max_radius();
  const double e[3] = {extent.x, extent.y, extent.z};
  double size[3];
  for (int a = 0; a < 3; ++a) {
    if (!(e[a] >= d_max))
      throw std::invalid_argument(fmt::format(
          "{}: the box is {:.6g} m wide along {}, less than the largest grain ({:.6g} m)",
          spec.name, e[a], "xyz"[a], d_max));
    const auto n = static_cast<int>(std::max(1.0, std::floor(e[a] / (kCellDiameters * d_max))));
    cells_[static_cast<std::size_t>(a)] = n;
    size[a] = e[a] / n;
  }
  cell_size_ = {size[0], size[1], size[2]};
  target_volume_ = spec.solid_fraction * size[0] * size[1] * size[2];
  const double r = spec.sizes.min_radius();
  const double per_cell = std::floor(target_volume_ / (4.0 / 3.0 * M_PI * r * r * r)) + 1.0;
  // Gids are int64: keep the reserved range far from overflow (2^62 items).
  if (per_cell * static_cast<double>(cells()) > 0x1.0p62)
    throw std::invalid_argument(fmt::format(
        "{}: the box holds up to {:.3g} grains of the smallest size: too many for 64-bit ids",
        spec.name, per_cell * static_cast<double>(cells())));
  per_cell_ = static_cast<std::int64_t>(per_cell);
}

std::mt19937_64 GrainSource::cell_stream(std::int64_t cell) const {
  return std::mt19937_64(mix(mix(spec_.seed) ^ static_cast<std::uint64_t>(cell)));
}

Vec3 GrainSource::cell_lower(std::int64_t cell) const {
  const std::int64_t ny = cells_[1], nz = cells_[2];
  const std::int64_t i = cell / (ny * nz), j = (cell / nz) % ny, k = cell % nz;
  return spec_.box_min + Vec3{static_cast<double>(i) * cell_size_.x,
                              static_cast<double>(j) * cell_size_.y,
                              static_cast<double>(k) * cell_size_.z};
}

std::int64_t GrainSource::count() const {
  if (!count_) {
    std::int64_t n = 0;
    for (std::int64_t cell = 0; cell < cells(); ++cell) {
      auto rng = cell_stream(cell);
      n += static_cast<std::int64_t>(draw_cell_radii(spec_.sizes, target_volume_, rng).size());
    }
    count_ = n;
  }
  return *count_;
}

void GrainSource::emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                       Model& model) const {
  if (first >= last) return;
  for (std::int64_t cell = first / per_cell_; cell <= (last - 1) / per_cell_; ++cell) {
    auto rng = cell_stream(cell);
    const std::vector<double> radii = draw_cell_radii(spec_.sizes, target_volume_, rng);
    const Vec3 lo = cell_lower(cell);
    std::vector<PackedGrain> grains;
    try {
      grains = place_grains(radii, lo, lo + cell_size_, rng);
    } catch (const GrainPackingError& e) {
      throw GrainPackingError(fmt::format(
          "{}: packing cell {} at ({:.6g}, {:.6g}, {:.6g}) m: {}; lower solid_fraction ({:.3g}): "
          "random sequential addition jams near 0.38 for equal spheres and lower next to the "
          "cell walls, and the grains pack denser as they settle",
          spec_.name, cell, lo.x, lo.y, lo.z, e.what(), spec_.solid_fraction));
    }
    order_by_space(grains, lo, 2.0 * spec_.sizes.max_radius());
    for (std::size_t k = 0; k < grains.size(); ++k) {
      const std::int64_t item = cell * per_cell_ + static_cast<std::int64_t>(k);
      if (item < first || item >= last) continue;
      ParticleStore::NewParticle np;
      np.gid = bases.gid + item;
      np.position = grains[k].centre;
      np.radius = grains[k].radius;
      np.velocity = spec_.velocity;
      np.density = spec_.density;
      np.damping = spec_.damping;
      np.material = spec_.material;
      np.group = spec_.group;
      model.particles.add(np);
    }
  }
}

}  // namespace ringdem

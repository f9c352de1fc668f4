#include "domain/SpatialBins.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ringdem {

namespace {

/// floor(c / width) modulo 2^bits, for any sign of c; 0 for a coordinate no integer holds (a
/// grain flung beyond 2^62 widths, or not a number), whose conversion would be undefined.
std::uint32_t wrapped_index(double c, double width, unsigned bits) {
  const double q = std::floor(c / width);
  if (!(std::abs(q) < 0x1p62)) return 0;
  const auto i = static_cast<std::int64_t>(q);
  return static_cast<std::uint32_t>(static_cast<std::uint64_t>(i) &
                                    ((std::uint64_t{1} << bits) - 1));
}
}  // namespace

std::uint32_t SpatialBins::bin_of(const Vec3& x, const Order& order) {
  const double c[3] = {x.x, x.y, x.z};
  // The other two axes in x, y, z order: the first of them fastest.
  const int fastest = order.slowest == kX ? kY : kX;
  const int middle = order.slowest == kZ ? kY : kZ;
  return kBinned | wrapped_index(c[order.slowest], order.width, 10) << 21 |
         wrapped_index(c[middle], order.width, 10) << 11 |
         wrapped_index(c[fastest], order.width, 11);
}

SpatialBins::Axis SpatialBins::slowest_axis(const Vec3& extent) {
  if (extent.z >= extent.x && extent.z >= extent.y) return kZ;
  return extent.y >= extent.x ? kY : kX;
}

void SpatialBins::assign(ParticleStore& p, const Order& order) {
  for (std::size_t k = 0; k < p.n_local(); ++k)
    p.sort_bin[k] = p.body[k] < 0 ? bin_of(p.position[k], order) : 0;
}

std::pair<Vec3, Vec3> SpatialBins::binned_box(const ParticleStore& p) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.body[k] >= 0) continue;
    const Vec3& x = p.position[k];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
  }
  return {lo, hi};
}

double SpatialBins::smallest_binned_radius(const ParticleStore& p) {
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] < 0) r = std::min(r, p.radius[k]);
  return r;
}

}  // namespace ringdem

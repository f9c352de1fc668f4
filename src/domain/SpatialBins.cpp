#include "domain/SpatialBins.hpp"

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

std::uint32_t SpatialBins::bin_of(const Vec3& x, double width) {
  return kBinned | wrapped_index(x.z, width, 10) << 21 | wrapped_index(x.y, width, 10) << 11 |
         wrapped_index(x.x, width, 11);
}

void SpatialBins::assign(ParticleStore& p, double width) {
  for (std::size_t k = 0; k < p.n_local(); ++k)
    p.sort_bin[k] = p.body[k] < 0 ? bin_of(p.position[k], width) : 0;
}

double SpatialBins::smallest_binned_radius(const ParticleStore& p) {
  double r = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.body[k] < 0) r = std::min(r, p.radius[k]);
  return r;
}

}  // namespace ringdem

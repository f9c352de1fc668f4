#include "domain/RingGenerator.hpp"

#include <cmath>
#include <stdexcept>

namespace ringdem {

double RingGeometry::spacing() const {
  return 2.0 * centreline_radius() * std::sin(M_PI / n_particles);
}

std::vector<Vec3> RingGeometry::positions() const {
  if (n_particles < 3) throw std::invalid_argument("a ring needs at least 3 particles");
  const Vec3 n = normalized(normal);
  Vec3 e1 = reference - n * dot(reference, n);
  e1 = norm2(e1) > 1e-24 ? normalized(e1) : any_perpendicular(n);
  const Vec3 e2 = cross(n, e1);
  const double r = centreline_radius();
  std::vector<Vec3> out(static_cast<std::size_t>(n_particles));
  for (int k = 0; k < n_particles; ++k) {
    const double phi = 2.0 * M_PI * k / n_particles;
    out[static_cast<std::size_t>(k)] = centre + e1 * (r * std::cos(phi)) + e2 * (r * std::sin(phi));
  }
  return out;
}

std::vector<std::pair<int, int>> RingGeometry::bonded_pairs() const {
  std::vector<std::pair<int, int>> out;
  out.reserve(static_cast<std::size_t>(n_particles));
  for (int k = 0; k < n_particles; ++k)
    out.emplace_back(k, (k + 1) % n_particles);
  return out;
}

}  // namespace ringdem

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

RingReductionFactors ring_reduction_factors(int windings, double wire_radius,
                                            double particle_radius, double radius_multiplier,
                                            double steel_youngs_modulus) {
  if (windings < 1 || !(wire_radius > 0.0) || !(particle_radius > 0.0) ||
      !(radius_multiplier > 0.0) || !(steel_youngs_modulus > 0.0))
    throw std::invalid_argument("ring reduction factors need positive windings, radii and modulus");
  RingReductionFactors f;
  f.equivalent_radius = std::sqrt(static_cast<double>(windings)) * wire_radius;  // Eq. 12
  f.gamma = radius_multiplier * particle_radius / f.equivalent_radius;  // gamma R_eq = lambda r_eq
  f.eta = 1.0 / (5.0 * f.gamma * f.gamma);                              // Eq. 17
  f.bond_youngs_modulus = f.eta * steel_youngs_modulus;                 // E_b = eta E
  return f;
}

}  // namespace ringdem

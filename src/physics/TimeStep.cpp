#include "physics/TimeStep.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ringdem {

double StabilityLimits::min() const {
  return std::min({rayleigh, bond_axial, bond_shear, bond_rotation, brake, rope, mesh});
}

std::vector<std::pair<std::string, double>> StabilityLimits::named() const {
  return {{"Rayleigh", rayleigh},
          {"bond axial", bond_axial},
          {"bond shear", bond_shear},
          {"bond rotation", bond_rotation},
          {"brake", brake},
          {"rope", rope},
          {"mesh", mesh}};
}

StabilityLimits stability_limits(const ParticleStore& p, const BondStore& bonds,
                                 const MaterialTable& materials) {
  constexpr double inf = std::numeric_limits<double>::infinity();
  StabilityLimits s{inf, inf, inf, inf, inf, inf};
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const Material& m = materials[static_cast<std::size_t>(p.material[k])];
    s.rayleigh = std::min(
        s.rayleigh, rayleigh_time_step(p.radius[k], m.density, m.shear_modulus(), m.poisson_ratio));
  }
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    const std::int64_t a = p.index_of(bonds.gid_a[k]);
    const std::int64_t b = p.index_of(bonds.gid_b[k]);
    if (a < 0 || b < 0) continue;
    const double mass = std::min(p.mass[a], p.mass[b]);
    const double inertia = std::min(p.inertia(a), p.inertia(b));
    s.bond_axial = std::min(s.bond_axial, spring_time_step(mass, bonds.k_axial[k]));
    s.bond_shear = std::min(s.bond_shear, spring_time_step(mass, bonds.k_shear[k]));
    s.bond_rotation =
        std::min(s.bond_rotation,
                 spring_time_step(inertia, std::max(bonds.k_bend_self[k], bonds.k_torsion[k])));
  }
  return s;
}

}  // namespace ringdem

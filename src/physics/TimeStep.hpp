#pragma once

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/ParticleStore.hpp"
#include "physics/MaterialTable.hpp"

namespace ringdem {

/// Stability limits of the explicit integrator (physics.md §4), each the smallest over all
/// owned particles and bonds of this rank (infinity where there is nothing to limit).
struct StabilityLimits {
  double rayleigh;       ///< pi R sqrt(rho/G) / (0.1631 nu + 0.8766)
  double bond_axial;     ///< sqrt(m / (E A / L))
  double bond_shear;     ///< sqrt(m / (12 c / L^3))
  double bond_rotation;  ///< sqrt(I / max((4 + Phi) c / L, G J / L))
  /// sqrt(M / k) of a braked body on its brake's spring (docs/physics.md "Brake elements")
  double brake = std::numeric_limits<double>::infinity();
  /// sqrt(M / k) of a body on a support rope: k = 4 EA / L0 sliding freely, EA (1 / lambda_a +
  /// 1 / lambda_b) held by friction ("Support ropes"; engine/FrameRestraints)
  double rope = std::numeric_limits<double>::infinity();
  /// sqrt(1 / (k (1 / m + 3 / M))) of the lightest grain a net's secondary mesh holds
  /// (RingMesh::time_step_limit; docs/physics.md "Secondary mesh")
  double mesh = std::numeric_limits<double>::infinity();

  double min() const;
  /// (name, value) of each limit, for the pre-flight report.
  std::vector<std::pair<std::string, double>> named() const;
};

/// Rayleigh limit of one sphere: pi R sqrt(rho/G) / (0.1631 nu + 0.8766) (physics.md §4).
inline double rayleigh_time_step(double radius, double density, double shear_modulus,
                                 double poisson_ratio) {
  return M_PI * radius * std::sqrt(density / shear_modulus) / (0.1631 * poisson_ratio + 0.8766);
}

/// Period-type limit of a mass (or moment of inertia) on a spring: sqrt(m / k) (physics.md §4).
inline double spring_time_step(double mass, double stiffness) {
  return std::sqrt(mass / stiffness);
}

StabilityLimits stability_limits(const ParticleStore& p, const BondStore& bonds,
                                 const MaterialTable& materials);

}  // namespace ringdem

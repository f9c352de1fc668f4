#pragma once

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

  double min() const;
  /// (name, value) of each limit, for the pre-flight report.
  std::vector<std::pair<std::string, double>> named() const;
};

StabilityLimits stability_limits(const ParticleStore& p, const BondStore& bonds,
                                 const MaterialTable& materials);

}  // namespace ringdem

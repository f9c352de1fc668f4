#pragma once

#include <utility>
#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// Geometry of one ring element: n particle centres on a circle, consecutive ones bonded
/// (physics.md §5: 300 mm internal diameter, 100 particles of 4.5 mm on a 154.5 mm circle).
struct RingGeometry {
  Vec3 centre;
  Vec3 normal{0, 1, 0};     ///< ring axis (normalised on use)
  Vec3 reference{1, 0, 0};  ///< direction of particle 0 (projected into the ring plane)
  double internal_diameter = 0.3;
  double particle_radius = 0.0045;
  int n_particles = 100;

  /// Radius of the circle through the particle centres.
  double centreline_radius() const { return 0.5 * internal_diameter + particle_radius; }
  /// Distance between neighbouring centres (the bond length).
  double spacing() const;
  std::vector<Vec3> positions() const;
  /// Local index pairs (k, k+1 mod n).
  std::vector<std::pair<int, int>> bonded_pairs() const;
};

/// Bond parameters of a ring of n_w windings derived from the reduction factors of the paper
/// (physics.md §2, Eq. 10-17). The ring's wire bundle has the equivalent radius
/// R_eq = sqrt(n_w) r_w (Eq. 12, chi = 1); the bond radius lambda r_eq (Eq. 11) is written
/// gamma R_eq, and the bond modulus eta E. The axial stiffness is a fifth of that of the wires
/// (Grassl 2002, Eq. 14), which fixes eta gamma^2 = 1/5 (Eq. 17); lambda, the one free parameter,
/// sets the bending reduction eta gamma^4.
struct RingReductionFactors {
  double equivalent_radius = 0.0;    ///< R_eq = sqrt(n_w) r_w
  double gamma = 0.0;                ///< bond radius / R_eq = lambda r_eq / R_eq
  double eta = 0.0;                  ///< bond modulus / steel modulus = 1 / (5 gamma^2)
  double bond_youngs_modulus = 0.0;  ///< E_b = eta E
  /// eta gamma^4: bending stiffness of the bond over that of the full wire bundle (Eq. 15/12).
  double bending_reduction() const { return eta * gamma * gamma * gamma * gamma; }
};

/// Reduction factors of a ring of `windings` turns of wire of radius `wire_radius`, modelled by
/// particles of radius `particle_radius` (r_eq) bonded with radius multiplier
/// `radius_multiplier` (lambda), steel Young's modulus `steel_youngs_modulus` (E).
/// Throws std::invalid_argument for non-positive inputs.
RingReductionFactors ring_reduction_factors(int windings, double wire_radius,
                                            double particle_radius, double radius_multiplier,
                                            double steel_youngs_modulus);

}  // namespace ringdem

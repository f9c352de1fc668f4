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

}  // namespace ringdem

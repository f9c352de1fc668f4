#pragma once

#include <cstddef>

#include "core/Vec3.hpp"

namespace ringdem {

/// The secondary mesh of a ring (docs/physics.md "Secondary mesh"): a membrane spanned by the
/// ring's beads that holds grains too coarse for its openings. It is a disc in the plane of the
/// bead polygon: through the beads' centroid c, with the normal n = A / |A| of the polygon's
/// vector area A = 1/2 sum_i q_i x q_(i+1) (q_i = p_i - c, beads in order round the ring), and
/// the radius a = sqrt(|A| / pi) of a circle of the polygon's area. A grain of radius r at x,
/// at the signed distance d = (x - c) . n and the in-plane distance rho = |(x - c)_perp| from c,
/// overlaps it by delta = r - |d| > 0 and holds (Eq. M1)
///   E = 1/2 k s delta^2,   s = S((a - rho) / w),   S(t) = 3 t^2 - 2 t^3 on [0, 1],
/// so that the mesh fades out over the width w = min(r, a / 2) inside the rim and E is
/// continuous wherever the grain goes. Every elastic load is minus a gradient of E (Eq. M2-M4),
/// so the loads on the grain and the beads balance in force and moment; the normal part
/// f = max(0, k s delta + c_d s delta') along the gradient of delta carries a dashpot,
/// c_d = 2 zeta sqrt(k m*) (Eq. M5). The mesh is frictionless.
struct RingMesh {
  struct Params {
    double opening = 0.0;        ///< grains of this diameter or more are held (m)
    double stiffness = 0.0;      ///< k of Eq. M1 (N/m)
    double damping_ratio = 0.0;  ///< zeta of Eq. M5
  };

  /// The plane of a ring's beads (positions in order round the ring).
  struct Plane {
    Vec3 centre;          ///< c: the beads' centroid
    Vec3 normal;          ///< n = A / |A|
    double area = 0.0;    ///< |A|
    double radius = 0.0;  ///< a = sqrt(|A| / pi), the disc's (Eq. M1)
    double reach = 0.0;   ///< max_i |q_i|: every bead lies within it of c
  };
  static Plane plane(const Vec3* bead, std::size_t n);

  /// How far a grain's signed distance to the plane, d = (x - c).n (Eq. M1), can change while
  /// every bead and the grain move at most `move`: by at most offset + tilt |x - c|, with x - c
  /// taken now. The grain and the centroid c each move at most `move` (offset 2 move); the
  /// normal n = A / |A| turns by at most 2 |dA| / |A| (as |a/|a| - b/|b|| <= 2 |a - b| / |a|),
  /// where for bead moves u_i the vector area A = 1/2 sum_i b_i x b_(i+1) changes by
  /// dA = 1/2 sum_i u_i x (b_(i+1) - b_(i-1)) + 1/2 sum_i u_i x u_(i+1). A grain farther from
  /// the plane than its radius plus that cannot touch the mesh meanwhile: a ring's candidates
  /// are a slab about its plane, not the whole sphere of its reach.
  struct Band {
    double offset = 0.0, tilt = 0.0;
  };
  static Band band(const Vec3* bead, std::size_t n, const Plane& plane, double move);

  /// A load on each bead of a ring in the form that every bead load of Eq. M3-M4 takes:
  /// F_i = uniform + turning x c_i, with c_i = p_(i-1) - p_(i+1) the chord across bead i.
  /// A ring's loads from all its grains then sum as two vectors, spread over its beads once
  /// (docs/physics.md "Secondary mesh", Eq. M6).
  struct BeadLoads {
    Vec3 uniform;
    Vec3 turning;
    BeadLoads& operator+=(const BeadLoads& o) {
      uniform += o.uniform;
      turning += o.turning;
      return *this;
    }
    /// Bead i's load, for the ring's n beads in order.
    Vec3 at(const Vec3* bead, std::size_t n, std::size_t i) const {
      const Vec3& before = bead[i == 0 ? n - 1 : i - 1];
      const Vec3& after = bead[i + 1 == n ? 0 : i + 1];
      return uniform + cross(turning, before - after);
    }
  };

  /// The sums over a ring's beads that a grain's overlap rate reads (Eq. M6): the beads'
  /// velocity sum V = sum_i v_i and the chords' moment K = sum_i c_i x v_i.
  struct Motion {
    Vec3 velocity_sum;
    Vec3 chord_moment;
  };
  static Motion motion(const Vec3* bead_position, const Vec3* bead_velocity, std::size_t n);

  struct Input {
    std::size_t n = 0;  ///< the ring's beads
    Vec3 position;      ///< the grain's centre
    Vec3 velocity;
    double radius = 0.0;
    double m_star = 0.0;  ///< effective mass of Eq. M5: m_grain m_ring / (m_grain + m_ring)
  };
  struct Output {
    double overlap = 0.0;         ///< delta (> 0 when touching)
    double weight = 0.0;          ///< s of Eq. M1
    double elastic_energy = 0.0;  ///< E of Eq. M1
    Vec3 outward;                 ///< sign(d) n: from the mesh towards the grain's centre
    Vec3 force;                   ///< the whole load on the grain
    Vec3 damping;                 ///< its viscous part, along n
  };
  /// The mesh's loads on a grain from the ring's `plane` and `motion`: false when they do not
  /// touch (the outputs then untouched). Touching, writes the beads' whole loads into
  /// `bead_force` and their viscous part into `bead_damping`. Its cost does not grow with the
  /// ring's beads (Eq. M6).
  static bool compute(const Params& params, const Plane& plane, const Motion& motion,
                      const Input& in, Output& out, BeadLoads& bead_force, BeadLoads& bead_damping);

  /// Stability limit sqrt(1 / (4 k (1 / m_grain + 3 / m_ring))): the normal frequency of one
  /// contact, omega^2 = k (1 / m_grain + sum_i |g_i|^2 / m_bead), with sum_i |g_i|^2 <= 3 / N
  /// for a grain inside a flat regular ring of N beads of m_ring / N each, and a factor 4 for
  /// the fade at the rim, whose stiffness across it is up to 3 k (delta / w)^2 <= 3 k.
  static double time_step_limit(double stiffness, double grain_mass, double ring_mass);
};

}  // namespace ringdem

#include "physics/BondTimoshenko.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace ringdem {

BondTimoshenko::Section BondTimoshenko::Section::make(const Params& p, double radius_a,
                                                      double radius_b, double length0) {
  Section s;
  s.r_b = p.radius_multiplier * std::min(radius_a, radius_b);  // Eq. 11
  s.area = M_PI * s.r_b * s.r_b;
  s.inertia = M_PI * s.r_b * s.r_b * s.r_b * s.r_b / 4.0;
  s.length0 = length0;
  const double e = p.youngs_modulus;
  const double g = e / (2.0 * (1.0 + p.poisson_ratio));
  const double nu = p.poisson_ratio;
  const double form_factor = (7.0 + 6.0 * nu) / (6.0 * (1.0 + nu));  // Cowper, solid circle
  const double l = length0;
  const double phi = 12.0 * e * s.inertia * form_factor / (g * s.area * l * l);
  const double c = e * s.inertia / (1.0 + phi);
  s.k_axial = e * s.area / l;
  s.k_torsion = g * 2.0 * s.inertia / l;
  s.k_shear = 12.0 * c / (l * l * l);
  s.k_couple = 6.0 * c / (l * l);
  s.k_bend_self = (4.0 + phi) * c / l;
  s.k_bend_cross = (2.0 - phi) * c / l;
  s.inv_area = 1.0 / s.area;
  s.bend_factor = s.r_b / s.inertia;
  return s;
}

BondTimoshenko::Reference BondTimoshenko::Reference::make(const Vec3& x_a, const Mat3& rot_a,
                                                          const Vec3& x_b, const Mat3& rot_b) {
  const Vec3 axis = normalized(x_b - x_a);
  const Vec3 perp = any_perpendicular(axis);
  Reference r;
  r.axis_a = rot_a.transpose_times(axis);
  r.perp_a = rot_a.transpose_times(perp);
  r.axis_b = rot_b.transpose_times(axis);
  r.perp_b = rot_b.transpose_times(perp);
  return r;
}

namespace {

/// Small rotation taking the chord frame C = (cx, cy, cz) to an end frame A = (ax, ay, az),
/// in chord components: the axial vector of the skew part of C^T A is sin(theta) * axis;
/// the cubic asin series restores the angle, exact to O(theta^5) for the per-bond angles of
/// any ring deformation.
struct LocalRotation {
  double x, y, z;
};
inline LocalRotation relative_rotation(const Vec3& cx, const Vec3& cy, const Vec3& cz,
                                       const Vec3& ax, const Vec3& ay, const Vec3& az) {
  const double sx = 0.5 * (dot(cz, ay) - dot(cy, az));
  const double sy = 0.5 * (dot(cx, az) - dot(cz, ax));
  const double sz = 0.5 * (dot(cy, ax) - dot(cx, ay));
  const double s2 = sx * sx + sy * sy + sz * sz;
  const double f = 1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0));
  return {sx * f, sy * f, sz * f};
}

}  // namespace

BondTimoshenko::Result BondTimoshenko::compute(const Section& s, const Reference& ref,
                                               const Vec3& x_a, const Mat3& rot_a, const Vec3& x_b,
                                               const Mat3& rot_b) {
  // Current end frames.
  const Vec3 ax = rot_a * ref.axis_a;
  const Vec3 ay = rot_a * ref.perp_a;
  const Vec3 az = cross(ax, ay);
  const Vec3 bx = rot_b * ref.axis_b;
  const Vec3 by = rot_b * ref.perp_b;
  const Vec3 bz = cross(bx, by);

  // Chord frame: x along the bond, y the bisector of the end frames' y axes.
  const Vec3 d = x_b - x_a;
  const double inv_length = 1.0 / std::sqrt(norm2(d));
  const double length = norm2(d) * inv_length;
  const Vec3 cx = d * inv_length;
  const Vec3 ysum = ay + by;
  const Vec3 yperp = ysum - cx * dot(ysum, cx);
  const Vec3 cy = yperp * (1.0 / std::sqrt(norm2(yperp)));
  const Vec3 cz = cross(cx, cy);

  // Local deformations: q = [0,0,0, th_a, dL,0,0, th_b] (physics.md §1 DOF order).
  const LocalRotation ta = relative_rotation(cx, cy, cz, ax, ay, az);
  const LocalRotation tb = relative_rotation(cx, cy, cz, bx, by, bz);
  const double du = length - s.length0;

  // K q, rows of physics.md §1 (external end loads holding the deformation).
  const double fx_b = s.k_axial * du;                                // K[6,6] u_bx
  const double mx_b = s.k_torsion * (tb.x - ta.x);                   // K[9,9], K[9,3]
  const double my_a = s.k_bend_self * ta.y + s.k_bend_cross * tb.y;  // K[4,4], K[4,10]
  const double mz_a = s.k_bend_self * ta.z + s.k_bend_cross * tb.z;  // K[5,5], K[5,11]
  const double my_b = s.k_bend_cross * ta.y + s.k_bend_self * tb.y;  // K[10,4], K[10,10]
  const double mz_b = s.k_bend_cross * ta.z + s.k_bend_self * tb.z;  // K[11,5], K[11,11]
  // Shear rows K[7,*], K[8,*] equal -(M_a + M_b) / L0; dividing by the current length
  // instead makes the end loads balance exactly, so angular momentum is conserved.
  const double fy_b = -(mz_a + mz_b) * inv_length;
  const double fz_b = (my_a + my_b) * inv_length;

  // The beam acts on the particles with -K q; end a carries the opposite forces of end b.
  Result r;
  r.force_a = cx * fx_b + cy * fy_b + cz * fz_b;
  r.force_b = -r.force_a;
  r.torque_a = cx * mx_b - cy * my_a - cz * mz_a;
  r.torque_b = -(cx * mx_b + cy * my_b + cz * mz_b);

  r.axial_force = fx_b;
  r.shear_force = std::sqrt(fy_b * fy_b + fz_b * fz_b);
  r.torsion = mx_b;
  r.bending_a = std::sqrt(my_a * my_a + mz_a * mz_a);
  r.bending_b = std::sqrt(my_b * my_b + mz_b * mz_b);
  // 1/2 q^T K q = 1/2 (F . u) summed over the DOFs.
  r.energy = 0.5 * (fx_b * du + mx_b * (tb.x - ta.x) + my_a * ta.y + mz_a * ta.z + my_b * tb.y +
                    mz_b * tb.z);
  return r;
}

BondTimoshenko::Stresses BondTimoshenko::stresses(const Section& s, const Result& r) {
  Stresses st;
  const double axial = r.axial_force * s.inv_area;
  const double bend = s.bend_factor * std::max(r.bending_a, r.bending_b);
  st.tensile = axial + bend;       // Eq. 4
  st.compressive = bend - axial;   // Eq. 3
  // Eq. 5: torque over J = 2I, plus 4/3 of the mean shear stress of a circular section.
  st.shear = 0.5 * s.bend_factor * std::abs(r.torsion) + 4.0 / 3.0 * r.shear_force * s.inv_area;
  return st;
}

BondTimoshenko::Failure BondTimoshenko::check_failure(const Stresses& st,
                                                      const Strength& strength) {
  if (st.tensile > strength.tensile) return Failure::kTensile;
  if (st.compressive > strength.compressive) return Failure::kCompressive;
  if (st.shear > strength.shear) return Failure::kShear;
  return Failure::kNone;
}

double BondTimoshenko::utilisation(const Stresses& st, const Strength& strength) {
  return std::max({st.tensile / strength.tensile, st.compressive / strength.compressive,
                   st.shear / strength.shear});
}

BondTimoshenko::Strength BondTimoshenko::draw_strength(const Params& p, std::uint64_t seed,
                                                       std::int64_t gid_a, std::int64_t gid_b) {
  Strength s{p.tensile_strength, p.compressive_strength, p.shear_strength};
  if (p.strength_cov <= 0.0) return s;
  // SplitMix64 of (seed, gid pair): a fixed stream per bond, independent of ranks.
  auto mix = [](std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  const std::uint64_t key =
      mix(mix(mix(seed) ^ static_cast<std::uint64_t>(gid_a)) ^ static_cast<std::uint64_t>(gid_b));
  std::uint64_t state = key;
  auto uniform = [&]() {
    state = mix(state);
    return (static_cast<double>(state >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  };
  // Box–Muller, written out so the result does not depend on the standard library.
  auto normal = [&]() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  };
  // Strengths stay positive: a draw below 1 % of the mean is clamped there.
  auto vary = [&](double mean) { return mean * std::max(0.01, 1.0 + p.strength_cov * normal()); };
  s.tensile = vary(s.tensile);
  s.compressive = vary(s.compressive);
  s.shear = vary(s.shear);
  return s;
}

}  // namespace ringdem

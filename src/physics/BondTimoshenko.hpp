#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/BondFailure.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"

namespace ringdem {

/// EBPM bond: a Timoshenko beam between two particle centres (physics.md §1, Eq. 1–5).
///
/// Total co-rotational form: a chord frame follows the bond (x along the current axis, y the
/// bisector of the two end frames' y axes), the end rotations relative to it and the change
/// of length are the only deformations, and the 12x12 stiffness of physics.md §1 maps them
/// to end forces. Rigid motion of any size gives exactly zero force, nothing accumulates, and
/// the same inputs give the same bits on every rank.
struct BondTimoshenko {
  struct Params {
    double youngs_modulus = 0.0;     ///< E_b
    double poisson_ratio = 0.3;      ///< nu_b
    double radius_multiplier = 1.0;  ///< lambda (Eq. 11)
    double tensile_strength = 0.0;   ///< sigma_T mean
    double compressive_strength = 0.0;
    double shear_strength = 0.0;
    double strength_cov = 0.0;  ///< coefficient of variation of the strengths
  };

  /// Section and stiffness coefficients of one bond, fixed at creation.
  struct Section {
    double r_b = 0.0;           ///< bond radius lambda * min(r_a, r_b)
    double area = 0.0;          ///< A = pi r_b^2
    double inertia = 0.0;       ///< I = pi r_b^4 / 4, J = 2I
    double length0 = 0.0;       ///< reference length L0
    double k_axial = 0.0;       ///< E A / L
    double k_torsion = 0.0;     ///< G J / L
    double k_shear = 0.0;       ///< 12 c / L^3
    double k_couple = 0.0;      ///< 6 c / L^2
    double k_bend_self = 0.0;   ///< (4 + Phi) c / L
    double k_bend_cross = 0.0;  ///< (2 - Phi) c / L
    double inv_area = 0.0;      ///< 1 / A, for Eq. 3–5
    double bend_factor = 0.0;   ///< r_b / I

    static Section make(const Params& p, double radius_a, double radius_b, double length0);
  };

  /// Orientation of the bond frame at creation, stored in each particle's body frame.
  struct Reference {
    Quat frame_a;  ///< the bond frame (x along the bond) relative to a's body frame
    Quat frame_b;  ///< the same relative to b's body frame

    /// Rotation is a Mat3 or a unit Quat (body to world) of each end particle.
    template <class Rotation>
    static Reference make(const Vec3& x_a, const Rotation& rot_a, const Vec3& x_b,
                          const Rotation& rot_b) {
      const Quat bond = quat_between({1, 0, 0}, normalized(x_b - x_a));
      return {normalized(conjugate(as_quat(rot_a)) * bond),
              normalized(conjugate(as_quat(rot_b)) * bond)};
    }
  };

  struct Strength {
    double tensile = 0.0, compressive = 0.0, shear = 0.0;
  };

  struct Result {
    Vec3 force_a, torque_a;    ///< on particle a (global frame)
    Vec3 force_b, torque_b;    ///< on particle b
    double axial_force = 0.0;  ///< F_x, tension positive
    double shear_force = 0.0;  ///< |F_shear|
    double torsion = 0.0;      ///< M_x
    double bending_a = 0.0;    ///< |M_bend| at end a
    double bending_b = 0.0;    ///< |M_bend| at end b
    double energy = 0.0;       ///< 1/2 q^T K q
    /// shear_force^2 and max(bending_a, bending_b)^2, before the square roots: may_fail()
    /// needs no root, and a loop that reads only these does not compute the roots.
    double shear_force_squared = 0.0;
    double bending_squared = 0.0;
  };

  /// Forces, moments and stress resultants of one bond (inline: the bond loop vectorises it).
  /// Rotation is a Mat3 or a unit Quat (body to world) of each end particle.
  template <class Rotation>
  static Result compute(const Section& s, const Reference& ref, const Vec3& x_a,
                        const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b);

  /// The same co-rotational kernel with a constitutive hook, shared with the elastoplastic bond
  /// (BondTimoshenkoPlastic): the chord frame and the local deformations q of the ends, then
  /// `elastic_part(q, chord)` returns the part of q that K maps to loads (compute() passes all
  /// of q; the plastic bond, q minus its plastic deformations after the return mapping; the
  /// chord frame lets it move a plastic hinge into its end frames). The energy is
  /// 1/2 q_e^T K q_e of that part.
  struct Deformation;
  struct ChordFrame;
  template <class Rotation, class ElasticPart>
  static Result compute(const Section& s, const Reference& ref, const Vec3& x_a,
                        const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b,
                        ElasticPart&& elastic_part);

  /// Small rotation taking the chord frame C = (cx, cy, cz) to an end frame A = (ax, ay, az),
  /// in chord components: the axial vector of the skew part of C^T A is sin(theta) * axis;
  /// the cubic asin series restores the angle, exact to O(theta^5) for the per-bond angles
  /// of any ring deformation.
  struct LocalRotation {
    double x, y, z;
  };

  /// The chord frame's axes in the world frame: x along the bond, y the bisector of the end
  /// frames' y axes, z = x cross y.
  struct ChordFrame {
    Vec3 x, y, z;
  };

  /// Local deformations (physics.md §1 DOF order, q = [0,0,0, th_a, du,0,0, th_b]): change of
  /// length du and the end rotations ta, tb relative to the chord frame, in its components.
  struct Deformation {
    double du;
    LocalRotation ta, tb;
  };

  /// K q in the chord frame: the external end loads holding a deformation (tension positive).
  struct EndLoads {
    double fx_b;        ///< axial force, K[6,6] u_bx
    double mx_b;        ///< torque, K[9,9], K[9,3]
    double my_a, mz_a;  ///< bending moments at end a, K[4,*], K[5,*]
    double my_b, mz_b;  ///< bending moments at end b, K[10,*], K[11,*]
  };
  static EndLoads end_loads(const Section& s, const Deformation& q);
  static LocalRotation relative_rotation(const Vec3& cx, const Vec3& cy, const Vec3& cz,
                                         const Vec3& ax, const Vec3& ay, const Vec3& az);

  /// Largest stresses of Eq. 3–5 for a computed state.
  struct Stresses {
    double tensile = 0.0;      ///< sigma_T,max (Eq. 4)
    double compressive = 0.0;  ///< sigma_C,max (Eq. 3)
    double shear = 0.0;        ///< tau_max (Eq. 5)
  };
  static Stresses stresses(const Section& s, const Result& r);
  /// Whether Eq. 3–5 may break the bond: true wherever check_failure(stresses(s, r),
  /// strength) is not kNone, otherwise only within about 1e-9 of a strength. It compares
  /// squares and takes no square root, so that the bond loop can test every bond every step
  /// with it and decide the few it flags exactly afterwards.
  static bool may_fail(const Section& s, const Result& r, const Strength& strength);

  using Failure = BondFailure;
  /// Which criterion broke the bond (first of tensile, compressive, shear), or kNone.
  static Failure check_failure(const Stresses& st, const Strength& strength);
  /// Largest stress-to-strength ratio (1 = at failure).
  static double utilisation(const Stresses& st, const Strength& strength);

  /// Strengths of one bond: the mean values, varied with the coefficient of variation by a
  /// normal draw from a generator seeded by (seed, gid_a, gid_b) so no rank count changes it.
  static Strength draw_strength(const Params& p, std::uint64_t seed, std::int64_t gid_a,
                                std::int64_t gid_b);
};

[[gnu::always_inline]] inline BondTimoshenko::LocalRotation BondTimoshenko::relative_rotation(
    const Vec3& cx, const Vec3& cy, const Vec3& cz, const Vec3& ax, const Vec3& ay,
    const Vec3& az) {
  const double sx = 0.5 * (dot(cz, ay) - dot(cy, az));
  const double sy = 0.5 * (dot(cx, az) - dot(cz, ax));
  const double sz = 0.5 * (dot(cy, ax) - dot(cx, ay));
  const double s2 = sx * sx + sy * sy + sz * sz;
  const double f = 1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0));
  return {sx * f, sy * f, sz * f};
}

[[gnu::always_inline]] inline BondTimoshenko::EndLoads BondTimoshenko::end_loads(
    const Section& s, const Deformation& q) {
  // K q, rows of physics.md §1 (external end loads holding the deformation).
  return EndLoads{s.k_axial * q.du,                                   // K[6,6] u_bx
                  s.k_torsion * (q.tb.x - q.ta.x),                    // K[9,9], K[9,3]
                  s.k_bend_self * q.ta.y + s.k_bend_cross * q.tb.y,   // K[4,4], K[4,10]
                  s.k_bend_self * q.ta.z + s.k_bend_cross * q.tb.z,   // K[5,5], K[5,11]
                  s.k_bend_cross * q.ta.y + s.k_bend_self * q.tb.y,   // K[10,4], K[10,10]
                  s.k_bend_cross * q.ta.z + s.k_bend_self * q.tb.z};  // K[11,5], K[11,11]
}

template <class Rotation>
[[gnu::always_inline]] inline BondTimoshenko::Result BondTimoshenko::compute(
    const Section& s, const Reference& ref, const Vec3& x_a, const Rotation& rot_a, const Vec3& x_b,
    const Rotation& rot_b) {
  return compute(s, ref, x_a, rot_a, x_b, rot_b,
                 [](const Deformation& q, const ChordFrame&) [[gnu::always_inline]] { return q; });
}

template <class Rotation, class ElasticPart>
[[gnu::always_inline]] inline BondTimoshenko::Result BondTimoshenko::compute(
    const Section& s, const Reference& ref, const Vec3& x_a, const Rotation& rot_a, const Vec3& x_b,
    const Rotation& rot_b, ElasticPart&& elastic_part) {
  // Current end frames: particle orientation times the bond frame stored at creation.
  const Quat frame_a = as_quat(rot_a) * ref.frame_a;
  const Quat frame_b = as_quat(rot_b) * ref.frame_b;
  const Vec3 ax = body_x_axis(frame_a), ay = body_y_axis(frame_a), az = body_z_axis(frame_a);
  const Vec3 bx = body_x_axis(frame_b), by = body_y_axis(frame_b), bz = body_z_axis(frame_b);

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
  // The part K acts on: all of q for the elastic bond (elastic_part is then the identity).
  const Deformation q =
      elastic_part(Deformation{length - s.length0, relative_rotation(cx, cy, cz, ax, ay, az),
                               relative_rotation(cx, cy, cz, bx, by, bz)},
                   ChordFrame{cx, cy, cz});
  const double du = q.du;
  const LocalRotation& ta = q.ta;
  const LocalRotation& tb = q.tb;
  const EndLoads k = end_loads(s, q);
  const double fx_b = k.fx_b, mx_b = k.mx_b, my_a = k.my_a, mz_a = k.mz_a, my_b = k.my_b,
               mz_b = k.mz_b;
  // Shear rows K[7,*], K[8,*] equal -(M_a + M_b) / L0; dividing by the current length
  // instead makes the end loads balance exactly, so angular momentum is conserved.
  const double fy_b = -(mz_a + mz_b) * inv_length;
  const double fz_b = (my_a + my_b) * inv_length;

  // The beam acts on the particles with -K q; end a carries the opposite forces of end b.
  // Built in one aggregate so the compiler can keep every member in registers (the bond
  // loop vectorises only then).
  const Vec3 force_a = cx * fx_b + cy * fy_b + cz * fz_b;
  const double shear2 = fy_b * fy_b + fz_b * fz_b;
  const double bending_a2 = my_a * my_a + mz_a * mz_a;
  const double bending_b2 = my_b * my_b + mz_b * mz_b;
  return Result{force_a, cx * mx_b - cy * my_a - cz * mz_a, -force_a,
                -(cx * mx_b + cy * my_b + cz * mz_b), fx_b, std::sqrt(shear2), mx_b,
                std::sqrt(bending_a2), std::sqrt(bending_b2),
                // 1/2 q^T K q = 1/2 (F . u) summed over the DOFs.
                0.5 * (fx_b * du + mx_b * (tb.x - ta.x) + my_a * ta.y + mz_a * ta.z + my_b * tb.y +
                       mz_b * tb.z),
                shear2, std::max(bending_a2, bending_b2)};
}

[[gnu::always_inline]] inline BondTimoshenko::Stresses BondTimoshenko::stresses(const Section& s,
                                                                                const Result& r) {
  Stresses st;
  const double axial = r.axial_force * s.inv_area;
  const double bend = s.bend_factor * std::max(r.bending_a, r.bending_b);
  st.tensile = axial + bend;      // Eq. 4
  st.compressive = bend - axial;  // Eq. 3
  // Eq. 5: torque over J = 2I, plus 4/3 of the mean shear stress of a circular section.
  st.shear = 0.5 * s.bend_factor * std::abs(r.torsion) + 4.0 / 3.0 * r.shear_force * s.inv_area;
  return st;
}

[[gnu::always_inline]] inline bool BondTimoshenko::may_fail(const Section& s, const Result& r,
                                                            const Strength& strength) {
  // Eq. 3 and 4 fail where the bending stress b M exceeds h = min(sigma_T - a, sigma_C + a),
  // a the axial stress; Eq. 5 where the shear stress 4/3 F_s / A exceeds g = tau - b |M_x| / 2.
  // stresses() rounds each product and sum once (no contraction: -ffp-contract=off), an error
  // of a few 1e-16 of the terms' magnitudes (near the limit b M <= |min(sigma_T, sigma_C)| +
  // 2 |a|); h and g lowered by 1e-9 of those magnitudes therefore flag every bond
  // that stresses() fails, and above them the squares decide alone. Both bending strengths
  // infinite make h NaN, an infinite shear strength g: NaN flags nothing, as such a criterion
  // cannot fail; with one of the two bending strengths infinite, h is the other's.
  const double axial = r.axial_force * s.inv_area;
  const double bending_margin =
      1e-9 * (std::abs(std::min(strength.tensile, strength.compressive)) + std::abs(axial));
  const double h =
      std::min(strength.tensile - axial, strength.compressive + axial) - bending_margin;
  const double bending2 = s.bend_factor * s.bend_factor * r.bending_squared;
  const double torsion_stress = 0.5 * s.bend_factor * std::abs(r.torsion);
  const double g =
      strength.shear - torsion_stress - 1e-9 * (std::abs(strength.shear) + torsion_stress);
  const double shear_factor = 4.0 / 3.0 * s.inv_area;
  const double shear2 = shear_factor * shear_factor * r.shear_force_squared;
  // With | and no early return, so that the bond loop stays free of branches. A NaN state
  // compares false throughout, as in fails(); the loop masks broken bonds, which may have one.
  return (h < 0.0) | (bending2 > h * h) | (g < 0.0) | (shear2 > g * g);
}

}  // namespace ringdem

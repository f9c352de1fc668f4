#pragma once

#include <cstdint>

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
    Vec3 axis_a, perp_a;  ///< bond x and y axes in a's body frame
    Vec3 axis_b, perp_b;  ///< same in b's body frame

    static Reference make(const Vec3& x_a, const Mat3& rot_a, const Vec3& x_b, const Mat3& rot_b);
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
  };

  static Result compute(const Section& s, const Reference& ref, const Vec3& x_a, const Mat3& rot_a,
                        const Vec3& x_b, const Mat3& rot_b);

  /// Largest stresses of Eq. 3–5 for a computed state.
  struct Stresses {
    double tensile = 0.0;      ///< sigma_T,max (Eq. 4)
    double compressive = 0.0;  ///< sigma_C,max (Eq. 3)
    double shear = 0.0;        ///< tau_max (Eq. 5)
  };
  static Stresses stresses(const Section& s, const Result& r);

  enum class Failure : std::uint8_t { kNone = 0, kTensile = 1, kCompressive = 2, kShear = 3 };
  /// Which criterion broke the bond (first of tensile, compressive, shear), or kNone.
  static Failure check_failure(const Stresses& st, const Strength& strength);
  /// Largest stress-to-strength ratio (1 = at failure).
  static double utilisation(const Stresses& st, const Strength& strength);

  /// Strengths of one bond: the mean values, varied with the coefficient of variation by a
  /// normal draw from a generator seeded by (seed, gid_a, gid_b) so no rank count changes it.
  static Strength draw_strength(const Params& p, std::uint64_t seed, std::int64_t gid_a,
                                std::int64_t gid_b);
};

}  // namespace ringdem

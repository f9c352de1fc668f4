#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>

#include "core/BondFailure.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {

/// Elastoplastic wire-bundle bond (physics.md §6; docs/physics.md "Plastic bond"): the
/// co-rotational Timoshenko beam of BondTimoshenko with a plastic elongation and plastic
/// rotations of both ends (plastic hinges).
///
/// The plastic elongation is per-bond state. A plastic end rotation is moved into the bond's
/// end frame (Reference) in the step it happens: the frame is re-based so that it measures the
/// returned elastic rotation exactly. The kernel then only ever measures elastic rotations,
/// which stay below the yield rotation M_p / k, where its small-rotation measure and its
/// loads are those of the elastic bond. (Kept as angles beside a total rotation of tens of
/// degrees, the plastic rotations made the loads of a bent hinge non-conservative: an undamped
/// hinge ringing about its permanent shape gained energy.)
///
/// Each call is one backward-Euler step of resultant plasticity:
///  - elastic predictor: the end loads K (q - q_p) of the deformation q measured from the end
///    frames (which hold the hinges of earlier steps) minus the plastic elongation;
///  - yield function at each end i = a, b, on the ring's real resultants (not on stresses in
///    the surrogate bond section):  F_i = t(N / N_p, |M_i| / M_p) <= Y = 1 + h kappa,
///    where t is the gauge of the parabolic interaction n^2 + m = 1 (EN 1993-1-1 eq. 6.32;
///    Neal 1977), t(n, m) = (m + sqrt(m^2 + 4 n^2)) / 2;
///  - closest-point return (Simo & Hughes 1998, ch. 3) in the metric of the elastic compliance,
///    with both ends active at once where needed, associative flow q_p += sum_i lambda_i dF_i/ds,
///    and the apex N = +-Y N_p, M = 0 of full axial yield handled in closed form;
///  - linear isotropic work hardening: kappa is the work-equivalent plastic strain of the wire
///    bundle over the bond length, dkappa = dW_p / (Y N_p L0) = sum_i lambda_i / (N_p L0);
///  - unloading along the elastic slope K.
/// Torsion and shear stay elastic (the bundle's wires carry little of them in a ring; Eq. 5
/// still limits them). Rigid motion changes no deformation, so it gives no force and no flow.
/// The result depends only on the arguments: the same bits on every rank.
///
/// For a force term: Params per bond type, State per bond (State::kNames, one column each,
/// zero at creation, migrated and checkpointed with the bond) and the Reference frames (which
/// compute() updates), compute() every step,
/// evaluate() for output columns and break energies, check_failure() for the failure rule,
/// State::work summed for the ledger's plastic-work column. A vectorised loop can run the
/// elastic predictor and beyond_yield() for all bonds and call compute() only where it is true.
struct BondTimoshenkoPlastic {
  using Section = BondTimoshenko::Section;
  using Reference = BondTimoshenko::Reference;
  using Deformation = BondTimoshenko::Deformation;
  using EndLoads = BondTimoshenko::EndLoads;
  using Strength = BondTimoshenko::Strength;

  /// Plastic limits of the ring's real resultants (physics.md §6), not of the surrogate section.
  struct Params {
    double axial_yield = 0.0;     ///< N_p = n_w f_y pi d^2 / 4 [N] (N_y: a tie yields at once)
    double plastic_moment = 0.0;  ///< M_p = n_w f_y d^3 / 6 [N m]: the hinge moment
    double yield_moment = 0.0;    ///< M_y = n_w f_y pi d^3 / 32 [N m]: first yield (reports only)
    double hardening = 0.0;       ///< h = E_h / f_y: the limits grow by the factor 1 + h kappa
    double failure_strain = 0.0;  ///< kappa at which the bond breaks; <= 0: no limit

    /// A strand of `windings` wires of diameter d in parallel (tension) that bend as separate
    /// wires (bending), of yield stress f_y and bilinear hardening ratio b = E_t / E
    /// (post-yield tangent over Young's modulus E of the wire): E_h = E b / (1 - b) is the
    /// slope of stress over plastic strain, h = E_h / f_y. Throws std::invalid_argument on
    /// non-positive sizes or strengths or b outside [0, 1).
    static Params from_wire_bundle(int windings, double wire_diameter, double yield_stress,
                                   double hardening_ratio, double youngs_modulus = 200e9,
                                   double failure_strain = 0.0);
  };

  /// Per-bond plastic state besides the hinges in the end frames, a POD of doubles (zero at
  /// creation).
  struct State {
    double elongation = 0.0;  ///< plastic elongation delta_p [m]
    double strain = 0.0;      ///< kappa, accumulated work-equivalent plastic strain [-]
    double work = 0.0;        ///< accumulated plastic work [J] (the energy ledger's column)

    static constexpr std::size_t kSize = 3;
    /// Column names, in index order (one bond-store column each).
    static constexpr std::array<std::string_view, kSize> kNames{"plastic_elongation",
                                                                "plastic_strain", "plastic_work"};
    double& operator[](std::size_t i) { return this->*member(i); }
    double operator[](std::size_t i) const { return this->*member(i); }

   private:
    static constexpr double State::*member(std::size_t i) {
      constexpr std::array<double State::*, kSize> members{&State::elongation, &State::strain,
                                                           &State::work};
      return members[i];
    }
  };

  /// The elastic bond's result for the elastic part of the deformation (energy: the elastic,
  /// recoverable 1/2 q_e^T K q_e), plus the plastic work of this call (also added to
  /// State::work).
  struct Result : BondTimoshenko::Result {
    double plastic_work = 0.0;
  };

  /// One step: elastic predictor, return mapping, `state` updated, and the end frames re-based
  /// where an end turned plastically (rebase()). Rotation is a Mat3 or a unit Quat (body to
  /// world) of each end particle. Inline: bonds that stay elastic take the elastic kernel's path
  /// plus one yield test (with a zero state, exactly the elastic bits), and leave `ref` as it
  /// is.
  template <class Rotation>
  static Result compute(const Section& s, const Params& p, Reference& ref, const Vec3& x_a,
                        const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b,
                        State& state);

  /// compute() on copies of `ref` and `state`: what the bond exerts now, nothing changed
  /// (output columns, break energies). Right after a compute() at the same positions no flow
  /// remains.
  template <class Rotation>
  static Result evaluate(const Section& s, const Params& p, const Reference& ref, const Vec3& x_a,
                         const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b,
                         const State& state) {
    Reference frames = ref;
    State copy = state;
    return compute(s, p, frames, x_a, rot_a, x_b, rot_b, copy);
  }

  /// The measured deformation minus the plastic elongation: what K acts on (the plastic
  /// rotations are in the end frames already).
  static Deformation elastic_part(const Deformation& q, const State& st) {
    return {q.du - st.elongation, q.ta, q.tb};
  }

  /// Moves the hinges of a step into the end frames (relative to the particles' body frames,
  /// as Reference stores them): after it, the kernel measures the returned elastic rotations
  /// `ta`, `tb` from the same chord frame C at these positions, to round-off. Each frame
  /// becomes conj(rot) C R(t), R(t) the turn about t / |t| whose sine the kernel's arcsine
  /// series maps to |t| (turn()). C's y axis is the bisector of the end frames' y
  /// axes, which the return (it changes the bending rotations) would tilt about the chord by
  /// O(theta_e dtheta_p); a common twist delta of both ends, t.x + delta, keeps it: it changes
  /// no load (torsion is tb.x - ta.x), and both frames are re-based with it.
  template <class Rotation>
  static void rebase(Reference& ref, const Rotation& rot_a, const Rotation& rot_b,
                     const BondTimoshenko::ChordFrame& c, const BondTimoshenko::LocalRotation& ta,
                     const BondTimoshenko::LocalRotation& tb) {
    const Quat chord =
        quat_from_matrix(Mat3{{c.x.x, c.y.x, c.z.x, c.x.y, c.y.y, c.z.y, c.x.z, c.y.z, c.z.z}});
    const double twist = bisector_twist(ta, tb);
    ref.frame_a = normalized(conjugate(as_quat(rot_a)) * chord * turn({ta.x + twist, ta.y, ta.z}));
    ref.frame_b = normalized(conjugate(as_quat(rot_b)) * chord * turn({tb.x + twist, tb.y, tb.z}));
  }

  /// The turn R(t) that the kernel measures as t: about t / |t|, by the angle whose sine s
  /// the kernel's arcsine series maps to |t| (BondTimoshenko::relative_rotation), built from s
  /// and sqrt(1 - s^2) by the half-angle formulas. Past the series' range (|t| > 1.24) no
  /// sine exists: the angle is then |t|.
  static Quat turn(const Vec3& t);
  /// The common twist delta of rebase(): the root of z(delta) = (R(ta + delta x) y).z +
  /// (R(tb + delta x) y).z, by the secant method from delta = 0 and -z(0)/2 (dz/ddelta = 2
  /// (1 - O(theta^2))), each z from Rodrigues' formula with the sine and cosine of turn().
  static double bisector_twist(const BondTimoshenko::LocalRotation& ta,
                               const BondTimoshenko::LocalRotation& tb);
  /// The s in [0, 1] with s (1 + s^2/6 + 3 s^4/40) = m (the kernel's series), by Newton's
  /// method from `guess` (clamped to [0, 1]); 1 where m is past the series' range (1.24).
  static double series_sine(double m, double guess);

  /// Yield test of the elastic predictor f (end loads of elastic_part()): whether an end is
  /// beyond Y (1 + kYieldTolerance). t(n, m) <= Y is n^2 + Y m <= Y^2, no square root of t.
  static bool beyond_yield(const Params& p, const EndLoads& f, const State& st) {
    return beyond_yield(p, st.strain, f.fx_b, std::sqrt(f.my_a * f.my_a + f.mz_a * f.mz_a),
                        std::sqrt(f.my_b * f.my_b + f.mz_b * f.mz_b));
  }
  /// The same test on the resultants of an elastic result (BondTimoshenko::Result's
  /// axial_force, bending_a and bending_b, which are these very values): the same bits, for a
  /// vector loop that has run the elastic kernel on elastic_part(). Branch-free.
  [[gnu::always_inline]] static bool beyond_yield(const Params& p, double strain, double axial,
                                                  double bending_a, double bending_b) {
    const double n = axial / p.axial_yield;
    const double ma = bending_a / p.plastic_moment;
    const double mb = bending_b / p.plastic_moment;
    const double y = (1.0 + p.hardening * strain) * (1.0 + kYieldTolerance);  // yield_factor
    return !((n * n + y * ma <= y * y) & (n * n + y * mb <= y * y));
  }

  /// Gauge of the interaction n^2 + m = 1 (m >= 0): the t > 0 with (n/t)^2 + m/t = 1.
  static double interaction(double n, double m) { return 0.5 * (m + std::sqrt(m * m + 4 * n * n)); }
  /// Current yield limit factor Y = 1 + h kappa.
  static double yield_factor(const Params& p, const State& st) {
    return 1.0 + p.hardening * st.strain;
  }
  /// Largest F_i / Y of the two ends for a computed result (1 on the yield surface).
  static double yield_ratio(const Params& p, const State& st, const BondTimoshenko::Result& r);

  /// Relative tolerance of the yield test: F_i <= Y (1 + kYieldTolerance) is elastic, so
  /// round-off (of a rigid motion, of a state just returned to the surface) causes no flow.
  static constexpr double kYieldTolerance = 1e-10;

  /// Return mapping of a trial that yields. q: the deformation measured from the end frames
  /// (rotations: the trial elastic rotations; length: total). Updates `st` (plastic
  /// elongation, kappa, work) and returns the new elastic part of q, which ends turned
  /// plastically (their frames are to be re-based on it) and, in `work`, the plastic work of
  /// the step.
  struct Return {
    Deformation elastic;
    bool hinge_a = false, hinge_b = false;
  };
  static Return return_map(const Section& s, const Params& p, const Deformation& q, State& st,
                           double& work);

  /// Failure (issue 14): the bond breaks by Eq. 3–5 on its (returned) resultants or when its
  /// plastic strain reaches the limit, whichever comes first.
  static bool strain_limit_reached(const Params& p, const State& st) {
    return p.failure_strain > 0.0 && st.strain >= p.failure_strain;
  }
  struct Failure {
    BondFailure stress = BondFailure::kNone;  ///< Eq. 3–5 (first of tensile, compressive, shear)
    bool strain = false;                      ///< plastic strain limit reached
    bool broken() const { return stress != BondFailure::kNone || strain; }
  };
  static Failure check_failure(const Section& s, const Params& p, const Strength& strength,
                               const BondTimoshenko::Result& r, const State& st) {
    return {BondTimoshenko::check_failure(BondTimoshenko::stresses(s, r), strength),
            strain_limit_reached(p, st)};
  }
};

template <class Rotation>
[[gnu::always_inline]] inline BondTimoshenkoPlastic::Result BondTimoshenkoPlastic::compute(
    const Section& s, const Params& p, Reference& ref, const Vec3& x_a, const Rotation& rot_a,
    const Vec3& x_b, const Rotation& rot_b, State& state) {
  double work = 0.0;
  Reference next = ref;
  const BondTimoshenko::Result r =
      BondTimoshenko::compute(s, ref, x_a, rot_a, x_b, rot_b,
                              [&](const Deformation& q, const BondTimoshenko::ChordFrame& chord) {
                                // Elastic predictor and yield test at both ends.
                                const Deformation e = elastic_part(q, state);
                                if (!beyond_yield(p, BondTimoshenko::end_loads(s, e), state))
                                  return e;
                                const Return ret = return_map(s, p, q, state, work);
                                // The hinges into the end frames: from now on they measure the
                                // returned rotations.
                                if (ret.hinge_a || ret.hinge_b)
                                  rebase(next, rot_a, rot_b, chord, ret.elastic.ta, ret.elastic.tb);
                                return ret.elastic;
                              });
  ref = next;
  return Result{r, work};
}

}  // namespace ringdem

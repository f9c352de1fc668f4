#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <string_view>

#include "core/BondFailure.hpp"
#include "core/Vec3.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {

/// Elastoplastic wire-bundle bond (physics.md §6; docs/physics.md "Plastic bond"): the
/// co-rotational Timoshenko beam of BondTimoshenko with a plastic elongation and plastic
/// rotations of both ends (plastic hinges) as per-bond state.
///
/// Each call is one backward-Euler step of resultant plasticity:
///  - elastic predictor: the end loads K (q - q_p) of the total deformation q minus the plastic
///    one q_p (q from the shared kernel BondTimoshenko::compute);
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
/// zero at creation, migrated and checkpointed with the bond), compute() every step,
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

  /// Per-bond plastic state, a POD of doubles (zero at creation). The rotations are components
  /// in the bond's chord frame, which follows the bond: rigid motion leaves them unchanged.
  struct State {
    double elongation = 0.0;   ///< plastic elongation delta_p [m]
    double rotation_ay = 0.0;  ///< plastic rotation of end a about the chord y axis [rad]
    double rotation_az = 0.0;  ///< ... of end a about the chord z axis [rad]
    double rotation_by = 0.0;  ///< ... of end b about the chord y axis [rad]
    double rotation_bz = 0.0;  ///< ... of end b about the chord z axis [rad]
    double strain = 0.0;       ///< kappa, accumulated work-equivalent plastic strain [-]
    double work = 0.0;         ///< accumulated plastic work [J] (the energy ledger's column)

    static constexpr std::size_t kSize = 7;
    /// Column names, in index order (one bond-store column each).
    static constexpr std::array<std::string_view, kSize> kNames{
        "plastic_elongation",  "plastic_rotation_ay", "plastic_rotation_az", "plastic_rotation_by",
        "plastic_rotation_bz", "plastic_strain",      "plastic_work"};
    double& operator[](std::size_t i) { return this->*member(i); }
    double operator[](std::size_t i) const { return this->*member(i); }

   private:
    static constexpr double State::*member(std::size_t i) {
      constexpr std::array<double State::*, kSize> members{
          &State::elongation,  &State::rotation_ay, &State::rotation_az, &State::rotation_by,
          &State::rotation_bz, &State::strain,      &State::work};
      return members[i];
    }
  };

  /// The elastic bond's result for the elastic part of the deformation (energy: the elastic,
  /// recoverable 1/2 q_e^T K q_e), plus the plastic work of this call (also added to
  /// State::work).
  struct Result : BondTimoshenko::Result {
    double plastic_work = 0.0;
  };

  /// One step: elastic predictor, return mapping, `state` updated. Rotation is a Mat3 or a unit
  /// Quat (body to world) of each end particle. Inline: bonds that stay elastic take the
  /// elastic kernel's path plus one yield test (with a zero state, exactly the elastic bits).
  template <class Rotation>
  static Result compute(const Section& s, const Params& p, const Reference& ref, const Vec3& x_a,
                        const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b,
                        State& state);

  /// compute() on a copy of `state`: what the bond exerts now, state unchanged (output
  /// columns, break energies). Right after a compute() at the same positions no flow remains.
  template <class Rotation>
  static Result evaluate(const Section& s, const Params& p, const Reference& ref, const Vec3& x_a,
                         const Rotation& rot_a, const Vec3& x_b, const Rotation& rot_b,
                         const State& state) {
    State copy = state;
    return compute(s, p, ref, x_a, rot_a, x_b, rot_b, copy);
  }

  /// The total deformation minus the plastic one: what K acts on.
  static Deformation elastic_part(const Deformation& q, const State& st) {
    return {q.du - st.elongation,
            {q.ta.x, q.ta.y - st.rotation_ay, q.ta.z - st.rotation_az},
            {q.tb.x, q.tb.y - st.rotation_by, q.tb.z - st.rotation_bz}};
  }

  /// Yield test of the elastic predictor f (end loads of elastic_part()): whether an end is
  /// beyond Y (1 + kYieldTolerance). t(n, m) <= Y is n^2 + Y m <= Y^2, no square root of t.
  static bool beyond_yield(const Params& p, const EndLoads& f, const State& st) {
    const double n = f.fx_b / p.axial_yield;
    const double ma = std::sqrt(f.my_a * f.my_a + f.mz_a * f.mz_a) / p.plastic_moment;
    const double mb = std::sqrt(f.my_b * f.my_b + f.mz_b * f.mz_b) / p.plastic_moment;
    const double y = yield_factor(p, st) * (1.0 + kYieldTolerance);
    return !(n * n + y * ma <= y * y && n * n + y * mb <= y * y);
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

  /// Return mapping of a trial that yields: updates `st` (plastic deformations, kappa, work)
  /// and returns the new elastic part of q and, in `work`, the plastic work of the step.
  static Deformation return_map(const Section& s, const Params& p, const Deformation& q, State& st,
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
    const Section& s, const Params& p, const Reference& ref, const Vec3& x_a, const Rotation& rot_a,
    const Vec3& x_b, const Rotation& rot_b, State& state) {
  double work = 0.0;
  const BondTimoshenko::Result r =
      BondTimoshenko::compute(s, ref, x_a, rot_a, x_b, rot_b, [&](const Deformation& q) {
        // Elastic predictor and yield test at both ends.
        const Deformation e = elastic_part(q, state);
        if (!beyond_yield(p, BondTimoshenko::end_loads(s, e), state)) return e;
        return return_map(s, p, q, state, work);
      });
  return Result{r, work};
}

}  // namespace ringdem

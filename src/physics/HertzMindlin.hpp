#pragma once

#include <algorithm>
#include <cmath>

#include "core/Vec3.hpp"

namespace ringdem {

/// Hertz–Mindlin (no slip) contact with restitution damping, Coulomb cap and EDEM-style
/// constant-torque rolling friction (physics.md §3, paper Eq. 6–9).
///
/// Convention: the pair is (i, j) with i the lower gid (or the particle, for a particle–
/// rigid-body contact). n is the unit normal from i to j. Forces are returned for i; j gets
/// the opposite force. The tangential spring is history carried by the caller.
struct HertzMindlin {
  struct Params {
    double e_star = 0.0;    ///< 1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j
    double g_star = 0.0;    ///< 1/G* = (2-nu_i)/G_i + (2-nu_j)/G_j (Mindlin, not the paper's typo)
    double beta = 0.0;      ///< ln e / sqrt(ln^2 e + pi^2), negative
    double friction = 0.0;  ///< mu_s
    double rolling_friction = 0.0;  ///< mu_r

    /// Mixing of two materials (E, nu) with the pair's restitution and friction coefficients.
    static Params mix(double youngs_i, double poisson_i, double youngs_j, double poisson_j,
                      double restitution, double friction, double rolling_friction) {
      Params p;
      const double inv_e =
          (1.0 - poisson_i * poisson_i) / youngs_i + (1.0 - poisson_j * poisson_j) / youngs_j;
      p.e_star = 1.0 / inv_e;
      const double g_i = youngs_i / (2.0 * (1.0 + poisson_i));
      const double g_j = youngs_j / (2.0 * (1.0 + poisson_j));
      p.g_star = 1.0 / ((2.0 - poisson_i) / g_i + (2.0 - poisson_j) / g_j);
      p.beta = damping_ratio(restitution);
      p.friction = friction;
      p.rolling_friction = rolling_friction;
      return p;
    }

    /// beta of Eq. 7; e = 1 gives 0 (no damping), e -> 0 tends to -1.
    static double damping_ratio(double restitution) {
      if (restitution >= 1.0) return 0.0;
      const double l = std::log(restitution);
      return l / std::sqrt(l * l + M_PI * M_PI);
    }
  };

  struct Input {
    Vec3 normal;     ///< unit, from i to j
    double overlap;  ///< delta_n > 0
    double r_star;   ///< effective radius R*
    double m_star;   ///< effective mass m*
    Vec3 v_rel;      ///< velocity of j's surface relative to i's at the contact point
    double dt;       ///< time step (tangential spring increment)
    double arm_i;    ///< distance from i's centre to the contact point
    double arm_j;    ///< same for j (0 for a rigid body whose torque the caller computes)
    Vec3 omega_i;    ///< angular velocities, for the rolling-friction direction
    Vec3 omega_j;
  };

  struct Result {
    Vec3 force_i;              ///< total contact force on i (j receives -force_i)
    Vec3 rolling_torque_i;     ///< rolling-friction torque on i
    Vec3 rolling_torque_j;     ///< rolling-friction torque on j
    double normal_force;       ///< signed normal force (spring + damping), repulsive positive
    double elastic_energy;     ///< normal (2/5 F_ns delta) + tangential (|F_t|^2 / 2 S_t)
    Vec3 damping_force_i;      ///< viscous part of force_i (normal + tangential), for energy
                               ///< bookkeeping
    double tangential_energy;  ///< |F_t|^2 / 2 S_t of the updated spring (part of elastic_energy)
    bool sliding;
  };

  /// spring: tangential spring force on i, carried from the previous step (in/out).
  /// Branch-free: every case is computed and the case that holds is selected, so that the pair
  /// kernel's loop over a chunk of contacts vectorises (PairContactChunk). A select gives the
  /// bits the branch would (a skipped rescale is a product by 1, exact). kRolling = false
  /// leaves the rolling-friction torques out (zero), for chunks whose pairs have mu_r = 0.
  template <bool kRolling = true>
  [[gnu::always_inline]] static Result compute(const Params& p, const Input& in, Vec3& spring) {
    // The result is built at the end with every member given: a Result{} zeroed first became a
    // 128-byte memset (rep stos) in every contact, 4 % of a dense packing's pair loop.
    const Vec3& n = in.normal;
    const double sqrt_rd = std::sqrt(in.r_star * in.overlap);
    // Eq. 6; normal stiffness S_n of Eq. 7.
    const double f_spring = 4.0 / 3.0 * p.e_star * sqrt_rd * in.overlap;
    const double s_n = 2.0 * p.e_star * sqrt_rd;
    const double v_n = dot(in.v_rel, n);                      // > 0: separating
    const double damp = 2.0 * std::sqrt(5.0 / 6.0) * p.beta;  // negative
    // Eq. 7: beta < 0, so the damping force opposes the normal relative velocity.
    const double f_n_damp = damp * std::sqrt(s_n * in.m_star) * v_n;
    const double f_n = f_spring + f_n_damp;

    // Tangential (Eq. 8–9). Keep the stored spring in the current tangent plane, at its length
    // (a zero spring, or one that was all normal, is not rescaled).
    const Vec3 v_t = in.v_rel - n * v_n;
    const double s_t = 8.0 * p.g_star * sqrt_rd;
    const double old_mag2 = norm2(spring);
    Vec3 s = spring - n * dot(spring, n);
    const double new_mag2 = norm2(s);
    const bool rescale = old_mag2 > 0.0 && new_mag2 > 0.0;
    s *= rescale ? std::sqrt(old_mag2 / new_mag2) : 1.0;
    s += v_t * (s_t * in.dt);  // j slides along +v_t relative to i: drags i along +v_t
    const double f_cap = p.friction * std::max(f_n, 0.0);
    const double spring_mag = norm(s);
    // Coulomb slip: the spring saturates at the cap (spring_mag > f_cap >= 0, so no division
    // by zero where it applies), and there is no viscous tangential force.
    const bool sliding = spring_mag > f_cap;
    s = select(sliding, s * (f_cap / spring_mag), s);
    const Vec3 f_t_damp =
        select(sliding, Vec3{}, v_t * (-damp * std::sqrt(s_t * in.m_star)));  // Eq. 9
    const Vec3 f_t = select(sliding, s, s + f_t_damp);
    const double tangential_energy = s_t > 0.0 ? 0.5 * norm2(s) / s_t : 0.0;
    spring = s;

    // Rolling friction, EDEM "standard": tau = -mu_r F_n R_i omega_hat_i.
    Vec3 rolling_i, rolling_j;
    if constexpr (kRolling) {
      const bool rolls = p.rolling_friction > 0.0 && f_n > 0.0;
      const double k = p.rolling_friction * f_n;
      rolling_i = select(rolls, normalized(in.omega_i) * (-k * in.arm_i), Vec3{});
      rolling_j = select(rolls, normalized(in.omega_j) * (-k * in.arm_j), Vec3{});
    }
    return Result{f_t - n * f_n,
                  rolling_i,
                  rolling_j,
                  f_n,
                  0.4 * f_spring * in.overlap + tangential_energy,
                  f_t_damp - n * f_n_damp,
                  tangential_energy,
                  sliding};
  }
};

}  // namespace ringdem

#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "core/Vec3.hpp"
#include "engine/Loop.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {

/// Scratch for PairContactTerm's kernel: up to kSize touching pairs of one chunk of
/// candidates, their inputs copied into columns (structure of arrays) in pair order, the
/// contact law run over them as one vectorised loop, and its results in columns for the
/// in-order scatter. The contact law of a pair is a long chain of square roots and divisions;
/// one pair at a time it waited on them (40 ns a contact), across the lanes of a vector it
/// does not. Every lane does the operations the scalar loop did, in the same order, and the
/// build rounds vector and scalar code alike (no FMA contraction): the same bits.
struct PairContactChunk {
  static constexpr std::size_t kSize = 64;

  /// One Vec3 column: kSize x, then y, then z.
  struct Column {
    alignas(64) double v[3][kSize];
    Vec3 get(std::size_t c) const { return {v[0][c], v[1][c], v[2][c]}; }
    void set(std::size_t c, const Vec3& x) {
      v[0][c] = x.x;
      v[1][c] = x.y;
      v[2][c] = x.z;
    }
  };

  std::size_t n = 0;  ///< touching pairs in the chunk
  bool any_rolling = false;
  std::uint32_t pair[kSize], end_a[kSize], end_b[kSize];
  /// The ends' entries in the energy ledger's moments (EnergyLedger::moments_entry), where the
  /// ledger is booked and the end is owned.
  std::uint32_t moments_a[kSize], moments_b[kSize];

  // Inputs: the separation b - a and its square, the radii, the effective mass, velocities,
  // the pair's material parameters, and the tangential spring carried from the last step.
  Column separation;
  alignas(64) double dist2[kSize], radius_a[kSize], radius_b[kSize], m_star[kSize];
  Column velocity_a, velocity_b, omega_a, omega_b;
  alignas(64) double e_star[kSize], g_star[kSize], beta[kSize], friction[kSize],
      rolling_friction[kSize];
  Column spring;  ///< in: carried; out: updated (physics.md §3)

  // Results: the force on a (b gets its opposite), each end's torque, and for the energy
  // ledger each end's viscous load and moments (ContactMoments) and half the pair's energies.
  Column force_a, torque_a, torque_b;
  Column damping_a, damping_moment_a, damping_moment_b, friction_moment_a, friction_moment_b;
  alignas(64) double half_tangential_energy[kSize], half_elastic_energy[kSize];

  /// Appends a touching pair (the caller has tested it).
  void add(std::uint32_t m, std::uint32_t a, std::uint32_t b, const Vec3& d, double d2, double ra,
           double rb, double mass, const Vec3& va, const Vec3& vb, const Vec3& wa, const Vec3& wb,
           const HertzMindlin::Params& params, const Vec3& carried) {
    const std::size_t c = n++;
    pair[c] = m;
    end_a[c] = a;
    end_b[c] = b;
    separation.set(c, d);
    dist2[c] = d2;
    radius_a[c] = ra;
    radius_b[c] = rb;
    m_star[c] = mass;
    velocity_a.set(c, va);
    velocity_b.set(c, vb);
    omega_a.set(c, wa);
    omega_b.set(c, wb);
    e_star[c] = params.e_star;
    g_star[c] = params.g_star;
    beta[c] = params.beta;
    friction[c] = params.friction;
    rolling_friction[c] = params.rolling_friction;
    any_rolling = any_rolling || params.rolling_friction > 0.0;
    spring.set(c, carried);
  }

  /// The contact law (physics.md §3, HertzMindlin) over lanes 0..n-1, as one loop.
  template <bool kBook>
  void compute(double dt) {
    if (any_rolling)
      compute_lanes<kBook, true>(dt);
    else
      compute_lanes<kBook, false>(dt);
  }

 private:
  template <bool kBook, bool kRolling>
  void compute_lanes(double dt) {
    for_each(
        IndexRange{0, n}, [&](std::size_t c) __attribute__((always_inline)) {
          const Vec3 d = separation.get(c);
          const double dist = std::sqrt(dist2[c]);
          const Vec3 normal = d / dist;
          const double reach = radius_a[c] + radius_b[c];
          const double overlap = reach - dist;
          const double arm_a = radius_a[c] - 0.5 * overlap;
          const double arm_b = radius_b[c] - 0.5 * overlap;
          HertzMindlin::Input in;
          in.normal = normal;
          in.overlap = overlap;
          in.r_star = radius_a[c] * radius_b[c] / reach;
          in.m_star = m_star[c];
          const Vec3 wa = omega_a.get(c), wb = omega_b.get(c);
          in.v_rel = (velocity_b.get(c) + cross(wb, normal * (-arm_b))) -
                     (velocity_a.get(c) + cross(wa, normal * arm_a));
          in.dt = dt;
          in.arm_i = arm_a;
          in.arm_j = arm_b;
          in.omega_i = wa;
          in.omega_j = wb;
          HertzMindlin::Params params;
          params.e_star = e_star[c];
          params.g_star = g_star[c];
          params.beta = beta[c];
          params.friction = friction[c];
          params.rolling_friction = rolling_friction[c];
          Vec3 s = spring.get(c);
          const auto r = HertzMindlin::compute<kRolling>(params, in, s);
          spring.set(c, s);
          const Vec3 lever_a = normal * arm_a;   // from a's centre to the contact point
          const Vec3 lever_b = normal * -arm_b;  // from b's centre to the contact point
          force_a.set(c, r.force_i);
          torque_a.set(c, cross(lever_a, r.force_i) + r.rolling_torque_i);
          torque_b.set(c, cross(normal * arm_b, r.force_i) + r.rolling_torque_j);
          if constexpr (kBook) {
            damping_a.set(c, r.damping_force_i);
            damping_moment_a.set(c, cross(lever_a, r.damping_force_i));
            damping_moment_b.set(c, cross(lever_b, -r.damping_force_i));
            friction_moment_a.set(c, cross(lever_a, s) + r.rolling_torque_i);
            friction_moment_b.set(c, cross(lever_b, -s) + r.rolling_torque_j);
            half_tangential_energy[c] = 0.5 * r.tangential_energy;
            half_elastic_energy[c] = 0.5 * r.elastic_energy;
          }
        });
  }
};

}  // namespace ringdem

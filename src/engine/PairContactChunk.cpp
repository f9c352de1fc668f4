#include "engine/PairContactChunk.hpp"

#include <cmath>

#include "engine/Loop.hpp"

namespace ringdem {

std::size_t PairContactChunk::pad_to_whole_vectors() {
  const std::size_t lanes = (n + kLaneMultiple - 1) / kLaneMultiple * kLaneMultiple;
  if (n == 0) return 0;
  const std::size_t last = n - 1;
  for (std::size_t c = n; c < lanes; ++c) {
    separation.copy_lane(last, c);
    dist2[c] = dist2[last];
    radius_a[c] = radius_a[last];
    radius_b[c] = radius_b[last];
    m_star[c] = m_star[last];
    velocity_a.copy_lane(last, c);
    velocity_b.copy_lane(last, c);
    omega_a.copy_lane(last, c);
    omega_b.copy_lane(last, c);
    e_star[c] = e_star[last];
    g_star[c] = g_star[last];
    beta[c] = beta[last];
    friction[c] = friction[last];
    rolling_friction[c] = rolling_friction[last];
    spring.copy_lane(last, c);
    carried_ledger.copy_lane(last, c);
  }
  return lanes;
}

template <PairContactChunk::Ledger kLedger, bool kRolling>
void PairContactChunk::compute_lanes(double dt, std::size_t lanes) {
  constexpr bool kPerParticle = kLedger == Ledger::kPerParticle;
  constexpr bool kPerContact =
      kLedger == Ledger::kPerContact || kLedger == Ledger::kPerContactWithEnergies;
  for_each(
      IndexRange{0, lanes}, [&](std::size_t c) __attribute__((always_inline)) {
        const Vec3 d = separation.get(c);
        const double dist = std::sqrt(dist2[c]);
        const Vec3 unit = d / dist;
        const double reach = radius_a[c] + radius_b[c];
        const double depth = reach - dist;
        const double arm_a = radius_a[c] - 0.5 * depth;
        const double arm_b = radius_b[c] - 0.5 * depth;
        HertzMindlin::Input in;
        in.normal = unit;
        in.overlap = depth;
        in.r_star = radius_a[c] * radius_b[c] / reach;
        in.m_star = m_star[c];
        const Vec3 wa = omega_a.get(c), wb = omega_b.get(c);
        const Vec3 va = velocity_a.get(c), vb = velocity_b.get(c);
        in.v_rel = relative_contact_velocity(unit, arm_a, arm_b, va, vb, wa, wb);
        in.dt = dt;
        in.arm_i = arm_a;
        in.arm_j = arm_b;
        in.omega_i = wa;
        in.omega_j = wb;
        const HertzMindlin::Params params{e_star[c], g_star[c], beta[c], friction[c],
                                          rolling_friction[c]};
        const Vec3 s_carried = spring.get(c);
        Vec3 s = s_carried;
        const auto r = HertzMindlin::compute<kRolling>(params, in, s);
        spring.set(c, s);
        const Vec3 lever_a = unit * arm_a;   // from a's centre to the contact point
        const Vec3 lever_b = unit * -arm_b;  // from b's centre to the contact point
        force_a.set(c, r.force_i);
        torque_a.set(c, cross(lever_a, r.force_i) + r.rolling_torque_i);
        torque_b.set(c, cross(unit * arm_b, r.force_i) + r.rolling_torque_j);
        if constexpr (kPerContact) {
          // The work of the step: the loads of its start (carried, at the contact point of
          // the start: its normal one drift back) and of its end (at this contact point), each
          // at the relative velocity of the step's middle, which the law read and the drift
          // used (docs/physics.md "Energy ledger"). The spring is the tangential force on a, as
          // the damping force is.
          const double depth_carried = carried_ledger.overlap[c];
          const Vec3 v_carried = relative_contact_velocity(
              step_start_normal(d, vb - va, dt), radius_a[c] - 0.5 * depth_carried,
              radius_b[c] - 0.5 * depth_carried, va, vb, wa, wb);
          // The carried loads do work where the pair carries it (ContactLedgerState::
          // carries_work()).
          const double start = depth_carried >= 0.0 ? 1.0 : 0.0;
          start_half_work.damping[c] = 0.5 * (start * dot(carried_ledger.damping(c), v_carried));
          start_half_work.friction[c] = 0.5 * (start * dot(s_carried, v_carried));
          end_half_work.damping[c] = 0.5 * dot(r.damping_force_i, in.v_rel);
          end_half_work.friction[c] = 0.5 * dot(s, in.v_rel);
          ledger_to_carry.store(c, r.damping_force_i, depth);
          if constexpr (kLedger == Ledger::kPerContactWithEnergies) {
            half_tangential_energy[c] = 0.5 * r.tangential_energy;
            half_elastic_energy[c] = 0.5 * r.elastic_energy;
          }
        }
        if constexpr (kPerParticle) {
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

template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kOff, false>(double,
                                                                                     std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kOff, true>(double,
                                                                                    std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerParticle, false>(
    double, std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerParticle, true>(
    double, std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerContact, false>(
    double, std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerContact, true>(
    double, std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerContactWithEnergies,
                                              false>(double, std::size_t);
template void PairContactChunk::compute_lanes<PairContactChunk::Ledger::kPerContactWithEnergies,
                                              true>(double, std::size_t);

}  // namespace ringdem

#include "engine/PairContactChunk.hpp"

#include <cmath>

#include "engine/Loop.hpp"

namespace ringdem {

template <bool kBook, bool kRolling>
void PairContactChunk::compute_lanes(double dt) {
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
        const HertzMindlin::Params params{e_star[c], g_star[c], beta[c], friction[c],
                                          rolling_friction[c]};
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

template void PairContactChunk::compute_lanes<false, false>(double);
template void PairContactChunk::compute_lanes<false, true>(double);
template void PairContactChunk::compute_lanes<true, false>(double);
template void PairContactChunk::compute_lanes<true, true>(double);

}  // namespace ringdem

#include "engine/BodyContactChunk.hpp"

#include "engine/Loop.hpp"

namespace ringdem {

template <bool kRolling>
void BodyContactChunk::compute_lanes(double dt) {
  for_each(
      IndexRange{0, n}, [&](std::size_t c) __attribute__((always_inline)) {
        HertzMindlin::Input in;
        in.normal = normal.get(c);
        in.overlap = overlap[c];
        in.r_star = r_star[c];
        in.m_star = m_star[c];
        in.v_rel = v_rel.get(c);
        in.dt = dt;
        in.arm_i = arm[c];
        in.arm_j = 0.0;
        in.omega_i = omega_particle.get(c);
        in.omega_j = omega_body.get(c);
        const HertzMindlin::Params params{e_star[c], g_star[c], beta[c], friction[c],
                                          rolling_friction[c]};
        Vec3 s = spring.get(c);
        const auto r = HertzMindlin::compute<kRolling>(params, in, s);
        spring.set(c, s);
        force.set(c, r.force_i);
        torque.set(c, cross(in.normal * in.arm_i, r.force_i) + r.rolling_torque_i);
        damping.set(c, r.damping_force_i);
        rolling.set(c, r.rolling_torque_i);
        tangential_energy[c] = r.tangential_energy;
        elastic_energy[c] = r.elastic_energy;
      });
}

template void BodyContactChunk::compute_lanes<false>(double);
template void BodyContactChunk::compute_lanes<true>(double);

}  // namespace ringdem

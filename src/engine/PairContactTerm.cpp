#include "engine/PairContactTerm.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "engine/ContactKeys.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {

double PairContactTerm::ghost_width(const ParticleStore& p) const {
  double r_max = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    r_max = std::max(r_max, p.radius[k]);
  return 2.0 * r_max;
}

void PairContactTerm::find_overlaps(const ParticleStore& p, const std::vector<RigidBody>&,
                                    double fraction, std::vector<ContactOverlap>& out) const {
  for (std::size_t m = 0; m < pairs_.size(); ++m) {
    const std::uint32_t a = pairs_.i[m];
    const std::uint32_t b = pairs_.j[m];
    const double depth = p.radius[a] + p.radius[b] - norm(p.position[b] - p.position[a]);
    if (depth > fraction * std::min(p.radius[a], p.radius[b])) out.push_back({a, b, false, depth});
  }
}

void PairContactTerm::rebuild(RebuildContext& ctx) {
  const ParticleStore& p = ctx.particles;
  const std::size_t n_total = p.n_total();
  // Exclusion lists by particle (the bonded terms' entries), as offsets into one array.
  exclusions_.offset.assign(n_total + 1, 0);
  for (const auto& e : ctx.excluded)
    ++exclusions_.offset[e.particle + 1];
  for (std::size_t k = 0; k < n_total; ++k)
    exclusions_.offset[k + 1] += exclusions_.offset[k];
  exclusions_.partner_gid.assign(exclusions_.offset[n_total], 0);
  {
    std::vector<std::uint32_t> fill(exclusions_.offset.begin(), exclusions_.offset.end() - 1);
    for (const auto& e : ctx.excluded)
      exclusions_.partner_gid[fill[e.particle]++] = e.partner_gid;
  }

  search_.build(p, ctx.skin, exclusions_, pairs_);
  // The store's rows (the springs carried across the migration) become the new candidates.
  const auto old_springs = springs_by_key(springs_);
  const std::size_t np = pairs_.size();
  springs_.resize(np);
  for (std::size_t m = 0; m < np; ++m) {
    springs_.gid[m] = p.gid[pairs_.i[m]];
    springs_.partner[m] = p.gid[pairs_.j[m]];
    const auto it = old_springs.find(PairKey{springs_.gid[m], springs_.partner[m]});
    springs_.spring[m] = it != old_springs.end() ? it->second : Vec3{};
  }

  slots_a_ = ctx.allocator.take(np);
  slots_b_ = ctx.allocator.take(np);
  for (std::size_t m = 0; m < np; ++m) {
    const auto s = static_cast<std::uint32_t>(m);
    ctx.gather.add(pairs_.i[m], springs_.partner[m], ctx.term_number, slots_a_.begin + s, true);
    ctx.gather.add(pairs_.j[m], springs_.gid[m], ctx.term_number, slots_b_.begin + s, true);
  }
}

void PairContactTerm::compute(ComputeContext& ctx) {
  const ParticleStore& p = ctx.particles;
  ForceSlots& slots = ctx.slots;
  EnergyLedger& ledger = ctx.ledger;
  const std::size_t np = pairs_.size();
  std::vector<Vec3>& spring = springs_.spring;
  // Particle contacts (physics.md §3).
  for (std::size_t m = 0; m < np; ++m) {
    const std::uint32_t a = pairs_.i[m];
    const std::uint32_t b = pairs_.j[m];
    const std::uint32_t slot_a = slots_a_.begin + static_cast<std::uint32_t>(m);
    const std::uint32_t slot_b = slots_b_.begin + static_cast<std::uint32_t>(m);
    const Vec3 d = p.position[b] - p.position[a];
    const double reach = p.radius[a] + p.radius[b];
    const double dist2 = norm2(d);
    if (dist2 >= reach * reach) {
      spring[m] = {};
      slots.set(slot_a, {}, {});
      slots.set(slot_b, {}, {});
      ledger.record(slot_a) = {};
      ledger.record(slot_b) = {};
      continue;
    }
    const double dist = std::sqrt(dist2);
    const Vec3 n = d / dist;
    const double overlap = reach - dist;
    const double arm_a = p.radius[a] - 0.5 * overlap;
    const double arm_b = p.radius[b] - 0.5 * overlap;
    HertzMindlin::Input in;
    in.normal = n;
    in.overlap = overlap;
    in.r_star = p.radius[a] * p.radius[b] / reach;
    in.m_star = effective_mass(p.mass[a], p.motion[a], p.mass[b], p.motion[b]);
    in.v_rel = (p.velocity[b] + cross(p.omega[b], n * (-arm_b))) -
               (p.velocity[a] + cross(p.omega[a], n * arm_a));
    in.dt = ctx.dt;
    in.arm_i = arm_a;
    in.arm_j = arm_b;
    in.omega_i = p.omega[a];
    in.omega_j = p.omega[b];
    const auto r =
        HertzMindlin::compute(ctx.materials.pair(p.material[a], p.material[b]), in, spring[m]);
    slots.set(slot_a, r.force_i, cross(n * arm_a, r.force_i) + r.rolling_torque_i);
    slots.set(slot_b, -r.force_i, cross(n * arm_b, r.force_i) + r.rolling_torque_j);
    // Ledger: each end's loads; the tangential energy half to each end.
    ledger.record(slot_a) = {
        r.damping_force_i,     spring[m], n * arm_a, r.rolling_torque_i, 0.5 * r.tangential_energy,
        0.5 * r.elastic_energy};
    ledger.record(slot_b) = {-r.damping_force_i,
                             -spring[m],
                             n * (-arm_b),
                             r.rolling_torque_j,
                             0.5 * r.tangential_energy,
                             0.5 * r.elastic_energy};
  }
}

}  // namespace ringdem

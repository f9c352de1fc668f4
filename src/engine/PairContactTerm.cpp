#include "engine/PairContactTerm.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ContactKeys.hpp"
#include "engine/Loop.hpp"
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
  // The keyed rows (the touching springs packed before the migration, or a checkpoint's)
  // become the new candidates' springs. The candidates are in ascending (gid, partner) order,
  // and so are the rows once sorted (they are, unless migration appended arrivals): one merge
  // pass pairs them. Of two rows with one key (both ends' ranks held the pair) the first in
  // storage order is taken.
  const ContactSpringStore& carried = springs_;
  const std::size_t n_carried = carried.size();
  carried_order_.resize(n_carried);
  for (std::uint32_t r = 0; r < n_carried; ++r)
    carried_order_[r] = r;
  const auto row_before = [&carried](std::uint32_t x, std::uint32_t y) {
    return PairKey::less(carried.gid[x], carried.partner[x], carried.gid[y], carried.partner[y]);
  };
  if (!std::is_sorted(carried_order_.begin(), carried_order_.end(), row_before))
    std::stable_sort(carried_order_.begin(), carried_order_.end(), row_before);
  const std::size_t np = pairs_.size();
  spring_.reset(np);
  std::size_t c = 0;
  for (std::size_t m = 0; m < np && c < n_carried; ++m) {
    const std::int64_t key_a = p.gid[pairs_.i[m]], key_b = p.gid[pairs_.j[m]];
    while (c < n_carried && PairKey::less(carried.gid[carried_order_[c]],
                                          carried.partner[carried_order_[c]], key_a, key_b))
      ++c;
    if (c < n_carried && carried.gid[carried_order_[c]] == key_a &&
        carried.partner[carried_order_[c]] == key_b)
      spring_.take(m) = carried.spring[carried_order_[c]];
  }
  // Read back: the keyed rows' memory goes until the next pack.
  springs_ = ContactSpringStore{ContactSpringStore::Partner::kParticle};
  std::vector<std::uint32_t>().swap(carried_order_);
}

void PairContactTerm::pack_springs(const ParticleStore& p) {
  // Rows already in the store (a checkpoint's, before the first rebuild) stay.
  springs_.drop_released();
  for (std::size_t m = 0; m < spring_.n_candidates(); ++m)
    if (spring_.holds(m) && norm2(spring_.value(m)) > 0.0)
      springs_.append(p.gid[pairs_.i[m]], p.gid[pairs_.j[m]], spring_.value(m));
  // The candidates are rebuilt next: their springs' memory goes before the search's comes.
  spring_.release_memory();
}

ContactSpringStore PairContactTerm::touching_springs(const ParticleStore& p) const {
  ContactSpringStore out = springs_;
  out.drop_released();
  for (std::size_t m = 0; m < spring_.n_candidates(); ++m)
    if (spring_.holds(m) && norm2(spring_.value(m)) > 0.0)
      out.append(p.gid[pairs_.i[m]], p.gid[pairs_.j[m]], spring_.value(m));
  return out;
}

void PairContactTerm::compute(ComputeContext& ctx) {
  // Compiled with and without the ledger's sums (a branch on it in the loop cost the loop with
  // them 6 %). Two loops call the contact law and the pair kernel twice, so GCC inlines them
  // only when told to (always_inline): called out of line they cost the loop 60 %.
  if (ctx.ledger.enabled())
    compute_pairs<true>(ctx);
  else
    compute_pairs<false>(ctx);
}

template <bool kBook>
void PairContactTerm::compute_pairs(ComputeContext& ctx) {
  const ParticleStore& p = ctx.particles;
  const ParticleLoads loads = ctx.loads;
  EnergyLedger& ledger = ctx.ledger;
  // Raw pointers, read once (nothing in the loop can move them).
  const std::uint32_t* const pair_a = pairs_.i.data();
  const std::uint32_t* const pair_b = pairs_.j.data();
  const Vec3* const position = p.position.data();
  const double* const radius = p.radius.data();
  SpringSlots& springs = spring_;
  // Particle contacts (physics.md §3). The pairs come in ascending (gid of a, gid of b) order
  // (NeighbourSearch), and each adds its loads to both ends at once: every particle then gets
  // its contacts in ascending partner gid, the gather order (DESIGN §4), without a slot per
  // pair. Most candidates do not touch: they cost a distance test and a slot read, and hold no
  // spring.
  for_each_in_order(
      IndexRange{0, pairs_.size()}, [&](std::size_t m) __attribute__((always_inline)) {
        const std::uint32_t a = pair_a[m];
        const std::uint32_t b = pair_b[m];
        const Vec3 d = position[b] - position[a];
        const double reach = radius[a] + radius[b];
        const double dist2 = norm2(d);
        if (dist2 >= reach * reach) {
          springs.release(m);  // an open contact's spring is zero (physics.md §3)
          return;
        }
        Vec3& spring = springs.take(m);
        const double dist = std::sqrt(dist2);
        const Vec3 n = d / dist;
        const double overlap = reach - dist;
        const double arm_a = radius[a] - 0.5 * overlap;
        const double arm_b = radius[b] - 0.5 * overlap;
        HertzMindlin::Input in;
        in.normal = n;
        in.overlap = overlap;
        in.r_star = radius[a] * radius[b] / reach;
        in.m_star = effective_mass(p.mass[a], p.motion[a], p.mass[b], p.motion[b]);
        in.v_rel = (p.velocity[b] + cross(p.omega[b], n * (-arm_b))) -
                   (p.velocity[a] + cross(p.omega[a], n * arm_a));
        in.dt = ctx.dt;
        in.arm_i = arm_a;
        in.arm_j = arm_b;
        in.omega_i = p.omega[a];
        in.omega_j = p.omega[b];
        const auto r =
            HertzMindlin::compute(ctx.materials.pair(p.material[a], p.material[b]), in, spring);
        const Vec3 lever_a = n * arm_a;   // from a's centre to the contact point
        const Vec3 lever_b = n * -arm_b;  // from b's centre to the contact point
        // Each end's loads, and for the ledger its viscous and spring loads and moments
        // (ContactMoments) with half of the pair's tangential and elastic energy.
        if (loads.owned(a)) {
          loads.force[a] += r.force_i;
          loads.torque[a] += cross(lever_a, r.force_i) + r.rolling_torque_i;
          if constexpr (kBook) {
            ContactMoments& c = ledger.moments(a);
            c.damping += r.damping_force_i;
            c.damping_moment += cross(lever_a, r.damping_force_i);
            c.friction += spring;
            c.friction_moment += cross(lever_a, spring) + r.rolling_torque_i;
            c.tangential_energy += 0.5 * r.tangential_energy;
            c.elastic_energy += 0.5 * r.elastic_energy;
          }
        }
        if (loads.owned(b)) {
          loads.force[b] += -r.force_i;
          loads.torque[b] += cross(n * arm_b, r.force_i) + r.rolling_torque_j;
          if constexpr (kBook) {
            ContactMoments& c = ledger.moments(b);
            c.damping += -r.damping_force_i;
            c.damping_moment += cross(lever_b, -r.damping_force_i);
            c.friction += -spring;
            c.friction_moment += cross(lever_b, -spring) + r.rolling_torque_j;
            c.tangential_energy += 0.5 * r.tangential_energy;
            c.elastic_energy += 0.5 * r.elastic_energy;
          }
        }
      });
}

}  // namespace ringdem

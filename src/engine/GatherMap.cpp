#include "engine/GatherMap.hpp"

#include <algorithm>
#include <stdexcept>
#include <tuple>

namespace ringdem {

void GatherMap::begin(std::size_t n_local) {
  n_local_ = n_local;
  entries_.clear();
}

void GatherMap::finish(const ParticleStore& p) {
  std::sort(entries_.begin(), entries_.end(), [](const Entry& x, const Entry& y) {
    return std::tie(x.particle, x.key, x.term) < std::tie(y.particle, y.key, y.term);
  });
  all_.build(entries_, -1);
  // Energy ledger: the owned particles with ledger slots (in gather order), and driven ones.
  ledger_all_.build(entries_, -1, true);
  entry_of_slot_.clear();
  if (split_by_rate_) {
    std::uint32_t n_slots = 0;
    for (const Entry& e : entries_)
      n_slots = std::max(n_slots, e.slot + 1);
    entry_of_slot_.assign(n_slots, kNoEntry);
    for (std::size_t i = 0; i < entries_.size(); ++i)
      entry_of_slot_[entries_[i].slot] = static_cast<std::uint32_t>(i);
  }
  finish_rates();
  driven_particle_.clear();
  for (std::size_t k = 0; k < n_local_; ++k)
    if (p.motion[k] != Motion::kFree) driven_particle_.push_back(static_cast<std::uint32_t>(k));
}

void GatherMap::set_rate(std::uint32_t slot, bool fast) {
  if (!split_by_rate_) throw std::logic_error("GatherMap::set_rate without set_split_by_rate()");
  if (slot < entry_of_slot_.size() && entry_of_slot_[slot] != kNoEntry)
    entries_[entry_of_slot_[slot]].fast = fast;
}

void GatherMap::finish_rates() {
  if (!split_by_rate_) return;
  fast_.build(entries_, 1);
  slow_.build(entries_, 0);
  ledger_fast_.build(entries_, 1, true);
  ledger_slow_.build(entries_, 0, true);
}

void GatherMap::SlotLists::build(const std::vector<Entry>& entries, int fast, bool ledger_only) {
  particle.clear();
  offset.assign(1, 0);
  slot.clear();
  for (const Entry& e : entries) {
    if (fast >= 0 && e.fast != (fast == 1)) continue;
    if (ledger_only && !e.ledger) continue;
    if (particle.empty() || particle.back() != e.particle) {
      particle.push_back(e.particle);
      offset.push_back(offset.back());
    }
    ++offset.back();
    slot.push_back(e.slot);
  }
}

void GatherMap::initialise_loads(ParticleStore& p, const Vec3& gravity) {
  const std::size_t n_local = p.n_local();
  const double* const mass = p.mass.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  // Component by component (no Vec3 copies), so that the loop vectorises.
#pragma omp simd
  for (std::size_t k = 0; k < n_local; ++k) {
    force[k].x = gravity.x * mass[k];
    force[k].y = gravity.y * mass[k];
    force[k].z = gravity.z * mass[k];
    torque[k].x = 0.0;
    torque[k].y = 0.0;
    torque[k].z = 0.0;
  }
}

void GatherMap::apply_point_loads(ParticleStore& p, const std::vector<PointLoad>& loads) {
  external_.clear();
  applied_.clear();
  for (const PointLoad& load : loads) {
    const std::int64_t k = p.index_of(load.gid);
    if (k < 0 || static_cast<std::size_t>(k) >= p.n_local()) continue;
    const auto i = static_cast<std::uint32_t>(k);
    p.force[i] += load.force;
    applied_.emplace_back(i, load.force);
    // Energy ledger: the power at the mid-step velocity (the drift x += v dt used it).
    if (p.motion[i] == Motion::kFree) external_.push_back({i, dot(load.force, p.velocity[i])});
  }
}

void GatherMap::gather(ParticleStore& p, const ForceSlots& slots, const Vec3& gravity,
                       ForceRate rate, const ParticleLoads* loads) {
  // Raw pointers, read once (nothing in the loop can move them).
  Vec3* const force = loads ? loads->force : p.force.data();
  Vec3* const torque = loads ? loads->torque : p.torque.data();
  const bool split = rate != ForceRate::kAll;
  if (split && !split_by_rate_)
    throw std::logic_error("GatherMap::gather of one rate without set_split_by_rate()");
  const SlotLists& lists = !split ? all_ : rate == ForceRate::kFast ? fast_ : slow_;
  const std::vector<std::uint32_t>& particles = lists.particle;
  const std::uint32_t* const offset = lists.offset.data();
  const std::uint32_t* const slot = lists.slot.data();
  const double *const fx = slots.fx.data(), *const fy = slots.fy.data(),
                      *const fz = slots.fz.data();
  const double *const tx = slots.tx.data(), *const ty = slots.ty.data(),
                      *const tz = slots.tz.data();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const std::uint32_t k = particles[i];
    Vec3 f = force[k];
    Vec3 t = torque[k];
    for (std::uint32_t e = offset[i]; e < offset[i + 1]; ++e) {
      const std::uint32_t s = slot[e];
      f += Vec3{fx[s], fy[s], fz[s]};
      t += Vec3{tx[s], ty[s], tz[s]};
    }
    force[k] = f;
    torque[k] = t;
  }
  // Energy ledger: whatever a driven particle's interactions push against, the driver supplies.
  // (Multi-rate stepping holds every particle that is not free at the fast rate.)
  if (rate == ForceRate::kSlow) return;
  driven_.clear();
  for (const std::uint32_t k : driven_particle_) {
    Vec3 applied;
    for (const auto& [particle, load] : applied_)
      if (particle == k) applied += load;
    const Vec3 interaction = force[k] - gravity * p.mass[k] - applied;
    driven_.push_back({k, dot(interaction, p.velocity[k]) + dot(torque[k], p.omega[k])});
  }
}

}  // namespace ringdem

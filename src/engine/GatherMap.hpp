#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/Model.hpp"

namespace ringdem {

/// For every owned particle, its force slots in a fixed order: by partner key (the partner's
/// gid, or a rigid body's key after every gid), then by term. The sum is then the same whatever
/// the storage order or the rank count (DESIGN §4). Written once for all force terms.
class GatherMap {
 public:
  /// Rigid bodies sort after every particle partner: key = kBodyKeyBase + body index.
  static constexpr std::int64_t kBodyKeyBase = std::int64_t{1} << 62;

  /// Starts a rebuild over `n_local` owned particles.
  void begin(std::size_t n_local);
  /// One slot of particle `particle` (ignored unless owned), from term number `term`;
  /// `ledger`: the slot carries a dissipation record for the energy ledger.
  /// `fast`: the slot's interaction is fast (ForceRate), which matters only where the gather
  /// is split by rate.
  void add(std::uint32_t particle, std::int64_t partner_key, std::uint32_t term, std::uint32_t slot,
           bool ledger, bool fast = true) {
    if (particle < n_local_) entries_.push_back({particle, partner_key, term, slot, ledger, fast});
  }
  /// Multi-rate stepping: finish() also lists each rate's slots, which gather() of a fast or
  /// slow evaluation sums alone.
  void set_split_by_rate(bool split) { split_by_rate_ = split; }
  /// Sorts the entries into the gather order and builds the ledger's particle lists: owned
  /// particles with ledger slots, and driven ones (`p.motion`).
  void finish(const ParticleStore& p);
  /// Multi-rate stepping, between two rebuilds: the interaction of `slot` now has the rate
  /// `fast` (ForceTerm::change_rates()); a slot that no owned particle has is ignored.
  /// finish_rates() then lists each rate's slots anew.
  void set_rate(std::uint32_t slot, bool fast);
  /// Each rate's slots and ledger slots from the entries' rates, in gather order (finish() does
  /// it too). Nothing where the gather is not split by rate.
  void finish_rates();

  /// Starts a force evaluation: force = gravity * mass, torque = 0 (owned particles). The step
  /// does this in its drift pass instead (Integrator::first_half).
  static void initialise_loads(ParticleStore& p, const Vec3& gravity);
  /// Adds the point loads on owned particles to the initial loads, and notes the power
  /// F_ext . v of those on free particles at the mid-step velocity, for the ledger. Terms that
  /// sum per particle (ParticleLoads) add to these next.
  void apply_point_loads(ParticleStore& p, const std::vector<PointLoad>& loads);
  /// Adds each owned particle's slots in gather order. Notes the power of the interaction loads
  /// on driven particles (their velocity is not changed by the kicks), for the ledger.
  /// `rate`: the slots of that rate only (ForceRate::kAll: every slot), added to `loads`
  /// (default: the particles' force and torque).
  void gather(ParticleStore& p, const ForceSlots& slots, const Vec3& gravity,
              ForceRate rate = ForceRate::kAll, const ParticleLoads* loads = nullptr);

  /// The owned particles with slots of `rate` (ascending; of fast or slow only where the gather
  /// is split by rate).
  const std::vector<std::uint32_t>& particles_with_slots(ForceRate rate) const {
    return rate == ForceRate::kFast   ? fast_.particle
           : rate == ForceRate::kSlow ? slow_.particle
                                      : all_.particle;
  }
  /// The owned particles with ledger slots, with those slots in gather order (those of one
  /// rate where the gather is split by rate: each rate's ledger books its own).
  const std::vector<std::uint32_t>& ledger_particles(ForceRate rate = ForceRate::kAll) const {
    return ledger_lists(rate).particle;
  }
  const std::vector<std::uint32_t>& ledger_offsets(ForceRate rate = ForceRate::kAll) const {
    return ledger_lists(rate).offset;
  }
  const std::vector<std::uint32_t>& ledger_slots(ForceRate rate = ForceRate::kAll) const {
    return ledger_lists(rate).slot;
  }

  struct ParticlePower {
    std::uint32_t particle;
    double power;
  };
  /// F_ext . v at the mid-step velocity, for free particles with an external load.
  const std::vector<ParticlePower>& external_powers() const { return external_; }
  /// Power of the interaction loads on each driven particle (ascending index): what the
  /// driver supplies is minus this.
  const std::vector<ParticlePower>& driven_powers() const { return driven_; }

 private:
  struct Entry {
    std::uint32_t particle;
    std::int64_t key;
    std::uint32_t term;
    std::uint32_t slot;
    bool ledger;
    bool fast;
  };

  std::size_t n_local_ = 0;
  std::vector<Entry> entries_;
  /// Owned particles with slots, and their slots in gather order (see all_).
  struct SlotLists {
    std::vector<std::uint32_t> particle, offset, slot;
    /// fast: -1 any, 0 slow, 1 fast; `ledger_only`: the slots with ledger records alone.
    void build(const std::vector<Entry>& entries, int fast, bool ledger_only = false);
  };
  /// The owned particles with slots (ascending), and theirs in gather order: those of
  /// all_.particle[i] are all_.slot[e] for e in [all_.offset[i], all_.offset[i + 1]).
  /// Only these are visited: most grains of a flow have no slot (their contacts add to the
  /// loads directly), and a pass over every particle's offsets took a third of the gather.
  /// fast_ and slow_: those of each rate (multi-rate stepping, set_split_by_rate()).
  SlotLists all_, fast_, slow_;
  /// The ledger's particles with their ledger slots: of every rate, and of each.
  SlotLists ledger_all_, ledger_fast_, ledger_slow_;
  const SlotLists& ledger_lists(ForceRate rate) const {
    return rate == ForceRate::kFast   ? ledger_fast_
           : rate == ForceRate::kSlow ? ledger_slow_
                                      : ledger_all_;
  }
  bool split_by_rate_ = false;
  /// Where the gather is split by rate: the entry of each slot (kNoEntry: none), for set_rate().
  static constexpr std::uint32_t kNoEntry = UINT32_MAX;
  std::vector<std::uint32_t> entry_of_slot_;
  std::vector<std::uint32_t> driven_particle_;
  std::vector<ParticlePower> external_, driven_;
  /// The point loads applied in this evaluation, by particle (the gather takes them out of a
  /// driven particle's interaction load).
  std::vector<std::pair<std::uint32_t, Vec3>> applied_;
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "comm/FarGhosts.hpp"
#include "domain/ContactSpringStore.hpp"
#include "domain/PairStore.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "engine/EnergyLedger.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/GatherMap.hpp"
#include "physics/MaterialTable.hpp"

namespace ringdem {

/// A pair that must get no contact: particle index and the partner's gid.
struct ExcludedPair {
  std::uint32_t particle;
  std::int64_t partner_gid;
};

/// What a force term reads at a neighbour-list rebuild (the particle index is current).
struct RebuildContext {
  const ParticleStore& particles;
  const std::vector<RigidBody>& bodies;
  double skin;
  /// Pairs that must not touch (intact bonds): bonded terms append both ends' entries in
  /// their rebuild, which runs before that of the contact terms (term order, Simulation).
  std::vector<ExcludedPair>& excluded;
  SlotAllocator& allocator;
  GatherMap& gather;
  std::uint32_t term_number;  ///< position in the term list: the gather order's tie-break
};

/// Whether particle k is part of a net: a ring's bead (body >= 0) or a held particle (a net's
/// shackle, a frame). Its interactions are all fast, and so are those of a grain it touches
/// (is_fast_particle()).
inline bool is_net_particle(const ParticleStore& p, std::size_t k) {
  return p.body[k] >= 0 || p.motion[k] != Motion::kFree;
}

/// Whether particle k steps at the fast rate wherever it takes part: a net particle, or a grain
/// that touched the net at the last check (ParticleStore::net_contact). Its interactions are all
/// fast.
inline bool is_fast_particle(const ParticleStore& p, std::size_t k) {
  return is_net_particle(p, k) || (!p.net_contact.empty() && p.net_contact[k] != 0);
}

/// What a force term reads and writes in one force evaluation.
struct ComputeContext {
  const ParticleStore& particles;
  std::vector<RigidBody>& bodies;
  const MaterialTable& materials;
  ForceSlots& slots;
  EnergyLedger& ledger;
  double time;
  double dt;
  ParticleLoads loads;  ///< for a term that sums per particle (ForceSlots.hpp)
  ForceRate rate = ForceRate::kAll;
};

/// A contact that overlaps (Simulation::initial_overlaps): particle `index` and its partner, a
/// particle (by index) or a rigid body (by number).
struct ContactOverlap {
  std::uint32_t index;
  std::uint32_t partner;
  bool partner_is_body;
  double depth;  ///< r_i + r_j - distance, or r_i - distance to the body's surface (m)
};

/// One kind of interaction (DESIGN §2): bonds of one model, particle pairs, particle–rigid-
/// body contacts; later ropes and brakes. A term owns its parameters and state, takes its
/// slot ranges from the allocator at every rebuild, registers each slot with the gather map
/// (and with the ledger when it dissipates), and evaluates its kernel through the loop
/// helper (engine/Loop.hpp). It never calls MPI and never asks whether a particle is a ghost:
/// the gather map keeps only owned particles' slots.
class ForceTerm {
 public:
  virtual ~ForceTerm() = default;

  virtual std::string_view name() const = 0;
  /// Largest centre distance of two particles this term couples (before the skin): every
  /// partner of an owned particle within it must be present as a ghost.
  virtual double ghost_width(const ParticleStore& p) const = 0;
  /// Particles this term couples farther apart than any term's ghost width, where only a few
  /// reach that far (FarGhostRule; its reach before the skin): nothing by default.
  virtual std::optional<FarGhostRule> far_ghosts(const ParticleStore& /*p*/) const {
    return std::nullopt;
  }
  /// Resolves particle indices, builds candidate lists, takes slots, fills the gather map.
  virtual void rebuild(RebuildContext& ctx) = 0;
  /// Writes this term's slots for the current state.
  virtual void compute(ComputeContext& ctx) = 0;
  /// The term's store of tangential springs (its contact state), or nullptr for a term without
  /// one. Migration and checkpoints reach it only through this and its field registry; its
  /// rows survive a rebuild when the term's rebuild() reads them back by key.
  virtual ContactSpringStore* springs() { return nullptr; }
  virtual const ContactSpringStore* springs() const { return nullptr; }
  /// Before a migration: the spring store keeps only its touching contacts, keyed by gid,
  /// which the term's rebuild() then reads back. A term that keeps its springs elsewhere
  /// between rebuilds (per candidate, without keys) adds its touching ones to the store here.
  virtual void pack_springs(const ParticleStore& /*p*/) {
    if (ContactSpringStore* s = springs()) s->drop_released();
  }
  /// Before pack_springs() at a rebuild: where the energy ledger books this term's contacts one
  /// by one, what they carry to the next step, and where `mid_step` (the drift of the step of
  /// `dt` done: the velocities are those of the step's middle) the work it stands for is booked
  /// now instead, so that the keyed rows need not carry it (PairContactTerm).
  virtual void book_carried_work(const ParticleStore& /*p*/, EnergyLedger& /*ledger*/,
                                 bool /*mid_step*/, double /*dt*/) {}
  /// Which touching springs touching_springs() gives: those this rank counts
  /// (domain/PairStore.hpp's counted_here: a pair across ranks is held by both ranks and written
  /// once, a checkpoint's), or every one it holds.
  enum class SpringRows { kCounted, kAll };
  /// The touching contacts' springs, keyed by gid, at any time (checkpoints). Sized exactly:
  /// the checkpoint of a bed in contact held a copy of every spring grown by doubling beside
  /// the run's own (docs/performance.md, fifty-seventh round).
  ContactSpringStore touching_springs(const ParticleStore& p,
                                      SpringRows rows = SpringRows::kCounted) const {
    return touching_springs_part(p, rows, 0, 1);
  }
  /// What touching_springs() looks through: the keyed rows, and a pair term's candidates.
  virtual std::size_t spring_sources() const {
    const ContactSpringStore* s = springs();
    return s == nullptr ? 0 : s->size();
  }
  /// touching_springs() in `parts` parts, so that a checkpoint need not hold them all at once
  /// (they were 41 MiB of a write's peak at 2.5 x 10^5 grains in contact a rank: docs/
  /// performance.md, fifty-eighth round): part k holds what the k-th of `parts` equal slices
  /// of spring_sources() gives, and the parts one after another are touching_springs().
  virtual ContactSpringStore touching_springs_part(const ParticleStore& p, SpringRows rows,
                                                   std::size_t part, std::size_t parts) const {
    const std::size_t n = spring_sources();
    return keyed_touching_springs(p, rows, slice_begin(n, part, parts),
                                  slice_begin(n, part + 1, parts));
  }
  /// Where the k-th of `parts` equal slices of `n` items begins (n * parts stays far below
  /// 2^64: a rank's springs by the parts of a few MiB each).
  static std::size_t slice_begin(std::size_t n, std::size_t k, std::size_t parts) {
    return n * k / parts;
  }
  /// The term's store of rows that join two particles (its bonds, its contact springs), or
  /// none: the decomposition moves every term's rows through this one handle. A contact term's
  /// is its spring store.
  virtual std::optional<PairStore> pair_store() {
    if (ContactSpringStore* s = springs()) return PairStore{s};
    return std::nullopt;
  }
  /// Appends this term's contact candidates (since the last rebuild) that overlap by more than
  /// `fraction` of the smaller radius (a body's radius counts as infinite).
  virtual void find_overlaps(const ParticleStore& /*p*/, const std::vector<RigidBody>& /*bodies*/,
                             double /*fraction*/, std::vector<ContactOverlap>& /*out*/) const {}
  /// Set when the last compute() changed the topology (a bond broke): forces a rebuild.
  virtual bool topology_changed() const { return false; }
  /// Whether some of this term's interactions are slow (ForceRate): such a term computes only
  /// those of the evaluation's rate. A term without (bonds, a net's mesh) is fast throughout:
  /// a slow evaluation skips it, and its slots are gathered with the fast loads.
  virtual bool has_slow_interactions() const { return false; }
  /// Multi-rate stepping: sets fast[k] = 1 for each owned particle k (k < fast.size()) that
  /// this term's fast interactions may load or read, other than through its slots, which the
  /// gather map lists (SubstepParticles): the sub-steps move only such particles. A term that
  /// adds loads directly (ParticleLoads) and has fast interactions must mark their particles,
  /// candidates that do not touch included: the sub-steps leave the others where they were.
  virtual void mark_fast_particles(const ParticleStore& /*p*/,
                                   std::vector<std::uint8_t>& /*fast*/) {}
  /// Multi-rate stepping: sets touching[k] = 1 for each owned particle k (k < touching.size())
  /// that is not a net particle (is_net_particle()) and that one of this term's interactions
  /// with a net particle or a net's mesh loaded in the last evaluation (positions unchanged
  /// since). Simulation::note_net_contacts() makes those grains' interactions fast.
  virtual void mark_net_contacts(const ParticleStore& /*p*/,
                                 std::vector<std::uint8_t>& /*touching*/) const {}
  /// Multi-rate stepping, between two rebuilds: some grain's net_contact changed (owned and
  /// ghost particles alike), so is_fast_particle() may now answer otherwise for the same
  /// candidates. A term whose rates follow it re-decides them, and tells `gather` the new rate
  /// of each of its slots (GatherMap::set_rate()); the others keep theirs.
  virtual void change_rates(const ParticleStore& /*p*/, GatherMap& /*gather*/) {}

 protected:
  /// The keyed rows [first, last) that carry state and that `rows` selects, in order.
  ContactSpringStore keyed_touching_springs(const ParticleStore& p, SpringRows rows,
                                            std::size_t first, std::size_t last) const {
    const ContactSpringStore* s = springs();
    if (s == nullptr) return ContactSpringStore{};
    ContactSpringStore out(s->partner_kind());
    out.set_carries_ledger(s->carries_ledger());
    const auto kept = [&](std::size_t k) {
      return s->carries_state(k) && (rows == SpringRows::kAll || counted_here(p, *s, k));
    };
    std::size_t n = 0;
    for (std::size_t k = first; k < last; ++k)
      n += kept(k) ? 1 : 0;
    out.reserve(n);
    for (std::size_t k = first; k < last; ++k)
      if (kept(k))
        out.append(s->gid[k], s->partner[k], s->spring[k],
                   s->carries_ledger() ? s->ledger[k] : ContactLedgerState{});
    return out;
  }
};

}  // namespace ringdem

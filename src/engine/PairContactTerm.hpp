#pragma once

#include <cstdint>
#include <vector>

#include "domain/NeighbourSearch.hpp"
#include "domain/SpringSlots.hpp"
#include "engine/ForceTerm.hpp"
#include "engine/PairContactChunk.hpp"

namespace ringdem {

/// Contacts between particles (Hertz–Mindlin, physics.md §3): cell-grid candidate pairs with
/// a Verlet skin in ascending order of the ends' sort keys (ParticleStore::sorts_before), each
/// with its tangential spring. Between rebuilds the
/// springs of the touching candidates are in SpringSlots (their keys are the candidates' gids,
/// so no key columns; no spring where nothing touches); at a rebuild they go into the
/// ContactSpringStore keyed by the gid pair, for migration, and come back by key. It takes no
/// slots: each pair adds its loads to both ends' ParticleLoads, in the gather order
/// (ForceSlots.hpp), and books its work in the energy ledger: per contact, or through both
/// ends' ContactMoments (EnergyLedger::PairBooking).
class PairContactTerm final : public ForceTerm {
 public:
  std::string_view name() const override { return "particle_contacts"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  ContactSpringStore* springs() override { return &springs_; }
  const ContactSpringStore* springs() const override { return &springs_; }
  void pack_springs(const ParticleStore& p) override;
  void book_carried_work(const ParticleStore& p, EnergyLedger& ledger, bool mid_step,
                         double dt) override;
  std::size_t spring_sources() const override { return springs_.size() + spring_.n_candidates(); }
  ContactSpringStore touching_springs_part(const ParticleStore& p, SpringRows rows,
                                           std::size_t part, std::size_t parts) const override;
  void find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies, double fraction,
                     std::vector<ContactOverlap>& out) const override;

  std::size_t n_candidates() const { return pairs_.size(); }
  bool has_slow_interactions() const override { return true; }
  void mark_fast_particles(const ParticleStore& p, std::vector<std::uint8_t>& fast) override;
  void mark_net_contacts(const ParticleStore& p,
                         std::vector<std::uint8_t>& touching) const override;
  /// The candidates' rates are decided again at the next evaluation that asks (no slots: the
  /// pairs add to the loads directly).
  void change_rates(const ParticleStore& /*p*/, GatherMap& /*gather*/) override {
    rates_current_ = false;
  }

 private:
  /// compute() with what the energy ledger books of the pairs (PairContactChunk::Ledger).
  template <PairContactChunk::Ledger kLedger>
  void compute_pairs(ComputeContext& ctx);
  /// Whether held candidate m has a state to carry through a rebuild: a spring, or a damping
  /// force (a head-on contact has no spring).
  bool carries_state(std::size_t m) const;
  /// Held candidate m's ledger state (zero where the slots keep none).
  ContactLedgerState carried_ledger(std::size_t m) const;
  /// The keyed rows' springs to the new candidates (rebuild()).
  void carry_springs(const ParticleStore& p);

  NeighbourSearch search_;
  PairExclusions exclusions_;
  PairCandidates pairs_;
  /// The springs of pairs_'s touching candidates (physics.md §3).
  SpringSlots spring_;
  /// Keyed rows (gid of end a, partner the gid of end b), only from pack_springs() (or a
  /// restart) to the next rebuild(): empty between rebuilds.
  ContactSpringStore springs_{ContactSpringStore::Partner::kParticle};
  /// Whether the next pack_springs() keys the ledger states with the springs (set by
  /// book_carried_work(): only where the ledger books per contact and did not book them).
  bool rows_carry_ledger_ = true;
  PairContactChunk chunk_;  ///< compute scratch (28 KB)
  /// Multi-rate stepping (ForceRate): per chunk of PairContactChunk::kSize candidates, bit c
  /// set where candidate c has a fast particle at one end, and the chunks with any such bit
  /// (from the last rebuild or rate change; empty while no evaluation has asked for a rate).
  std::vector<std::uint64_t> fast_mask_;
  std::vector<std::uint32_t> fast_chunks_;
  bool rates_current_ = false;  ///< fast_mask_ is of the current candidates
  /// Sets fast_mask_ and fast_chunks_ for the current candidates.
  void classify_rates(const ParticleStore& p);
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <vector>

#include "domain/NeighbourSearch.hpp"
#include "engine/ForceTerm.hpp"

namespace ringdem {

/// Contacts between particles (Hertz–Mindlin, physics.md §3): cell-grid candidate pairs with
/// a Verlet skin, each pair's tangential spring (history keyed by the gid pair), two slots
/// per pair (one for each end) and a dissipation record per slot for the ledger.
class PairContactTerm final : public ForceTerm {
 public:
  std::string_view name() const override { return "particle_contacts"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  void export_history(ContactHistory& out) const override;
  void find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies, double fraction,
                     std::vector<ContactOverlap>& out) const override;

  std::size_t n_candidates() const { return pairs_.size(); }

 private:
  NeighbourSearch search_;
  PairExclusions exclusions_;
  PairCandidates pairs_;
  std::vector<Vec3> spring_;
  std::vector<std::int64_t> gid_a_, gid_b_;  ///< gids of pairs_ (history keys)
  SlotRange slots_a_, slots_b_;
};

}  // namespace ringdem

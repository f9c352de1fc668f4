#pragma once

#include <cstdint>
#include <vector>

#include "domain/NeighbourSearch.hpp"
#include "engine/ForceTerm.hpp"

namespace ringdem {

/// Contacts between particles (Hertz–Mindlin, physics.md §3): cell-grid candidate pairs with
/// a Verlet skin in ascending gid order, each pair's tangential spring (its ContactSpringStore,
/// one row per candidate, keyed by the gid pair). It takes no slots: each pair adds its loads
/// to both ends' ParticleLoads and ContactMoments, in the gather order (ForceSlots.hpp).
class PairContactTerm final : public ForceTerm {
 public:
  std::string_view name() const override { return "particle_contacts"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  ContactSpringStore* springs() override { return &springs_; }
  const ContactSpringStore* springs() const override { return &springs_; }
  void find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies, double fraction,
                     std::vector<ContactOverlap>& out) const override;

  std::size_t n_candidates() const { return pairs_.size(); }

 private:
  NeighbourSearch search_;
  PairExclusions exclusions_;
  PairCandidates pairs_;
  /// Row m: pair m of pairs_ (gid of its end a, partner the gid of its end b).
  ContactSpringStore springs_{ContactSpringStore::Partner::kParticle};
  std::vector<std::uint32_t> carried_order_;  ///< rebuild scratch: the carried rows' key order
};

}  // namespace ringdem

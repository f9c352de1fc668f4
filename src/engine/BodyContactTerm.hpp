#pragma once

#include <cstdint>
#include <vector>

#include "comm/ExactSum.hpp"
#include "engine/BodyContactChunk.hpp"
#include "engine/ForceTerm.hpp"

namespace ringdem {

/// Contacts between particles and rigid bodies (Hertz–Mindlin with R_j, m_j of the body,
/// physics.md §3): candidates within the skin of a body's surface, one slot per contact, the
/// tangential spring in its ContactSpringStore (one row per candidate, keyed by (gid, body)). Also
/// each contact's load on its body, for the rank-independent reduction of the body loads.
class BodyContactTerm final : public ForceTerm {
 public:
  std::string_view name() const override { return "body_contacts"; }
  double ghost_width(const ParticleStore&) const override { return 0.0; }
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  ContactSpringStore* springs() override { return &springs_; }
  const ContactSpringStore* springs() const override { return &springs_; }
  void find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies, double fraction,
                     std::vector<ContactOverlap>& out) const override;

  /// Columns of body_load_sums(), per body.
  enum LoadColumn { kForceX, kForceY, kForceZ, kTorqueX, kTorqueY, kTorqueZ, kLoadColumns };
  /// This rank's exact partial sums (comm/ExactSum) of the contact loads on each rigid body in
  /// the last compute(): body b's column c at kLoadColumns b + c. The force on the body, and
  /// its torque about the body's reference point. Exact, so the simulation's sum over the ranks
  /// does not depend on how the contacts are spread over them.
  const std::vector<ExactSum>& body_load_sums() const { return body_load_sums_; }
  /// The particle–body pairs within reach since the last rebuild (on this rank).
  std::size_t n_candidates() const { return particle_.size(); }
  /// Those of them whose particle is fast (multi-rate stepping: evaluated at every sub-step).
  std::size_t n_fast_candidates() const { return fast_list_.size(); }
  bool has_slow_interactions() const override { return true; }
  /// Each candidate's rate from its particle's again, and its slot's with it.
  void change_rates(const ParticleStore& p, GatherMap& gather) override;

 private:
  /// fast_list_ from fast_.
  void list_fast_candidates();
  std::vector<std::uint32_t> particle_, body_;
  std::vector<std::uint8_t> fast_;        ///< per candidate: its particle is fast (ForceRate)
  std::vector<std::uint32_t> fast_list_;  ///< the candidates with fast_ set
  /// Row w: contact w (gid of particle_[w], partner the body's number).
  ContactSpringStore springs_{ContactSpringStore::Partner::kRigidBody};
  SlotRange slots_;
  std::vector<ExactSum> body_load_sums_;
  BodyContactChunk chunk_;  ///< compute scratch (20 KB)
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <vector>

#include "domain/BondStore.hpp"
#include "engine/BondTerm.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {

/// Bonds of the co-rotational Timoshenko beam law (model "timoshenko", physics.md §1,
/// Eq. 1–5): elastic, brittle. The bond store is the model's (frames and checkpoints read it);
/// this term keeps the bond types' parameters, its slot ranges and the kernel's scratch.
class TimoshenkoBondTerm final : public BondTerm {
 public:
  TimoshenkoBondTerm(BondStore& bonds, std::vector<BondTimoshenko::Params> types);

  std::string_view name() const override { return "timoshenko"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  /// Forces and the failure test of Eq. 3–5. Bonds that fail are marked broken with their
  /// time and the elastic energy they held (break_energy: the mean of the energy at the end of
  /// the step and at its start, x - v dt with the mid-step velocities; dt = 0 takes the end).
  void compute(ComputeContext& ctx) override;
  bool topology_changed() const override { return broke_; }

  /// Recomputes the output columns (axial force, largest bending moment, utilisation, energy)
  /// for the current configuration; returns the summed energy.
  double update_diagnostics(const ParticleStore& p) const override;

  /// Creates bond `id` between two ends (either order; the store keeps the lower gid first):
  /// section from the type's parameters and the end radii, reference frames from the ends'
  /// orientations, strengths drawn by (seed, gid pair). Returns the bond's index in the store.
  static std::size_t create(BondStore& bonds, const BondTimoshenko::Params& params,
                            std::int32_t type, std::int64_t id, const BondEnd& a, const BondEnd& b,
                            std::uint64_t seed);
  /// Stores a section, reference and strengths in bond k's columns.
  static void store(BondStore& bonds, std::size_t k, const BondTimoshenko::Section& s,
                    const BondTimoshenko::Reference& ref, const BondTimoshenko::Strength& st);
  /// The kernel's view of bond k's columns.
  static BondTimoshenko::Section section(const BondStore& bonds, std::size_t k);
  static BondTimoshenko::Reference reference(const BondStore& bonds, std::size_t k) {
    return {bonds.frame_a[k], bonds.frame_b[k]};
  }
  static BondTimoshenko::Strength strength(const BondStore& bonds, std::size_t k) {
    return {bonds.tensile_strength[k], bonds.compressive_strength[k], bonds.shear_strength[k]};
  }

  // Shared with the other beam laws over the same store (TimoshenkoPlasticBondTerm).
  /// Ghost width of a store of beam bonds: 1.25 times the longest bond.
  static double bond_reach(const BondStore& bonds);
  /// rebuild() of a store of beam bonds: resolves both ends' indices (throws if an intact
  /// bond lacks one), excludes intact pairs from contact, takes one slot range per end and
  /// registers the intact bonds' slots with the gather map.
  static void register_bonds(BondStore& bonds, RebuildContext& ctx, SlotRange& slots_a,
                             SlotRange& slots_b);
  /// The orientation a particle had one step earlier (for the energy a breaking bond held at
  /// the start of its last step): the inverse of the integrator's Cayley update.
  static Quat rotated_back(const Quat& q, const Vec3& omega, double dt);

 private:
  void book_failures(const ParticleStore& p, double time, double dt);

  std::vector<BondTimoshenko::Params> types_;
  SlotRange slots_a_, slots_b_;
  std::vector<std::uint8_t> failed_;  ///< scratch: bonds that failed in this step
  bool broke_ = false;
  /// Scratch of the bond loop: end positions and orientations of one chunk, by component.
  static constexpr std::size_t kChunk = 256;
  struct Scratch {
    double xa[3][kChunk], xb[3][kChunk], qa[4][kChunk], qb[4][kChunk];
  };
  Scratch scratch_;
};

}  // namespace ringdem

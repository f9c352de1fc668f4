#pragma once

#include <cstdint>
#include <vector>

#include "domain/BondStore.hpp"
#include "engine/BondTerm.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"

namespace ringdem {

/// Bonds of the elastoplastic wire-bundle beam (model "timoshenko_plastic", docs/physics.md
/// "Plastic bond"): the co-rotational Timoshenko beam of TimoshenkoBondTerm with plastic
/// elongation and end hinges, linear hardening and plastic work. The bond store holds the
/// beam's common columns plus one model column per BondTimoshenkoPlastic::State member
/// (state_columns()), which migrate and are checkpointed with the bond; the hinges live in the
/// beam's reference frames (frame_a, frame_b), which this term re-bases where an end turns
/// plastically. It keeps the bond types' parameters and its slot ranges.
///
/// A bond fails by Eq. 3–5 on its returned resultants or when its plastic strain reaches the
/// limit, whichever comes first (BondFailure::kPlasticStrain for the latter). A broken bond
/// keeps its plastic state, its plastic work included (the ledger still counts it).
class TimoshenkoPlasticBondTerm final : public BondTerm {
 public:
  using State = BondTimoshenkoPlastic::State;

  /// `plastic`: the plastic limits of each bond type (the beam's own parameters are in the
  /// store's columns). Throws std::invalid_argument if the store lacks the state columns;
  /// rebuild() throws if a bond's type has no entry.
  TimoshenkoPlasticBondTerm(BondStore& bonds, std::vector<BondTimoshenkoPlastic::Params> plastic);

  /// The model columns of the law, in State index order: plastic elongation, strain and work
  /// migrate and are checkpointed; plastic_strain and plastic_work are also written to frames.
  static std::vector<BondStore::ModelColumn> state_columns();

  std::string_view name() const override { return "timoshenko_plastic"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  /// One step of every intact bond (BondTimoshenkoPlastic::compute: elastic predictor, return
  /// mapping, state updated in the store) and the failure test. A bond that fails in this
  /// step exerts no force from it on and is marked broken with its time, the elastic energy it
  /// held (break_energy, the mean of the energy at the start and at the end of the step, as
  /// the elastic term) and, since its force acted through half the step, half of the step's
  /// plastic work.
  void compute(ComputeContext& ctx) override;
  bool topology_changed() const override { return broke_; }

  /// Output columns from BondTimoshenkoPlastic::evaluate (no state change): axial force,
  /// largest bending moment, utilisation (the larger of Eq. 3–5's ratio and plastic strain
  /// over its limit) and elastic energy; returns the summed elastic energy.
  double update_diagnostics(const ParticleStore& p) const override;
  const std::vector<double>* plastic_work() const override;

  /// Bond k's plastic state from the store's model columns, and back.
  State state(std::size_t k) const;
  void store_state(std::size_t k, const State& st);

 private:
  void book_failures(const ParticleStore& p, double time, double dt);
  const BondTimoshenkoPlastic::Params& params(std::size_t k) const {
    return plastic_[static_cast<std::size_t>(bonds_.type[k])];
  }

  std::vector<BondTimoshenkoPlastic::Params> plastic_;
  SlotRange slots_a_, slots_b_;
  // 64-bit flags: a byte column in the vector loop would size its vectors by bytes (BeamChunk).
  std::vector<std::int64_t> failed_;    ///< scratch: bonds that failed in this step
  std::vector<std::int64_t> yielding_;  ///< scratch: bonds beyond yield at the predictor
  bool broke_ = false;
  /// Scratch of the vector pass: the chunk's ends, and its bonds' plastic limits (by type).
  BeamChunk scratch_;
  struct ChunkLimits {  // by component: an array of Params does not vectorise
    double axial_yield[BeamChunk::kSize], plastic_moment[BeamChunk::kSize],
        hardening[BeamChunk::kSize], failure_strain[BeamChunk::kSize];
    void load(std::size_t c, const BondTimoshenkoPlastic::Params& p) {
      axial_yield[c] = p.axial_yield;
      plastic_moment[c] = p.plastic_moment;
      hardening[c] = p.hardening;
      failure_strain[c] = p.failure_strain;
    }
    BondTimoshenkoPlastic::Params operator[](std::size_t c) const {
      BondTimoshenkoPlastic::Params p;
      p.axial_yield = axial_yield[c];
      p.plastic_moment = plastic_moment[c];
      p.hardening = hardening[c];
      p.failure_strain = failure_strain[c];
      return p;
    }
  };
  ChunkLimits limits_;
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "domain/ParticleStore.hpp"
#include "engine/ForceTerm.hpp"
#include "engine/GatherMap.hpp"
#include "engine/Model.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {

/// Multi-rate stepping's movers (docs/physics.md "Two time scales"): which owned particles the
/// sub-steps drift and kick. A particle that no fast interaction can load in a grain step (a
/// grain far from the net) keeps its velocity through the sub-steps, so its r drifts are
/// x += v h, r times; they are done together when its position is next read (catch_up()),
/// not in r passes over the whole store. The same operations on every particle, so the same
/// bits as moving them all at every sub-step; only the sub-steps' cost falls, to that of the
/// net and the grains around it.
///
/// A mover is a particle that a fast interaction may load or read until the next rebuild: a
/// fast particle (is_fast_particle()), one with fast slots (GatherMap), one a term marks
/// (ForceTerm::mark_fast_particles(): the fast candidate pairs' ends), one with a point load,
/// and one whose fast load of the last evaluation is not zero (the first sub-step's half kick
/// applies it). The interactions that read a particle also load it, and its owner computes
/// every interaction that loads it: so a particle that is not a mover on its owner is read by
/// none on any rank, and its ghosts may lag with it.
class SubstepParticles {
 public:
  /// Every owned particle a mover (tests compare that path with this one).
  void set_move_all(bool all) { move_all_ = all; }
  /// Whether classify() ran since the last rebuild (invalidate()).
  bool current() const { return current_; }
  void invalidate() { current_ = false; }

  /// The movers from the state of the last rebuild and evaluation (see the class), their
  /// runs, the others' runs and squared speeds; no drifts pending. Call when no drift is
  /// pending (after catch_up()) and after the slow kick of the grain step: the others'
  /// velocities stay as they are until its end.
  void classify(const ParticleStore& p, const GatherMap& gather,
                const std::vector<std::unique_ptr<ForceTerm>>& terms,
                const std::vector<PointLoad>& point_loads);
  /// The others' squared speeds from their velocities now: at each grain step, after its slow
  /// kick (classify() does it at a classification).
  void measure_others(const ParticleStore& p) {
    others_speeds_ = Integrator::squared_speeds(p, others_);
  }
  /// The runs the sub-steps' drift and kicks visit, and the others' squared speeds for the
  /// drift's maxima (Integrator::first_half()).
  const std::vector<Integrator::Run>& mover_runs() const { return movers_; }
  const Integrator::SquaredSpeeds& others_speeds() const { return others_speeds_; }
  /// A sub-step's drift of the movers is done: the others owe one more.
  void note_drift() { ++pending_; }
  /// Moves the others by the drifts they owe (sub-step `h`): before anything reads every
  /// position (the ghosts sent at a grain step's end, the rebuild test's outflow scan, a
  /// rebuild).
  void catch_up(ParticleStore& p, double h);
  /// Owned particles that are movers (from the last classify()).
  std::size_t n_movers() const { return n_movers_; }
  /// Per owned particle, 1 where a fast interaction may load or read it (the class), from the
  /// last classify(): their ghosts are the ones the sub-steps refresh.
  const std::vector<std::uint8_t>& read_by_fast() const { return flag_; }

 private:
  bool move_all_ = false;
  bool current_ = false;
  int pending_ = 0;
  std::size_t n_movers_ = 0;
  std::vector<std::uint8_t> flag_;  ///< read_by_fast()
  std::vector<Integrator::Run> movers_, others_;
  Integrator::SquaredSpeeds others_speeds_;
};

}  // namespace ringdem

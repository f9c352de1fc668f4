#pragma once

#include <cstdint>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/ExactSum.hpp"
#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "engine/Model.hpp"

namespace ringdem {

/// The terms of the momentum balance at one time, summed over the ranks
/// (Simulation::momentum_balance): impulses in N s, momenta in kg m/s.
struct MomentumBalance {
  Vec3 momentum;  ///< of the free particles now
  Vec3 initial;   ///< of the free particles at the start of the run
  Vec3 outflow;   ///< carried out through outflow boxes
  Vec3 inflow;    ///< brought in by inlets
  Vec3 gravity, point_loads, held, exchange;
  std::vector<Vec3> bodies;  ///< on the particles by each rigid body: -int F_b dt

  Vec3 impulse() const {
    Vec3 sum = gravity + point_loads + held + exchange;
    for (const Vec3& b : bodies)
      sum += b;
    return sum;
  }
  /// p - p(0) + p_out - p_in - impulse: zero up to round-off when every load is booked.
  Vec3 residual() const { return momentum - initial + outflow - inflow - impulse(); }
};

/// The momentum balance of the free particles (docs/physics.md "Momentum balance"), booked
/// from the loads the code reports, not from the particles' own sums:
///
///   p(t) - p(0) + p_out - p_in = I_gravity + I_point + I_held + I_exchange + sum_b I_b
///
/// - I_b = -int F_b dt: body b's contact force F_b (the reduced load that series.csv reports)
///   acts on the particles with the opposite sign;
/// - I_held = -int sum_held (F_k - m_k g - P_k) dt: the loads that fixed and driven particles
///   (a net's frame and shackles) receive from everything but gravity and point loads. Their
///   contacts and bonds with free particles are the only part that does not cancel, since the
///   bodies' loads on them are in F_b and their loads on each other cancel in pairs;
/// - I_gravity = int M_free g dt, I_point = int sum_free P_k dt;
/// - I_exchange: grains an outflow box takes out miss the first half kick of the loads they
///   had, and inflow grains get theirs: both change what the next half kick applies.
///
/// Every impulse is booked as velocity Verlet applies it, half a step at each half kick (the
/// loads of an evaluation kick at the end of its step and at the start of the next), so the
/// balance closes to round-off, not to O(dt). Interactions between free particles cancel in
/// pairs (each applies f and -f), so a residual well above round-off means a reported load
/// differs from the load applied. Cundall global damping of free particles is a load that is
/// not booked: its impulse shows in the residual.
///
/// Each rank sums its own terms exactly (comm/ExactSum); replicated terms (bodies, gravity) are
/// booked on the root alone. Totals are the same bits on any rank count.
class MomentumLedger {
 public:
  /// The booked columns, three components each (x, y, z), then one per rigid body.
  enum Source { kInitial, kGravity, kPointLoads, kHeld, kExchange, kFixedSources };

  /// `enabled`: false books nothing and costs nothing per step (scenarios that do not report
  /// the balance); its state is then zero.
  explicit MomentumLedger(std::size_t n_bodies = 0, bool enabled = true);
  bool enabled() const { return enabled_; }

  /// The momentum of the free particles at the start of the run (owned ones).
  void book_initial_momentum(const ParticleStore& p);
  /// Owned particles that are not free (fixed, driven): the held loads are theirs. Call after
  /// each rebuild (indices change) with the global mass of the free particles.
  void rebuild(const ParticleStore& p, double free_mass);
  /// The external loads of one force evaluation (bodies reduced, before global damping),
  /// weighted by dt/2: kept for the next first half kick, and booked now for this step's second
  /// half kick unless `initial` (the evaluation of the initial state kicks only forward).
  /// `body_contact_loads`: each rigid body's reduced contact load (without the loads of brakes
  /// and ropes, which act on the body, not on the particles).
  /// `loads`: the particles' loads of the evaluation (default: their force; multi-rate
  /// stepping books its slow evaluations from ParticleStore::slow_force).
  void book_evaluation(const ParticleStore& p, const std::vector<Vec3>& body_contact_loads,
                       const std::vector<PointLoad>& point_loads, const Vec3& gravity,
                       double half_dt, bool root, bool initial,
                       const std::vector<Vec3>* loads = nullptr);
  /// Owned particle k leaves the model before the next first half kick: its load (of `loads`,
  /// default its force) will not kick.
  void book_leaving(const ParticleStore& p, std::size_t k, double half_dt,
                    const std::vector<Vec3>* loads = nullptr);
  /// Owned particles [first, last) came in with their loads before the next first half kick.
  void book_arrivals(const ParticleStore& p, std::size_t first, std::size_t last, double half_dt);
  /// The first half kick of a step: the loads of the last evaluation kick again.
  void book_first_half();

  std::size_t n_sources() const { return kFixedSources + n_bodies_; }
  /// The totals over the ranks and the free particles' momentum now (owned ones of `p`); the
  /// outflow and inflow terms are left to the caller, who holds those sums. Collective.
  MomentumBalance balance(const ParticleStore& p, const Communicator& comm) const;

  /// Totals and pending half kick over the ranks as ExactSum words. Collective.
  std::vector<std::int64_t> export_state(const Communicator& comm) const;
  /// From a checkpoint: the root takes the totals, the other ranks start from zero (empty
  /// `words`: a model without a momentum record, which starts from zero).
  void import_state(const std::vector<std::int64_t>& words, bool root);

 private:
  void add(std::vector<ExactSum>& columns, std::size_t source, const Vec3& v) {
    columns[3 * source].add(v.x);
    columns[3 * source + 1].add(v.y);
    columns[3 * source + 2].add(v.z);
  }

  std::size_t n_bodies_ = 0;
  bool enabled_ = true;
  std::vector<ExactSum> totals_;   ///< 3 per source
  std::vector<ExactSum> pending_;  ///< 3 per source: the next first half kick
  std::vector<std::uint32_t> held_;
  double free_mass_ = 0.0;
};

}  // namespace ringdem

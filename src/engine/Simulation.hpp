#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/DomainDecomposition.hpp"
#include "comm/ExactSumReducer.hpp"
#include "domain/SpatialBins.hpp"
#include "engine/BodyContactTerm.hpp"
#include "engine/BondTerm.hpp"
#include "engine/EnergyGuard.hpp"
#include "engine/EnergyLedger.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/GatherMap.hpp"
#include "engine/InflowSource.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/MomentumLedger.hpp"
#include "engine/MoveBounds.hpp"
#include "engine/OutflowSink.hpp"
#include "engine/RestartState.hpp"
#include "engine/SubstepParticles.hpp"
#include "io/CaseConfig.hpp"
#include "physics/Integrator.hpp"
#include "physics/TimeStep.hpp"

namespace ringdem {

struct SimulationSettings {
  double dt = 0.0;  ///< <= 0: automatic, dt_safety times the smallest stability limit
  double dt_safety = 0.3;
  double skin = 0.001;
  Vec3 gravity{0, 0, -9.81};
  double imbalance_threshold = 0.1;  ///< repartition when max/mean particles - 1 exceeds it
  /// Book the momentum balance (engine/MomentumLedger): free runs report it; off, it costs
  /// nothing per step (about 3 % of the rockfall demo's step on).
  bool momentum_ledger = true;
  /// Book the energy ledger (engine/EnergyLedger, docs/physics.md "Energy ledger"). Off, the
  /// contact terms keep no per-particle sums of their dissipative loads and nothing is booked
  /// after the kicks; the dissipation, boundary work and contact elastic energy then stay at
  /// 0 and the energy guard is off (the per-step runaway guard stays). The trajectory is the
  /// same bits either way.
  bool energy_ledger = true;
  /// Steps between re-sorts of the grains by space (SpatialBins; docs/architecture.md "Order of
  /// the particles"): at every step number that is a multiple, the lists are rebuilt with each
  /// grain in the bin of its position. 0: never (every particle stays in gid order).
  std::int64_t sort_every = 1000;
  /// Multi-rate stepping (docs/physics.md "Two time scales"): the fast interactions (bonds and
  /// every interaction with a net particle, ForceRate) step dt / substeps within each step of
  /// dt, which the slow ones (gravity, grain–grain and grain–body contacts) take as impulses at
  /// its ends (impulse r-RESPA). 1: one rate.
  std::int64_t substeps = 1;
  /// How the energy ledger books particle pairs (EnergyLedger::PairBooking): per contact where
  /// true, per particle where false; unset, per contact where it can (one rate, no rolling
  /// friction). Not a case-file key: the tests compare the two.
  std::optional<bool> pair_ledger_per_contact;
};

/// The settings a case file asks for.
SimulationSettings settings_from_case(const CaseConfig& config);

/// Global energies (exact sums over the ranks, comm/ExactSum: the same bits on any rank count).
struct Energies {
  double kinetic = 0.0;    ///< particles (translation + rotation) and free rigid bodies
  double potential = 0.0;  ///< -m g.x of free particles and free bodies
  double bond_elastic = 0.0;
  double contact_elastic = 0.0;
  // Energy ledger (docs/physics.md "Energy ledger"): totals since the start of the run, each
  // the trapezoidal time integral of a load's power at the synchronised velocities.
  double contact_damping = 0.0;  ///< dissipated by viscous contact damping (Eq. 7, 9)
  /// dissipated by Coulomb slip and rolling friction, and by support ropes sliding through the
  /// shackles
  double friction = 0.0;
  double global_damping = 0.0;  ///< dissipated by Cundall global damping
  double broken_bonds = 0.0;    ///< elastic energy the bonds held when they broke
  double plastic_work = 0.0;    ///< dissipated by plastic flow of the bonds (broken ones too)
  double brake_work = 0.0;      ///< dissipated by the brakes (of shackles and of ropes) sliding
  double brake_elastic = 0.0;   ///< held by the brake elements' springs and the support ropes
  /// Work done on the particles by driven (prescribed) rigid bodies and particles and by
  /// external forces: energy put in, so it enters the balance with a minus sign.
  double boundary_work = 0.0;
  /// Energy that grains carried out through outflow boxes (kinetic, potential, contact
  /// elastic share at the moment they left); their dissipation stays in the columns above.
  double outflow = 0.0;
  /// Energy that inlets brought in with their grains (kinetic and potential).
  double inflow = 0.0;

  /// Mechanical energy: kinetic + potential + bond, contact and brake elastic.
  double total() const {
    return kinetic + potential + bond_elastic + contact_elastic + brake_elastic;
  }
  double dissipated() const {
    return contact_damping + friction + global_damping + broken_bonds + plastic_work + brake_work;
  }
  /// Mechanical + dissipated - boundary work + carried out - brought in: constant in time, up to
  /// the integrator's O(dt^2) energy error.
  double ledger() const { return total() + dissipated() - boundary_work + outflow - inflow; }
  /// How far the ledger moved since `initial` (energies() at the start): 0 when it closes.
  double balance_error(const Energies& initial) const { return ledger() - initial.ledger(); }
};

/// Contacts of a state that overlap by more than a tolerance (Simulation::overlaps): the count
/// over all ranks and the deepest, the same on every rank.
struct OverlapReport {
  struct Entry {
    double relative_depth;  ///< depth / the smaller radius (a body's radius counts as infinite)
    double depth;           ///< m
    std::int64_t gid;       ///< the particle (the lower gid of a pair)
    std::int64_t partner;   ///< the other particle's gid, or the rigid body's number
    std::int32_t partner_is_body;
    std::int32_t group, partner_group;  ///< particle groups (-1 for a body)
    double radius, partner_radius;      ///< 0 for a plane
    Vec3 position, partner_position;    ///< centres (a body's reference point)
  };
  std::int64_t count = 0;
  std::vector<Entry> deepest;  ///< deepest first, ties by gids
};

/// The time-step loop of DESIGN §3 over one Model.
class Simulation {
 public:
  Simulation(Model model, const Communicator& comm, const SimulationSettings& settings);
  /// Continues from a checkpoint: `model` holds the checkpointed fields (forces and torques
  /// included, so the loads of the last step are not recomputed: the run goes on bit for bit).
  /// Its springs are moved into the contact terms, not copied.
  Simulation(Model model, const Communicator& comm, const SimulationSettings& settings,
             RestartState restart);

  /// Each contact term's tangential springs of touching contacts whose particle (the first
  /// of a pair) is owned here: each contact once over the ranks, held whole (tests).
  std::vector<RestartState::TermSprings> owned_springs() const;
  /// Everything a checkpoint needs besides the model's fields: time, step, dt, rebuilds, the
  /// owned springs and what the rebuild criterion reads. Collective (whether a bond broke
  /// anywhere in the last force evaluation). The springs come in parts that the checkpoint
  /// builds as it writes them (RestartState::TermSprings::part): valid while this Simulation
  /// lives and takes no step.
  RestartState restart_state() const;

  /// From now on steps of `dt` (a restart that applies a changed time step). The energy
  /// ledger's trapezoid weights are carried over, so its tallies go on without a jump.
  void change_time_step(double dt);
  /// The time step the case asks for: simulation.dt, or dt_safety times the smallest
  /// stability limit when it is left out. A scenario may step otherwise for a while.
  /// With multi-rate stepping (settings().substeps > 1) this is the grain step, substeps
  /// times that (the step of the fast interactions).
  double case_time_step() const {
    return static_cast<double>(settings_.substeps) *
           (settings_.dt > 0.0 ? settings_.dt : settings_.dt_safety * limits_.min());
  }
  /// The step at which the time reaches `end_time` (within 1e-9 of a step), counted from the
  /// step the current dt began at (0, or the restart that changed it).
  std::int64_t steps_until(double end_time) const;
  /// Steps (at least 1) that can be run in one batch without passing an event due once
  /// time() + tolerance >= `event_time`: the event is due at the batch's last step at the
  /// earliest. For loops that check their schedules only between batches.
  std::int64_t steps_short_of(double event_time, double tolerance) const;

  /// Contact candidates of the current neighbour lists (particle pairs and particle–rigid-body
  /// contacts) that overlap by more than `fraction` of the smaller radius, of which at least one
  /// side is free (two fixed or driven sides never respond to their contact). Each contact is
  /// counted once over the ranks; the `listed` deepest are listed. Collective; the same report
  /// on every rank and rank count.
  OverlapReport overlaps(double fraction, std::size_t listed = 5) const;

  /// Advances one step of dt.
  void step();
  /// Called once per step with the rigid bodies at the end of that step (their loads, positions
  /// and velocities) and the time at its end. Only the bodies are complete there: in a batch
  /// the particles are already on their way into the next step.
  using BodyObserver = std::function<void(const std::vector<RigidBody>& bodies, double time)>;
  /// Advances n steps, or fewer when a stop is agreed (stop_agreed()), calling `before_each`
  /// (if given) before each and `observe_bodies` (if given) at the end of each. The same bits
  /// as n calls of step(), faster: between two steps of the batch the particles are kicked,
  /// booked and drifted in one pass.
  void run_steps(std::int64_t n, const std::function<void()>& before_each = {},
                 const BodyObserver& observe_bodies = {});

  double time() const { return time_; }
  double dt() const { return dt_; }
  std::int64_t steps() const { return steps_; }
  std::int64_t rebuilds() const { return rebuilds_; }
  /// Multi-rate stepping: the rate changes without a rebuild (change_rates()) since set-up.
  std::int64_t rate_changes() const { return rate_changes_; }
  const StabilityLimits& limits() const { return limits_; }
  /// The fast interactions' step: dt() / settings().substeps (dt() with one rate).
  double substep() const { return dt_ / static_cast<double>(settings_.substeps); }
  /// The smallest Rayleigh limit of the particles that take the grain step (multi-rate
  /// stepping: those that are not fast, is_fast_particle()), over the ranks; infinite where
  /// there are none.
  double grain_rayleigh_limit() const { return grain_rayleigh_limit_; }
  const SimulationSettings& settings() const { return settings_; }
  Model& model() { return model_; }
  const Model& model() const { return model_; }
  /// Multi-rate stepping: whether the sub-steps move every owned particle (tests) or only
  /// those that fast interactions can load (SubstepParticles, the default); the same bits.
  void set_substeps_move_all(bool all) {
    movers_.set_move_all(all);
    movers_.invalidate();
  }
  /// Multi-rate stepping: whether a changed net contact rebuilds the lists (tests compare that
  /// path with change_rates(), the default); the same bits.
  void set_rebuild_on_rate_change(bool rebuild) { rebuild_on_rate_change_ = rebuild; }
  /// Owned particles the sub-steps move (multi-rate stepping; this rank, at the last grain
  /// step's classification).
  std::size_t n_substep_movers() const { return movers_.n_movers(); }
  /// The energy ledger's bookkeeping (tests set its choices; energies() reports it).
  EnergyLedger& energy_ledger() { return ledger_; }
  /// The ledger of the fast interactions (multi-rate stepping); off in a single-rate run.
  const EnergyLedger& fast_energy_ledger() const { return fast_ledger_; }
  /// Contact candidates of the particle-pair term at the last rebuild (this rank).
  std::size_t n_contact_candidates() const;
  /// Particle–rigid-body contact candidates at the last rebuild (this rank).
  std::size_t n_body_contact_candidates() const {
    return body_term_ != nullptr ? body_term_->n_candidates() : 0;
  }
  /// Those of them evaluated at the fast rate (multi-rate stepping).
  std::size_t n_fast_body_contact_candidates() const {
    return body_term_ != nullptr ? body_term_->n_fast_candidates() : 0;
  }
  const Communicator& comm() const { return comm_; }
  const DomainDecomposition& decomposition() const { return decomposition_; }
  /// The ranks' imbalance in the weights the partition balances (particles, and bonds weighed
  /// as they cost: DomainDecomposition::weighted_imbalance). Collective.
  double partition_imbalance() const {
    return decomposition_.weighted_imbalance(model_.particles, pair_stores());
  }

  /// True on every rank when a bond broke on any rank in the force evaluation of the
  /// previous step (known from the step's one reduction, so it costs no communication).
  bool bonds_broke_anywhere() const { return bonds_broke_anywhere_; }

  /// Moves rigid body `index` (every rank calls it alike: bodies are replicated) and sets its
  /// motion; the neighbour lists are rebuilt at the next step. The energy it adds is outside
  /// the ledger: the energy guard takes a new reference at the next energies().
  void place_body(std::size_t index, const Vec3& position, const Vec3& velocity, Motion motion);
  /// Holds the bodies of brakes and ropes (fixed, at rest) or sets them free
  /// (hold_restrained_bodies(), every rank alike); like place_body(), what that moves in the
  /// ledger is the caller's to book.
  void hold_restrained_bodies(bool held);
  /// Sets the Cundall coefficient of every particle of a group (physics.md §4).
  void set_group_damping(int group, double coefficient);

  /// A stop request of this rank (signal, wall-time limit): a reason code, 0 for none, that
  /// means nothing to the simulation. It rides on the step's one reduction, so after the next
  /// step every rank knows, at the same step, whether any rank asked (stop_agreed()) and the
  /// largest code asked for (stop_reason()).
  void request_stop(int reason) { stop_local_ = reason; }
  bool stop_agreed() const { return stop_agreed_ > 0; }
  int stop_reason() const { return stop_agreed_; }

  /// The divergence guard's limits: a particle may move at most max_step_fraction of the
  /// skin and turn at most max_turn radians in one step; beyond that (or with a non-finite
  /// state) step() throws DivergenceError on every rank.
  static constexpr double kMaxStepFraction = 1.0;
  static constexpr double kMaxTurn = 0.5;

  /// Grains that crossed the model's boundary so far: count, mass, momentum.
  struct GrainFlux {
    std::int64_t grains = 0;
    double mass = 0.0;
    Vec3 momentum;
  };
  /// What left through the outflow boxes. Collective.
  GrainFlux outflow_totals() const;
  /// What the inlets brought in. Collective.
  GrainFlux inflow_totals() const;
  /// The momentum balance of the free particles since the start of the run (engine/
  /// MomentumLedger, docs/physics.md "Momentum balance"). Collective.
  MomentumBalance momentum_balance() const;

  std::int64_t global_particles() const;
  std::int64_t global_bonds() const;
  std::int64_t global_broken_bonds() const;
  /// Recomputes the bond output fields (axial force, moment, utilisation, energy) for the
  /// current configuration (frames read them).
  void refresh_bond_diagnostics();
  /// Refreshes the bond diagnostics (forces, utilisation, energy) and sums the energies.
  /// Collective. Throws DivergenceError on every rank when the ledger has grown beyond what
  /// the run had (engine/EnergyGuard).
  Energies energies();

  /// Seconds spent per phase since the start (this rank).
  /// Where the loop's time goes. kComm is the per-step traffic (ghost refresh, the one
  /// reduction, grains in and out) and the waiting in it for slower ranks; kNeighbour is the
  /// rebuild (migration, ghost lists, pair lists).
  enum Phase { kIntegrate, kComm, kNeighbour, kBonds, kContacts, kGather, kPhaseCount };
  static const char* phase_name(int phase);
  const std::array<double, kPhaseCount>& phase_seconds() const { return phase_seconds_; }

 private:
  /// Particle index and the stability limits (global minima).
  void init_limits();
  /// A neighbour-list rebuild of the trajectory: lists from the current positions, which
  /// become the reference of the skin criterion.
  /// `sort` with a width > 0: a re-sort, each grain binned in its order first.
  /// `mid_step`: the drift is done (the velocities are the step's middle ones), so that the
  /// contacts' carried loads can be booked first (ForceTerm::book_carried_work()).
  void rebuild(const SpatialBins::Order& sort = {}, bool mid_step = false);
  /// Migration, lists, slots and gather map from the current positions and the terms'
  /// spring stores; `sort` and `mid_step` as rebuild()'s.
  void build_lists(const SpatialBins::Order& sort = {}, bool mid_step = false);
  /// Flags the owned particles that are ends of intact bonds (after the terms' rebuild).
  void flag_turning_particles();
  /// Which particles the drift turns: none without orientations, else the flagged ones.
  Integrator::Turning turning() const;
  /// The bins of a re-sort (collective, one reduction): twice the smallest radius of the grains
  /// it bins wide, numbered slowest along the axis they reach farthest along
  /// (SpatialBins::slowest_axis), all over the ranks; a width of 0 where there is nothing to
  /// bin.
  SpatialBins::Order sort_order();
  /// sort_order() where a re-sort is due at this step's evaluation, else a width of 0: at every
  /// positive multiple of sort_every, the same step numbers on every rank and after a restart. Step
  /// 0's comes at set-up, before the initial evaluation (see the constructor).
  SpatialBins::Order sort_order_due();
  /// Every term's pair store (bonds, contact springs), in term order: what migration moves.
  std::vector<PairStore> pair_stores() const;
  /// One force evaluation of the interactions of `rate`, over a step of `dt`. `loads_started`:
  /// the drift pass already set F = m g, T = 0 (Integrator::first_half); otherwise this does.
  /// A slow evaluation (multi-rate stepping) writes the particles' slow loads (slow_force,
  /// slow_torque, with gravity), a fast one their loads without gravity.
  void compute_forces(bool loads_started = false, ForceRate rate = ForceRate::kAll,
                      double dt = 0.0);
  /// Multi-rate stepping (settings().substeps > 1, SimulationSubsteps.cpp): checks that the
  /// model is one it can step and sets the rates up (constructors).
  void set_up_substeps();
  /// grain_rayleigh_limit() of the particles now (collective).
  double slow_particles_rayleigh_limit() const;
  /// The initial evaluation of both rates (a fresh start).
  void compute_initial_substep_forces();
  /// One step of dt_: the slow half kick, substeps fast velocity-Verlet steps, the slow
  /// evaluation and its half kick.
  void substepped_step(const BodyObserver& observe_bodies);
  /// movers_ from the current lists and loads.
  void classify_movers();
  /// Multi-rate stepping, at the end of every kNetContactStride-th grain step: sets each owned
  /// grain's net_contact to whether the net touched it in the last evaluation (ForceTerm::
  /// mark_net_contacts()); where that changed on some rank, the next step starts with
  /// change_rates() (or a rebuild, where grains come or go then), which sends the flags to the
  /// ghosts and decides the rates from them.
  void note_net_contacts();
  /// The rates of the interactions from the grains' net_contact flags, with the candidates of
  /// the last rebuild: the flags to the ghosts, each term's rates and the gather map's, the
  /// ledgers' records and the movers. Collective.
  void change_rates();
  /// Takes the grains out and in that are due at the start of a step, and rebuilds if that
  /// changed the particles (start_step()); else changes the rates if a net contact changed.
  void exchange_grains_and_rebuild();
  void reduce_body_loads(ForceRate rate);
  /// Books the loads of the evaluation just done in the momentum ledger (after the bodies'
  /// loads are reduced, before global damping changes the particles' loads).
  void book_momentum(bool initial, ForceRate rate = ForceRate::kAll);
  bool needs_rebuild();
  /// Names the particle (or body) that ran away and the likely cause; throws
  /// DivergenceError on every rank. Collective. `energy_excess`: the energy guard fired (its
  /// description); the fastest particle is named then.
  [[noreturn]] void report_divergence(const std::string& energy_excess = {}) const;
  /// The force terms of the model's bond and contact models (engine/ModelTable).
  static std::vector<std::unique_ptr<ForceTerm>> make_terms(Model& m);
  /// Takes out the grains that left an outflow box and puts in the inlets' due batches, at
  /// the start of a step. Returns whether either changed the particles on some rank (the
  /// same answer on every rank): then the lists must be rebuilt. Collective.
  bool exchange_grains();
  /// The parts of step(): grains in and out and the first half kick and drift; ghosts,
  /// neighbour lists and loads; the second half kick and the energy ledger.
  void start_step();
  /// Returns whether the step can be finished together with the start of the next
  /// (finish_step_and_start_next()): `batch_continues`, and nothing the next step's start must
  /// do first. A step that cannot ends with finish_step(), which books the held energies: its
  /// evaluation books them (evaluation_booking_).
  bool evaluate_step(bool batch_continues = false);
  void finish_step(const BodyObserver& observe_bodies = {});
  /// Whether the next step's start_step() does no more than its drift (no grains in or out).
  bool can_fuse_with_next_step() const;
  /// finish_step() then start_step() in one pass over the particles (Integrator::
  /// second_then_first_half), when can_fuse_with_next_step().
  void finish_step_and_start_next(const BodyObserver& observe_bodies);
  /// Sets bond_term_ and body_term_, the terms the simulation asks more of than compute().
  void find_typed_terms();
  /// Block width of the decomposition: the widest term's partner distance plus the skin (the
  /// same on every rank).
  double block_size() const;
  /// The terms' far-coupled particles (ForceTerm::far_ghosts) to the decomposition.
  void add_far_ghosts();

  Model model_;
  const Communicator& comm_;
  SimulationSettings settings_;
  /// The force terms in gather order: bonds, particle pairs, particle–rigid-body contacts
  /// (declared before the decomposition, whose block width they set).
  std::vector<std::unique_ptr<ForceTerm>> terms_;
  DomainDecomposition decomposition_;
  BondTerm* bond_term_ = nullptr;
  BodyContactTerm* body_term_ = nullptr;
  SlotAllocator allocator_;
  ForceSlots slots_;
  GatherMap gather_;
  EnergyLedger ledger_;
  /// What the next force evaluation books in the ledger besides the contacts' work
  /// (EnergyLedger::begin_step()): the initial one's start, the held energies unless the step
  /// is finished together with the next, the grains about to leave.
  EnergyLedger::EvaluationBooking evaluation_booking_;
  std::vector<ExcludedPair> excluded_;  ///< rebuild scratch
  StabilityLimits limits_{};
  double grain_rayleigh_limit_ = 0.0;  ///< grain_rayleigh_limit()
  double dt_ = 0.0;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  /// Grains outside an outflow box are looked for at the steps that are multiples of this
  /// (needs_rebuild): each removal rebuilds the lists. At 16, a pile at a net whose flow
  /// passed on to the box took grains out at nearly every check, and that was most of its
  /// rebuilds (docs/performance.md, forty-ninth round).
  static constexpr std::int64_t kOutflowStride = 64;
  /// Multi-rate stepping: the grains' contacts with the net are checked at the end of the
  /// grain steps that are multiples of this (note_net_contacts()); a change costs no search.
  static constexpr std::int64_t kNetContactStride = 16;
  std::int64_t rebuilds_ = 0;
  std::int64_t dt_origin_step_ = 0;  ///< RestartState::dt_origin_step
  double dt_origin_time_ = 0.0;
  bool force_rebuild_ = false;
  /// Some grain's net_contact changed at the last check (on some rank): the next step starts
  /// by changing the rates (note_net_contacts()).
  bool net_contacts_changed_ = false;
  bool rebuild_on_rate_change_ = false;            ///< set_rebuild_on_rate_change()
  std::int64_t rate_changes_ = 0;                  ///< rate_changes()
  std::vector<std::uint8_t> net_contact_scratch_;  ///< note_net_contacts()'s marks
  bool bonds_broke_before_restart_ = false;        ///< RestartState::bonds_broke, for the next step
  bool bonds_broke_anywhere_ = false;
  /// Whether some rank has a particle within reach of a rigid body since the last rebuild:
  /// where none has, every body's contact load is zero and needs no reduction.
  bool bodies_in_reach_ = true;
  /// The same for the fast particles alone (BodyContactTerm::n_fast_candidates): a sub-step's
  /// evaluation reduces the bodies' loads only where some rank has one.
  bool fast_bodies_in_reach_ = true;
  /// The bodies' load sums over the ranks, every step: in the few words their magnitudes need.
  ExactSumReducer body_load_reducer_;
  int stop_local_ = 0;
  int stop_agreed_ = 0;
  MoveBounds move_bounds_;  ///< the particles' moves since the last rebuild (all ranks)
  /// move_bounds_.absolute() when the outflow noted the positions (OutflowSink::note_positions)
  double move_bound_at_outflow_note_ = 0.0;
  bool track_orientations_ = true;  ///< some particle has a bond (Integrator::first_half)
  Integrator::Drift drift_;         ///< the last drift pass (this rank), for the divergence guard
  /// Multi-rate stepping: each body's contact load of the last fast evaluation (reduced), to
  /// which the slow evaluation's adds.
  std::vector<Vec3> fast_body_force_, fast_body_torque_;
  /// Multi-rate stepping: the ledgers of the fast interactions, booked at every sub-step with
  /// its step (ledger_ and momentum_ book the slow ones at the grain step).
  EnergyLedger fast_ledger_;
  MomentumLedger fast_momentum_{0, false};
  /// Multi-rate stepping: the particles the sub-steps move (the others catch up).
  SubstepParticles movers_;
  /// The ledger that books the interactions of `rate`.
  EnergyLedger& ledger_of(ForceRate rate) {
    return rate == ForceRate::kFast ? fast_ledger_ : ledger_;
  }
  EnergyGuard energy_guard_;      ///< the divergence guard's energy part, at every energies()
  OutflowSink outflow_;           ///< model_.outflow's boxes and what went out
  InflowSource inflow_;           ///< model_.inflow's inlets and what came in
  MomentumLedger momentum_;       ///< impulses of the reported loads on the free particles
  bool outflow_pending_ = false;  ///< a grain left a box in the last drift (on some rank)
  /// Per owned particle, 1 where it is an end of an intact bond (flag_turning_particles()).
  std::vector<std::uint8_t> turning_;
  /// Every owned particle is flagged: turning() passes no flags.
  bool all_turning_ = false;
  std::vector<Vec3> body_position_at_rebuild_;
  /// Each rigid body's reduced contact load of the last evaluation (with sub-steps, of its rate
  /// alone), before brakes and ropes: what the momentum ledger of that rate books.
  std::vector<Vec3> body_contact_loads_;
  std::vector<Quat> body_orientation_at_rebuild_;
  std::array<double, kPhaseCount> phase_seconds_{};
};

}  // namespace ringdem

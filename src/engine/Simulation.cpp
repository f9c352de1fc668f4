#include "engine/Simulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "domain/SpatialBins.hpp"
#include "engine/DivergenceError.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/ModelTable.hpp"
#include "engine/PairContactTerm.hpp"
#include "engine/PhaseTimer.hpp"
#include "engine/RingMeshTerm.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {

SimulationSettings settings_from_case(const CaseConfig& c) {
  SimulationSettings s;
  s.dt = c.simulation.dt.value_or(0.0);
  s.dt_safety = c.simulation.dt_safety;
  s.skin = c.simulation.skin;
  s.gravity = c.simulation.gravity;
  s.imbalance_threshold = c.simulation.imbalance_threshold;
  s.momentum_ledger = c.scenario.type == "free_run";
  s.energy_ledger = c.simulation.energy_ledger;
  s.sort_every = c.simulation.sort_every;
  s.substeps = c.simulation.substeps;
  return s;
}

const char* Simulation::phase_name(int phase) {
  static const char* names[] = {"integrate", "comm", "neighbour", "bonds", "contacts", "gather"};
  return names[phase];
}

std::vector<std::unique_ptr<ForceTerm>> Simulation::make_terms(Model& m) {
  const BondModelEntry* bond_model = find_bond_model(m.bond_model);
  const ContactModelEntry* contact_model = find_contact_model(m.contact_model);
  if (bond_model == nullptr) throw std::runtime_error("unknown bond model '" + m.bond_model + "'");
  if (contact_model == nullptr)
    throw std::runtime_error("unknown contact model '" + m.contact_model + "'");
  std::vector<std::unique_ptr<ForceTerm>> terms;
  terms.push_back(bond_model->make(m));
  for (auto& t : contact_model->make())
    terms.push_back(std::move(t));
  // A net's secondary mesh is part of the case, not a model choice: present when asked for.
  if (!m.ring_meshes.empty()) terms.push_back(std::make_unique<RingMeshTerm>(m.ring_meshes));
  return terms;
}

void Simulation::find_typed_terms() {
  // make_terms() puts the bond term first; the body-contact term is found by type.
  bond_term_ = static_cast<BondTerm*>(terms_.front().get());
  for (auto& t : terms_)
    if (auto* b = dynamic_cast<BodyContactTerm*>(t.get())) body_term_ = b;
  // Only bonds read a particle's orientation: without any, the drift leaves it alone.
  track_orientations_ = comm_.max(model_.bonds.size() > 0 ? 1.0 : 0.0) > 0.0;
  if (track_orientations_ && !model_.particles.tracks_orientation())
    throw std::logic_error("a model with bonds must keep the particles' orientations");
}

void Simulation::add_far_ghosts() {
  for (const auto& t : terms_) {
    std::optional<FarGhostRule> rule = t->far_ghosts(model_.particles);
    // Every rank takes the rule (the collective index of FarGhosts), with the widest reach.
    const double reach = comm_.max(rule ? rule->reach : 0.0);
    if (!rule || !(reach > 0.0)) continue;
    rule->reach = reach + settings_.skin;
    decomposition_.add_far_ghosts(std::move(*rule));
  }
}

double Simulation::block_size() const {
  double width = 0.0;
  for (const auto& t : terms_)
    width = std::max(width, t->ghost_width(model_.particles));
  const double reach = comm_.max(width) + settings_.skin;
  return reach > 0.0 ? reach : 1.0;
}

void Simulation::init_limits() {
  model_.particles.rebuild_index();
  limits_ = stability_limits(model_.particles, model_.bonds, model_.materials);
  limits_.rayleigh = comm_.min(limits_.rayleigh);
  limits_.bond_axial = comm_.min(limits_.bond_axial);
  limits_.bond_shear = comm_.min(limits_.bond_shear);
  limits_.bond_rotation = comm_.min(limits_.bond_rotation);
  set_restraint_limits(model_, limits_);  // replicated: the same on every rank
  limits_.mesh = RingMeshTerm::time_step_limit(model_);
  grain_rayleigh_limit_ = slow_particles_rayleigh_limit();
}

Simulation::Simulation(Model model, const Communicator& comm, const SimulationSettings& settings)
    : model_(std::move(model)),
      comm_(comm),
      settings_(settings),
      terms_(make_terms(model_)),
      decomposition_(comm, block_size(), settings.imbalance_threshold) {
  find_typed_terms();
  add_far_ghosts();
  ledger_.set_enabled(settings_.energy_ledger);
  model_.particles.set_tracks_ledger(settings_.energy_ledger);
  outflow_ = OutflowSink(model_.outflow);
  inflow_ = InflowSource(model_.inflow);
  momentum_ = MomentumLedger(model_.bodies.size(), settings_.momentum_ledger);
  set_up_substeps();
  ParticleStore& p = model_.particles;
  // Each rank built a slice of every source; move the particles to the owners of their blocks.
  decomposition_.distribute_initial(p, pair_stores());
  momentum_.book_initial_momentum(p);
  // After the distribution: every intact bond then has both ends on the ranks that hold it.
  init_limits();
  dt_ = case_time_step();
  if (!(dt_ > 0.0) || !std::isfinite(dt_))
    throw std::runtime_error("cannot choose a time step: give simulation.dt explicitly");
  // The lists of the initial evaluation are built with the grains already sorted by space (the
  // re-sort of step 0), as LAMMPS sorts at set-up: built in gid order and re-sorted at the first
  // step, every fresh run paid a second full rebuild (docs/performance.md, twenty-ninth round).
  rebuild(settings_.sort_every > 0 ? sort_order() : SpatialBins::Order{});
  if (settings_.substeps > 1) {
    compute_initial_substep_forces();
    return;
  }
  evaluation_booking_.initial = true;
  compute_forces();  // loads of the initial state, for the first half kick
  evaluation_booking_ = {};
  book_momentum(/*initial=*/true);
  apply_global_damping(model_.particles, dt_);
  ledger_.accumulate(model_.particles, model_.bodies, slots_, gather_, dt_, /*initial=*/true);
}

Simulation::Simulation(Model model, const Communicator& comm, const SimulationSettings& settings,
                       RestartState restart)
    : model_(std::move(model)),
      comm_(comm),
      settings_(settings),
      terms_(make_terms(model_)),
      decomposition_(comm, block_size(), settings.imbalance_threshold) {
  find_typed_terms();
  add_far_ghosts();
  // The sub-steps are part of the trajectory (RestartChanges refuses a change of
  // simulation.substeps); this guards a checkpoint written without their state.
  if (restart.substepped != (settings_.substeps > 1))
    throw std::runtime_error(
        restart.substepped ? "restart state is of a sub-stepped run, the settings step one rate"
                           : "restart state is of a single-rate run, the settings sub-step it "
                             "(simulation.substeps)");
  ledger_.set_enabled(settings_.energy_ledger);
  model_.particles.set_tracks_ledger(settings_.energy_ledger);
  ParticleStore& p = model_.particles;
  // The checkpoint's dt, whatever the case now says: a different dt would not continue the
  // same trajectory.
  dt_ = restart.dt;
  time_ = restart.time;
  steps_ = restart.steps;
  rebuilds_ = restart.rebuilds;  // the lists built below are those of the last rebuild
  dt_origin_step_ = restart.dt_origin_step;
  dt_origin_time_ = restart.dt_origin_time;
  force_rebuild_ = restart.rebuild_forced;
  bonds_broke_before_restart_ = restart.bonds_broke;
  outflow_ = OutflowSink(model_.outflow);
  outflow_.import_totals(restart.outflow_totals, comm_.is_root());
  outflow_pending_ = restart.outflow_pending;
  inflow_ = InflowSource(model_.inflow);
  inflow_.restore(restart.inflow_batches, restart.inflow_next_due, restart.inflow_totals,
                  comm_.is_root());
  momentum_ = MomentumLedger(model_.bodies.size(), settings_.momentum_ledger);
  momentum_.import_state(restart.momentum, comm_.is_root());
  // The slow loads came in with the particles; the fast ledgers go on from their totals.
  set_up_substeps();
  if (restart.substepped) fast_momentum_.import_state(restart.fast_momentum, comm_.is_root());
  // A ledger switched on at this restart starts from zero (no words); one switched off keeps
  // none.
  if (ledger_.enabled())
    ledger_.restore(
        sums_of_words(restart.energy_ledger, EnergyLedger::kStateSums, "energy ledger state"),
        comm_.is_root());
  if (restart.substepped && fast_ledger_.enabled())
    fast_ledger_.restore(sums_of_words(restart.fast_energy_ledger, EnergyLedger::kStateSums,
                                       "fast energy ledger state"),
                         comm_.is_root());
  if (!(dt_ > 0.0) || !std::isfinite(dt_))
    throw std::runtime_error("restart state has no valid time step");
  std::vector<RigidBody>& bodies = model_.bodies;
  if (restart.body_position_at_rebuild.size() != bodies.size() ||
      restart.body_orientation_at_rebuild.size() != bodies.size())
    throw std::runtime_error("restart state has no rebuild reference for every rigid body");
  // The rebuild criterion goes on from the checkpoint's move bound and body references, so
  // the next rebuild comes at the same step as in the run never interrupted. The lists are
  // built now, from the particles' current positions and the bodies' reference ones: every
  // pair that can touch before that rebuild is in them (a particle moves at most the rest of
  // the bound from here). The forces do not depend on which further candidates a list holds.
  move_bounds_.reset(model_.bodies);
  move_bounds_.restore(restart.move_bound, restart.relative_move_bound, restart.surface_move_bound);
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    body_position_at_rebuild_.push_back(bodies[b].position);
    body_orientation_at_rebuild_.push_back(bodies[b].orientation);
    bodies[b].position = restart.body_position_at_rebuild[b];
    bodies[b].orientation = restart.body_orientation_at_rebuild[b];
  }
  // Each rank read a block of the checkpoint's rows: particles go to the owners of their
  // blocks, bonds and contact springs to the owners of their particles.
  // Moved, not copied: a restart of a bed in contact held the springs twice (docs/performance.md,
  // fifty-seventh round).
  for (RestartState::TermSprings& saved : restart.springs) {
    ContactSpringStore* store = nullptr;
    for (auto& t : terms_)
      if (t->name() == saved.term) store = t->springs();
    if (store == nullptr)
      throw std::runtime_error("restart state holds springs of '" + saved.term +
                               "', which is no contact term of this model");
    store->assign_rows(std::move(saved.store));
  }
  decomposition_.distribute_initial(p, pair_stores());
  build_lists();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    std::swap(bodies[b].position, body_position_at_rebuild_[b]);
    std::swap(bodies[b].orientation, body_orientation_at_rebuild_[b]);
  }
  init_limits();
  // No force evaluation: forces, torques and body loads come from the checkpoint (a new
  // evaluation would advance the tangential springs a second time).
}

std::vector<PairStore> Simulation::pair_stores() const {
  std::vector<PairStore> stores;
  for (auto& t : terms_)
    if (const auto s = t->pair_store()) stores.push_back(*s);
  return stores;
}

SpatialBins::Order Simulation::sort_order_due() {
  if (settings_.sort_every <= 0 || steps_ == 0 || steps_ % settings_.sort_every != 0) return {};
  return sort_order();
}

SpatialBins::Order Simulation::sort_order() {
  const ParticleStore& p = model_.particles;
  const auto [lo, hi] = SpatialBins::binned_box(p);
  // Minima as maxima of the negatives: the radius and the box in one reduction.
  const auto m = comm_.max(std::array<double, 7>{-SpatialBins::smallest_binned_radius(p), -lo.x,
                                                 -lo.y, -lo.z, hi.x, hi.y, hi.z});
  const double r_min = -m[0];
  if (!std::isfinite(r_min)) return {};
  const Vec3 extent{m[4] + m[1], m[5] + m[2], m[6] + m[3]};
  return {2.0 * r_min, SpatialBins::slowest_axis(extent)};
}

void Simulation::rebuild(const SpatialBins::Order& sort, bool mid_step) {
  build_lists(sort, mid_step);
  move_bounds_.reset(model_.bodies);
  move_bound_at_outflow_note_ = 0.0;
  body_position_at_rebuild_.clear();
  body_orientation_at_rebuild_.clear();
  for (const auto& b : model_.bodies) {
    body_position_at_rebuild_.push_back(b.position);
    body_orientation_at_rebuild_.push_back(b.orientation);
  }
  force_rebuild_ = false;
  net_contacts_changed_ = false;
  ++rebuilds_;
}

std::size_t Simulation::n_contact_candidates() const {
  for (const auto& t : terms_)
    if (const auto* pairs = dynamic_cast<const PairContactTerm*>(t.get()))
      return pairs->n_candidates();
  return 0;
}

void Simulation::build_lists(const SpatialBins::Order& sort, bool mid_step) {
  ParticleStore& p = model_.particles;
  // Only touching contacts carry a spring across the rebuild; migration moves those rows with
  // their particles, and each term's rebuild() reads its own store back by key.
  ledger_.release_moments();
  fast_ledger_.release_moments();
  for (auto& t : terms_) {
    t->book_carried_work(p, ledger_, mid_step, dt_);
    t->pack_springs(p);
  }
  // Before the migration, which stores the owned particles in the new keys' order and sends
  // the ghosts theirs.
  if (sort.width > 0.0) SpatialBins::assign(p, sort);
  decomposition_.redistribute(p, pair_stores());
  // Each term takes its slots and registers them with the gather map, in term order; bonded
  // terms first, so the contact terms see their exclusions.
  allocator_.reset();
  gather_.begin(p.n_local());
  excluded_.clear();
  RebuildContext ctx{p, model_.bodies, settings_.skin, excluded_, allocator_, gather_, 0};
  for (auto& t : terms_) {
    t->rebuild(ctx);
    ++ctx.term_number;
  }
  slots_.assign(allocator_.size());
  gather_.finish(p);
  flag_turning_particles();
  outflow_.note_positions(p);
  move_bound_at_outflow_note_ = move_bounds_.absolute();  // after a restart, the checkpoint's bound
  ledger_.rebuild(gather_, allocator_.size());
  fast_ledger_.rebuild(gather_, allocator_.size());
  // A rebuild is collective (every rank rebuilds at the same step): so is this flag.
  if (!model_.bodies.empty() && body_term_ != nullptr) {
    const auto in_reach =
        comm_.max(std::array<double, 2>{body_term_->n_candidates() > 0 ? 1.0 : 0.0,
                                        body_term_->n_fast_candidates() > 0 ? 1.0 : 0.0});
    bodies_in_reach_ = in_reach[0] > 0.0;
    fast_bodies_in_reach_ = in_reach[1] > 0.0;
  }
  // The mass that gravity pulls on changes only when particles come or go, which rebuilds.
  ExactSum free_mass;
  if (momentum_.enabled())
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (p.motion[k] == Motion::kFree) free_mass.add(p.mass[k]);
  const double total_free_mass = momentum_.enabled() ? comm_.sum_exact({free_mass})[0] : 0.0;
  momentum_.rebuild(p, total_free_mass);
  fast_momentum_.rebuild(p, total_free_mass);
  movers_.invalidate();
}

void Simulation::flag_turning_particles() {
  // Only bonds read orientations: a particle turns while it is an end of an intact bond
  // (the bond terms' ends resolved at this rebuild). Grains of a debris flow beside a net keep
  // theirs; their turn was most of the drift pass there. A bond that breaks before the next
  // rebuild forces one, which takes its ends off. Where every owned particle turns, the
  // integrator needs no flags.
  const ParticleStore& p = model_.particles;
  const BondStore& bonds = model_.bonds;
  turning_.assign(track_orientations_ ? p.n_local() : 0, 0);
  if (!track_orientations_) return;
  const std::size_t n_owned = p.n_local();
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (bonds.broken[k]) continue;
    if (bonds.index_a[k] < n_owned) turning_[bonds.index_a[k]] = 1;
    if (bonds.index_b[k] < n_owned) turning_[bonds.index_b[k]] = 1;
  }
  all_turning_ = std::find(turning_.begin(), turning_.end(), 0) == turning_.end();
}

Integrator::Turning Simulation::turning() const {
  return {track_orientations_, all_turning_ ? nullptr : turning_.data()};
}

bool Simulation::needs_rebuild() {
  // A bond that broke in the last evaluation before a restart counts as one of this step's.
  bool topology_changed = bonds_broke_before_restart_;
  bonds_broke_before_restart_ = false;
  for (const auto& t : terms_)
    topology_changed |= t->topology_changed();
  // One reduction per step for both triggers — the moves, and whether a bond broke anywhere
  // in the last force evaluation (its pair may now touch) — and for stop requests. A
  // non-finite body state counts as a runaway too.
  double runaway = drift_.worst_runaway;
  for (const RigidBody& b : model_.bodies)
    if (!std::isfinite(norm2(b.position) + norm2(b.velocity) + norm2(b.omega)))
      runaway = Integrator::kRunaway;
  // Grains out of an outflow box at the positions this drift reached leave before the next
  // step, when the state is synchronised (OutflowSink); they ride on the same reduction.
  // The particles moved at most the bound since the outflow noted them, plus this drift.
  // Their removal rebuilds the lists, so they are looked for only at every kOutflowStride-th
  // step (at fixed step numbers, as the re-sorts: the same steps on any rank count, with any
  // skin, and after a restart). Looked for at every step, a steady outflow rebuilt at nearly
  // every step (a 10^5-grain channel: 1 325 rebuilds in 1 058 grain steps); at every 16th, it
  // still made most rebuilds of the channel's pile at its net.
  const bool outflow_due = steps_ % kOutflowStride == 0;
  const bool leaving =
      outflow_due &&
      outflow_.any_leaving(model_.particles, move_bounds_.absolute() - move_bound_at_outflow_note_ +
                                                 drift_.max_speed * substep());
  const Integrator::VelocityBox& v = drift_.velocities;
  const auto global = comm_.max(std::array<double, 11>{
      drift_.max_speed, topology_changed ? 1.0 : 0.0, static_cast<double>(stop_local_), runaway,
      leaving ? 1.0 : 0.0, v.high.x, v.high.y, v.high.z, -v.low.x, -v.low.y, -v.low.z});
  if (global[3] > 1.0) report_divergence();
  outflow_pending_ = global[4] > 0.0;
  Integrator::VelocityBox velocities;  // over every rank
  velocities.high = {global[5], global[6], global[7]};
  velocities.low = {-global[8], -global[9], -global[10]};
  // Bounds on the moves since the last rebuild, summed over the drifts (MoveBounds): no
  // column of reference positions, read every step, the same on any rank count. They rebuild
  // somewhat earlier than the largest actual move would; the forces do not depend on when
  // lists are rebuilt.
  move_bounds_.advance(global[0], velocities, model_.bodies, substep());
  const bool bond_broke = global[1] > 0.0;
  stop_agreed_ = static_cast<int>(global[2]);
  bonds_broke_anywhere_ = bond_broke;
  // Two particles close by at most twice the relative move; a particle and a surface by the
  // particle's move toward it plus how far any point of the surface moved (translation plus
  // rotation angle times extent).
  bool surface_reached = false;
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    const RigidBody& body = model_.bodies[b];
    double body_move = 0.0;
    if (body.motion != Motion::kFixed) {
      const double angle =
          norm(rotation_vector(body.orientation * conjugate(body_orientation_at_rebuild_[b])));
      const double turn = angle > 0.0 ? angle * body.extent() : 0.0;
      body_move = norm(body.position - body_position_at_rebuild_[b]) + turn;
    }
    surface_reached = surface_reached || move_bounds_.toward(b) + body_move > settings_.skin;
  }
  return force_rebuild_ || bond_broke || 2.0 * move_bounds_.relative() > settings_.skin ||
         surface_reached;
}

void Simulation::step() {
  if (settings_.substeps > 1) {
    substepped_step({});
    return;
  }
  start_step();
  evaluate_step();
  finish_step();
}

void Simulation::start_step() {
  ParticleStore& p = model_.particles;
  exchange_grains_and_rebuild();
  momentum_.book_first_half();
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    // The drift also starts the next loads (F = m g, T = 0): compute_forces() goes on from them.
    drift_ = Integrator::first_half(p, dt_, settings_.gravity, kMaxStepFraction * settings_.skin,
                                    kMaxTurn, turning());
    Integrator::first_half(model_.bodies, dt_, settings_.gravity);
  }
  time_ += dt_;
}

void Simulation::exchange_grains_and_rebuild() {
  bool changed = false;
  if (outflow_pending_ || !inflow_.empty()) {
    PhaseTimer t(phase_seconds_[kComm]);
    changed = exchange_grains();
  }
  // A grain's contact with the net changed (on some rank): the rates change, at the rebuild
  // if there is one (every rank knows both).
  if (changed || (net_contacts_changed_ && rebuild_on_rate_change_)) {
    PhaseTimer t(phase_seconds_[kNeighbour]);
    rebuild();  // owned indices changed (on some rank): every rank rebuilds
  } else if (net_contacts_changed_) {
    PhaseTimer t(phase_seconds_[kNeighbour]);
    change_rates();
  }
}

void Simulation::change_rates() {
  // The flags change no candidate: a grain is a candidate of the same pairs and bodies at
  // either rate. At a rebuild for them, a pile at a net rebuilt at nearly every check
  // (docs/performance.md, forty-eighth round); this is a few passes over the candidates.
  ParticleStore& p = model_.particles;
  decomposition_.update_ghosts(p, field_flag::kGhostRates);
  for (auto& t : terms_)
    t->change_rates(p, gather_);
  gather_.finish_rates();
  // Each ledger's records are of its rate's slots (filled by the next evaluations).
  ledger_.rebuild(gather_, allocator_.size());
  fast_ledger_.rebuild(gather_, allocator_.size());
  if (!model_.bodies.empty() && body_term_ != nullptr)
    fast_bodies_in_reach_ = comm_.any(body_term_->n_fast_candidates() > 0);
  movers_.invalidate();
  net_contacts_changed_ = false;
  ++rate_changes_;
}

bool Simulation::evaluate_step(bool batch_continues) {
  ParticleStore& p = model_.particles;
  bool rebuild_now = false;
  {
    PhaseTimer t(phase_seconds_[kComm]);
    decomposition_.update_ghosts(p);
    rebuild_now = needs_rebuild();
  }
  // Known now (needs_rebuild() agreed on the stops and the outflow): how the step ends, and
  // so what its evaluation books.
  const bool fuse = batch_continues && !stop_agreed_ && can_fuse_with_next_step();
  evaluation_booking_.held = !fuse;
  if (outflow_pending_)
    evaluation_booking_.leaving = [this, &p](std::size_t k) { return outflow_.leaving(p, k); };
  // A re-sort comes at fixed step numbers, at a rebuild of its own: the forces do not depend on
  // when the lists are rebuilt, and a restart, whose lists are built afresh, re-sorts at the
  // same steps as the run never interrupted.
  const SpatialBins::Order sort = sort_order_due();
  if (rebuild_now || sort.width > 0.0) {
    PhaseTimer t(phase_seconds_[kNeighbour]);
    rebuild(sort, /*mid_step=*/true);
  }
  compute_forces(/*loads_started=*/true);
  evaluation_booking_ = {};
  book_momentum(/*initial=*/false);
  return fuse;
}

void Simulation::finish_step(const BodyObserver& observe_bodies) {
  ParticleStore& p = model_.particles;
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    Integrator::second_half(p, dt_);
    Integrator::second_half(model_.bodies, dt_, settings_.gravity);
    // Needs both at v^{n+1}. Grains an outflow box takes out before the next step end their
    // trapezoid here.
    EnergyLedger::LeavingTest leaving;
    if (outflow_pending_) leaving = [this, &p](std::size_t k) { return outflow_.leaving(p, k); };
    ledger_.accumulate(p, model_.bodies, slots_, gather_, dt_, /*initial=*/false, leaving);
  }
  ++steps_;
  if (observe_bodies) observe_bodies(model_.bodies, time_);
}

bool Simulation::can_fuse_with_next_step() const {
  // The next step's start_step() would take grains out or put a batch in before its drift.
  if (outflow_pending_) return false;
  for (std::size_t i = 0; i < inflow_.size(); ++i)
    if (inflow_.due(i, time_)) return false;
  return true;
}

void Simulation::finish_step_and_start_next(const BodyObserver& observe_bodies) {
  // finish_step() and the next start_step() (which takes no grains in or out: see
  // can_fuse_with_next_step()) as one pass over the particles: the ledger books each chunk of
  // particles at its end-of-step velocities, before the chunk drifts. The rigid bodies' halves
  // and the momentum ledger's booking are independent of the particles' pass.
  ParticleStore& p = model_.particles;
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    Integrator::second_half(model_.bodies, dt_, settings_.gravity);
    // The bodies are at the end of this step, time_ too (the next step's starts below).
    if (observe_bodies) observe_bodies(model_.bodies, time_);
    // The next step replaces the held energies before anything can read them.
    ledger_.start_accumulation(p, gather_, /*book_held=*/false);
    drift_ = Integrator::second_then_first_half(
        p, dt_, settings_.gravity, kMaxStepFraction * settings_.skin, kMaxTurn, turning(),
        [this, &p](std::size_t end) {
          ledger_.accumulate_below(end, p, model_.bodies, slots_, gather_);
        });
    ledger_.finish_accumulation(gather_, dt_);
    momentum_.book_first_half();
    Integrator::first_half(model_.bodies, dt_, settings_.gravity);
  }
  ++steps_;
  time_ += dt_;
}

void Simulation::run_steps(std::int64_t n, const std::function<void()>& before_each,
                           const BodyObserver& observe_bodies) {
  if (settings_.substeps > 1) {
    for (std::int64_t k = 0; k < n; ++k) {
      if (before_each) before_each();
      substepped_step(observe_bodies);
      if (stop_agreed_) break;
    }
    return;
  }
  bool started = false;  // the next step's first half is done
  for (std::int64_t k = 0; k < n; ++k) {
    if (before_each) before_each();
    if (!started) start_step();
    started = evaluate_step(/*batch_continues=*/k + 1 < n);
    if (started)
      finish_step_and_start_next(observe_bodies);
    else
      finish_step(observe_bodies);
    if (stop_agreed_) break;
  }
}

bool Simulation::exchange_grains() {
  ParticleStore& p = model_.particles;
  // Taking grains out or putting them in moves particle indices: the contact terms key their
  // springs by gid first, once, and the rebuild below reads them back.
  bool changed = false;
  const auto before_change = [&] {
    if (!changed)
      for (auto& t : terms_) {
        // The start of a step: the contacts' rows carry what they owe the ledger.
        t->book_carried_work(p, ledger_, /*mid_step=*/false, dt_);
        t->pack_springs(p);
      }
    changed = true;
  };
  if (outflow_pending_) {  // every rank knows: the last step's reduction
    before_change();
    const bool two_rates = settings_.substeps > 1;
    for (std::size_t k = 0; k < p.n_local() && momentum_.enabled(); ++k) {
      if (!outflow_.leaving(p, k)) continue;
      // With two rates a leaving grain misses the next half kicks of both its loads.
      momentum_.book_leaving(p, k, 0.5 * dt_, two_rates ? &p.slow_force : nullptr);
      if (two_rates) fast_momentum_.book_leaving(p, k, 0.5 * substep());
    }
    auto held = ledger_.held_by_leaving();
    if (two_rates)
      for (int h = 0; h < EnergyLedger::kHeldSums; ++h)
        held[h] += fast_ledger_.held_by_leaving()[h];
    outflow_.remove_leaving(p, settings_.gravity, dt_, held[EnergyLedger::kContactHeld],
                            held[EnergyLedger::kTangentialHeld]);
    outflow_pending_ = false;
  }
  for (std::size_t i = 0; i < inflow_.size(); ++i) {
    if (!inflow_.due(i, time_)) continue;  // every step: no allocation, no communication
    // Due batches are rare (one per inlet interval), so one more reduction here is cheap.
    if (comm_.any(inflow_.occupied(i, p))) continue;  // the flow backs up: try next step
    before_change();
    const std::size_t first_new = p.n_local();
    inflow_.emit(i, p, time_, settings_.gravity, comm_.rank(), comm_.size());
    momentum_.book_arrivals(p, first_new, p.n_local(), 0.5 * dt_);
    if (settings_.substeps > 1)  // their weight is a slow load
      for (std::size_t k = first_new; k < p.n_local(); ++k) {
        p.slow_force[k] = p.force[k];
        p.slow_torque[k] = p.torque[k];
        p.force[k] = p.torque[k] = Vec3{};
      }
  }
  return changed;
}

void Simulation::place_body(std::size_t index, const Vec3& position, const Vec3& velocity,
                            Motion motion) {
  RigidBody& b = model_.bodies.at(index);
  b.position = position;
  b.velocity = velocity;
  b.omega = {};
  b.motion = motion;
  force_rebuild_ = true;
  energy_guard_.rebase();
}

void Simulation::hold_restrained_bodies(bool held) {
  ringdem::hold_restrained_bodies(model_, held);
  energy_guard_.rebase();
}

void Simulation::set_group_damping(int group, double coefficient) {
  ParticleStore& p = model_.particles;
  // Every rank sets the same coefficients, so every rank turns the columns on alike.
  if (coefficient != 0.0) p.set_tracks_damping(true);
  if (!p.tracks_damping()) return;  // every particle is undamped already
  for (std::size_t k = 0; k < p.n_total(); ++k)
    if (p.group[k] == group) p.damping[k] = coefficient;
}

void Simulation::refresh_bond_diagnostics() {
  bond_term_->update_diagnostics(model_.particles);
}

}  // namespace ringdem

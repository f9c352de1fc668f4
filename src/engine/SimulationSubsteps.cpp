// Multi-rate stepping (docs/physics.md "Two time scales"): Simulation's steps when
// settings().substeps > 1.
#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "engine/DivergenceError.hpp"
#include "engine/PhaseTimer.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

void Simulation::set_up_substeps() {
  // One rate books everything in ledger_: the fast ledger keeps no records (a record per
  // ledger slot, 5.5 bytes a grain of a 10^6-grain bed on its floor: docs/performance.md,
  // forty-fifth round).
  fast_ledger_.set_enabled(settings_.substeps > 1 && settings_.energy_ledger);
  // One rate books each particle pair's work in the pair loop; a slow contact's law reads
  // velocities that are not its step's middle, and a rolling torque is not carried, so those
  // keep the per-particle sums (docs/physics.md "Energy ledger").
  const bool per_contact = settings_.pair_ledger_per_contact.value_or(
      settings_.substeps <= 1 && !model_.materials.any_rolling_friction());
  if (per_contact && settings_.substeps > 1)
    throw std::logic_error("pair_ledger_per_contact: a sub-stepped run books pairs per particle");
  ledger_.set_pair_booking(per_contact ? EnergyLedger::PairBooking::kPerContact
                                       : EnergyLedger::PairBooking::kPerParticle);
  if (settings_.substeps <= 1) return;
  const auto refuse = [](const std::string& why) {
    throw std::runtime_error("simulation.substeps > 1: " + why);
  };
  for (const RigidBody& b : model_.bodies)
    if (b.motion != Motion::kFixed)
      refuse("every rigid body must be fixed (a free or driven body is stepped at one rate)");
  if (!model_.brakes.empty() || !model_.ropes.empty())
    refuse("brakes and support ropes are not sub-stepped; leave them out");
  if (model_.particles.tracks_damping())
    refuse("global (Cundall) damping is not sub-stepped; leave damping out");
  model_.particles.set_tracks_slow_loads(true);
  // A bond is evaluated at every sub-step, a grain's contacts once a grain step: weighed so, a
  // net is shared by the ranks instead of sitting on one while the others wait out its
  // sub-steps (the debris demo on 2 ranks: docs/debris.md). A bond then weighs r particles
  // (its store's weight 2 times r / 2), not 2 r: a grain in a flow costs a grain step about
  // what a net particle's r sub-steps cost (docs/debris.md's c_g and c_n), and at 2 r the rank
  // with the net of a 10^5-grain channel held a sixth of the grains and the other rank was the
  // one waited for (docs/performance.md, fortieth round).
  decomposition_.set_row_weight_scale(std::max(1, static_cast<int>(settings_.substeps) / 2));
  gather_.set_split_by_rate(true);
  // A ledger per rate, each booked with its own step; the fast one books the held particles'
  // drivers and the point loads, whose loads are all fast.
  fast_ledger_.set_rate(ForceRate::kFast);
  ledger_.set_rate(ForceRate::kSlow);
  fast_momentum_ = MomentumLedger(model_.bodies.size(), settings_.momentum_ledger);
}

double Simulation::slow_particles_rayleigh_limit() const {
  const ParticleStore& p = model_.particles;
  double limit = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (is_net_particle(p, k)) continue;
    const Material& m = model_.materials[static_cast<std::size_t>(p.material[k])];
    limit = std::min(
        limit, rayleigh_time_step(p.radius[k], m.density, m.shear_modulus(), m.poisson_ratio));
  }
  return comm_.min(limit);
}

void Simulation::compute_initial_substep_forces() {
  const double h = substep();
  compute_forces(false, ForceRate::kFast, h);
  book_momentum(/*initial=*/true, ForceRate::kFast);
  fast_ledger_.accumulate(model_.particles, model_.bodies, slots_, gather_, h, /*initial=*/true);
  compute_forces(false, ForceRate::kSlow, dt_);
  book_momentum(/*initial=*/true, ForceRate::kSlow);
  ledger_.accumulate(model_.particles, model_.bodies, slots_, gather_, dt_, /*initial=*/true);
}

void Simulation::classify_movers() {
  movers_.classify(model_.particles, gather_, terms_, model_.point_loads);
  // A ghost that a fast interaction reads is one of a particle that the interaction loads, on
  // its owner too: the owners' flags select every ghost the sub-steps read. Every interaction
  // a rank computes loads a particle it owns, a mover then: a rank without movers reads none.
  decomposition_.select_ghost_subset(model_.particles, movers_.read_by_fast(),
                                     movers_.n_movers() > 0);
}

void Simulation::note_net_contacts() {
  // The grains that touch the net step all their interactions at the fast rate from the next
  // step on. A grain pinched between a ring and the bed had its bed contact at the grains'
  // step while the ring moved it at every sub-step: the bed's impulses, read at positions the
  // sub-steps had moved, pumped energy into it (r-RESPA resonance; docs/physics.md "Two time
  // scales"). Decided from the contacts themselves, at fixed step numbers: the same grains on
  // any rank count, with any skin, and after a restart.
  ParticleStore& p = model_.particles;
  std::vector<std::uint8_t>& touching = net_contact_scratch_;
  touching.assign(p.n_local(), 0);
  for (const auto& term : terms_)
    term->mark_net_contacts(p, touching);
  bool changed = false;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.net_contact[k] != touching[k]) {
      p.net_contact[k] = touching[k];
      changed = true;
    }
  net_contacts_changed_ = comm_.any(changed);
}

void Simulation::substepped_step(const BodyObserver& observe_bodies) {
  // Impulse r-RESPA: the slow loads kick half a grain step at each end of the step; between
  // the kicks, `substeps` velocity-Verlet steps under the fast loads alone. A particle with no
  // fast load drifts in a straight line meanwhile, as it would over the whole step.
  ParticleStore& p = model_.particles;
  exchange_grains_and_rebuild();
  const double start = time_;
  const std::int64_t r = settings_.substeps;
  const double h = substep();
  momentum_.book_first_half();
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    Integrator::kick(p, p.slow_force, p.slow_torque, 0.5 * dt_);
    // The kick changed every velocity: the speeds of the particles the sub-steps leave behind
    // enter each sub-step's rebuild test and divergence guard as they are now.
    if (movers_.current()) movers_.measure_others(p);
  }
  if (!movers_.current()) {
    // After the slow kick: the velocities of the particles that the sub-steps do not move stay
    // as they are now until the grain step's end (SubstepParticles). Counted with the rebuild
    // that made the lists it reads.
    PhaseTimer t(phase_seconds_[kNeighbour]);
    classify_movers();
  }
  for (std::int64_t k = 0; k < r; ++k) {
    fast_momentum_.book_first_half();
    {
      PhaseTimer t(phase_seconds_[kIntegrate]);
      // No gravity in the fast loads: the slow ones carry it.
      drift_ = Integrator::first_half(p, h, Vec3{}, kMaxStepFraction * settings_.skin, kMaxTurn,
                                      turning(), movers_.mover_runs(), movers_.others_speeds());
      movers_.note_drift();
      // Every position is read from here to the step's end: the ghosts, the outflow's test,
      // the slow evaluation.
      if (k + 1 == r) movers_.catch_up(p, h);
    }
    time_ = start + static_cast<double>(k + 1) * h;
    bool rebuild_now = false;
    {
      PhaseTimer t(phase_seconds_[kComm]);
      decomposition_.update_ghost_subset(p);  // those the fast interactions read
      try {
        rebuild_now = needs_rebuild();
      } catch (const DivergenceError&) {
        // The diverged state goes into a frame for inspection: every particle where it is.
        movers_.catch_up(p, h);
        throw;
      }
    }
    // A re-sort comes at the step numbers of grain steps, at their first sub-step.
    const SpatialBins::Order sort = k == 0 ? sort_order_due() : SpatialBins::Order{};
    if (rebuild_now || sort.width > 0.0) {
      PhaseTimer t(phase_seconds_[kNeighbour]);
      movers_.catch_up(p, h);  // the search reads every position
      rebuild(sort);
      classify_movers();
    }
    compute_forces(/*loads_started=*/true, ForceRate::kFast, h);
    book_momentum(/*initial=*/false, ForceRate::kFast);
    {
      PhaseTimer t(phase_seconds_[kIntegrate]);
      Integrator::second_half(p, h, movers_.mover_runs());
      // Grains an outflow box takes out before the next step end their trapezoids here.
      EnergyLedger::LeavingTest leaving;
      if (k + 1 == r && outflow_pending_)
        leaving = [this, &p](std::size_t i) { return outflow_.leaving(p, i); };
      // The held energies are read at grain steps' ends only (reports, checkpoints): booked
      // at the last sub-step, not with two exact additions a particle at every sub-step.
      fast_ledger_.accumulate(p, model_.bodies, slots_, gather_, h, /*initial=*/false, leaving,
                              /*book_held=*/k + 1 == r);
    }
  }
  time_ = start + dt_;
  {
    // The ghosts at their owners' velocities of the step's end: each slow contact then reads
    // the same velocities on every rank that holds it.
    PhaseTimer t(phase_seconds_[kComm]);
    decomposition_.update_ghosts(p);
  }
  compute_forces(/*loads_started=*/false, ForceRate::kSlow, dt_);
  book_momentum(/*initial=*/false, ForceRate::kSlow);
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    Integrator::kick(p, p.slow_force, p.slow_torque, 0.5 * dt_);
    EnergyLedger::LeavingTest leaving;
    if (outflow_pending_) leaving = [this, &p](std::size_t i) { return outflow_.leaving(p, i); };
    ledger_.accumulate(p, model_.bodies, slots_, gather_, dt_, /*initial=*/false, leaving);
  }
  if (steps_ % kNetContactStride == 0) {
    PhaseTimer t(phase_seconds_[kNeighbour]);
    note_net_contacts();
  }
  ++steps_;
  if (observe_bodies) observe_bodies(model_.bodies, time_);
}

}  // namespace ringdem

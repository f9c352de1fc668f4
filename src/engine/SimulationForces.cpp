// Simulation's force evaluation (DESIGN §3): the terms in gather order, the bodies' loads
// reduced over the ranks, and their booking in the momentum ledger.
#include "engine/FrameRestraints.hpp"
#include "engine/PhaseTimer.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

void Simulation::compute_forces(bool loads_started, ForceRate rate, double dt) {
  ParticleStore& p = model_.particles;
  const bool slow = rate == ForceRate::kSlow;
  // The fast loads of multi-rate stepping carry no gravity: the slow ones do.
  const Vec3 gravity = rate == ForceRate::kFast ? Vec3{} : settings_.gravity;
  const ParticleLoads loads =
      slow ? ParticleLoads{p.slow_force.data(), p.slow_torque.data(), p.n_local()}
           : ParticleLoads{p.force.data(), p.torque.data(), p.n_local()};
  {
    PhaseTimer t(phase_seconds_[kGather]);
    if (slow) {
      for (std::size_t k = 0; k < p.n_local(); ++k) {
        p.slow_force[k] = gravity * p.mass[k];
        p.slow_torque[k] = Vec3{};
      }
    } else {
      if (!loads_started) GatherMap::initialise_loads(p, gravity);
      gather_.apply_point_loads(p, model_.point_loads);
    }
    ledger_of(rate).begin_step(p.n_local(), evaluation_booking_);
  }
  ComputeContext ctx{
      p,     model_.bodies, model_.materials, slots_, ledger_of(rate), time_, dt > 0.0 ? dt : dt_,
      loads, rate};
  if (!slow) {
    PhaseTimer t(phase_seconds_[kBonds]);
    bond_term_->compute(ctx);
  }
  {
    PhaseTimer t(phase_seconds_[kContacts]);
    for (std::size_t k = 1; k < terms_.size(); ++k)
      if (!slow || terms_[k]->has_slow_interactions()) terms_[k]->compute(ctx);
  }
  {
    // An all-reduce: it waits for the slowest rank, which is the comm phase's to show.
    PhaseTimer t(phase_seconds_[kComm]);
    reduce_body_loads(rate);
  }
  // The contact loads of this evaluation, for the momentum balance: the restraints' loads act
  // on the bodies alone.
  const std::size_t n_bodies = model_.bodies.size();
  body_contact_loads_.resize(n_bodies);
  for (std::size_t b = 0; b < n_bodies; ++b)
    body_contact_loads_[b] = model_.bodies[b].force;
  // Multi-rate stepping: a body's load is that of its fast contacts of the last sub-step plus
  // that of its slow ones of the last grain step.
  if (rate == ForceRate::kFast) {
    fast_body_force_.resize(n_bodies);
    fast_body_torque_.resize(n_bodies);
    for (std::size_t b = 0; b < n_bodies; ++b) {
      fast_body_force_[b] = model_.bodies[b].force;
      fast_body_torque_[b] = model_.bodies[b].torque;
    }
  } else if (rate == ForceRate::kSlow) {
    for (std::size_t b = 0; b < n_bodies; ++b) {
      model_.bodies[b].force += fast_body_force_[b];
      model_.bodies[b].torque += fast_body_torque_[b];
    }
  }
  if (rate == ForceRate::kAll)
    apply_restraints(model_);  // on the reduced loads, alike on every rank
  {
    PhaseTimer t(phase_seconds_[kGather]);
    gather_.gather(p, slots_, gravity, rate, &loads);
  }
}

void Simulation::reduce_body_loads(ForceRate rate) {
  if (model_.bodies.empty() || body_term_ == nullptr) return;
  // Each body's load is the exact sum of its contacts' loads: the same bits on any rank count,
  // in one all-reduce of a few words per body whatever the number of contacts (only the limbs
  // their magnitudes need: ExactSumReducer). No rank gathers the others' contacts (a debris
  // flow's bed touches every grain that rests on it).
  using L = BodyContactTerm::LoadColumn;
  if (!(rate == ForceRate::kFast ? fast_bodies_in_reach_ : bodies_in_reach_)) {
    // No particle within reach of any body on any rank: each load is the sum of no terms, +0
    // (a body waiting out of play, such as the rockfall's boulder while the net sags; a debris
    // channel's bodies in a sub-step, which evaluates the fast particles' contacts alone).
    for (RigidBody& b : model_.bodies)
      b.force = b.torque = Vec3{};
    return;
  }
  const std::vector<double>& total = body_load_reducer_.sum(comm_, body_term_->body_load_sums());
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    const double* const t = &total[L::kLoadColumns * b];
    model_.bodies[b].force = {t[L::kForceX], t[L::kForceY], t[L::kForceZ]};
    model_.bodies[b].torque = {t[L::kTorqueX], t[L::kTorqueY], t[L::kTorqueZ]};
  }
}

void Simulation::book_momentum(bool initial, ForceRate rate) {
  const ParticleStore& p = model_.particles;
  switch (rate) {
    case ForceRate::kAll:
      momentum_.book_evaluation(p, body_contact_loads_, model_.point_loads, settings_.gravity,
                                0.5 * dt_, comm_.is_root(), initial);
      break;
    case ForceRate::kFast:  // no gravity; the held particles' loads and the point loads
      fast_momentum_.book_evaluation(p, body_contact_loads_, model_.point_loads, Vec3{},
                                     0.5 * substep(), comm_.is_root(), initial);
      break;
    case ForceRate::kSlow:  // gravity; a held particle's slow load is its weight alone
      momentum_.book_evaluation(p, body_contact_loads_, {}, settings_.gravity, 0.5 * dt_,
                                comm_.is_root(), initial, &p.slow_force);
      break;
  }
}

}  // namespace ringdem

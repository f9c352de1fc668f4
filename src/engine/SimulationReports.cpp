// Simulation's collective reports on its state (energies, momentum, counts, overlaps, the
// divergence report): queries that leave the state as it is, apart from the time-step loop
// of Simulation.cpp.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "engine/DivergenceError.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {

namespace {

/// Count, mass and momentum of the grains that crossed the boundary: the first five columns
/// of an outflow's or an inflow's sums (OutflowSink::Column, InflowSource::Column), summed
/// exactly over the ranks.
Simulation::GrainFlux sum_flux(const Communicator& comm, const std::vector<ExactSum>& partial) {
  static_assert(OutflowSink::kMomentumZ == 4 && InflowSource::kMomentumZ == 4);
  const std::vector<double> sums =
      comm.sum_exact(std::vector<ExactSum>(partial.begin(), partial.begin() + 5));
  return {static_cast<std::int64_t>(sums[0]), sums[1], {sums[2], sums[3], sums[4]}};
}

}  // namespace

OverlapReport Simulation::overlaps(double fraction, std::size_t listed) const {
  const ParticleStore& p = model_.particles;
  std::vector<ContactOverlap> found;
  for (const auto& t : terms_)
    t->find_overlaps(p, model_.bodies, fraction, found);
  std::vector<OverlapReport::Entry> mine;
  for (const ContactOverlap& o : found) {
    OverlapReport::Entry e{};
    e.depth = o.depth;
    e.partner_is_body = o.partner_is_body ? 1 : 0;
    std::uint32_t a = o.index;
    if (o.partner_is_body) {
      const RigidBody& body = model_.bodies[o.partner];
      if (p.motion[a] != Motion::kFree && body.motion != Motion::kFree) continue;
      e.partner = o.partner;
      e.partner_group = -1;
      e.partner_radius = body.shape == RigidShape::kPlane ? 0.0 : body.radius;
      e.partner_position = body.position;
      e.relative_depth = o.depth / p.radius[a];
    } else {
      std::uint32_t b = o.partner;
      if (p.gid[b] < p.gid[a]) std::swap(a, b);
      // Counted where the lower gid is owned: each pair once over the ranks.
      if (a >= p.n_local()) continue;
      if (p.motion[a] != Motion::kFree && p.motion[b] != Motion::kFree) continue;
      e.partner = p.gid[b];
      e.partner_group = p.group[b];
      e.partner_radius = p.radius[b];
      e.partner_position = p.position[b];
      e.relative_depth = o.depth / std::min(p.radius[a], p.radius[b]);
    }
    e.gid = p.gid[a];
    e.group = p.group[a];
    e.radius = p.radius[a];
    e.position = p.position[a];
    mine.push_back(e);
  }
  const auto deeper = [](const OverlapReport::Entry& x, const OverlapReport::Entry& y) {
    if (x.relative_depth != y.relative_depth) return x.relative_depth > y.relative_depth;
    if (x.gid != y.gid) return x.gid < y.gid;
    if (x.partner_is_body != y.partner_is_body) return x.partner_is_body < y.partner_is_body;
    return x.partner < y.partner;
  };
  OverlapReport report;
  report.count = comm_.sum(static_cast<std::int64_t>(mine.size()));
  std::sort(mine.begin(), mine.end(), deeper);
  if (mine.size() > listed) mine.resize(listed);
  report.deepest = comm_.allgather(mine);
  std::sort(report.deepest.begin(), report.deepest.end(), deeper);
  if (report.deepest.size() > listed) report.deepest.resize(listed);
  return report;
}

void Simulation::report_divergence(const std::string& energy_excess) const {
  // Every rank offers its worst particle; all pick the same one (largest ratio, then lowest
  // gid) and throw the same message. For the energy guard the worst is the fastest particle
  // (the ratio of its move and turn in one step to the limits), for the step guard the one
  // the drift pass found.
  struct Offender {
    double ratio;
    std::int64_t gid;
    std::int32_t group, rank;
    Vec3 position, velocity, omega;
  };
  const ParticleStore& p = model_.particles;
  Offender mine{0.0, -1, -1, comm_.rank(), {}, {}, {}};
  double worst_ratio = drift_.worst_runaway;
  std::size_t worst_index = drift_.worst_index;
  if (!energy_excess.empty()) {
    worst_ratio = -1.0;
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      double r =
          std::max(norm(p.velocity[k]) * dt_ / settings_.skin, norm(p.omega[k]) * dt_ / kMaxTurn);
      if (!std::isfinite(r)) r = Integrator::kRunaway;
      // Of equal ratios the lowest gid: the same particle on any rank count and storage order.
      if (r > worst_ratio || (r == worst_ratio && p.gid[k] < p.gid[worst_index]))
        worst_ratio = r, worst_index = k;
    }
  }
  if ((!energy_excess.empty() || worst_ratio > 1.0) && worst_index < p.n_local()) {
    const std::size_t k = worst_index;
    mine = {worst_ratio,   p.gid[k],      p.group[k], comm_.rank(),
            p.position[k], p.velocity[k], p.omega[k]};
  }
  const auto all = comm_.allgather(std::vector<Offender>{mine});
  const Offender* worst = nullptr;
  for (const Offender& o : all)
    if (o.gid >= 0 &&
        (!worst || o.ratio > worst->ratio || (o.ratio == worst->ratio && o.gid < worst->gid)))
      worst = &o;
  const auto group_name = [this](std::int32_t g) {
    return g >= 0 && static_cast<std::size_t>(g) < model_.group_names.size()
               ? model_.group_names[static_cast<std::size_t>(g)]
               : std::string("?");
  };
  std::string what = energy_excess.empty() ? std::string() : energy_excess + "; fastest ";
  if (worst && !energy_excess.empty()) {
    what += fmt::format(
        "particle {} (group {}, rank {}) at ({:.6g}, {:.6g}, {:.6g}) m, velocity ({:.6g}, "
        "{:.6g}, {:.6g}) m/s",
        worst->gid, group_name(worst->group), worst->rank, worst->position.x, worst->position.y,
        worst->position.z, worst->velocity.x, worst->velocity.y, worst->velocity.z);
  } else if (worst) {
    const std::string group = group_name(worst->group);
    const bool finite =
        std::isfinite(norm2(worst->position) + norm2(worst->velocity) + norm2(worst->omega));
    what = fmt::format(
        "particle {} (group {}, rank {}) at ({:.6g}, {:.6g}, {:.6g}) m, velocity ({:.6g}, "
        "{:.6g}, {:.6g}) m/s, angular velocity |omega| = {:.6g} rad/s: ",
        worst->gid, group, worst->rank, worst->position.x, worst->position.y, worst->position.z,
        worst->velocity.x, worst->velocity.y, worst->velocity.z, norm(worst->omega));
    what += finite ? fmt::format(
                         "it moved {:.3g} m in one step (the neighbour skin is {:.3g} m) "
                         "or turned {:.3g} rad (limit {:.3g})",
                         norm(worst->velocity) * dt_, settings_.skin, norm(worst->omega) * dt_,
                         kMaxTurn)
                   : std::string("its state is not finite (NaN or infinity)");
  } else {
    for (const RigidBody& b : model_.bodies)
      if (!std::isfinite(norm2(b.position) + norm2(b.velocity) + norm2(b.omega))) {
        what = "rigid body '" + b.name + "': its state is not finite (NaN or infinity)";
        break;
      }
  }
  const double stable = limits_.min();
  std::string cause;
  if (dt_ > stable)
    cause = fmt::format(
        "the time step {:.4g} s is {:.3g} times the stable estimate {:.4g} s: "
        "lower simulation.dt (or leave it out to take the estimate)",
        dt_, dt_ / stable, stable);
  else if (steps_ < 100)
    cause =
        "a blow-up right at the start: particles overlapping at creation (two at the same "
        "place give NaN), or a body placed inside the particles";
  else
    cause = fmt::format(
        "an interaction too stiff for dt = {:.4g} s (stable estimate {:.4g} s), "
        "or a driven body pushed through the particles",
        dt_, stable);
  throw DivergenceError(fmt::format("the run diverged at step {}, t = {:.9g} s: {}. Likely "
                                    "cause: {}.",
                                    steps_ + 1, time_, what, cause),
                        steps_ + 1, time_);
}

Simulation::GrainFlux Simulation::outflow_totals() const {
  return sum_flux(comm_, outflow_.partial());
}

Simulation::GrainFlux Simulation::inflow_totals() const {
  return sum_flux(comm_, inflow_.partial());
}

MomentumBalance Simulation::momentum_balance() const {
  MomentumBalance b = momentum_.balance(model_.particles, comm_);
  if (fast_momentum_.enabled()) {
    // Multi-rate stepping: the impulses of the fast loads, booked at the sub-steps.
    const MomentumBalance fast = fast_momentum_.balance(model_.particles, comm_);
    b.gravity += fast.gravity;
    b.point_loads += fast.point_loads;
    b.held += fast.held;
    b.exchange += fast.exchange;
    for (std::size_t i = 0; i < b.bodies.size() && i < fast.bodies.size(); ++i)
      b.bodies[i] += fast.bodies[i];
  }
  b.outflow = outflow_totals().momentum;
  b.inflow = inflow_totals().momentum;
  return b;
}

std::int64_t Simulation::global_particles() const {
  return comm_.sum(static_cast<std::int64_t>(model_.particles.n_local()));
}

std::int64_t Simulation::global_bonds() const {
  std::int64_t n = 0;
  for (std::size_t k = 0; k < model_.bonds.size(); ++k)
    n += counted_here(model_.particles, model_.bonds, k);
  return comm_.sum(n);
}

std::int64_t Simulation::global_broken_bonds() const {
  std::int64_t n = 0;
  for (std::size_t k = 0; k < model_.bonds.size(); ++k)
    n += counted_here(model_.particles, model_.bonds, k) && model_.bonds.broken[k] != 0;
  return comm_.sum(n);
}

Energies Simulation::energies() {
  bond_term_->update_diagnostics(model_.particles);
  const ParticleStore& p = model_.particles;
  // Exact sums (comm/ExactSum), all in one all-reduce: the same bits on any rank count,
  // whatever the gids, and no rank holds more than its own terms.
  enum Column {
    kKinetic,
    kPotential,
    kDamping,
    kFriction,
    kGlobal,
    kBoundary,
    kContact,
    kBond,
    kBreak,
    kPlastic,
    kOutflow,
    kInflow,
    kDampingSteps,  // the contact terms' trapezoidal sums (EnergyLedger::intervals)
    kFrictionSteps,
    kBoundarySteps,
    kDampingSubsteps,  // multi-rate stepping: the fast ledger's, of the sub-step
    kFrictionSubsteps,
    kBoundarySubsteps,
    kColumns
  };
  static_assert(kFrictionSteps - kDampingSteps == EnergyLedger::kFriction &&
                    kBoundarySteps - kDampingSteps == EnergyLedger::kBoundary &&
                    kBoundarySubsteps - kDampingSubsteps == EnergyLedger::kBoundary,
                "each ledger's step columns in the order of its tallies");
  std::vector<ExactSum> partial(kColumns);
  // The contact terms' tallies, this rank's part (EnergyLedger::tally), of a ledger whose
  // trapezoidal sums go to the three columns from `first_steps` (each ledger's own step). What
  // the contacts hold now: friction counts the tangential springs' energy as not yet dissipated
  // (EnergyLedger::held()).
  const auto book_ledger = [&partial](const EnergyLedger& ledger, int first_steps) {
    const auto& steps = ledger.intervals();
    const auto& direct = ledger.direct();
    for (const int t : {EnergyLedger::kDamping, EnergyLedger::kFriction, EnergyLedger::kBoundary})
      partial[static_cast<std::size_t>(first_steps + t)] += steps[t];
    partial[kDamping] += direct[EnergyLedger::kDamping];
    partial[kFriction] += direct[EnergyLedger::kFriction];
    partial[kBoundary] += direct[EnergyLedger::kBoundary];
    const auto& held = ledger.held();
    partial[kFriction] += held[EnergyLedger::kTangentialHeld].negated();
    partial[kContact] += held[EnergyLedger::kContactHeld];
  };
  book_ledger(ledger_, kDampingSteps);
  // Multi-rate stepping: the fast ledger's, of the sub-step.
  if (settings_.substeps > 1) book_ledger(fast_ledger_, kDampingSubsteps);
  // What left through outflow boxes: the dissipation it had booked stays in the ledger, the
  // tangential energy its springs held went out with it (friction counts what they hold).
  const std::vector<ExactSum>& gone = outflow_.partial();
  partial[kGlobal] += gone[OutflowSink::kGlobalDamping];
  partial[kFriction] += gone[OutflowSink::kTangentialEnergy].negated();
  partial[kOutflow] += gone[OutflowSink::kEnergy];
  partial[kInflow] += inflow_.partial()[InflowSource::kEnergy];
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.books_global_damping()) partial[kGlobal].add(p.global_damping_tally(k, dt_));
    if (p.motion[k] == Motion::kFree) {
      partial[kKinetic].add(p.kinetic_energy(k));
      partial[kPotential].add(p.potential_energy(k, settings_.gravity));
    }
  }
  const BondStore& bonds = model_.bonds;
  const std::vector<double>* plastic_work = bond_term_->plastic_work();
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!counted_here(p, bonds, k)) continue;
    partial[kBond].add(bonds.energy[k]);
    partial[kBreak].add(bonds.break_energy[k]);
    if (plastic_work) partial[kPlastic].add((*plastic_work)[k]);
  }
  const std::vector<double> sums = comm_.sum_exact(partial);
  Energies e;
  e.kinetic = sums[kKinetic];
  e.potential = sums[kPotential];
  // The fast ledger's sums are zero in a single-rate run.
  const double h = substep();
  e.contact_damping = EnergyLedger::tally(sums[kDampingSteps], sums[kDamping], dt_) +
                      EnergyLedger::tally(sums[kDampingSubsteps], 0.0, h);
  e.friction = EnergyLedger::tally(sums[kFrictionSteps], sums[kFriction], dt_) +
               EnergyLedger::tally(sums[kFrictionSubsteps], 0.0, h);
  e.global_damping = sums[kGlobal];
  e.boundary_work = EnergyLedger::tally(sums[kBoundarySteps], sums[kBoundary], dt_) +
                    EnergyLedger::tally(sums[kBoundarySubsteps], 0.0, h);
  e.contact_elastic = sums[kContact];
  e.bond_elastic = sums[kBond];
  e.broken_bonds = sums[kBreak];
  e.plastic_work = sums[kPlastic];
  e.outflow = sums[kOutflow];
  e.inflow = sums[kInflow];
  for (const auto& b : model_.bodies) {
    if (b.motion != Motion::kFree) continue;
    const Mat3 r = rotation_matrix(b.orientation);
    const Vec3 wb = r.transpose_times(b.omega);
    e.kinetic += 0.5 * b.mass * norm2(b.velocity) +
                 0.5 * (b.principal_inertia.x * wb.x * wb.x + b.principal_inertia.y * wb.y * wb.y +
                        b.principal_inertia.z * wb.z * wb.z);
    if (b.gravity) e.potential += -b.mass * dot(settings_.gravity, b.position);
  }
  // Replicated like the bodies they hold: the same on every rank without a reduction.
  const RestraintTotals restraints = restraint_totals(model_);
  e.brake_elastic = restraints.elastic_energy;
  e.brake_work = restraints.work;
  e.friction += restraints.friction_work;  // the ropes' sliding through the shackles
  // The sums are the same on every rank, so every rank decides alike. Without the ledger
  // the guard has no balance to check: work put in by driven bodies would look like energy
  // from nowhere.
  if (settings_.energy_ledger)
    if (const auto excess = energy_guard_.check(e))
      report_divergence(EnergyGuard::describe(*excess));
  return e;
}

}  // namespace ringdem

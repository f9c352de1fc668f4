// Simulation's clock and what a checkpoint takes from it: the restart state, a change of the
// time step, and the step counts to an end or an event. Split from Simulation.cpp, which keeps
// the time-step loop.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "comm/ExactSum.hpp"
#include "domain/PairStore.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

RestartState Simulation::restart_state() const {
  RestartState s;
  s.time = time_;
  s.steps = steps_;
  s.dt = dt_;
  s.rebuilds = rebuilds_;
  // Built part by part as the checkpoint writes them (RestartState::TermSprings::part).
  const ParticleStore& p = model_.particles;
  for (const auto& t : terms_) {
    const ForceTerm* term = t.get();
    if (term->springs() == nullptr) continue;
    // No rows: the kind of the term's, which every part has.
    ContactSpringStore kind(term->springs()->partner_kind());
    kind.set_carries_ledger(term->springs()->carries_ledger());
    RestartState::TermSprings& saved = s.springs.emplace_back(
        RestartState::TermSprings{std::string(term->name()), std::move(kind)});
    saved.part = [term, &p](std::size_t part, std::size_t parts) {
      return term->touching_springs_part(p, ForceTerm::SpringRows::kCounted, part, parts);
    };
    saved.sources = term->spring_sources();
  }
  s.dt_origin_step = dt_origin_step_;
  s.dt_origin_time = dt_origin_time_;
  s.move_bound = move_bounds_.absolute();
  s.relative_move_bound = move_bounds_.relative();
  s.surface_move_bound = move_bounds_.toward();
  s.body_position_at_rebuild = body_position_at_rebuild_;
  s.body_orientation_at_rebuild = body_orientation_at_rebuild_;
  s.rebuild_forced = force_rebuild_;
  bool broke = bonds_broke_before_restart_;
  for (const auto& t : terms_)
    broke = broke || t->topology_changed();
  s.bonds_broke = comm_.any(broke);
  s.outflow_pending = outflow_pending_;
  s.outflow_totals = outflow_.export_totals(comm_);
  s.inflow_batches = inflow_.batches();
  s.inflow_next_due = inflow_.next_due();
  s.inflow_totals = inflow_.export_totals(comm_);
  s.momentum = momentum_.export_state(comm_);
  if (ledger_.enabled()) s.energy_ledger = words_of_sums(comm_.reduce_exact(ledger_.state()));
  s.substepped = settings_.substeps > 1;
  if (s.substepped) {
    s.fast_momentum = fast_momentum_.export_state(comm_);
    if (fast_ledger_.enabled())
      s.fast_energy_ledger = words_of_sums(comm_.reduce_exact(fast_ledger_.state()));
  }
  return s;
}

void Simulation::change_time_step(double dt) {
  if (!(dt > 0.0) || !std::isfinite(dt))
    throw std::runtime_error("change_time_step: the time step must be positive and finite");
  if (settings_.substeps > 1)
    throw std::runtime_error("change_time_step: not with simulation.substeps > 1");
  // The global-damping accumulators hold tally + dt/2 P of their last power P
  // (ParticleStore::ledger_value): re-weight that last half step so the tally is unchanged
  // under the new dt. The contact terms' sums of the intervals so far are totalled over the
  // ranks and booked at the old dt (collective: every rank changes the step together).
  ParticleStore& p = model_.particles;
  const double shift = 0.5 * (dt - dt_);
  for (std::size_t k = 0; p.books_global_damping() && k < p.n_local(); ++k)
    p.dissipated_global[k] += shift * p.power_global[k];
  if (ledger_.enabled()) {
    const auto& steps = ledger_.intervals();
    const std::vector<double> totals =
        comm_.sum_exact(std::vector<ExactSum>(steps.begin(), steps.end()));
    ledger_.close_intervals({totals[0], totals[1], totals[2]}, dt_, comm_.is_root());
  }
  // The momentum ledger's booked half kick (MomentumLedger) stays at the old dt/2: an exact sum
  // cannot be rescaled exactly, so the balance keeps (dt - dt_old)/2 times that step's loads.
  dt_ = dt;
  dt_origin_step_ = steps_;
  dt_origin_time_ = time_;
}

std::int64_t Simulation::steps_until(double end_time) const {
  return dt_origin_step_ +
         static_cast<std::int64_t>(std::ceil((end_time - dt_origin_time_) / dt_ - 1e-9));
}

std::int64_t Simulation::steps_short_of(double event_time, double tolerance) const {
  // The event is due after about x steps; times are sums of steps, so one step short of
  // ceil(x) is never past it whatever the rounding.
  const double x = (event_time - time_ - tolerance) / dt_;
  if (!(x < 1e15)) return std::numeric_limits<std::int64_t>::max();
  return std::max<std::int64_t>(1, static_cast<std::int64_t>(std::ceil(x)) - 1);
}

std::vector<RestartState::TermSprings> Simulation::owned_springs() const {
  const ParticleStore& p = model_.particles;
  std::vector<RestartState::TermSprings> out;
  for (const auto& t : terms_) {
    if (t->springs() == nullptr) continue;
    // A pair across ranks is evaluated on both: each touching one once, where it counts.
    out.push_back({std::string(t->name()), t->touching_springs(p)});
  }
  return out;
}

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "domain/ContactSpringStore.hpp"

namespace ringdem {

/// What a checkpoint restores besides the particle, bond and body fields (io/Checkpoint).
struct RestartState {
  double time = 0.0;
  std::int64_t steps = 0;
  double dt = 0.0;
  std::int64_t rebuilds = 0;
  /// Each contact term's tangential springs, by term name (ForceTerm::name): every spring once
  /// over the ranks (a checkpoint's writer holds those of its owned particles; its reader any).
  struct TermSprings {
    TermSprings() = default;
    TermSprings(std::string term_name, ContactSpringStore rows)
        : term(std::move(term_name)), store(std::move(rows)) {}
    std::string term;
    ContactSpringStore store;
    /// A writer's springs in parts instead of in `store` (Simulation::restart_state(); `store`
    /// then has no rows, only their kind): part(k, parts) gives the k-th, each built as the
    /// checkpoint writes it (ForceTerm::touching_springs_part), from `sources` rows looked
    /// through. The writer picks `parts` so that none looks through more than `rows_per_part`.
    std::function<ContactSpringStore(std::size_t part, std::size_t parts)> part;
    std::size_t sources = 0;
    std::size_t rows_per_part = kSpringRowsPerPart;
  };
  /// About 4 MiB of springs a part (ContactSpringStore rows of 56 B with the ledger's state).
  static constexpr std::size_t kSpringRowsPerPart = std::size_t{1} << 16;
  std::vector<TermSprings> springs;
  /// Step and time from which dt is the time step (0 unless a restart changed it): the step
  /// that reaches a given time is counted from there (Simulation::steps_until).
  std::int64_t dt_origin_step = 0;
  double dt_origin_time = 0.0;
  /// What the neighbour-list rebuild criterion reads (Simulation::needs_rebuild), so that a
  /// restart rebuilds at the same steps as the run never interrupted: the bounds on the
  /// particles' moves since the last rebuild (engine/MoveBounds: absolute, relative to a
  /// common translation, and toward each rigid body), each rigid body's position and
  /// orientation at the last rebuild, a rebuild asked for and not yet done
  /// (Simulation::place_body), and whether a bond broke in the last force evaluation (on any
  /// rank).
  double move_bound = 0.0;
  double relative_move_bound = 0.0;
  std::vector<double> surface_move_bound;  ///< one a rigid body
  std::vector<Vec3> body_position_at_rebuild;
  std::vector<Quat> body_orientation_at_rebuild;
  bool rebuild_forced = false;
  bool bonds_broke = false;
  /// Outflow (engine/OutflowSink): grains found outside their box after the last drift, to be
  /// taken out at the next step (the same on every rank), and what went out so far, as the
  /// exact totals' words (empty: nothing yet, or a checkpoint from before outflow existed).
  bool outflow_pending = false;
  std::vector<std::int64_t> outflow_totals;
  /// Inflow (engine/InflowSource): per inlet the batches put in and the time the next is due,
  /// and the exact totals of what came in (all empty: no inlet, or none put in yet).
  std::vector<std::int64_t> inflow_batches;
  std::vector<double> inflow_next_due;
  std::vector<std::int64_t> inflow_totals;
  /// The momentum ledger (engine/MomentumLedger): its totals and the half kick it has booked
  /// for the next step, as exact sums' words.
  std::vector<std::int64_t> momentum;
  /// The energy ledger's exact tallies (EnergyLedger::state) totalled over the ranks, as exact
  /// sums' words (empty: the ledger was off).
  std::vector<std::int64_t> energy_ledger;
  /// Multi-rate stepping (simulation.substeps > 1; docs/physics.md "Two time scales"): whether
  /// the run that wrote the state was sub-stepped, and the fast rate's momentum and energy
  /// ledgers as `momentum` and `energy_ledger` hold the slow (grain-step) ones. The slow loads
  /// of the last grain step travel with the particles (ParticleStore::slow_force). A checkpoint
  /// is written between grain steps, where nothing else of the sub-steps is pending: the fast
  /// loads of the last sub-step are the particles' force and torque.
  bool substepped = false;
  std::vector<std::int64_t> fast_momentum;
  std::vector<std::int64_t> fast_energy_ledger;
};

}  // namespace ringdem

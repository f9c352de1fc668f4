#pragma once

#include <optional>
#include <string>

#include "core/Vec3.hpp"
#include "engine/Model.hpp"
#include "io/CaseMagnitudes.hpp"
#include "physics/TimeStep.hpp"

namespace ringdem {

/// The restraints that hold rigid bodies (a net's shackles) to the frame: brake elements
/// (BrakeElement, docs/physics.md "Brake elements") and support ropes with their end brakes
/// (SlidingRope, "Support ropes"). They are replicated like the bodies they hold, and every rank
/// runs these functions on the same bodies and restraints, so they stay the same bits.

/// After the bodies' contact loads are reduced: adds each brake's and each rope's loads to the
/// forces of the bodies they hold and takes the step's slip.
void apply_restraints(Model& model);

/// Sets the restraints' stability limits in `limits`: `brake`, sqrt(M / k) of a body on its
/// brake's spring, and `rope`, sqrt(M / k) of a body on a rope: k = 4 EA / L0 where it slides
/// freely (a body's move changes the rope's length by at most twice its size), EA (1 / lambda_a +
/// 1 / lambda_b) where friction can hold it (the segments beside it, as laid). The tension's
/// transverse stiffness T (1/l_a + 1/l_b) is left out, small beside those while T << EA.
void set_restraint_limits(const Model& model, StabilityLimits& limits);

/// plan_time_steps (what `ringdem check` prints) with the limits of the case's brakes and ropes
/// and of its nets' secondary meshes, from the model as a run builds it without its particles,
/// so that the plan has the step a run will take where one of them sets it.
std::optional<TimeStepPlan> plan_time_steps_with_restraints(const CaseConfig& config);

/// The warning for a fixed simulation.dt above a brake's or a rope's stability limit (the
/// loader warns of one above the particles' and bonds' limits, which it knows without the
/// built restraints): the message of fixed_step_above_limit(), or none where the case's dt is
/// automatic, within the plan's limit, or above a limit the loader has named already.
std::optional<std::string> restraint_step_warning(const CaseConfig& config,
                                                  const TimeStepPlan& plan);

/// Every body a brake or a rope holds (body indices; a body on a brake before those on ropes).
std::vector<std::int32_t> restrained_bodies(const Model& model);

/// Holds the restrained bodies where they are (fixed, at rest) or sets them free. A settling
/// aid: the rockfall holds them while the net sags under its own weight, far below the brakes'
/// activation forces, so that their free turning does not keep the net from coming to rest.
/// Held, a body's kinetic and potential energy are out of the ledger (the caller books that).
void hold_restrained_bodies(Model& model, bool held);

/// What the restraints hold and have done, from their state (the same on every rank).
struct RestraintTotals {
  double elastic_energy = 0.0;   ///< the brake springs' k |d - s|^2 / 2 and the ropes' k e^2 / 2
  double work = 0.0;             ///< dissipated by the brakes (of shackles and ropes) [J]
  double friction_work = 0.0;    ///< dissipated by the ropes sliding through the bodies [J]
  Vec3 frame_load;               ///< what the anchors receive: minus the loads on the bodies [N]
  double largest_travel = 0.0;   ///< the largest path slid by a brake, or paid out by a rope [m]
  int used_up = 0;               ///< brakes and ropes whose brakes have used their whole stroke
  double largest_tension = 0.0;  ///< the largest rope tension of the last step [N] (0 without)
};
RestraintTotals restraint_totals(const Model& model);

}  // namespace ringdem

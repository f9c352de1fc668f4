#pragma once

#include <vector>

#include "core/Vec3.hpp"
#include "domain/BrakeStore.hpp"
#include "domain/RigidBody.hpp"

namespace ringdem {

/// After the bodies' contact loads are reduced: adds each brake's load (BrakeElement, docs/
/// physics.md "Brake elements") to the force of the body it holds and takes the step's slip.
/// Every rank runs it on the same replicated bodies and brakes, so they stay the same bits.
void apply_brakes(BrakeStore& brakes, std::vector<RigidBody>& bodies);

/// Holds the braked bodies where they are (fixed, at rest) or sets them free. A settling aid:
/// the rockfall holds braked shackles while the net sags under its own weight, far below their
/// activation forces, so that their free turning does not keep the net from coming to rest.
/// Held, a body's kinetic and potential energy are out of the ledger (the caller books that).
void hold_braked_bodies(const BrakeStore& brakes, std::vector<RigidBody>& bodies, bool held);

/// What the brakes hold and have done, from their state (the same on every rank).
struct BrakeTotals {
  double elastic_energy = 0.0;  ///< the springs' k |d - s|^2 / 2 [J]
  double work = 0.0;            ///< dissipated by sliding, sum of F_b ds [J]
  Vec3 frame_load;              ///< what the anchors receive: minus the loads on the bodies [N]
  double largest_travel = 0.0;  ///< the largest slid path of any brake [m]
  int used_up = 0;              ///< brakes that have slid their whole stroke
};
BrakeTotals brake_totals(const BrakeStore& brakes, const std::vector<RigidBody>& bodies);

}  // namespace ringdem

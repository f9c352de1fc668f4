#include "engine/BrakeLoads.hpp"

#include <algorithm>

#include "physics/BrakeElement.hpp"

namespace ringdem {

namespace {

BrakeElement::Params params_of(const BrakeStore& s, std::size_t k) {
  return {s.stiffness[k], s.activation_force[k], s.stroke[k]};
}

Vec3 displacement_of(const BrakeStore& s, std::size_t k, const std::vector<RigidBody>& bodies) {
  return bodies[static_cast<std::size_t>(s.body[k])].position - s.anchor[k];
}

}  // namespace

void apply_brakes(BrakeStore& brakes, std::vector<RigidBody>& bodies) {
  for (std::size_t k = 0; k < brakes.size(); ++k) {
    BrakeElement::State state{brakes.slip[k], brakes.travel[k], brakes.work[k]};
    // At the body's centre: a load without torque.
    bodies[static_cast<std::size_t>(brakes.body[k])].force +=
        BrakeElement::compute(params_of(brakes, k), displacement_of(brakes, k, bodies), state);
    brakes.slip[k] = state.slip;
    brakes.travel[k] = state.travel;
    brakes.work[k] = state.work;
  }
}

void hold_braked_bodies(const BrakeStore& brakes, std::vector<RigidBody>& bodies, bool held) {
  for (const std::int32_t b : brakes.body) {
    RigidBody& body = bodies[static_cast<std::size_t>(b)];
    body.motion = held ? Motion::kFixed : Motion::kFree;
    if (held) body.velocity = body.omega = {};
  }
}

BrakeTotals brake_totals(const BrakeStore& brakes, const std::vector<RigidBody>& bodies) {
  BrakeTotals t;
  for (std::size_t k = 0; k < brakes.size(); ++k) {
    const BrakeElement::Params p = params_of(brakes, k);
    const Vec3 d = displacement_of(brakes, k, bodies);
    const BrakeElement::State state{brakes.slip[k], brakes.travel[k], brakes.work[k]};
    t.elastic_energy += BrakeElement::elastic_energy(p, d, state);
    t.work += state.work;
    // The load on the body is k (s - d) (BrakeElement::compute after its return mapping).
    t.frame_load += (d - state.slip) * p.stiffness;
    t.largest_travel = std::max(t.largest_travel, state.travel);
    t.used_up += state.travel >= p.stroke ? 1 : 0;
  }
  return t;
}

}  // namespace ringdem

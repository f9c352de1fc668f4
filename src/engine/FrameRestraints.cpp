#include "engine/FrameRestraints.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "engine/ModelBuilder.hpp"
#include "physics/BrakeElement.hpp"
#include "physics/SlidingRope.hpp"

namespace ringdem {

namespace {

BrakeElement::Params brake_params(const BrakeStore& s, std::size_t k) {
  return {s.stiffness[k], s.activation_force[k], s.stroke[k]};
}

Vec3 displacement_of(const BrakeStore& s, std::size_t k, const std::vector<RigidBody>& bodies) {
  return bodies[static_cast<std::size_t>(s.body[k])].position - s.anchor[k];
}

SlidingRope::Params rope_params(const RopeStore& s, std::size_t r) {
  return {s.stiffness[r], s.rest_length[r], s.activation_force[r], s.stroke[r]};
}

}  // namespace

std::vector<std::int32_t> restrained_bodies(const Model& model) {
  std::vector<std::int32_t> held = model.brakes.body;
  held.insert(held.end(), model.ropes.nodes.begin(), model.ropes.nodes.end());
  return held;
}

void apply_restraints(Model& model) {
  BrakeStore& brakes = model.brakes;
  std::vector<RigidBody>& bodies = model.bodies;
  for (std::size_t k = 0; k < brakes.size(); ++k) {
    BrakeElement::State state{brakes.slip[k], brakes.travel[k], brakes.work[k]};
    // At the body's centre: a load without torque.
    bodies[static_cast<std::size_t>(brakes.body[k])].force +=
        BrakeElement::compute(brake_params(brakes, k), displacement_of(brakes, k, bodies), state);
    brakes.slip[k] = state.slip;
    brakes.travel[k] = state.travel;
    brakes.work[k] = state.work;
  }
  RopeStore& ropes = model.ropes;
  std::vector<Vec3> loads;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const std::vector<Vec3> path = ropes.path_of(r, bodies);
    loads.resize(path.size());
    SlidingRope::State state{ropes.slip[r], ropes.work[r]};
    ropes.tension[r] = SlidingRope::compute(rope_params(ropes, r), path, state, loads);
    ropes.slip[r] = state.slip;
    ropes.work[r] = state.work;
    // At each body's centre, as a pulley's (no torque); the anchors' loads go to the frame.
    const auto carried = ropes.bodies_of(r);
    for (std::size_t i = 0; i < carried.size(); ++i)
      bodies[static_cast<std::size_t>(carried[i])].force += loads[i + 1];
  }
}

void set_restraint_limits(const Model& model, StabilityLimits& limits) {
  const BrakeStore& brakes = model.brakes;
  for (std::size_t k = 0; k < brakes.size(); ++k)
    limits.brake = std::min(
        limits.brake, spring_time_step(model.bodies[static_cast<std::size_t>(brakes.body[k])].mass,
                                       brakes.stiffness[k]));
  const RopeStore& ropes = model.ropes;
  for (std::size_t r = 0; r < ropes.size(); ++r)
    for (const std::int32_t b : ropes.bodies_of(r))
      limits.rope =
          std::min(limits.rope, spring_time_step(model.bodies[static_cast<std::size_t>(b)].mass,
                                                 4.0 * ropes.stiffness[r]));
}

std::optional<TimeStepPlan> plan_time_steps_with_restraints(const CaseConfig& config) {
  std::optional<TimeStepPlan> plan = plan_time_steps(config);
  const bool restrained = std::any_of(config.nets.begin(), config.nets.end(), [](const auto& n) {
    return n.shackles.brake.has_value() || n.shackles.ropes.has_value();
  });
  if (!plan || !restrained) return plan;
  StabilityLimits limits{};
  set_restraint_limits(build_model_without_particles(config), limits);
  plan->tighten(limits.brake, "the brake limit sqrt(M/k) of a shackle torus on its brake",
                config.simulation.dt_safety);
  plan->tighten(limits.rope, "the rope limit sqrt(M/4k) of a shackle torus on its rope",
                config.simulation.dt_safety);
  return plan;
}

void hold_restrained_bodies(Model& model, bool held) {
  for (const std::int32_t b : restrained_bodies(model)) {
    RigidBody& body = model.bodies[static_cast<std::size_t>(b)];
    body.motion = held ? Motion::kFixed : Motion::kFree;
    if (held) body.velocity = body.omega = {};
  }
}

RestraintTotals restraint_totals(const Model& model) {
  RestraintTotals t;
  const BrakeStore& brakes = model.brakes;
  for (std::size_t k = 0; k < brakes.size(); ++k) {
    const BrakeElement::Params p = brake_params(brakes, k);
    const Vec3 d = displacement_of(brakes, k, model.bodies);
    const BrakeElement::State state{brakes.slip[k], brakes.travel[k], brakes.work[k]};
    t.elastic_energy += BrakeElement::elastic_energy(p, d, state);
    t.work += state.work;
    // The load on the body is k (s - d) (BrakeElement::compute after its return mapping).
    t.frame_load += (d - state.slip) * p.stiffness;
    t.largest_travel = std::max(t.largest_travel, state.travel);
    t.used_up += state.travel >= p.stroke ? 1 : 0;
  }
  const RopeStore& ropes = model.ropes;
  std::vector<Vec3> loads;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const SlidingRope::Params p = rope_params(ropes, r);
    const std::vector<Vec3> path = ropes.path_of(r, model.bodies);
    SlidingRope::State state{ropes.slip[r], ropes.work[r]};
    t.elastic_energy += SlidingRope::elastic_energy(p, SlidingRope::length(path), state);
    t.work += state.work;
    // The loads on a copy of the state: where the bodies moved since the step, the return
    // mapping caps the tension at F_b as the next step will.
    loads.resize(path.size());
    SlidingRope::compute(p, path, state, loads);
    t.largest_tension = std::max(t.largest_tension, ropes.tension[r]);  // the step's own
    t.frame_load += loads.front() + loads.back();
    t.largest_travel = std::max(t.largest_travel, ropes.slip[r]);  // the state, not the copy's
    const bool braked = std::isfinite(p.activation_force);
    t.used_up += braked && ropes.slip[r] >= p.stroke ? 1 : 0;
  }
  return t;
}

}  // namespace ringdem

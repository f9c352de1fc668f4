#include "engine/FrameRestraints.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <vector>

#include "engine/ModelBuilder.hpp"
#include "engine/RingMeshTerm.hpp"
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
  return {s.axial_rigidity[r], s.friction[r], s.activation_force[r], s.stroke[r]};
}

/// A rope's per-call buffers, kept between steps so that a step allocates nothing once they
/// hold the longest rope.
struct RopeBuffers {
  std::vector<Vec3> path, loads;
  std::vector<double> length, capstan, start;

  SlidingRope::Segments segments_for(const RopeStore& ropes, std::size_t r,
                                     const std::vector<RigidBody>& bodies,
                                     std::span<double> tension) {
    ropes.path_of(r, bodies, path);
    loads.resize(path.size());
    length.resize(path.size() - 1);
    capstan.resize(path.size());
    start.resize(path.size() - 1);
    return {length, tension, capstan, start, loads};
  }
};

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
  static thread_local RopeBuffers buffers;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const std::span<double> tension = std::span<double>(ropes.segment_tension)
                                          .subspan(ropes.segment_begin(r), ropes.segments_of(r));
    const SlidingRope::Segments out = buffers.segments_for(ropes, r, bodies, tension);
    SlidingRope::State state{ropes.slip[r], ropes.brake_work[r], ropes.friction_work[r]};
    SlidingRope::compute(rope_params(ropes, r), buffers.path, ropes.rest_of(r), state, out);
    ropes.slip[r] = state.slip;
    ropes.brake_work[r] = state.brake_work;
    ropes.friction_work[r] = state.friction_work;
    // At each body's centre, as a pulley's (no torque); the anchors' loads go to the frame.
    const auto carried = ropes.bodies_of(r);
    for (std::size_t i = 0; i < carried.size(); ++i)
      bodies[static_cast<std::size_t>(carried[i])].force += out.loads[i + 1];
  }
}

void set_restraint_limits(const Model& model, StabilityLimits& limits) {
  const BrakeStore& brakes = model.brakes;
  for (std::size_t k = 0; k < brakes.size(); ++k)
    limits.brake = std::min(
        limits.brake, spring_time_step(model.bodies[static_cast<std::size_t>(brakes.body[k])].mass,
                                       brakes.stiffness[k]));
  const RopeStore& ropes = model.ropes;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const std::span<const std::int32_t> carried = ropes.bodies_of(r);
    const std::span<const double> rest = ropes.rest_of(r);
    const double ea = ropes.axial_rigidity[r];
    for (std::size_t i = 0; i < carried.size(); ++i) {
      // Sliding freely, a body's move lengthens the rope by at most twice the move: 4 EA / L0.
      // Held by friction, it stretches the two segments beside it: EA (1 / l_a + 1 / l_b).
      const double stiffness = ropes.friction[r] > 0.0 ? ea * (1.0 / rest[i] + 1.0 / rest[i + 1])
                                                       : 4.0 * ea / ropes.rest_length[r];
      limits.rope = std::min(
          limits.rope,
          spring_time_step(model.bodies[static_cast<std::size_t>(carried[i])].mass, stiffness));
    }
  }
}

std::optional<TimeStepPlan> plan_time_steps_with_restraints(const CaseConfig& config) {
  std::optional<TimeStepPlan> plan = plan_time_steps(config);
  const bool restrained = std::any_of(config.nets.begin(), config.nets.end(), [](const auto& n) {
    return n.shackles.brake.has_value() || n.shackles.ropes.has_value() || n.mesh.has_value();
  });
  if (!plan || !restrained) return plan;
  StabilityLimits limits{};
  const Model model = build_model_without_particles(config);
  set_restraint_limits(model, limits);
  plan->tighten(RingMeshTerm::time_step_limit(model),
                "the mesh limit of the lightest grain a net's secondary mesh holds",
                config.simulation.dt_safety);
  plan->tighten(limits.brake, "the brake limit sqrt(M/k) of a shackle torus on its brake",
                config.simulation.dt_safety);
  plan->tighten(limits.rope, "the rope limit sqrt(M/k) of a shackle torus on its rope",
                config.simulation.dt_safety);
  return plan;
}

std::optional<std::string> restraint_step_warning(const CaseConfig& config,
                                                  const TimeStepPlan& plan) {
  if (!plan.fixed || !(plan.dt > plan.limit)) return std::nullopt;
  // Above the particles' and bonds' limit too: the loader's warning names that one.
  const std::optional<TimeStepPlan> particles = plan_time_steps(config);
  if (particles && plan.dt > particles->limit) return std::nullopt;
  return fixed_step_above_limit(plan.dt, plan.limit, plan.limit_what);
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
  RopeBuffers buffers;
  std::vector<double> rest, tension;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const SlidingRope::Params p = rope_params(ropes, r);
    const auto last_tension =
        ropes.segment_tension.begin() + static_cast<std::ptrdiff_t>(ropes.segment_begin(r));
    tension.assign(last_tension, last_tension + static_cast<std::ptrdiff_t>(ropes.segments_of(r)));
    const SlidingRope::Segments out = buffers.segments_for(ropes, r, model.bodies, tension);
    t.elastic_energy += SlidingRope::elastic_energy(p, buffers.path, ropes.rest_of(r));
    t.work += ropes.brake_work[r];
    t.friction_work += ropes.friction_work[r];
    // The loads on a copy of the state: where the bodies moved since the step, the sliders
    // slide as the next step will.
    const std::span<const double> segment_rest = ropes.rest_of(r);
    rest.assign(segment_rest.begin(), segment_rest.end());
    SlidingRope::State state{ropes.slip[r], ropes.brake_work[r], ropes.friction_work[r]};
    SlidingRope::compute(p, buffers.path, rest, state, out);
    t.frame_load += out.loads.front() + out.loads.back();
    for (std::size_t j = 0; j < ropes.segments_of(r); ++j)  // the step's own
      t.largest_tension =
          std::max(t.largest_tension, ropes.segment_tension[ropes.segment_begin(r) + j]);
    t.largest_travel = std::max(t.largest_travel, ropes.slip[r]);  // the state, not the copy's
    const bool braked = std::isfinite(p.activation_force);
    t.used_up += braked && ropes.slip[r] >= p.stroke ? 1 : 0;
  }
  return t;
}

}  // namespace ringdem

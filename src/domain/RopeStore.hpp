#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"

namespace ringdem {

/// The support ropes of a model (docs/physics.md "Support ropes"): each runs from one anchor to
/// another through rigid bodies (a net side's shackles) that slide on it. Like the bodies they
/// carry, ropes are few and replicated on every rank, and every rank updates them alike from the
/// bodies' reduced state: no migration, no ghosts. for_each_field() is the registry: the case
/// builds the parameters, checkpoints carry the state (kCheckpoint: one row per rope, or one
/// per segment for the segment columns).
struct RopeStore {
  /// Rope r runs through the bodies nodes[node_begin[r] .. node_begin[r + 1]) in order; its
  /// path has one segment more than bodies, from segment_begin(r) on in the segment columns.
  std::vector<std::int32_t> node_begin{0};
  std::vector<std::int32_t> nodes;  ///< indices into Model::bodies
  std::vector<Vec3> first_anchor, last_anchor;
  /// SlidingRope::Params, and the unstretched length the rope was laid with (sum of lambda_j).
  std::vector<double> axial_rigidity, friction, activation_force, stroke, rest_length;
  std::vector<double> slip, brake_work, friction_work;  ///< SlidingRope::State
  /// lambda_j of each segment: the rope's unstretched length between two points (state).
  std::vector<double> segment_rest;
  /// Each segment's tension of the last force evaluation [N] (apply_restraints sets it every
  /// step): for output, and the start of the next step's dissipation trapezoid (SlidingRope), so
  /// checkpointed.
  std::vector<double> segment_tension;

  std::size_t size() const { return axial_rigidity.size(); }
  bool empty() const { return axial_rigidity.empty(); }
  std::span<const std::int32_t> bodies_of(std::size_t rope) const {
    return std::span<const std::int32_t>(nodes).subspan(
        static_cast<std::size_t>(node_begin[rope]),
        static_cast<std::size_t>(node_begin[rope + 1] - node_begin[rope]));
  }
  /// Rope r's segments: from segment_begin(r), segments_of(r) of them.
  std::size_t segment_begin(std::size_t rope) const {
    return static_cast<std::size_t>(node_begin[rope]) + rope;
  }
  std::size_t segments_of(std::size_t rope) const { return bodies_of(rope).size() + 1; }
  std::span<double> rest_of(std::size_t rope) {
    return std::span<double>(segment_rest).subspan(segment_begin(rope), segments_of(rope));
  }
  std::span<const double> rest_of(std::size_t rope) const {
    return std::span<const double>(segment_rest).subspan(segment_begin(rope), segments_of(rope));
  }

  /// Rope r's path into `path`: its first anchor, the centres of the bodies it runs through, its
  /// last anchor (the vector's capacity is kept: no allocation once it holds the longest path).
  void path_of(std::size_t rope, const std::vector<RigidBody>& bodies,
               std::vector<Vec3>& path) const {
    path.clear();
    path.push_back(first_anchor[rope]);
    for (const std::int32_t b : bodies_of(rope))
      path.push_back(bodies[static_cast<std::size_t>(b)].position);
    path.push_back(last_anchor[rope]);
  }
  std::vector<Vec3> path_of(std::size_t rope, const std::vector<RigidBody>& bodies) const {
    std::vector<Vec3> path;
    path_of(rope, bodies, path);
    return path;
  }
  /// The points of all the ropes' paths together: every body on a rope and two anchors a rope.
  std::size_t path_points() const { return nodes.size() + 2 * size(); }
  /// The segments of all the ropes together.
  std::size_t segments() const { return nodes.size() + size(); }

  /// Appends a rope from `first` through `bodies` to `last`, its segments' lambda_j `rest` (one
  /// more than bodies) at tension `tension`, with zero state.
  void append(std::span<const std::int32_t> bodies, const Vec3& first, const Vec3& last,
              std::span<const double> rest, double tension, double ea, double mu, double force,
              double travel_max) {
    nodes.insert(nodes.end(), bodies.begin(), bodies.end());
    node_begin.push_back(static_cast<std::int32_t>(nodes.size()));
    first_anchor.push_back(first);
    last_anchor.push_back(last);
    axial_rigidity.push_back(ea);
    friction.push_back(mu);
    activation_force.push_back(force);
    stroke.push_back(travel_max);
    double total = 0.0;
    for (const double r : rest)
      total += r;
    rest_length.push_back(total);
    slip.push_back(0.0);
    brake_work.push_back(0.0);
    friction_work.push_back(0.0);
    segment_rest.insert(segment_rest.end(), rest.begin(), rest.end());
    segment_tension.insert(segment_tension.end(), rest.size(), tension);
  }

  template <class F>
  void for_each_field(F&& f) {
    fields(*this, f);
  }
  template <class F>
  void for_each_field(F&& f) const {
    fields(*this, f);
  }

 private:
  template <class Self, class F>
  static void fields(Self& s, F& f) {
    using namespace field_flag;
    f(FieldInfo{"node_begin", 0}, s.node_begin);
    f(FieldInfo{"nodes", 0}, s.nodes);
    f(FieldInfo{"first_anchor", 0}, s.first_anchor);
    f(FieldInfo{"last_anchor", 0}, s.last_anchor);
    f(FieldInfo{"axial_rigidity", 0}, s.axial_rigidity);
    f(FieldInfo{"friction", 0}, s.friction);
    f(FieldInfo{"activation_force", 0}, s.activation_force);
    f(FieldInfo{"stroke", 0}, s.stroke);
    f(FieldInfo{"rest_length", 0}, s.rest_length);
    f(FieldInfo{"slip", kCheckpoint}, s.slip);
    f(FieldInfo{"brake_work", kCheckpoint}, s.brake_work);
    f(FieldInfo{"friction_work", kCheckpoint}, s.friction_work);
    f(FieldInfo{"segment_rest", kCheckpoint}, s.segment_rest);
    f(FieldInfo{"segment_tension", kCheckpoint}, s.segment_tension);
  }
};

}  // namespace ringdem

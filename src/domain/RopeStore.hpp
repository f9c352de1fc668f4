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
/// builds the parameters, checkpoints carry the state (kCheckpoint, one row per rope).
struct RopeStore {
  /// Rope r runs through the bodies nodes[node_begin[r] .. node_begin[r + 1]) in order.
  std::vector<std::int32_t> node_begin{0};
  std::vector<std::int32_t> nodes;  ///< indices into Model::bodies
  std::vector<Vec3> first_anchor, last_anchor;
  std::vector<double> stiffness, rest_length, activation_force, stroke;  ///< SlidingRope::Params
  std::vector<double> slip, work;                                        ///< SlidingRope::State
  /// The tension of the last force evaluation [N]: derived (apply_restraints sets it every
  /// step), for output; not checkpointed, a restart's first evaluation sets it again.
  std::vector<double> tension;

  std::size_t size() const { return stiffness.size(); }
  bool empty() const { return stiffness.empty(); }
  std::span<const std::int32_t> bodies_of(std::size_t rope) const {
    return std::span<const std::int32_t>(nodes).subspan(
        static_cast<std::size_t>(node_begin[rope]),
        static_cast<std::size_t>(node_begin[rope + 1] - node_begin[rope]));
  }

  /// Rope r's path: its first anchor, the centres of the bodies it runs through, its last anchor.
  std::vector<Vec3> path_of(std::size_t rope, const std::vector<RigidBody>& bodies) const {
    std::vector<Vec3> path{first_anchor[rope]};
    for (const std::int32_t b : bodies_of(rope))
      path.push_back(bodies[static_cast<std::size_t>(b)].position);
    path.push_back(last_anchor[rope]);
    return path;
  }
  /// The points of all the ropes' paths together: every body on a rope and two anchors a rope.
  std::size_t path_points() const { return nodes.size() + 2 * size(); }

  /// Appends a rope from `first` through `bodies` to `last`, with zero state.
  void append(std::span<const std::int32_t> bodies, const Vec3& first, const Vec3& last, double k,
              double length, double force, double travel_max) {
    nodes.insert(nodes.end(), bodies.begin(), bodies.end());
    node_begin.push_back(static_cast<std::int32_t>(nodes.size()));
    first_anchor.push_back(first);
    last_anchor.push_back(last);
    stiffness.push_back(k);
    rest_length.push_back(length);
    activation_force.push_back(force);
    stroke.push_back(travel_max);
    slip.push_back(0.0);
    work.push_back(0.0);
    tension.push_back(0.0);
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
    f(FieldInfo{"stiffness", 0}, s.stiffness);
    f(FieldInfo{"rest_length", 0}, s.rest_length);
    f(FieldInfo{"activation_force", 0}, s.activation_force);
    f(FieldInfo{"stroke", 0}, s.stroke);
    f(FieldInfo{"slip", kCheckpoint}, s.slip);
    f(FieldInfo{"work", kCheckpoint}, s.work);
    f(FieldInfo{"tension", 0}, s.tension);
  }
};

}  // namespace ringdem

#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "core/Vec3.hpp"

namespace ringdem {

/// A rope that a net's shackles slide on (docs/physics.md "Support ropes"): a wire rope from one
/// anchor to another through a sequence of points (the shackles' centres) that it does not hold
/// along its length, only across it, as a frictionless pulley holds a cable. The tension T is
/// then the same in every segment, and the rope's energy depends only on its path length
/// L = sum |x_{i+1} - x_i| over the path: anchor, shackles, anchor.
///
///   stretch e = L - L0 - s      L0: the unstretched length, s: rope paid out by the brakes
///   T = k e for e > 0,  0 for e <= 0 (a rope carries no compression; it goes slack)
///   the load on point i: T (u_{i,i-1} + u_{i,i+1}), u_{i,j} the unit vector from i towards j
///   (one term at an anchor), which is -dE/dx_i of E = k e^2 / 2
///
/// k = EA / L0 (the rope's axial rigidity over its length). A shackle that moves along a straight
/// rope does not change L: it slides freely; one that pulls the rope sideways lengthens it.
/// Brakes at the rope's ends pay out rope once the tension reaches their activation force F_b,
/// the 1-D form of BrakeElement's Coulomb slider (one backward-Euler step per call, Simo &
/// Hughes 1998, ch. 1): with the trial tension k e above F_b, s grows by
/// ds = min(e - F_b / k, stroke - s), the tension is F_b again and the brakes dissipate F_b ds.
/// After `stroke` m the brakes are used up and the rope holds elastically at any load. The
/// stiffness stays EA / L0 while s grows (an error of s / L0 in it). The result depends only on
/// the arguments: the same bits on every rank.
struct SlidingRope {
  struct Params {
    double stiffness = 0.0;    ///< k = EA / L0 [N/m]
    double rest_length = 0.0;  ///< L0 [m]
    /// F_b [N]: the tension at which the end brakes pay out rope; infinite without brakes.
    double activation_force = std::numeric_limits<double>::infinity();
    double stroke = 0.0;  ///< [m] of rope the brakes can pay out in all, then they lock
  };
  /// Per rope: zero at creation, checkpointed.
  struct State {
    double slip = 0.0;  ///< s [m]: rope paid out by the brakes (grows only, <= stroke)
    double work = 0.0;  ///< dissipated by the brakes: the sum of F_b ds [J]
  };

  /// L: the length of the path through `path` in order.
  static double length(std::span<const Vec3> path) {
    double l = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i)
      l += norm(path[i] - path[i - 1]);
    return l;
  }

  /// The tension for the path `path` (anchor, points, anchor); `state` takes the step's slip
  /// and `loads[i]` receives the rope's load on `path[i]` (at the anchors: what the frame
  /// receives). `loads` has the size of `path`.
  static double compute(const Params& p, std::span<const Vec3> path, State& state,
                        std::span<Vec3> loads) {
    double stretch = length(path) - p.rest_length - state.slip;
    const double left = p.stroke - state.slip;
    if (stretch * p.stiffness > p.activation_force && left > 0.0) {
      const double paid_out = std::min(stretch - p.activation_force / p.stiffness, left);
      state.slip += paid_out;
      state.work += p.activation_force * paid_out;
      stretch -= paid_out;
    }
    const double tension = stretch > 0.0 ? p.stiffness * stretch : 0.0;
    for (Vec3& load : loads)
      load = {};
    if (tension == 0.0) return 0.0;
    for (std::size_t i = 1; i < path.size(); ++i) {
      const Vec3 segment = path[i] - path[i - 1];
      const double l = norm(segment);
      if (!(l > 0.0)) continue;  // two points at one place: no direction, no load
      const Vec3 pull = segment * (tension / l);
      loads[i - 1] += pull;  // towards the next point
      loads[i] -= pull;      // towards the previous one
    }
    return tension;
  }

  /// The elastic energy the rope holds: k e^2 / 2 for e > 0.
  static double elastic_energy(const Params& p, double path_length, const State& state) {
    const double stretch = path_length - p.rest_length - state.slip;
    return stretch > 0.0 ? 0.5 * p.stiffness * stretch * stretch : 0.0;
  }
};

}  // namespace ringdem

#pragma once

#include <algorithm>
#include <cmath>

#include "core/Vec3.hpp"

namespace ringdem {

/// A brake element holding a rigid body (a net's shackle) to the frame: the energy-absorbing
/// device of a ring-net barrier's ropes (docs/physics.md "Brake elements"). An elastic spring
/// of stiffness k joins the body's centre to an anchor point that slides once the spring's load
/// reaches the activation force F_b: rigid-plastic friction in series with the spring, the
/// elastic–perfectly plastic force–stroke curve by which barrier models idealise brake elements
/// (a plateau at F_b after a steep rise: Cazzani et al. 2002; the devices: Volkwein et al.
/// 2011), acting in the direction the load pulls. After `stroke` m of sliding the brake is used
/// up and holds elastically at any load.
///
/// Each call is one backward-Euler step (the return mapping of a Coulomb slider; Simo & Hughes
/// 1998, ch. 1): with the body's displacement d from its anchor and the slip s so far,
///   F_trial = -k (d - s);
///   |F_trial| <= F_b, or the stroke used up:  F = F_trial (elastic);
///   otherwise the slider moves along the load by  ds = min(|F_trial|/k - F_b/k, stroke left),
///   s += ds (d - s)/|d - s|,  F = -k (d - s),  and dissipates F_b ds.
/// Rigid motion does not exist for it (the anchor is fixed in space); a body at its anchor
/// carries no load. The result depends only on the arguments: the same bits on every rank.
struct BrakeElement {
  struct Params {
    double stiffness = 0.0;         ///< k [N/m]: the brake's rope and its elastic range
    double activation_force = 0.0;  ///< F_b [N]: the load at which it slides
    double stroke = 0.0;            ///< [m] of sliding it has; then it locks
  };
  /// Per brake: zero at creation, checkpointed.
  struct State {
    Vec3 slip;            ///< s [m]: how far the anchor has slid
    double travel = 0.0;  ///< the path length slid so far [m] (<= stroke)
    double work = 0.0;    ///< dissipated: the sum of F_b ds [J]
  };

  /// The load on the body for its displacement `d` from the anchor; `state` takes the step's
  /// slip.
  static Vec3 compute(const Params& p, const Vec3& d, State& state) {
    const Vec3 stretch = d - state.slip;
    const double length = norm(stretch);
    const double left = p.stroke - state.travel;
    if (length > 0.0 && left > 0.0) {
      const double slide = std::min(length - p.activation_force / p.stiffness, left);
      if (slide > 0.0) {
        state.slip += stretch * (slide / length);
        state.travel += slide;
        state.work += p.activation_force * slide;
      }
    }
    return (state.slip - d) * p.stiffness;
  }
  /// The elastic energy the spring holds: |F|^2 / 2k = k |d - s|^2 / 2.
  static double elastic_energy(const Params& p, const Vec3& d, const State& state) {
    return 0.5 * p.stiffness * norm2(d - state.slip);
  }
};

}  // namespace ringdem

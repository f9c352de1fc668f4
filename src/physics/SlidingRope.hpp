#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <span>

#include "core/Vec3.hpp"

namespace ringdem {

/// A rope that a net's shackles slide on (docs/physics.md "Support ropes"): a wire rope from one
/// anchor to another through a sequence of points (the shackles' centres) that hold it across its
/// length and let it slide through them, as a pulley or a slip ring holds a cable. The path
/// anchor, points, anchor has segments j = 0 .. n-1 of length l_j; each holds a share lambda_j of
/// the unstretched rope (the rope's material between two points), so that
///
///   T_j = EA (l_j - lambda_j) / lambda_j  for l_j > lambda_j,  0 otherwise (slack)
///   E   = sum_j EA (l_j - lambda_j)^2 / (2 lambda_j)  over the taut segments
///
/// and segment j pulls its two ends towards each other with T_j: the loads are -dE/dx at fixed
/// lambda. Rope slides through a point when the tensions on its two sides differ more than the
/// capstan equation allows (Euler–Eytelwein): with the rope's turn theta_i at point i and the
/// friction coefficient mu, T_high <= T_low exp(mu theta_i). Past it, rope passes from the low to
/// the high side (lambda moves between the two segments) until T_high = T_low exp(mu theta_i);
/// without friction the tension is then the same in every segment (equal strain), and a point
/// on a straight rope slides freely. Brakes at the two ends pay out rope into the end segments
/// once their tension reaches the activation force F_b (lambda_end grows until T_end = F_b),
/// the 1-D form of BrakeElement's Coulomb slider, until the two ends together have paid out
/// `stroke` m; after that the rope holds elastically at any load.
///
/// Each call is one backward-Euler step of these sliders at the call's geometry (Simo & Hughes
/// 1998, ch. 1): without friction in closed form, with it by Gauss–Seidel sweeps over the points
/// and ends, each a closed-form local slide. The step dissipates sum_j g_j d lambda_j over its
/// segments' changes d lambda_j, with the driving force -dE/d lambda_j = T_j + T_j^2 / (2 EA) =:
/// g(T_j) taken as the mean of the last step's (the tensions the call finds in `out`) and this
/// step's: the trapezoid that the energy ledger takes of the loads' work, so that the balance
/// closes to second order in the step (exactly, for an energy quadratic in x and lambda). Of
/// it the brakes take their end segments' g times what they paid out, the friction the rest.
/// The result depends only on the arguments: the same bits on every rank.
struct SlidingRope {
  struct Params {
    double axial_rigidity = 0.0;  ///< EA [N]
    double friction = 0.0;        ///< mu between the rope and the points it runs through
    /// F_b [N]: the tension at which the end brakes pay out rope; infinite without brakes.
    double activation_force = std::numeric_limits<double>::infinity();
    double stroke = 0.0;  ///< [m] of rope the two end brakes can pay out in all, then they lock
  };
  /// Per rope, besides the segments' lambda_j: zero at creation, checkpointed.
  struct State {
    double slip = 0.0;           ///< rope paid out by the brakes, both ends [m] (<= stroke)
    double brake_work = 0.0;     ///< dissipated by the brakes [J]
    double friction_work = 0.0;  ///< dissipated by the rope sliding through its points [J]
  };
  /// What one call leaves besides the state: per segment, and per path point.
  struct Segments {
    std::span<double> length;   ///< l_j [m]
    std::span<double> tension;  ///< T_j [N]: in, the last call's (or the laid rope's); out, this
    std::span<double> capstan;  ///< exp(mu theta_i) at each point (scratch; path-sized)
    std::span<double> start;    ///< lambda_j at the call's start (scratch; segment-sized)
    std::span<Vec3> loads;      ///< the rope's load on each path point [N] (at the anchors: the
                                ///< frame's)
  };

  /// The largest number of Gauss–Seidel sweeps in one call; what is left to slide slides at the
  /// next call.
  static constexpr int kMaxSweeps = 200;
  /// Relative excess of a tension ratio over the capstan factor below which nothing slides.
  static constexpr double kSlideTolerance = 1e-10;

  /// L: the length of the path through `path` in order.
  static double length(std::span<const Vec3> path) {
    double l = 0.0;
    for (std::size_t i = 1; i < path.size(); ++i)
      l += norm(path[i] - path[i - 1]);
    return l;
  }
  static double tension(double ea, double l, double rest) {
    return l > rest ? ea * (l - rest) / rest : 0.0;
  }
  static double energy(double ea, double l, double rest) {
    return l > rest ? 0.5 * ea * (l - rest) * (l - rest) / rest : 0.0;
  }
  /// g(T) = -dE/d lambda of a segment at tension T: what a slide of its lambda works against.
  static double driving_force(double ea, double t) { return t + 0.5 * t * t / ea; }

  /// The lambda_j of a rope laid along `path` at tension `pretension`: equal strain T0 / EA.
  static void lay(double ea, double pretension, std::span<const Vec3> path,
                  std::span<double> rest) {
    for (std::size_t j = 0; j + 1 < path.size(); ++j)
      rest[j] = norm(path[j + 1] - path[j]) * ea / (ea + pretension);
  }

  /// The elastic energy E the rope holds on `path` with segments `rest`.
  static double elastic_energy(const Params& p, std::span<const Vec3> path,
                               std::span<const double> rest) {
    double e = 0.0;
    for (std::size_t j = 0; j + 1 < path.size(); ++j)
      e += energy(p.axial_rigidity, norm(path[j + 1] - path[j]), rest[j]);
    return e;
  }

  /// One step on the path `path` (anchor, points, anchor): slides rope through the points and
  /// out of the brakes (updating `rest` and `state`), then fills `out`. `rest` and out's
  /// length and tension have path.size() - 1 entries, capstan and loads path.size().
  static void compute(const Params& p, std::span<const Vec3> path, std::span<double> rest,
                      State& state, const Segments& out) {
    const std::size_t n = path.size() - 1;
    for (std::size_t j = 0; j < n; ++j)
      out.length[j] = norm(path[j + 1] - path[j]);
    if (p.friction > 0.0)
      slide_with_friction(p, path, rest, state, out);
    else
      slide_freely(p, rest, state, out.length, out.tension[0]);
    for (Vec3& load : out.loads)
      load = {};
    for (std::size_t j = 0; j < n; ++j) {
      const double t = tension(p.axial_rigidity, out.length[j], rest[j]);
      out.tension[j] = t;
      if (t == 0.0) continue;  // slack (or two points at one place: no direction)
      const Vec3 pull = (path[j + 1] - path[j]) * (t / out.length[j]);
      out.loads[j] += pull;      // towards the next point
      out.loads[j + 1] -= pull;  // towards the previous one
    }
  }

 private:
  static bool braked(const Params& p) { return std::isfinite(p.activation_force); }

  /// Without friction: one tension, T = EA (L - Lambda) / Lambda over the path length L and the
  /// rope's unstretched length Lambda = sum lambda_j, which the brakes raise to EA L / (EA + F_b)
  /// where T exceeds F_b; the segments then share Lambda in proportion to their lengths.
  static void slide_freely(const Params& p, std::span<double> rest, State& state,
                           std::span<const double> length, double last_tension) {
    const double ea = p.axial_rigidity;
    double total_length = 0.0, total_rest = 0.0;
    for (std::size_t j = 0; j < rest.size(); ++j) {
      total_length += length[j];
      total_rest += rest[j];
    }
    if (braked(p) && tension(ea, total_length, total_rest) > p.activation_force &&
        state.slip < p.stroke) {
      const double paid_out = std::min(ea * total_length / (ea + p.activation_force) - total_rest,
                                       p.stroke - state.slip);
      if (paid_out > 0.0) {
        state.slip += paid_out;
        total_rest += paid_out;
        state.brake_work += 0.5 *
                            (driving_force(ea, last_tension) +
                             driving_force(ea, tension(ea, total_length, total_rest))) *
                            paid_out;
      }
    }
    if (!(total_length > 0.0)) return;
    const double share = total_rest / total_length;
    for (std::size_t j = 0; j < rest.size(); ++j)
      rest[j] = length[j] * share;
  }

  /// Moves rope into segment `to` out of segment `from` (whose tensions are T_to > c T_from)
  /// until T_to = c T_from. With A the new lambda_to and
  /// S = lambda_to + lambda_from: l_to / A - 1 = c (l_from / (S - A) - 1), the one root of
  /// (c - 1) A^2 + (l_to + c l_from - (c - 1) S) A - l_to S = 0 in (0, S); where that root
  /// would leave both slack, A = l_to (the to segment just slack).
  static void slide(double c, double l_to, double& rest_to, double l_from, double& rest_from) {
    const double s = rest_to + rest_from;
    const double alpha = c - 1.0;
    const double beta = l_to + c * l_from - alpha * s;
    const double root = std::sqrt(beta * beta + 4.0 * alpha * l_to * s);
    double a = beta > 0.0 ? 2.0 * l_to * s / (beta + root) : (root - beta) / (2.0 * alpha);
    a = std::clamp(a, rest_to, std::max(rest_to, std::min(l_to, s)));
    rest_to = a;
    rest_from = s - a;
  }

  /// An end brake on segment j: lambda_j grows to EA l_j / (EA + F_b) (T_j = F_b), at most by
  /// what is left of the stroke. Returns what it paid out.
  static double pay_out(const Params& p, std::size_t j, std::span<double> rest, State& state,
                        std::span<const double> length) {
    const double ea = p.axial_rigidity;
    if (!(tension(ea, length[j], rest[j]) > p.activation_force) || !(state.slip < p.stroke))
      return 0.0;
    const double paid_out =
        std::min(ea * length[j] / (ea + p.activation_force) - rest[j], p.stroke - state.slip);
    if (!(paid_out > 0.0)) return 0.0;
    state.slip += paid_out;
    rest[j] += paid_out;
    return paid_out;
  }

  static void slide_with_friction(const Params& p, std::span<const Vec3> path,
                                  std::span<double> rest, State& state, const Segments& out) {
    const double ea = p.axial_rigidity;
    const std::size_t n = rest.size();
    const std::span<const double> length = out.length;
    // The rope turns by theta_i at point i, the angle between its segments' directions there.
    for (std::size_t i = 1; i < n; ++i) {
      const double lengths = length[i - 1] * length[i];
      double theta = 0.0;
      if (lengths > 0.0) {
        const double cosine = dot(path[i] - path[i - 1], path[i + 1] - path[i]) / lengths;
        theta = std::acos(std::clamp(cosine, -1.0, 1.0));
      }
      out.capstan[i] = std::exp(p.friction * theta);
    }
    std::copy(rest.begin(), rest.end(), out.start.begin());
    double paid_first = 0.0, paid_last = 0.0;
    for (int sweep = 0; sweep < kMaxSweeps; ++sweep) {
      bool moved = false;
      if (braked(p)) {
        const double first = pay_out(p, 0, rest, state, length);
        const double last = pay_out(p, n - 1, rest, state, length);
        paid_first += first;
        paid_last += last;
        moved = moved || first > 0.0 || last > 0.0;
      }
      for (std::size_t i = 1; i < n; ++i) {
        const double c = out.capstan[i] * (1.0 + kSlideTolerance);
        const double before = tension(ea, length[i - 1], rest[i - 1]);
        const double after = tension(ea, length[i], rest[i]);
        if (before > c * after) {
          slide(out.capstan[i], length[i - 1], rest[i - 1], length[i], rest[i]);
          moved = true;
        } else if (after > c * before) {
          slide(out.capstan[i], length[i], rest[i], length[i - 1], rest[i - 1]);
          moved = true;
        }
      }
      if (!moved) break;
    }
    // The step's dissipation: the trapezoid of g over each segment's change (out.tension still
    // holds the last step's tensions; compute() writes this step's after).
    const auto mean_force = [&](std::size_t j) {
      return 0.5 * (driving_force(ea, out.tension[j]) +
                    driving_force(ea, tension(ea, length[j], rest[j])));
    };
    double dissipated = 0.0;
    for (std::size_t j = 0; j < n; ++j)
      if (rest[j] != out.start[j]) dissipated += mean_force(j) * (rest[j] - out.start[j]);
    const double braking = mean_force(0) * paid_first + mean_force(n - 1) * paid_last;
    state.brake_work += braking;
    state.friction_work += dissipated - braking;
  }
};

}  // namespace ringdem

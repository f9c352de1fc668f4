// The support rope (physics/SlidingRope.hpp, docs/physics.md "Support ropes") against closed
// forms: its loads are minus the gradient of its energy and balance each other, a point slides
// freely along a straight rope, a V hangs with the tension of statics, a slack rope holds
// nothing, its brakes pay out rope at the activation force until their stroke is used up, and
// with friction a point holds until the tensions beside it reach the capstan ratio exp(mu theta),
// a rope wrapped over many points slides at exp(mu x total turn) (Euler–Eytelwein), and what the
// sliders take is the work put in less what the rope holds.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/SlidingRope.hpp"

namespace ringdem {
namespace {

constexpr double kRigidity = 1.2e7;  // EA [N]: a 3 m rope of k = EA / L0 = 4e6 N/m

/// A rope along `path` with rest lengths laid at `pretension` (or given), its state and buffers.
struct Rope {
  SlidingRope::Params params;
  std::vector<Vec3> path;
  std::vector<double> rest, length, tension, capstan, start;
  std::vector<Vec3> loads;
  SlidingRope::State state;

  Rope(std::vector<Vec3> points, double pretension, double friction = 0.0)
      : path(std::move(points)),
        rest(path.size() - 1),
        length(path.size() - 1),
        tension(path.size() - 1),
        capstan(path.size()),
        start(path.size() - 1),
        loads(path.size()) {
    params.axial_rigidity = kRigidity;
    params.friction = friction;
    SlidingRope::lay(kRigidity, pretension, path, rest);
  }
  /// Shortens every segment's rest length in proportion, to a total of `total`.
  void set_total_rest(double total) {
    double sum = 0.0;
    for (const double r : rest)
      sum += r;
    for (double& r : rest)
      r *= total / sum;
  }
  void step() {
    SlidingRope::compute(params, path, rest, state, {length, tension, capstan, start, loads});
  }
  double energy() const { return SlidingRope::elastic_energy(params, path, rest); }
  double total_rest() const {
    double sum = 0.0;
    for (const double r : rest)
      sum += r;
    return sum;
  }
};

double& component(Vec3& v, int axis) {
  return axis == 0 ? v.x : axis == 1 ? v.y : v.z;
}

// A bent path of five points, 2 mm longer than the rope: taut.
const std::vector<Vec3> kBentPath{
    {0.0, 0.0, 0.0}, {0.7, 0.1, -0.2}, {1.3, -0.05, -0.3}, {2.1, 0.2, -0.1}, {2.9, 0.0, 0.05}};

TEST(SlidingRope, ItsLoadsAreMinusTheGradientOfItsEnergyAndBalance) {
  for (const double friction : {0.0, 0.3}) {
    Rope rope(kBentPath, 0.0, friction);
    rope.set_total_rest(SlidingRope::length(kBentPath) - 2.0e-3);
    if (friction > 0.0) rope.rest[1] *= 0.999;  // unequal tensions, held by friction
    rope.step();
    Vec3 sum;
    for (const Vec3& f : rope.loads)
      sum += f;
    EXPECT_LT(norm(sum), 1e-9);  // tensions ~ 10 kN: internal forces cancel to rounding
    // Central differences of E at the step's lambda_j, every point and axis (O(h^2)).
    const double h = 1.0e-6;
    for (std::size_t i = 0; i < kBentPath.size(); ++i) {
      for (int axis = 0; axis < 3; ++axis) {
        Rope plus = rope, minus = rope;
        component(plus.path[i], axis) += h;
        component(minus.path[i], axis) -= h;
        const double gradient = (plus.energy() - minus.energy()) / (2.0 * h);
        EXPECT_NEAR(component(rope.loads[i], axis), -gradient, 1e-6 * 1.0e4)
            << "friction " << friction << " point " << i << " axis " << axis;
      }
    }
  }
}

TEST(SlidingRope, APointOnAStraightRopeSlidesFreely) {
  // Anchors 3 m apart on x, the rope 1 mm short of them: EA (L - L0) / L0 = 4 kN along it,
  // wherever the point is. With friction too: a straight rope presses on nothing (theta = 0).
  for (const double friction : {0.0, 0.5}) {
    for (const double at : {0.3, 1.5, 2.2}) {
      Rope rope({{0, 0, 0}, {1.5, 0, 0}, {3.0, 0, 0}}, 0.0, friction);
      rope.set_total_rest(2.999);
      rope.path[1].x = at;
      rope.step();
      const double expected = kRigidity * 1.0e-3 / 2.999;
      for (const double t : rope.tension)
        EXPECT_NEAR(t, expected, 1e-9 * expected) << at;
      EXPECT_LT(norm(rope.loads[1]), 1e-6);                     // no load along the rope
      EXPECT_NEAR(rope.loads[0].x, expected, 1e-9 * expected);  // the anchors pulled in
      EXPECT_NEAR(rope.loads[2].x, -expected, 1e-9 * expected);
      EXPECT_NEAR(rope.total_rest(), 2.999, 1e-12);  // rope slid through, none created
    }
  }
}

TEST(SlidingRope, APointPulledSidewaysHangsAsInStatics) {
  // Anchors at x = -a, a; the point at depth h: each half of length c = sqrt(a^2 + h^2) pulls
  // it up with T h / c, so the rope holds 2 T h / c with T = EA (2 c - L0) / L0.
  const double a = 1.5, h = 0.12, c = std::hypot(a, h);
  Rope rope({{-a, 0, 0}, {0, 0, -h}, {a, 0, 0}}, 0.0);
  rope.set_total_rest(3.0);
  rope.step();
  const double t = kRigidity * (2.0 * c - 3.0) / 3.0;
  EXPECT_NEAR(rope.tension[0], t, 1e-9 * t);
  EXPECT_NEAR(rope.tension[1], t, 1e-9 * t);
  EXPECT_NEAR(rope.loads[1].z, 2.0 * t * h / c, 1e-9 * t);
  EXPECT_NEAR(rope.loads[1].x, 0.0, 1e-9 * t);
  const double energy = 0.5 * kRigidity * (2.0 * c - 3.0) * (2.0 * c - 3.0) / 3.0;
  EXPECT_NEAR(rope.energy(), energy, 1e-9 * energy);
}

TEST(SlidingRope, ASlackRopeHoldsNothing) {
  Rope rope({{0, 0, 0}, {1.0, 0.0, -0.1}, {3.0, 0, 0}}, 0.0, 0.3);
  rope.set_total_rest(3.2);  // longer than the 3.0 m path
  rope.step();
  for (const Vec3& f : rope.loads)
    EXPECT_EQ(f, Vec3{});
  for (const double t : rope.tension)
    EXPECT_EQ(t, 0.0);
  EXPECT_EQ(rope.energy(), 0.0);
  EXPECT_EQ(rope.state.friction_work, 0.0);
}

TEST(SlidingRope, ItsBrakesPayOutRopeAtTheActivationForceUntilTheStrokeIsUsedUp) {
  Rope rope({{-1.5, 0, 0}, {0, 0, 0}, {1.5, 0, 0}}, 0.0);
  rope.set_total_rest(3.0);
  rope.params.activation_force = 2.0e3;  // reached at 0.5 mm of stretch
  rope.params.stroke = 0.05;
  double paid_work = 0.0;
  // Pull the middle point down in small steps; the work done on the rope goes into its spring
  // and its brakes (trapezoid of the point's load over the path).
  double before = 0.0;
  const int steps = 20000;
  const double depth = 0.45;  // path 3.131 m: 131 mm of stretch, more than the stroke
  const double ea = kRigidity, fb = rope.params.activation_force;
  for (int i = 1; i <= steps; ++i) {
    const double previous = rope.path[1].z;
    rope.path[1].z = -depth * i / steps;
    rope.step();
    const double load = rope.loads[1].z;
    paid_work -= 0.5 * (before + load) * (rope.path[1].z - previous);
    before = load;
    const double length = SlidingRope::length(rope.path);
    // Lambda where T = F_b: EA L / (EA + F_b).
    const double plateau = ea * length / (ea + fb);
    if (plateau <= 3.0) {
      EXPECT_EQ(rope.state.slip, 0.0) << "below F_b nothing is paid out";
    } else if (plateau - 3.0 < rope.params.stroke) {
      EXPECT_NEAR(rope.tension[0], fb, 1e-9 * fb) << "on the plateau";
      EXPECT_NEAR(rope.tension[1], fb, 1e-9 * fb) << "on the plateau";
      EXPECT_NEAR(rope.state.slip, plateau - 3.0, 1e-12);
    }
  }
  // Used up: the slip is the stroke, and the rope holds elastically above F_b.
  const double length = SlidingRope::length(rope.path);
  EXPECT_EQ(rope.state.slip, rope.params.stroke);
  const double lambda = 3.0 + rope.params.stroke;
  EXPECT_NEAR(rope.tension[0], ea * (length - lambda) / lambda, 1e-9 * rope.tension[0]);
  EXPECT_GT(rope.tension[0], 10.0 * fb);
  // The brakes worked at about F_b over the stroke (above it while a step's trial overshoots).
  EXPECT_NEAR(rope.state.brake_work, fb * rope.params.stroke, 1e-3 * fb * rope.params.stroke);
  // The work put in is the spring's energy plus the brakes' work, to the trapezoid's error.
  EXPECT_NEAR(paid_work, rope.energy() + rope.state.brake_work, 1e-5 * paid_work);
}

// A V of one point between two anchors, the point moved along x: friction holds it until the
// tension on one side reaches exp(mu theta) times the other's (theta the rope's turn there),
// then rope slides through and the ratio stays at that bound.
TEST(SlidingRope, FrictionHoldsAPointUntilTheCapstanRatio) {
  const double mu = 0.3;
  Rope rope({{-1.0, 0, 0}, {0, 0, -0.4}, {1.0, 0, 0}}, 5.0e3, mu);
  rope.step();
  EXPECT_NEAR(rope.tension[0], 5.0e3, 1e-9 * 5.0e3);
  EXPECT_NEAR(rope.tension[1], 5.0e3, 1e-9 * 5.0e3);
  const std::vector<double> laid = rope.rest;
  bool slid = false;
  for (int i = 1; i <= 400; ++i) {
    const double work_before = rope.state.friction_work;
    const std::vector<double> rest_before = rope.rest;
    rope.path[1].x = 0.3 * i / 400.0;  // towards the right anchor
    const Vec3 u = normalized(rope.path[1] - rope.path[0]);
    const Vec3 v = normalized(rope.path[2] - rope.path[1]);
    const double theta = std::acos(dot(u, v));
    const double bound = std::exp(mu * theta);
    // What the slide released at this geometry: E with the old lambda less E with the new.
    Rope held = rope;
    held.rest = rest_before;
    const double energy_held = held.energy();
    rope.step();
    const double ratio = rope.tension[0] / rope.tension[1];
    EXPECT_LE(ratio, bound * (1.0 + 1e-9)) << "step " << i;
    if (rope.rest == rest_before) {
      EXPECT_EQ(rope.state.friction_work, work_before);
    } else {
      slid = true;
      // Sliding: at the capstan bound, the left (longer, pulled) side the high one; the rope
      // passed from the right segment to the left.
      EXPECT_NEAR(ratio, bound, 1e-9 * bound) << "step " << i;
      EXPECT_GT(rope.rest[0], rest_before[0]);
      EXPECT_NEAR(rope.rest[0] + rope.rest[1], rest_before[0] + rest_before[1], 1e-14);
      // It dissipates, and no more than the slide released of the rope's energy at this
      // geometry (the rest: the trial's overshoot, which the slide's end state no longer holds).
      const double released = energy_held - rope.energy();
      const double dissipated = rope.state.friction_work - work_before;
      EXPECT_GT(dissipated, 0.0);
      EXPECT_LE(dissipated, released * (1.0 + 1e-12)) << "step " << i;
    }
  }
  EXPECT_TRUE(slid);
  EXPECT_NE(rope.rest, laid);
  // The same pull without friction: equal tensions all along.
  Rope free({{-1.0, 0, 0}, {0.3, 0, -0.4}, {1.0, 0, 0}}, 5.0e3, 0.0);
  free.rest = laid;
  free.step();
  EXPECT_NEAR(free.tension[0], free.tension[1], 1e-12 * free.tension[0]);
  EXPECT_EQ(free.state.friction_work, 0.0);
}

// A rope wrapped half round a drum of points (it turns by pi / 8 at each of 8 points), one
// anchor pulled away along the rope: once all of it slides, the tension falls from the pulled
// end to the held one by exp(mu x pi), the capstan equation over the whole wrap.
TEST(SlidingRope, ARopeWrappedOverManyPointsSlidesAtTheCapstanRatioOfTheWholeTurn) {
  const double mu = 0.2, radius = 0.5;
  const int points = 8;
  std::vector<Vec3> path;
  double turn = 0.0;
  for (int k = 0; k < points; ++k) {
    // Points on the upper half circle at angles pi - pi (k + 0.5) / 8: each chord turns by
    // pi / 8 from the last, and the vertical ends by pi / 8 from the outer chords.
    const double phi = M_PI - M_PI * (k + 0.5) / points;
    path.push_back({radius * std::cos(phi), 0, radius * std::sin(phi)});
  }
  path.insert(path.begin(), {path.front().x, 0, -1.0});  // the held end, below the first point
  path.push_back({path.back().x, 0, -1.0});              // the pulled end, below the last
  Rope rope(path, 1.0e3, mu);
  for (std::size_t i = 1; i + 1 < path.size(); ++i)
    turn += std::acos(dot(normalized(path[i] - path[i - 1]), normalized(path[i + 1] - path[i])));
  EXPECT_NEAR(turn, M_PI, 1e-12);
  double ratio = 1.0;
  const double initial = rope.energy();
  rope.step();
  double paid_work = 0.0, load_before = rope.loads.back().z;
  for (int i = 1; i <= 3000; ++i) {
    const double previous = rope.path.back().z;
    rope.path.back().z = -1.0 - 0.03 * i / 3000.0;
    rope.step();
    ratio = rope.tension.back() / rope.tension.front();
    paid_work -= 0.5 * (load_before + rope.loads.back().z) * (rope.path.back().z - previous);
    load_before = rope.loads.back().z;
  }
  EXPECT_NEAR(ratio, std::exp(mu * M_PI), 1e-6 * ratio);
  // The work put in at the pulled end is what the rope holds and what the eight slip rings took,
  // where each step slides rope through many of them at once.
  EXPECT_GT(rope.state.friction_work, 0.1 * paid_work);
  EXPECT_NEAR(paid_work, rope.energy() - initial + rope.state.friction_work, 1e-6 * paid_work);
  EXPECT_GT(rope.tension.back(), 10.0e3);
  // Each segment's tension is exp(mu x the turn before it) times the held end's.
  double before = 0.0;
  for (std::size_t j = 1; j < rope.tension.size(); ++j) {
    before += std::acos(dot(normalized(rope.path[j] - rope.path[j - 1]),
                            normalized(rope.path[j + 1] - rope.path[j])));
    EXPECT_NEAR(rope.tension[j] / rope.tension[0], std::exp(mu * before), 1e-6) << j;
  }
}

/// The V's point pulled sideways and back and down in `steps` steps: the work put in (minus the
/// trapezoid of the rope's load on the point over each move) less what the rope then holds and
/// what its friction took.
struct PullBalance {
  double paid_work = 0.0, stored = 0.0, friction_work = 0.0;
  double residual() const { return paid_work - stored - friction_work; }
};
PullBalance pull_sideways(int steps) {
  Rope rope({{-1.0, 0, 0}, {0, 0, -0.4}, {1.0, 0, 0}}, 5.0e3, 0.4);
  const double initial = rope.energy();
  rope.step();
  PullBalance b;
  Vec3 load_before = rope.loads[1];
  for (int i = 1; i <= steps; ++i) {
    const double s = static_cast<double>(i) / steps;
    const Vec3 previous = rope.path[1];
    rope.path[1] = {0.3 * std::sin(2.0 * M_PI * s), 0, -0.4 - 0.05 * s};
    rope.step();
    b.paid_work -= dot(0.5 * (load_before + rope.loads[1]), rope.path[1] - previous);
    load_before = rope.loads[1];
  }
  b.stored = rope.energy() - initial;
  b.friction_work = rope.state.friction_work;
  return b;
}

// Friction takes energy both ways, and the balance closes as the steps shrink: to 2e-5 of the
// work at 30 000 steps, and four times closer at twice as many (second order, as the
// trapezoid and the return mapping's end-of-step force).
TEST(SlidingRope, ThePulledInWorkIsWhatTheRopeHoldsAndItsFrictionTook) {
  const PullBalance coarse = pull_sideways(30000), fine = pull_sideways(60000);
  EXPECT_GT(coarse.friction_work, 0.1 * coarse.paid_work);
  EXPECT_LT(std::abs(coarse.residual()), 2e-5 * coarse.paid_work);
  EXPECT_LT(std::abs(fine.residual()), 0.3 * std::abs(coarse.residual()))
      << coarse.residual() << " then " << fine.residual();
  EXPECT_NEAR(fine.friction_work, coarse.friction_work, 1e-3 * coarse.friction_work);
}

}  // namespace
}  // namespace ringdem

// The support rope (physics/SlidingRope.hpp, docs/physics.md "Support ropes") against closed
// forms: its loads are minus the gradient of its energy and balance each other, a point slides
// freely along a straight rope, a V hangs with the tension of statics, a slack rope holds
// nothing, and its brakes pay out rope at the activation force until their stroke is used up.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "physics/SlidingRope.hpp"

namespace ringdem {
namespace {

constexpr double kRopeStiffness = 4.0e6;  // k = EA / L0 [N/m]

SlidingRope::Params rope_of_length(double rest_length) {
  SlidingRope::Params p;
  p.stiffness = kRopeStiffness;
  p.rest_length = rest_length;
  return p;
}

std::vector<Vec3> loads_on(const SlidingRope::Params& p, const std::vector<Vec3>& path,
                           SlidingRope::State& state, double* tension = nullptr) {
  std::vector<Vec3> loads(path.size());
  const double t = SlidingRope::compute(p, path, state, loads);
  if (tension) *tension = t;
  return loads;
}

// A bent path of five points, 2 mm longer than the rope: taut.
const std::vector<Vec3> kBentPath{
    {0.0, 0.0, 0.0}, {0.7, 0.1, -0.2}, {1.3, -0.05, -0.3}, {2.1, 0.2, -0.1}, {2.9, 0.0, 0.05}};

TEST(SlidingRope, ItsLoadsAreMinusTheGradientOfItsEnergyAndBalance) {
  const SlidingRope::Params p = rope_of_length(SlidingRope::length(kBentPath) - 2.0e-3);
  SlidingRope::State state;
  const std::vector<Vec3> loads = loads_on(p, kBentPath, state);
  Vec3 sum;
  for (const Vec3& f : loads)
    sum += f;
  EXPECT_LT(norm(sum), 1e-9);  // tension ~ 8 kN: internal forces cancel to rounding
  // Central differences of E = k e^2 / 2 at every point and axis (O(h^2) = 1e-12 relative).
  const double h = 1.0e-6;
  for (std::size_t i = 0; i < kBentPath.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      std::vector<Vec3> plus = kBentPath, minus = kBentPath;
      (axis == 0 ? plus[i].x : axis == 1 ? plus[i].y : plus[i].z) += h;
      (axis == 0 ? minus[i].x : axis == 1 ? minus[i].y : minus[i].z) -= h;
      const double gradient = (SlidingRope::elastic_energy(p, SlidingRope::length(plus), state) -
                               SlidingRope::elastic_energy(p, SlidingRope::length(minus), state)) /
                              (2.0 * h);
      const double load = axis == 0 ? loads[i].x : axis == 1 ? loads[i].y : loads[i].z;
      EXPECT_NEAR(load, -gradient, 1e-6 * 8.0e3) << "point " << i << " axis " << axis;
    }
  }
}

TEST(SlidingRope, APointOnAStraightRopeSlidesFreely) {
  // Anchors 3 m apart on x, the rope 1 mm short of them: 4 kN along it.
  const SlidingRope::Params p = rope_of_length(2.999);
  for (const double at : {0.3, 1.5, 2.2}) {
    SlidingRope::State state;
    double tension = 0.0;
    const std::vector<Vec3> loads =
        loads_on(p, {{0, 0, 0}, {at, 0, 0}, {3.0, 0, 0}}, state, &tension);
    EXPECT_NEAR(tension, kRopeStiffness * 1.0e-3, 1e-9 * tension);  // wherever the point is
    EXPECT_LT(norm(loads[1]), 1e-9);                                // no load along the rope
    EXPECT_NEAR(loads[0].x, tension, 1e-9 * tension);               // the anchors pulled in
    EXPECT_NEAR(loads[2].x, -tension, 1e-9 * tension);
  }
}

TEST(SlidingRope, APointPulledSidewaysHangsAsInStatics) {
  // Anchors at x = -a, a; the point at depth h: each half of length c = sqrt(a^2 + h^2) pulls
  // it up with T h / c, so the rope holds 2 T h / c with T = k (2 c - L0).
  const double a = 1.5, h = 0.12, c = std::hypot(a, h);
  const SlidingRope::Params p = rope_of_length(3.0);
  SlidingRope::State state;
  double tension = 0.0;
  const std::vector<Vec3> loads = loads_on(p, {{-a, 0, 0}, {0, 0, -h}, {a, 0, 0}}, state, &tension);
  EXPECT_NEAR(tension, kRopeStiffness * (2.0 * c - 3.0), 1e-9 * tension);
  EXPECT_NEAR(loads[1].z, 2.0 * tension * h / c, 1e-9 * tension);
  EXPECT_NEAR(loads[1].x, 0.0, 1e-9 * tension);
  EXPECT_NEAR(SlidingRope::elastic_energy(p, 2.0 * c, state),
              0.5 * tension * tension / kRopeStiffness, 1e-9 * tension * tension / kRopeStiffness);
}

TEST(SlidingRope, ASlackRopeHoldsNothing) {
  const SlidingRope::Params p = rope_of_length(3.2);  // longer than the 3.0 m path
  SlidingRope::State state;
  double tension = -1.0;
  for (const Vec3& f : loads_on(p, {{0, 0, 0}, {1.0, 0.0, -0.1}, {3.0, 0, 0}}, state, &tension))
    EXPECT_EQ(f, Vec3{});
  EXPECT_EQ(tension, 0.0);
  EXPECT_EQ(SlidingRope::elastic_energy(p, 3.0, state), 0.0);
}

TEST(SlidingRope, ItsBrakesPayOutRopeAtTheActivationForceUntilTheStrokeIsUsedUp) {
  SlidingRope::Params p = rope_of_length(3.0);
  p.activation_force = 2.0e3;  // reached at 0.5 mm of stretch
  p.stroke = 0.05;
  SlidingRope::State state;
  double paid_work = 0.0;
  // Pull the middle point down in small steps; the work done on the rope goes into its spring
  // and its brakes (trapezoid of the point's load over the path).
  std::vector<Vec3> path{{-1.5, 0, 0}, {0, 0, 0}, {1.5, 0, 0}};
  double before = 0.0;
  double tension = 0.0;
  const int steps = 20000;
  const double depth = 0.45;  // path 3.131 m: 131 mm of stretch, more than the stroke
  for (int i = 1; i <= steps; ++i) {
    const double z = -depth * i / steps;
    const Vec3 previous = path[1];
    path[1] = {0, 0, z};
    const double load = loads_on(p, path, state, &tension)[1].z;
    paid_work -= 0.5 * (before + load) * (path[1].z - previous.z);
    before = load;
    const double stretch = SlidingRope::length(path) - p.rest_length;
    if (stretch < 0.5e-3) {
      EXPECT_EQ(state.slip, 0.0) << "below F_b nothing is paid out";
    } else if (stretch - p.activation_force / p.stiffness < p.stroke) {
      EXPECT_NEAR(tension, p.activation_force, 1e-9 * p.activation_force) << "on the plateau";
      EXPECT_NEAR(state.slip, stretch - p.activation_force / p.stiffness, 1e-12);
    }
  }
  // Used up: the slip is the stroke, and the rope holds elastically above F_b.
  const double stretch = SlidingRope::length(path) - p.rest_length;
  EXPECT_EQ(state.slip, p.stroke);
  EXPECT_NEAR(tension, p.stiffness * (stretch - p.stroke), 1e-9 * tension);
  EXPECT_GT(tension, 10.0 * p.activation_force);
  EXPECT_NEAR(state.work, p.activation_force * p.stroke, 1e-12 * state.work);  // summed in steps
  // The work put in is the spring's energy plus the brakes' work, to the discretisation (the
  // return mapping's k ds^2 / 2 per step and the trapezoid).
  const double stored = SlidingRope::elastic_energy(p, SlidingRope::length(path), state);
  EXPECT_NEAR(paid_work, stored + state.work, 1e-4 * paid_work);
}

}  // namespace
}  // namespace ringdem

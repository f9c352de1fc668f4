// The bounds the neighbour-list test reads (engine/MoveBounds, docs/physics.md "Neighbour
// search"): each must hold for every velocity in the box it is given, and be reached by one
// (a corner), so that it is as tight as the box allows.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "engine/MoveBounds.hpp"

namespace ringdem {
namespace {

Integrator::VelocityBox box_of(const Vec3& low, const Vec3& high) {
  Integrator::VelocityBox b;
  b.add(low);
  b.add(high);
  return b;
}

std::vector<Vec3> corners(const Integrator::VelocityBox& b) {
  std::vector<Vec3> out;
  for (int i = 0; i < 8; ++i)
    out.push_back(
        {i & 1 ? b.high.x : b.low.x, i & 2 ? b.high.y : b.low.y, i & 4 ? b.high.z : b.low.z});
  return out;
}

// Random boxes and directions: no velocity drawn in the box is farther from its centre than
// the half diagonal or has a larger |n . v| than largest_speed_along(); a corner reaches each
// (to round-off, 1e-14 relative).
TEST(MoveBounds, HalfDiagonalAndSpeedAlongBoundTheBoxAndACornerReachesThem) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Vec3 a{20.0 * u(rng), 3.0 * u(rng), u(rng)}, b{20.0 * u(rng), 3.0 * u(rng), u(rng)};
    const Integrator::VelocityBox box =
        box_of({std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)},
               {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)});
    Vec3 n{u(rng), u(rng), u(rng)};
    n = n * (1.0 / norm(n));
    const Vec3 centre = (box.low + box.high) * 0.5;
    const double half = MoveBounds::half_diagonal(box);
    const double along = MoveBounds::largest_speed_along(box, n);
    std::uniform_real_distribution<double> fx(box.low.x, box.high.x), fy(box.low.y, box.high.y),
        fz(box.low.z, box.high.z);
    for (int k = 0; k < 100; ++k) {
      const Vec3 v{fx(rng), fy(rng), fz(rng)};
      ASSERT_LE(norm(v - centre), half * (1.0 + 1e-14)) << "trial " << trial;
      ASSERT_LE(std::abs(dot(n, v)), along * (1.0 + 1e-14)) << "trial " << trial;
    }
    double farthest = 0.0, fastest = 0.0;
    for (const Vec3& c : corners(box)) {
      farthest = std::max(farthest, norm(c - centre));
      fastest = std::max(fastest, std::abs(dot(n, c)));
    }
    EXPECT_NEAR(farthest, half, 1e-14 * half) << "trial " << trial;
    EXPECT_NEAR(fastest, along, 1e-14 * (1.0 + along)) << "trial " << trial;
  }
  // An empty box (no particles anywhere) moves nothing.
  EXPECT_EQ(MoveBounds::half_diagonal(Integrator::VelocityBox{}), 0.0);
  EXPECT_EQ(MoveBounds::largest_speed_along(Integrator::VelocityBox{}, {0, 0, 1}), 0.0);
}

// A flow at 10 m/s along x over a fixed floor, beside a post and a moving wall: the relative
// bound grows by the box's half diagonal, the floor's by the largest speed along its normal,
// and the post's, the moving plane's and the absolute one by the largest speed. Where the box
// is wider than the speeds allow (one particle at +10, one at -10 m/s), the largest speed.
TEST(MoveBounds, EachBoundTakesTheSpeedItsTestNeeds) {
  RigidBody floor;  // a plane z = 0, fixed
  RigidBody post;
  post.shape = RigidShape::kCylinder;
  post.radius = 0.05;
  post.half_length = 1.0;
  RigidBody wall;
  wall.motion = Motion::kPrescribed;
  const std::vector<RigidBody> bodies{floor, post, wall};
  MoveBounds m;
  m.reset(bodies);
  const double dt = 1e-5;
  const Integrator::VelocityBox flow = box_of({9.9, -0.2, -0.1}, {10.1, 0.2, 0.3});
  const double fastest = norm(Vec3{10.1, 0.2, 0.3});
  m.advance(fastest, flow, bodies, dt);
  m.advance(fastest, flow, bodies, dt);
  EXPECT_DOUBLE_EQ(m.absolute(), 2 * fastest * dt);
  EXPECT_DOUBLE_EQ(m.relative(), 2 * 0.5 * norm(Vec3{0.2, 0.4, 0.4}) * dt);
  EXPECT_DOUBLE_EQ(m.toward(0), 2 * 0.3 * dt);
  EXPECT_DOUBLE_EQ(m.toward(1), 2 * fastest * dt);
  EXPECT_DOUBLE_EQ(m.toward(2), 2 * fastest * dt);
  const Integrator::VelocityBox opposed = box_of({-10.0, 0.0, 0.0}, {10.0, 0.0, 0.0});
  m.reset(bodies);
  m.advance(10.0, opposed, bodies, dt);
  EXPECT_DOUBLE_EQ(m.relative(), 10.0 * dt);
  EXPECT_DOUBLE_EQ(m.toward(0), 0.0);
}

}  // namespace
}  // namespace ringdem

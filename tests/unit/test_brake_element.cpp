// The brake element (physics/BrakeElement.hpp, docs/physics.md "Brake elements") against its
// closed-form behaviour: a spring until the activation force, a plateau while it slides, the
// spring again on unloading and after the stroke, and its dissipation as the area under the
// force–displacement path.
#include <gtest/gtest.h>

#include <cmath>

#include "physics/BrakeElement.hpp"

namespace ringdem {
namespace {

constexpr BrakeElement::Params kBrake{2.0e6, 5.0e3, 0.4};  // k, F_b, stroke

/// Drives the body from its state's position to `to` in `steps` equal steps, and returns the
/// work done on the brake (the trapezoid of -F . dd: the load the body feels is F).
double drive(BrakeElement::State& s, Vec3& at, const Vec3& to, int steps, Vec3* last = nullptr) {
  double work = 0.0;
  Vec3 before = BrakeElement::compute(kBrake, at, s);
  for (int i = 1; i <= steps; ++i) {
    const Vec3 next = at + (to - at) * (1.0 / (steps - i + 1));
    const Vec3 after = BrakeElement::compute(kBrake, next, s);
    work -= dot(0.5 * (before + after), next - at);
    before = after;
    at = next;
  }
  if (last) *last = before;
  return work;
}

TEST(BrakeElement, BelowActivationItIsALinearSpring) {
  BrakeElement::State s;
  const Vec3 d{1.0e-3, -0.5e-3, 0.2e-3};  // |k d| = 2.3 kN < F_b
  const Vec3 f = BrakeElement::compute(kBrake, d, s);
  EXPECT_EQ(f, d * -kBrake.stiffness);
  EXPECT_EQ(s.travel, 0.0);
  EXPECT_EQ(s.work, 0.0);
  EXPECT_DOUBLE_EQ(BrakeElement::elastic_energy(kBrake, d, s), 0.5 * kBrake.stiffness * norm2(d));
  EXPECT_EQ(BrakeElement::compute(kBrake, {}, s), Vec3{});  // at its anchor: no load
}

TEST(BrakeElement, PulledPastActivationItSlidesAtTheActivationForceAndKeepsItsTravel) {
  BrakeElement::State s;
  Vec3 at{};
  const Vec3 axis = Vec3{3.0, -4.0, 12.0} / 13.0;  // an oblique pull
  Vec3 f;
  const double pulled = 0.1;
  const double work_in = drive(s, at, axis * pulled, 4000, &f);
  // Plateau: the load is F_b against the pull; the slide is the pull less the spring's share.
  EXPECT_NEAR(norm(f), kBrake.activation_force, 1e-9 * kBrake.activation_force);
  EXPECT_NEAR(dot(f, axis), -kBrake.activation_force, 1e-9 * kBrake.activation_force);
  const double slide = pulled - kBrake.activation_force / kBrake.stiffness;
  EXPECT_NEAR(s.travel, slide, 1e-12);
  EXPECT_NEAR(norm(s.slip - axis * slide), 0.0, 1e-12);
  EXPECT_NEAR(s.work, kBrake.activation_force * slide, 1e-9);
  // What went in is what it dissipated plus what its spring holds (to the trapezoid's error).
  const double held = BrakeElement::elastic_energy(kBrake, at, s);
  EXPECT_NEAR(held, 0.5 * kBrake.activation_force * kBrake.activation_force / kBrake.stiffness,
              1e-9);
  EXPECT_NEAR(work_in, s.work + held, 1e-3 * s.work);
  // Unloaded back to no load: along the spring's slope, and the slide stays (permanent).
  const BrakeElement::State loaded = s;
  drive(s, at, s.slip, 100, &f);
  EXPECT_EQ(s.travel, loaded.travel);
  EXPECT_EQ(s.work, loaded.work);
  EXPECT_NEAR(norm(f), 0.0, 1e-6);
  EXPECT_NEAR(norm(at), slide, 1e-12);
}

TEST(BrakeElement, AfterItsStrokeItHoldsLikeASpring) {
  BrakeElement::State s;
  Vec3 at{};
  Vec3 f;
  drive(s, at, {0.6, 0.0, 0.0}, 6000, &f);  // 0.2 m past the 0.4 m stroke
  EXPECT_NEAR(s.travel, kBrake.stroke, 1e-12);
  EXPECT_NEAR(s.work, kBrake.activation_force * kBrake.stroke, 1e-6);
  EXPECT_NEAR(f.x, -kBrake.stiffness * (0.6 - kBrake.stroke), 1e-6);
  const double more = norm(BrakeElement::compute(kBrake, {0.7, 0, 0}, s));
  EXPECT_NEAR(more - norm(f), 0.1 * kBrake.stiffness, 1e-6);  // the slope k, no more sliding
  EXPECT_NEAR(s.travel, kBrake.stroke, 1e-12);
}

TEST(BrakeElement, ACycleDissipatesTheAreaOfItsLoop) {
  // Out to +0.05 m and back to -0.05 m along x, and back to the start: a rectangle of height
  // 2 F_b and width 0.1 m - 2 F_b / k, less nothing: the loop's area is 2 F_b (0.1 - 2 F_b / k)
  // plus the first loading's F_b (0.05 - F_b / k) and the last unloading's (none: it ends on
  // the spring).
  BrakeElement::State s;
  Vec3 at{};
  double work_in = drive(s, at, {0.05, 0, 0}, 2000);
  work_in += drive(s, at, {-0.05, 0, 0}, 4000);
  work_in += drive(s, at, {0.0, 0, 0}, 2000);
  const double e = kBrake.activation_force / kBrake.stiffness;  // 2.5 mm of spring
  const double slid = (0.05 - e) + (0.1 - 2.0 * e) + (0.05 - 2.0 * e);
  EXPECT_NEAR(s.travel, slid, 1e-12);
  EXPECT_NEAR(s.work, kBrake.activation_force * slid, 1e-6);
  EXPECT_NEAR(work_in, s.work + BrakeElement::elastic_energy(kBrake, at, s), 1e-3 * s.work);
}

}  // namespace
}  // namespace ringdem

// The secondary mesh of a ring (physics/RingMesh, docs/physics.md "Secondary mesh"): its loads
// against the analytic central load, the gradient of its energy by finite differences, the
// balance of forces and moments, the power of its dashpot against the rate of the overlap by
// finite differences, the grains it does not hold, and the bound behind its stability limit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "physics/RingMesh.hpp"

namespace ringdem {
namespace {

constexpr double kRingRadius = 0.15;

/// n beads on a circle of kRingRadius about the origin in the z = 0 plane, counter-clockwise
/// seen from +z, each moved by up to `wobble` in every direction (a deformed, non-planar ring).
std::vector<Vec3> ring_beads(std::size_t n, double wobble, unsigned seed = 7) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-wobble, wobble);
  std::vector<Vec3> beads;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * M_PI * static_cast<double>(i) / static_cast<double>(n);
    beads.push_back(
        Vec3{kRingRadius * std::cos(a) + u(rng), kRingRadius * std::sin(a) + u(rng), u(rng)});
  }
  return beads;
}

struct Loads {
  bool touching = false;
  RingMesh::Output out;
  Vec3 grain;                 ///< the grain's load
  std::vector<Vec3> beads;    ///< each bead's load
  std::vector<Vec3> viscous;  ///< each bead's viscous load
};

Loads mesh_loads(const RingMesh::Params& params, const std::vector<Vec3>& beads,
                 const std::vector<Vec3>& bead_velocity, const Vec3& x, const Vec3& v,
                 double radius, double m_star = 1.0) {
  RingMesh::Input in;
  in.n = beads.size();
  in.position = x;
  in.velocity = v;
  in.radius = radius;
  in.m_star = m_star;
  Loads l;
  RingMesh::BeadLoads force, damping;
  l.touching = RingMesh::compute(params, RingMesh::plane(beads.data(), beads.size()),
                                 RingMesh::motion(beads.data(), bead_velocity.data(), beads.size()),
                                 in, l.out, force, damping);
  l.grain = l.out.force;
  for (std::size_t i = 0; i < beads.size(); ++i) {
    l.beads.push_back(force.at(beads.data(), beads.size(), i));
    l.viscous.push_back(damping.at(beads.data(), beads.size(), i));
  }
  return l;
}

/// E of Eq. M1 with k = 1, by the evaluator (0 when not touching).
double energy(const std::vector<Vec3>& beads, const Vec3& x, double radius) {
  const RingMesh::Params elastic{0.05, 1.0, 0.0};
  const std::vector<Vec3> still(beads.size());
  const Loads l = mesh_loads(elastic, beads, still, x, {}, radius);
  return l.touching ? l.out.elastic_energy : 0.0;
}

/// delta of Eq. M1, by the evaluator (0 when not touching).
double overlap(const std::vector<Vec3>& beads, const Vec3& x, double radius) {
  const RingMesh::Params elastic{0.05, 1.0, 0.0};
  const std::vector<Vec3> still(beads.size());
  const Loads l = mesh_loads(elastic, beads, still, x, {}, radius);
  return l.touching ? l.out.overlap : 0.0;
}

/// The grain's signed distance to the ring's plane, (x - c).n (Eq. M1).
double signed_distance(const std::vector<Vec3>& beads, const Vec3& x) {
  const RingMesh::Plane pl = RingMesh::plane(beads.data(), beads.size());
  return dot(x - pl.centre, pl.normal);
}

// RingMesh::band bounds how far a grain's signed distance to the plane moves while the beads
// and the grain each move at most `move`: checked against the planes recomputed after the
// moves, for deformed rings under random moves, and under the rigid tilt whose rim moves by
// `move` with a grain far out along the plane (where the tilt, not the translations, moves it
// most: 0.5 m out, 13 mm for a 4 mm move, beyond the 8 mm the translations allow). The band is
// also narrow enough to matter: for a 4 mm move on the 0.15 m ring it turns the normal by at
// most a quarter of a radian, where the whole sphere of the reach allows anything.
TEST(RingMesh, TheBandBoundsHowFarTheDistanceToThePlaneMoves) {
  const double move = 0.004;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto random_move = [&] {
    Vec3 v;
    do
      v = {u(rng), u(rng), u(rng)};
    while (norm(v) > 1.0);
    return v * move;
  };
  double worst = 0.0;  // largest change over its bound
  for (int trial = 0; trial < 400; ++trial) {
    const std::vector<Vec3> beads = ring_beads(24, 0.02, static_cast<unsigned>(trial));
    const RingMesh::Plane pl = RingMesh::plane(beads.data(), beads.size());
    const RingMesh::Band band = RingMesh::band(beads.data(), beads.size(), pl, move);
    ASSERT_LT(band.tilt, 0.25);
    std::vector<Vec3> moved = beads;
    if (trial % 2 == 0) {
      for (Vec3& b : moved)
        b += random_move();
    } else {  // a rigid tilt about the x axis, the rim moving by `move`
      const double angle = move / (kRingRadius + 0.02);
      for (Vec3& b : moved)
        b = {b.x, b.y * std::cos(angle) - b.z * std::sin(angle),
             b.y * std::sin(angle) + b.z * std::cos(angle)};
    }
    for (int g = 0; g < 20; ++g) {
      const Vec3 x = trial % 2 == 0 ? pl.centre + Vec3{u(rng), u(rng), u(rng)} * 0.3
                                    : Vec3{0.0, 0.5 * u(rng), 0.01 * u(rng)};
      const Vec3 x_moved = trial % 2 == 0 ? x + random_move() : x;
      const double change = std::abs(signed_distance(moved, x_moved) - signed_distance(beads, x));
      const double bound = band.offset + band.tilt * norm(x - pl.centre);
      EXPECT_LE(change, bound) << "trial " << trial << ", grain " << g;
      worst = std::max(worst, change / bound);
    }
  }
  // The tilt cases come within a factor of a few of the bound: it is not loose for nothing.
  EXPECT_GT(worst, 0.1);
}

// A grain on the axis of a flat regular ring: pushed along the axis by k delta (Eq. M1-M2),
// each of the N beads pulled back by k delta / N (Eq. M3 with w = 0).
TEST(RingMesh, AGrainOnTheAxisIsPushedByKDeltaAndEachBeadTakesAnEqualShare) {
  const RingMesh::Params params{0.05, 2.0e5, 0.0};
  const std::vector<Vec3> beads = ring_beads(12, 0.0);
  const std::vector<Vec3> still(beads.size());
  const double radius = 0.04;
  const Loads above = mesh_loads(params, beads, still, {0, 0, 0.03}, {}, radius);
  ASSERT_TRUE(above.touching);
  EXPECT_NEAR(above.out.overlap, 0.01, 1e-15);
  EXPECT_NEAR(above.grain.z, 2.0e5 * 0.01, 1e-9);
  EXPECT_NEAR(std::hypot(above.grain.x, above.grain.y), 0.0, 1e-9);
  EXPECT_NEAR(above.out.elastic_energy, 0.5 * 2.0e5 * 0.01 * 0.01, 1e-12);
  for (const Vec3& f : above.beads) {
    EXPECT_NEAR(f.z, -2.0e5 * 0.01 / 12.0, 1e-9);
    EXPECT_NEAR(std::hypot(f.x, f.y), 0.0, 1e-9);
  }
  // From below, pushed down.
  const Loads below = mesh_loads(params, beads, still, {0, 0, -0.03}, {}, radius);
  ASSERT_TRUE(below.touching);
  EXPECT_NEAR(below.grain.z, -2.0e5 * 0.01, 1e-9);
}

// Every elastic load is minus the gradient of E = k s delta^2 / 2 (Eq. M1): central
// differences of E in each coordinate of the grain and of every bead of a deformed, non-planar
// ring, with the grain off the axis where the mesh holds fully (s = 1) and in the fade at the
// rim (0 < s < 1). Tolerance 1e-6 of the largest load (the differences' own error is about
// 1e-9 of it at h = 1e-7 m).
TEST(RingMesh, ItsLoadsAreTheGradientOfItsEnergy) {
  const double k = 3.0e5;
  const RingMesh::Params params{0.05, k, 0.0};
  for (const Vec3& start : {Vec3{0.06, -0.035, 0.012}, Vec3{0.08, -0.1, 0.012}}) {
    std::vector<Vec3> beads = ring_beads(16, 0.01);
    const std::vector<Vec3> still(beads.size());
    Vec3 x = start;
    const double radius = 0.03;
    const Loads l = mesh_loads(params, beads, still, x, {}, radius);
    ASSERT_TRUE(l.touching);
    if (start.y < -0.05) {
      EXPECT_GT(l.out.weight, 0.1);  // in the fade
      EXPECT_LT(l.out.weight, 0.9);
    } else {
      EXPECT_EQ(l.out.weight, 1.0);
    }
    const double scale = norm(l.grain);
    const double h = 1e-7;
    const auto derivative = [&](double& coordinate) {
      const double saved = coordinate;
      coordinate = saved + h;
      const double up = k * energy(beads, x, radius);
      coordinate = saved - h;
      const double down = k * energy(beads, x, radius);
      coordinate = saved;
      return (up - down) / (2.0 * h);
    };
    EXPECT_NEAR(l.grain.x, -derivative(x.x), 1e-6 * scale);
    EXPECT_NEAR(l.grain.y, -derivative(x.y), 1e-6 * scale);
    EXPECT_NEAR(l.grain.z, -derivative(x.z), 1e-6 * scale);
    for (std::size_t i = 0; i < beads.size(); ++i) {
      EXPECT_NEAR(l.beads[i].x, -derivative(beads[i].x), 1e-6 * scale) << "bead " << i;
      EXPECT_NEAR(l.beads[i].y, -derivative(beads[i].y), 1e-6 * scale) << "bead " << i;
      EXPECT_NEAR(l.beads[i].z, -derivative(beads[i].z), 1e-6 * scale) << "bead " << i;
    }
  }
}

// E is continuous at the rim: a grain that slides in from the side, overlapping the plane by
// most of its radius, meets an energy that starts at zero, not a step of k delta^2 / 2.
TEST(RingMesh, AGrainEnteringFromTheSideMeetsNoStepInEnergy) {
  const std::vector<Vec3> beads = ring_beads(24, 0.0);
  const RingMesh::Plane plane = RingMesh::plane(beads.data(), beads.size());
  const double a = std::sqrt(plane.area / M_PI);
  const double radius = 0.03, full = 0.5 * 0.029 * 0.029;  // delta = 0.029 at d = 0.001
  EXPECT_EQ(energy(beads, {a + 1e-4, 0, 0.001}, radius), 0.0);
  EXPECT_LT(energy(beads, {a - 1e-4, 0, 0.001}, radius), 1e-4 * full);
  EXPECT_NEAR(energy(beads, {a - radius, 0, 0.001}, radius), full, 1e-12 * full);
}

// The loads on the grain and the beads, elastic and viscous, sum to zero force and zero moment
// (about the origin, 0.2 m from the ring's points), where the mesh holds fully and in the fade
// at the rim: the mesh neither makes nor takes momentum. The dashpot's power is
// -c s delta'^2 (Eq. M5), with delta' from central differences of delta along the velocities.
TEST(RingMesh, ItsLoadsBalanceAndItsDashpotDissipates) {
  const RingMesh::Params params{0.05, 3.0e5, 0.4};
  const Vec3 offset{0.2, -0.1, 0.05};
  std::vector<Vec3> beads = ring_beads(20, 0.008, 11);
  for (Vec3& b : beads)
    b += offset;
  std::vector<Vec3> bead_velocity;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (std::size_t i = 0; i < beads.size(); ++i)
    bead_velocity.push_back({u(rng), u(rng), u(rng)});
  for (const Vec3& place : {Vec3{-0.04, 0.05, -0.015}, Vec3{-0.09, 0.1, -0.015}}) {
    const Vec3 x = offset + place;
    const Vec3 v{0.3, -0.2, 2.0};  // towards the plane from below: the overlap grows
    const double radius = 0.025, m_star = 0.8;
    const Loads l = mesh_loads(params, beads, bead_velocity, x, v, radius, m_star);
    ASSERT_TRUE(l.touching);
    Vec3 force = l.grain;
    Vec3 moment = cross(x, l.grain);
    for (std::size_t i = 0; i < beads.size(); ++i) {
      force += l.beads[i];
      moment += cross(beads[i], l.beads[i]);
    }
    const double scale = norm(l.grain);
    EXPECT_LT(norm(force), 1e-12 * scale);
    EXPECT_LT(norm(moment), 1e-12 * scale);
    // delta' by central differences along the velocities
    const double h = 1e-8;
    const auto moved = [&](double t) {
      std::vector<Vec3> b = beads;
      for (std::size_t i = 0; i < b.size(); ++i)
        b[i] += bead_velocity[i] * t;
      return overlap(b, x + v * t, radius);
    };
    const double rate = (moved(h) - moved(-h)) / (2.0 * h);
    ASSERT_GT(rate, 0.0);
    const double c = 2.0 * params.damping_ratio * std::sqrt(params.stiffness * m_star);
    const double cs = c * l.out.weight;
    EXPECT_NEAR(norm(l.out.damping), cs * rate, 1e-6 * cs * rate);
    double power = dot(l.out.damping, v);
    for (std::size_t i = 0; i < beads.size(); ++i)
      power += dot(l.viscous[i], bead_velocity[i]);
    EXPECT_NEAR(power, -cs * rate * rate, 1e-6 * cs * rate * rate);
  }
}

// Not held: a grain whose centre lies outside the disc of the ring's area, one clear of the
// plane, and one leaving the plane so fast that the dashpot would pull (the load stays >= 0).
TEST(RingMesh, ItHoldsOnlyGrainsInsideTheRingAndNeverPulls) {
  const RingMesh::Params params{0.05, 2.0e5, 1.0};
  const std::vector<Vec3> beads = ring_beads(24, 0.0);
  const std::vector<Vec3> still(beads.size());
  EXPECT_FALSE(mesh_loads(params, beads, still, {0.16, 0, 0.01}, {}, 0.03).touching);
  EXPECT_FALSE(mesh_loads(params, beads, still, {0.11, 0.11, 0.01}, {}, 0.03).touching);
  EXPECT_TRUE(mesh_loads(params, beads, still, {0.1, 0.1, 0.01}, {}, 0.03).touching);
  EXPECT_FALSE(mesh_loads(params, beads, still, {0, 0, 0.031}, {}, 0.03).touching);
  const Loads leaving = mesh_loads(params, beads, still, {0, 0, 0.029}, {0, 0, 50.0}, 0.03);
  ASSERT_TRUE(leaving.touching);
  EXPECT_EQ(leaving.out.force, Vec3{});
  EXPECT_LT(leaving.out.damping.z, 0.0);  // minus the spring: the dashpot's pull, cut off
}

// The stability limit's bound: sum_i |g_i|^2 <= 3 / N for a grain anywhere the mesh holds
// fully in a flat regular ring (the gradients of Eq. M3, over a grid of the ring's inside), so
// that omega^2 = k (1 / m + N sum |g_i|^2 / M) stays within k (1 / m + 3 / M); the limit keeps
// a factor 4 for the fade at the rim.
TEST(RingMesh, ItsStabilityLimitBoundsEveryContactsFrequency) {
  for (const std::size_t n : {12u, 40u, 100u}) {
    const std::vector<Vec3> beads = ring_beads(n, 0.0);
    const std::vector<Vec3> still(n);
    double largest = 0.0;
    int held = 0;
    for (double px = -0.14; px <= 0.14; px += 0.005)
      for (double py = -0.14; py <= 0.14; py += 0.005) {
        const Loads l =
            mesh_loads(RingMesh::Params{0.05, 1.0, 0.0}, beads, still, {px, py, 0.01}, {}, 0.02);
        if (!l.touching || l.out.weight < 1.0) continue;
        ++held;
        double sum = 0.0;  // |g_i|^2 = |F_i|^2 / (k delta)^2 with k = 1
        for (const Vec3& f : l.beads)
          sum += norm2(f) / norm2(l.out.force);
        largest = std::max(largest, sum * static_cast<double>(n));
      }
    EXPECT_GT(held, 2000) << n;
    EXPECT_GT(largest, 1.0) << n;  // at least the centre's 1 / N
    EXPECT_LE(largest, 3.0) << n;
  }
  const double k = 1e5, m = 0.7, ring = 0.65;
  EXPECT_DOUBLE_EQ(RingMesh::time_step_limit(k, m, ring),
                   1.0 / std::sqrt(4 * k * (1 / m + 3 / ring)));
}

}  // namespace
}  // namespace ringdem

// The integrator's particle passes against a plain scalar velocity Verlet written here, one
// particle at a time, in the order of docs/physics.md §4: the passes run four particles at a
// time (core/Lanes4.hpp) with the last ones padded, so every particle must get the bits of
// the scalar update whatever its place in the arrays and whatever shares its lanes.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "physics/Integrator.hpp"

namespace ringdem {
namespace {

struct Reference {
  std::vector<Vec3> x, v, w, force, torque;
  std::vector<Quat> q;
  std::vector<double> dissipated, power;
};

Reference copy_of(const ParticleStore& p) {
  Reference r{p.position, p.velocity, p.omega, p.force, p.torque, p.orientation, {}, {}};
  if (p.books_global_damping()) {
    r.dissipated = p.dissipated_global;
    r.power = p.power_global;
  }
  return r;
}

double free_factor(Motion m) {
  return m == Motion::kFree ? 1.0 : 0.0;
}
double moving_factor(Motion m) {
  return m == Motion::kFixed ? 0.0 : 1.0;
}
double sign_of(double v) {
  return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0);
}

// Cundall damping of one component (physics.md §4), its kick, and its power at the new
// velocity.
double damp_kick(double& f, double& vel, double alpha, double factor) {
  const double df = alpha * std::abs(f) * sign_of(vel);
  if (alpha != 0.0) f = f - df;
  vel = vel + f * factor;
  return df * vel;
}

void reference_second_half(const ParticleStore& p, Reference& r, double dt) {
  const double half = 0.5 * dt;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const double free = free_factor(p.motion[k]);
    const double kick = free * half / p.mass[k];
    const double turn = free * half / ParticleStore::sphere_inertia(p.mass[k], p.radius[k]);
    const double alpha = p.tracks_damping() ? p.damping[k] : 0.0;
    double force_power[3], torque_power[3];
    double* const f = &r.force[k].x;
    double* const t = &r.torque[k].x;
    double* const v = &r.v[k].x;
    double* const w = &r.w[k].x;
    for (int c = 0; c < 3; ++c) {
      force_power[c] = damp_kick(f[c], v[c], alpha, kick);
      torque_power[c] = damp_kick(t[c], w[c], alpha, turn);
    }
    if (r.power.empty()) continue;
    const double q = free * ((force_power[0] + force_power[1] + force_power[2]) +
                             (torque_power[0] + torque_power[1] + torque_power[2]));
    if (alpha != 0.0) {
      r.dissipated[k] = r.dissipated[k] + q * dt;
      r.power[k] = q;
    } else if (r.power[k] != 0.0) {
      r.power[k] = 0.0;
    }
  }
}

// The drift and the Cayley update of the orientation, with the largest squared speeds.
void reference_first_half(const ParticleStore& p, Reference& r, double dt, const Vec3& gravity,
                          bool turning, double& max_v2, double& max_w2) {
  const double half = 0.5 * dt;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const double free = free_factor(p.motion[k]);
    const double moving = moving_factor(p.motion[k]);
    const double kick = free * half / p.mass[k];
    const double turn = free * half / ParticleStore::sphere_inertia(p.mass[k], p.radius[k]);
    r.v[k] = r.v[k] + r.force[k] * kick;
    r.w[k] = r.w[k] + r.torque[k] * turn;
    r.x[k] = r.x[k] + r.v[k] * (moving * dt);
    r.force[k] = gravity * p.mass[k];
    r.torque[k] = {};
    if (turning) {
      // The Cayley update dq(omega dt) q, normalised exactly (the pass brings it to unit norm
      // without a square root: compared within a few ulps).
      const Vec3 h = r.w[k] * moving * half;
      r.q[k] = normalized(Quat{1.0, h.x, h.y, h.z} * r.q[k]);
    }
    max_v2 = std::max(max_v2, norm2(r.v[k]));
    max_w2 = std::max(max_w2, norm2(r.w[k]));
  }
}

// n particles with every motion kind, damped and undamped (or all undamped), a stale damping
// power here and there, loads and spins that differ from particle to particle.
ParticleStore mixed_particles(std::size_t n, bool damped, bool ledger, bool turning = true) {
  ParticleStore p;
  p.set_tracks_orientation(turning);
  p.set_tracks_ledger(ledger);
  p.set_tracks_damping(true);
  for (std::size_t k = 0; k < n; ++k) {
    ParticleStore::NewParticle np;
    np.gid = static_cast<std::int64_t>(k);
    const double a = static_cast<double>(k);
    np.position = {0.1 * a, -0.02 * a, 0.3};
    np.velocity = {std::sin(a), std::cos(1.3 * a), -0.5 + 0.1 * a};
    np.omega = {3.0 * std::cos(a), -2.0 + a, 0.5 * std::sin(2.0 * a)};
    np.orientation = normalized(Quat{1.0, 0.1 * a, -0.2, 0.05 * a});
    np.radius = 0.004 + 0.001 * static_cast<double>(k % 3);
    np.density = 7800.0;
    np.damping = damped && k % 3 != 1 ? 0.2 : 0.0;
    np.motion = k % 5 == 3 ? Motion::kFixed : (k % 7 == 5 ? Motion::kPrescribed : Motion::kFree);
    if (np.motion == Motion::kFixed) np.velocity = np.omega = {};
    const std::size_t i = p.add(np);
    // Every component loaded and different from particle to particle, so that a lane or a
    // component that takes its neighbour's factor changes a bit.
    p.force[i] = {0.3 * std::cos(a), -0.1 * a, 0.05 + 0.02 * a};
    p.torque[i] = {1e-4 * a, -2e-4, 3e-5 * std::cos(2.0 * a)};
    if (ledger) {
      p.dissipated_global[i] = 0.01 * a;
      p.power_global[i] = k % 4 == 2 ? 0.5 : 0.0;
    }
  }
  return p;
}

void expect_same_bits(const Vec3& a, const Vec3& b, const char* what, std::size_t k) {
  EXPECT_EQ(a.x, b.x) << what << " of particle " << k;
  EXPECT_EQ(a.y, b.y) << what << " of particle " << k;
  EXPECT_EQ(a.z, b.z) << what << " of particle " << k;
}

void expect_matches(const ParticleStore& p, const Reference& r) {
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    expect_same_bits(p.position[k], r.x[k], "position", k);
    expect_same_bits(p.velocity[k], r.v[k], "velocity", k);
    expect_same_bits(p.omega[k], r.w[k], "omega", k);
    expect_same_bits(p.force[k], r.force[k], "force", k);
    expect_same_bits(p.torque[k], r.torque[k], "torque", k);
    if (p.tracks_orientation()) {
      const Quat& a = p.orientation[k];
      const Quat& b = r.q[k];
      constexpr double kUlps = 1e-15;
      EXPECT_NEAR(a.w, b.w, kUlps) << "orientation of particle " << k;
      EXPECT_NEAR(a.x, b.x, kUlps) << "orientation of particle " << k;
      EXPECT_NEAR(a.y, b.y, kUlps) << "orientation of particle " << k;
      EXPECT_NEAR(a.z, b.z, kUlps) << "orientation of particle " << k;
    }
    if (!r.power.empty()) {
      EXPECT_EQ(p.dissipated_global[k], r.dissipated[k]) << "dissipated of particle " << k;
      EXPECT_EQ(p.power_global[k], r.power[k]) << "power of particle " << k;
    }
  }
}

// The drift's box of velocities against the component-wise minima and maxima of the
// reference's velocities after it, every particle's (fixed ones at rest too), none else's.
void expect_box_of(const Integrator::VelocityBox& box, const std::vector<Vec3>& velocities) {
  Vec3 low = velocities.at(0), high = velocities.at(0);
  for (const Vec3& v : velocities) {
    low = {std::min(low.x, v.x), std::min(low.y, v.y), std::min(low.z, v.z)};
    high = {std::max(high.x, v.x), std::max(high.y, v.y), std::max(high.z, v.z)};
  }
  expect_same_bits(box.low, low, "box low", velocities.size());
  expect_same_bits(box.high, high, "box high", velocities.size());
}

// Both halves of a step, on 1 to 13 particles (every remainder of four lanes), damped with
// the ledger's columns, damped without them, undamped with stale powers to clear, and grains
// that keep no orientations.
void expect_the_scalar_update(std::size_t n) {
  const double dt = 1.3e-6;
  const Vec3 gravity{0.5, -1.0, -9.81};
  struct Kind {
    bool damped, ledger, turning;
  };
  for (const Kind& kind : {Kind{true, true, true}, Kind{true, false, true}, Kind{false, true, true},
                           Kind{false, false, false}}) {
    ParticleStore p = mixed_particles(n, kind.damped, kind.ledger, kind.turning);
    Reference r = copy_of(p);
    Integrator::second_half(p, dt);
    reference_second_half(p, r, dt);
    expect_matches(p, r);
    double max_v2 = 0.0, max_w2 = 0.0;
    const Integrator::Drift d = Integrator::first_half(p, dt, gravity, 1e-3, 0.5, kind.turning);
    reference_first_half(p, r, dt, gravity, kind.turning, max_v2, max_w2);
    expect_matches(p, r);
    EXPECT_EQ(d.max_speed, std::sqrt(max_v2));
    expect_box_of(d.velocities, r.v);
    const double step_scale = dt * dt / (1e-3 * 1e-3), turn_scale = dt * dt / (0.5 * 0.5);
    EXPECT_EQ(d.worst_runaway, std::max(max_v2 * step_scale, max_w2 * turn_scale));
  }
}

// The fused pass (the step batches of Simulation::run_steps) gives the bits of the two halves
// in turn, with the callback seeing every particle up to its end kicked and none drifted.
void expect_fused_like_apart(std::size_t n) {
  const double dt = 1.3e-6;
  const Vec3 gravity{0.0, 0.0, -9.81};
  ParticleStore fused = mixed_particles(n, true, true);
  ParticleStore apart = fused;
  std::size_t seen = 0;
  const Integrator::Drift d =
      Integrator::second_then_first_half(fused, dt, gravity, 1e-3, 0.5, true, [&](std::size_t end) {
        EXPECT_EQ(fused.position[end - 1], apart.position[end - 1]);  // not drifted yet
        seen = end;
      });
  Integrator::second_half(apart, dt);
  const Integrator::Drift e = Integrator::first_half(apart, dt, gravity, 1e-3, 0.5, true);
  EXPECT_EQ(seen, n);
  EXPECT_EQ(d.max_speed, e.max_speed);
  expect_box_of(d.velocities, apart.velocity);
  const Reference r = copy_of(apart);
  expect_matches(fused, r);
  for (std::size_t k = 0; k < n; ++k)
    EXPECT_EQ(fused.orientation[k], apart.orientation[k]) << "orientation of particle " << k;
}

// A particle spinning at a constant omega turns about it by 2 atan(|omega dt|/2) a step (the
// Cayley form, docs/physics.md §4), from slow turns to the divergence guard's 0.5 rad a step,
// and its quaternion stays a unit one: to round-off while |omega dt| < 0.02, within the
// two Newton steps' 0.21 e^4 (e = |omega dt|^2/4) above.
TEST(IntegratorPasses, TurnsByTheCayleyAngleAndStaysUnit) {
  const Vec3 axis = Vec3{1.0, -2.0, 0.5} * (1.0 / std::sqrt(5.25));
  for (const double turn : {1e-6, 1e-3, 0.02, 0.1, 0.5}) {
    ParticleStore p;
    ParticleStore::NewParticle np;
    np.gid = 0;
    np.radius = 0.01;
    np.density = 1000.0;
    const double dt = 1e-5;
    np.omega = axis * (turn / dt);
    p.add(np);
    const int steps = 1000;
    double largest_norm_error = 0.0;
    for (int s = 0; s < steps; ++s) {
      Integrator::first_half(p, dt, {0.0, 0.0, 0.0}, 1.0, 1.0, true);
      const Quat& q = p.orientation[0];
      largest_norm_error =
          std::max(largest_norm_error,
                   std::abs(std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z) - 1.0));
    }
    const double e = 0.25 * turn * turn;
    EXPECT_LT(largest_norm_error, 2e-15 + 0.25 * e * e * e * e) << "|omega dt| = " << turn;
    // The total angle about the axis, modulo 4 pi (q and -q are turns 2 pi apart), and no
    // component off the axis.
    const Quat& q = p.orientation[0];
    const Vec3 v = q.vec();
    const double along = dot(v, axis);
    const double angle = 2.0 * std::atan2(along, q.w);
    const double expected = std::remainder(steps * 2.0 * std::atan(0.5 * turn), 4.0 * M_PI);
    EXPECT_NEAR(angle, expected, 1e-12 * steps) << "|omega dt| = " << turn;
    EXPECT_LT(norm(v - axis * along), 1e-13) << "|omega dt| = " << turn;
  }
}

// One test each for all counts: a ctest entry per count would start the binary 13 times.
TEST(IntegratorPasses, GiveTheBitsOfTheScalarUpdate) {
  for (std::size_t n = 1; n <= 13; ++n) {
    SCOPED_TRACE(::testing::Message() << n << " particles");
    expect_the_scalar_update(n);
  }
}

TEST(IntegratorPasses, FusedPassGivesTheBitsOfTheTwoHalves) {
  for (std::size_t n = 1; n <= 13; ++n) {
    SCOPED_TRACE(::testing::Message() << n << " particles");
    expect_fused_like_apart(n);
  }
}

// Where only some particles turn (the ends of bonds, Integrator::Turning::only), those get
// the bits of a pass that turns every particle, and the others keep their orientation; the
// translation and the angular velocities are those of either pass. On 1 to 13 particles with
// flag patterns that leave fours all off, all on and mixed, in the plain and the fused pass.
TEST(IntegratorPasses, OnlyFlaggedParticlesTurn) {
  const double dt = 1.3e-6;
  const Vec3 gravity{0.5, -1.0, -9.81};
  for (std::size_t n = 1; n <= 13; ++n) {
    for (const std::uint32_t pattern : {0x0000u, 0x1ffeu, 0x00f0u, 0x1249u, 0x1fffu}) {
      SCOPED_TRACE(::testing::Message() << n << " particles, flags " << pattern);
      std::vector<std::uint8_t> flags;
      for (std::size_t k = 0; k < n; ++k)
        flags.push_back(static_cast<std::uint8_t>((pattern >> k) & 1u));
      for (const bool fused : {false, true}) {
        ParticleStore all = mixed_particles(n, true, true);
        ParticleStore some = all;
        const std::vector<Quat> before = all.orientation;
        const Integrator::Turning flagged{true, flags.data()};
        if (fused) {
          Integrator::second_then_first_half(all, dt, gravity, 1e-3, 0.5, true, [](std::size_t) {});
          Integrator::second_then_first_half(some, dt, gravity, 1e-3, 0.5, flagged,
                                             [](std::size_t) {});
        } else {
          Integrator::first_half(all, dt, gravity, 1e-3, 0.5, true);
          Integrator::first_half(some, dt, gravity, 1e-3, 0.5, flagged);
        }
        Reference translation = copy_of(all);
        translation.q = some.orientation;  // checked bit for bit below
        expect_matches(some, translation);
        for (std::size_t k = 0; k < n; ++k) {
          const Quat& expected = flags[k] ? all.orientation[k] : before[k];
          EXPECT_EQ(some.orientation[k], expected) << "orientation of particle " << k;
        }
        // Something turned, so the flags were tested against a change.
        if (n >= 3) {
          EXPECT_NE(all.orientation[2], before[2]);
        }
      }
    }
  }
}

// Multi-rate stepping's slow half kick (Integrator::kick, four lanes at a time) gives each
// particle the bits of the one-particle update v + F (h / m), omega + T (h / 0.4 m r^2) from
// the loads it is given, on free particles only, and reads those loads without changing them
// or the store's own loads. On 1 to 13 particles (every remainder of four lanes), with held and
// prescribed ones among them.
TEST(IntegratorPasses, SlowKickGivesTheBitsOfTheScalarKick) {
  const double half_dt = 0.5 * 1.9e-5;
  for (std::size_t n = 1; n <= 13; ++n) {
    SCOPED_TRACE(::testing::Message() << n << " particles");
    ParticleStore p = mixed_particles(n, false, false);
    std::vector<Vec3> slow_force, slow_torque;
    for (std::size_t k = 0; k < n; ++k) {
      const double a = static_cast<double>(k);
      slow_force.push_back({-0.2 + 0.03 * a, 0.7 * std::sin(a), -9.81e-3 * (1.0 + a)});
      slow_torque.push_back({2e-5 * std::cos(a), 1e-4 - 3e-5 * a, -4e-6 * a});
    }
    const std::vector<Vec3> loads = slow_force, moments = slow_torque;
    Reference expected = copy_of(p);
    for (std::size_t k = 0; k < n; ++k) {
      if (p.motion[k] != Motion::kFree) continue;
      const double inertia = 0.4 * p.mass[k] * p.radius[k] * p.radius[k];
      expected.v[k] = expected.v[k] + loads[k] * (half_dt / p.mass[k]);
      expected.w[k] = expected.w[k] + moments[k] * (half_dt / inertia);
    }
    Integrator::kick(p, slow_force, slow_torque, half_dt);
    expect_matches(p, expected);
    for (std::size_t k = 0; k < n; ++k) {
      expect_same_bits(slow_force[k], loads[k], "slow force", k);
      expect_same_bits(slow_torque[k], moments[k], "slow torque", k);
    }
  }
}

// A non-finite velocity anywhere, in the lanes or in the padded last ones, is a runaway.
TEST(IntegratorPasses, NonFiniteVelocityIsARunawayInEveryLane) {
  for (std::size_t n : {4u, 6u})
    for (std::size_t bad = 0; bad < n; ++bad) {
      ParticleStore p = mixed_particles(n, false, false);
      p.motion[bad] = Motion::kFree;
      p.velocity[bad].y = std::numeric_limits<double>::quiet_NaN();
      const Integrator::Drift d = Integrator::first_half(p, 1e-6, {0, 0, -9.81}, 1e-3, 0.5, true);
      EXPECT_EQ(d.worst_runaway, Integrator::kRunaway) << n << " particles, NaN in " << bad;
      EXPECT_EQ(d.worst_index, bad);
    }
}

}  // namespace
}  // namespace ringdem

namespace ringdem {
namespace {

// Free grains that all move one way (no velocity component near zero), on 1 to 21 particles:
// every count of eight- and four-lane groups and of padded last lanes (TailLanes pads with
// fixed particles at rest, whose zero velocity must not join the box); and the sub-stepped
// pass over runs of particles, whose others enter as squared_speeds() saw them.
TEST(IntegratorPasses, BoxOfVelocitiesHoldsTheParticlesVelocitiesOnly) {
  const double dt = 1e-6;
  for (std::size_t n = 1; n <= 21; ++n) {
    SCOPED_TRACE(::testing::Message() << n << " particles");
    ParticleStore p;
    p.set_tracks_orientation(false);
    for (std::size_t k = 0; k < n; ++k) {
      ParticleStore::NewParticle np;
      np.gid = static_cast<std::int64_t>(k);
      const double a = static_cast<double>(k);
      np.position = {0.01 * a, 0.0, 0.0};
      np.velocity = {10.0 + std::sin(a), -5.0 + 0.3 * std::cos(a), 3.0 + 0.01 * a};
      np.radius = 0.004;
      np.density = 2600.0;
      p.add(np);
    }
    const Integrator::Drift d = Integrator::first_half(p, dt, {0.0, 0.0, -9.81}, 1.0, 1.0, false);
    expect_box_of(d.velocities, p.velocity);
    EXPECT_GT(d.velocities.low.x, 8.0);
    EXPECT_LT(d.velocities.high.y, -4.0);
    // Runs: the first third and the last particle drifted, the others' box given.
    const std::size_t third = n / 3;
    std::vector<Integrator::Run> runs{{0, third}, {n - 1, n}};
    std::vector<Integrator::Run> others{{third, n - 1}};
    if (third >= n - 1) {
      runs = {{0, n}};
      others.clear();
    }
    const Integrator::SquaredSpeeds rest = Integrator::squared_speeds(p, others);
    const Integrator::Drift e =
        Integrator::first_half(p, dt, {0.0, 0.0, -9.81}, 1.0, 1.0, false, runs, rest);
    expect_box_of(e.velocities, p.velocity);
  }
}

}  // namespace
}  // namespace ringdem

// Whole-step checks of the serial core against analytic results (validation.md §1).
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "StepSettings.hpp"
#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {
namespace {

using testing::self_comm;

using testing::settings_at;

// A 100-particle ring pulled by two opposite small point loads P stretches along the load
// line by (pi/4 - 2/pi) P R^3 / EI (thin ring, bending only; physics.md §5). Axial and shear
// compliance add about (r_b / R)^2 ~ 1e-3 relative; the polygon of 100 bonds O(1/n^2).
// Tolerance 3 % (the issue's).
TEST(RingUnderPointLoads, ElongationMatchesThinRingTheory) {
  CaseConfig c = testing::base_case();
  c.bonds[0].youngs_modulus = 200e9;
  c.bonds[0].radius_multiplier = 0.8;
  c.damping.global = 0.7;  // quasi-static relaxation; Cundall damping does not shift statics
  c.rings.push_back(testing::paper_ring());
  Model model = build_model(c);
  ParticleStore& p = model.particles;
  const double radius = c.rings[0].internal_diameter / 2 + c.rings[0].particle_radius;
  const double r_b = 0.8 * 0.0045;
  const double ei = 200e9 * M_PI * std::pow(r_b, 4) / 4.0;
  const double expected_per_load = (M_PI / 4.0 - 2.0 / M_PI) * std::pow(radius, 3) / ei;
  const double load = 1e-3 * radius / expected_per_load;  // elongation of 0.1 % of R
  // Particle 0 sits at +x, particle 50 at -x (reference direction x).
  model.point_loads = {{p.gid[0], {load, 0, 0}}, {p.gid[50], {-load, 0, 0}}};
  const double l0 = norm(p.position[0] - p.position[50]);

  const Communicator comm = self_comm();
  Simulation sim(std::move(model), comm, settings_at(c, 0.0));
  sim.run_steps(150000);
  const ParticleStore& q = sim.model().particles;
  const double elongation = norm(q.position[0] - q.position[50]) - l0;
  EXPECT_NEAR(elongation / (load * expected_per_load), 1.0, 0.03);
  // The perpendicular diameter shortens by (2/pi - 1/2) P R^3 / EI.
  const double l_perp0 = 2 * radius;  // particles 25 and 75 sit at -y and +y
  const double shortening = l_perp0 - norm(q.position[25] - q.position[75]);
  EXPECT_NEAR(shortening / ((2.0 / M_PI - 0.5) * std::pow(radius, 3) / ei * load), 1.0, 0.03);
}

CaseConfig undamped_chain_case() {
  CaseConfig c = testing::base_case();
  // A ring is a closed chain; keep it free, undamped, with random initial velocities.
  c.rings.push_back(testing::paper_ring());
  c.rings[0].n_particles = 40;
  c.rings[0].internal_diameter = 0.115;
  return c;
}

void randomise_velocities(ParticleStore& p, unsigned seed, double v_scale, double w_scale) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    p.velocity[k] = Vec3{n(rng), n(rng), n(rng)} * v_scale;
    p.omega[k] = Vec3{n(rng), n(rng), n(rng)} * w_scale;
  }
}

// Relative total-energy error of the undamped chain, sampled every 1000 steps.
std::vector<double> energy_errors(double dt_safety, int blocks) {
  const CaseConfig c = undamped_chain_case();
  Model model = build_model(c);
  randomise_velocities(model.particles, 11, 0.01, 2.0);
  const Communicator comm = self_comm();
  SimulationSettings s = settings_at(c, 0.0);
  s.dt_safety = dt_safety;
  Simulation sim(std::move(model), comm, s);
  const double e0 = sim.energies().total();
  std::vector<double> err;
  for (int block = 0; block < blocks; ++block) {
    sim.run_steps(static_cast<std::int64_t>(1000 * 0.25 / dt_safety));
    err.push_back((sim.energies().total() - e0) / e0);
  }
  return err;
}

double mean(const std::vector<double>& v, std::size_t from, std::size_t to) {
  double s = 0.0;
  for (std::size_t k = from; k < to; ++k)
    s += v[k];
  return s / static_cast<double>(to - from);
}

// Velocity Verlet with conservative bond forces: the energy error is bounded and O(dt^2),
// with no drift. Bounds over 1e5 steps at a quarter of the stability limit: fluctuation
// below 2 % of the initial energy, drift (mean of the last 20 samples minus mean of the
// first 20) below 0.1 %; halving dt divides the fluctuation by 4 (between 3 and 5).
TEST(UndampedChain, EnergyDriftBounded) {
  const std::vector<double> err = energy_errors(0.25, 100);
  double worst = 0.0;
  for (double e : err)
    worst = std::max(worst, std::abs(e));
  EXPECT_LT(worst, 0.02);
  EXPECT_LT(std::abs(mean(err, 80, 100) - mean(err, 0, 20)), 1e-3);
  const std::vector<double> fine = energy_errors(0.125, 20);
  const double ratio = mean(err, 0, 20) / mean(fine, 0, 20);
  EXPECT_GT(ratio, 3.0);
  EXPECT_LT(ratio, 5.0);
}

// Reversing all velocities retraces the trajectory: after N steps forward and N back the
// state returns to the start up to round-off (1e-9 of the displacement scale).
TEST(UndampedChain, TimeReversible) {
  const CaseConfig c = undamped_chain_case();
  Model model = build_model(c);
  randomise_velocities(model.particles, 5, 0.05, 2.0);
  const std::vector<Vec3> x0 = model.particles.position;
  const std::vector<Quat> q0 = model.particles.orientation;
  const Communicator comm = self_comm();
  Simulation sim(std::move(model), comm, settings_at(c, 0.0));
  const int n = 20000;
  sim.run_steps(n);
  ParticleStore& p = sim.model().particles;
  double moved = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    moved = std::max(moved, norm(p.position[k] - x0[k]));
  ASSERT_GT(moved, 1e-4);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    p.velocity[k] = -p.velocity[k];
    p.omega[k] = -p.omega[k];
  }
  sim.run_steps(n);
  double err_x = 0.0, err_q = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    err_x = std::max(err_x, norm(p.position[k] - x0[k]));
    const Quat d = p.orientation[k] * conjugate(q0[k]);
    err_q = std::max(err_q, norm(rotation_vector(d)));
  }
  EXPECT_LT(err_x, 1e-9 * moved + 1e-13);
  EXPECT_LT(err_q, 1e-8);
}

// Head-on collision of two free spheres through the whole step loop: restitution = input e
// within 2 % (validation.md §1), and momentum conserved to round-off.
TEST(Collision, RestitutionThroughTheStepLoop) {
  for (double e : {0.2, 0.5, 0.9}) {
    CaseConfig c = testing::base_case();
    c.materials[0].restitution = e;
    SphereConfig a, b;
    a.position = {0, 0, 0};
    a.velocity = {0.5, 0, 0};
    b.position = {0.00901, 0, 0};  // 10 um gap: contact after 10 us
    b.velocity = {-0.5, 0, 0};
    c.spheres = {a, b};
    const Communicator comm = self_comm();
    Simulation sim(build_model(c, comm), comm, settings_at(c, 1e-8, 0.0005));
    sim.run_steps(6000);  // Hertz contact at 1 m/s lasts ~ 27 us; 60 us covers all of it
    const ParticleStore& p = sim.model().particles;
    // By gid: the re-sorts by space (every 1000 steps) may store them either way round.
    const Vec3 va = p.velocity[static_cast<std::size_t>(p.index_of(0))];
    const Vec3 vb = p.velocity[static_cast<std::size_t>(p.index_of(1))];
    const double v_rel_after = vb.x - va.x;
    EXPECT_NEAR(v_rel_after / 1.0, e, 0.02 * e) << "e = " << e;
    EXPECT_NEAR(va.x + vb.x, 0.0, 1e-12);
  }
}

/// Runs `sim` for 800 x 5 steps and, after each 5, compares its count of touching contacts
/// with an all-pairs count of the touching pairs and, where there is one, of the grains in the
/// floor plane z = 0; and that at least `contacts` were checked in all. Returns the rebuilds it
/// made.
std::int64_t expect_no_touching_contact_missed(Simulation& sim, std::int64_t contacts,
                                               bool floor = true) {
  const ParticleStore& p = sim.model().particles;
  EXPECT_GT(p.n_local(), 200u);
  std::int64_t checked_touching = 0;
  const std::int64_t rebuilds_before = sim.rebuilds();
  for (int check = 0; check < 800; ++check) {
    sim.run_steps(5);
    std::int64_t touching = 0;
    for (std::size_t a = 0; a < p.n_local(); ++a) {
      touching += floor && p.position[a].z < p.radius[a];  // the floor plane z = 0
      for (std::size_t b = a + 1; b < p.n_local(); ++b) {
        const double reach = p.radius[a] + p.radius[b];
        touching += norm2(p.position[b] - p.position[a]) < reach * reach;
      }
    }
    EXPECT_EQ(sim.overlaps(0.0, 0).count, touching) << "step " << sim.steps();
    if (sim.overlaps(0.0, 0).count != touching) break;
    checked_touching += touching;
  }
  const std::int64_t rebuilds = sim.rebuilds() - rebuilds_before;
  EXPECT_GT(checked_touching, contacts) << "too few contacts to test anything: " << p.n_local()
                                        << " grains, " << rebuilds << " rebuilds";
  return rebuilds;
}

// The neighbour lists are rebuilt when a bound on how far particles moved relative to one
// another (the sum over the steps of the half diagonal of each step's box of velocities, or
// of its largest speed, times dt) passes half the skin, or one on how far they moved toward a
// body (a fixed plane: the largest normal speed) passes the skin (engine/MoveBounds), not
// from a column of reference positions. Every touching contact must then be in the lists at
// every step: two clouds of grains thrown at each other and onto a floor are checked against
// an all-pairs count of the touching pairs and of the grains in the floor, every 5 steps over
// 4000 (about 70 rebuilds).
TEST(NeighbourLists, NoTouchingContactIsMissedBetweenRebuilds) {
  const CaseConfig c = testing::colliding_clouds();
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 1e-6, 0.0005));
  EXPECT_GT(expect_no_touching_contact_missed(sim, 800 * 10), 10)
      << "too few rebuilds to test anything";
}

// The clouds carried along the floor at 30 m/s (a common velocity, across y): grains that
// slide fast along a fixed plane move toward it only by their normal speed, and the lists
// must still miss no contact. (The floor's friction slows the grains it touches, so their
// velocities spread and the lists rebuild more often than at rest.)
TEST(NeighbourLists, NoContactIsMissedWhileGrainsSlideFastAlongTheFloor) {
  CaseConfig c = testing::colliding_clouds();
  for (GrainsConfig& g : c.grains)
    g.velocity.y += 30.0;
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 1e-6, 0.0005));
  expect_no_touching_contact_missed(sim, 5000);
}

// A lattice of grains that moves as one, 2 mm apart, at 20 m/s along the floor and 2 m/s onto
// it: their moves relative to one another never call for a rebuild, so only their moves
// toward the floor, its normal speed of 2 m/s, must. In the 0.9 ms before the bottom layer
// lands, 1.8 mm of fall, the lists rebuild once a skin's fall toward the floor (a 0.5 mm
// skin: three times, against about 70 by the largest speed); then every grain of the bottom
// layer must be listed against the floor when it lands and bounces (the all-pairs count).
TEST(NeighbourLists, AGrainLatticeLandsOnTheFloorListed) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, 0};
  c.simulation.dt = 1e-6;
  c.simulation.skin = 0.0005;
  LatticeConfig l;
  l.origin = {0.0, 0.0, 0.0065};  // the bottom layer 2 mm above the floor
  l.count = {8, 8, 4};
  l.spacing = 0.011;
  l.velocity = {20.0, 0.0, -2.0};
  c.lattices = {l};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  c.rigid_bodies = {floor};
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 1e-6, 0.0005));
  const std::int64_t before = sim.rebuilds();
  sim.run_steps(900);
  EXPECT_EQ(sim.overlaps(0.0, 0).count, 0);
  EXPECT_EQ(sim.rebuilds() - before, 3);
  expect_no_touching_contact_missed(sim, 800);
}

// The clouds in flight (no gravity, no floor), colliding at 8 m/s, once at rest and once
// carried at 30 m/s across y: the lists' test follows the grains' moves relative to one
// another, and neither run misses a contact. At rest the largest speed (4-5 m/s) is the
// tighter bound, carried the box's half diagonal, at most sqrt(3) times it where the
// velocities spread alike in x, y and z; bounded by the largest speed, the carried clouds
// would rebuild at least 480 times (30 m/s for 4 ms, a rebuild every 0.25 mm).
TEST(NeighbourLists, CloudsCarriedAtSpeedRebuildAboutAsAtRest) {
  const Communicator comm = self_comm();
  CaseConfig still = testing::colliding_clouds();
  still.simulation.gravity = {0, 0, 0};
  still.rigid_bodies.clear();
  for (GrainsConfig& g : still.grains)
    g.velocity.z = 0.0;
  CaseConfig carried = still;
  for (GrainsConfig& g : carried.grains)
    g.velocity.y += 30.0;
  Simulation at_rest(build_model(still, comm), comm, settings_at(still, 1e-6, 0.0005));
  Simulation moving(build_model(carried, comm), comm, settings_at(carried, 1e-6, 0.0005));
  const std::int64_t rebuilds_at_rest = expect_no_touching_contact_missed(at_rest, 3000, false);
  const std::int64_t rebuilds_moving = expect_no_touching_contact_missed(moving, 3000, false);
  EXPECT_GT(rebuilds_at_rest, 10);
  EXPECT_LE(rebuilds_moving, 1.8 * static_cast<double>(rebuilds_at_rest) + 3);
  EXPECT_LT(rebuilds_moving, 480 / 4);
}

// A sphere resting on a fixed plane under gravity: the plane carries exactly its weight
// once at rest (balance of forces, 1e-6 relative after damping has removed the bounce).
// A particle whose Cundall coefficient goes to 0 (the rockfall's phases switch the net's) must
// not keep its last damping power: the ledger reports accumulated - dt/2 power
// (ParticleStore::ledger_value), so a stale power would shift the tally for good. After one
// undamped step every power is zero, and the tally stands still from then on.
TEST(Simulation, SwitchingGlobalDampingOffLeavesNoDampingPowerBehind) {
  const CaseConfig c = testing::ring_patch_hit_by_sphere(-0.005, 60.0, 0.5);
  const Communicator self = testing::self_comm();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  sim.run_steps(100);
  const ParticleStore& p = sim.model().particles;
  const auto largest_power = [&] {
    double largest = 0.0;
    for (std::size_t k = 0; k < p.n_local(); ++k)
      largest = std::max(largest, std::abs(p.power_global[k]));
    return largest;
  };
  ASSERT_GT(largest_power(), 0.0);
  sim.set_group_damping(0, 0.0);
  for (std::size_t k = 0; k < p.n_local(); ++k)
    ASSERT_EQ(p.damping_of(k), 0.0) << "the rings are group 0";
  sim.step();
  EXPECT_EQ(largest_power(), 0.0);
  const double tally = sim.energies().global_damping;
  EXPECT_GT(tally, 0.0);
  sim.run_steps(50);
  EXPECT_EQ(sim.energies().global_damping, tally);
}

/// `spheres` (steel, 4.5 mm) over a fixed steel floor plane z = 0, under gravity, damped to
/// come to rest.
CaseConfig spheres_over_a_floor(std::vector<SphereConfig> spheres) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.damping.global = 0.3;
  c.spheres = std::move(spheres);
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  c.rigid_bodies = {floor};
  return c;
}

TEST(RigidBodies, PlaneCarriesWeightOfRestingSphere) {
  SphereConfig s;
  s.position = {0, 0, 0.0045};
  const CaseConfig c = spheres_over_a_floor({s});
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 0.0));
  sim.run_steps(100000);
  const double weight = sim.model().particles.mass[0] * 9.81;
  EXPECT_NEAR(sim.model().bodies[0].force.z / -weight, 1.0, 1e-6);
  EXPECT_NEAR(sim.model().bodies[0].force.x, 0.0, 1e-9 * weight);
}

// Held particles (fixed or prescribed) never move by a force: one pressed 0.5 mm into the floor
// and another 1 mm into the first exert nothing, on the floor or on each other (as the start's
// overlap check treats them). Beside them a free sphere comes to rest on the same floor, which
// then carries its weight alone, as in PlaneCarriesWeightOfRestingSphere. (The coarse debris
// demo's fixed shackles inside its fixed posts had put 2.5e8 N on each post and 4.6 MJ into the
// contact energy.) The held ones are not even candidates of the floor: a sub-stepped run would
// otherwise reduce the bodies' loads at every sub-step for a net's fixed shackles beside its
// posts.
TEST(RigidBodies, HeldParticlesExertNothingOnHeldBodiesOrEachOther) {
  SphereConfig held_in_floor, held_in_held, free_sphere;
  held_in_floor.position = {0, 0, 0.0040};
  held_in_floor.motion = Motion::kFixed;
  held_in_held.position = {0.008, 0, 0.0040};
  held_in_held.motion = Motion::kPrescribed;
  free_sphere.position = {0.1, 0, 0.0045};
  const CaseConfig c = spheres_over_a_floor({held_in_floor, held_in_held, free_sphere});
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 0.0));
  EXPECT_EQ(sim.n_body_contact_candidates(), 1u) << "the free sphere's alone";
  sim.run_steps(100000);
  const ParticleStore& p = sim.model().particles;
  const double weight = p.mass[2] * 9.81;
  EXPECT_NEAR(sim.model().bodies[0].force.z / -weight, 1.0, 1e-6);
  for (std::size_t k = 0; k < 2; ++k) {  // their own weight only
    EXPECT_NEAR(norm(p.force[k] - Vec3{0, 0, -9.81 * p.mass[k]}), 0.0, 1e-12) << k;
    EXPECT_EQ(norm(p.torque[k]), 0.0) << k;
  }
  // Hertz energy of the resting sphere alone, 2/5 F delta with delta = (3 F / (4 E* sqrt(R)))^(2/3)
  // at its weight: far below what the held overlaps would hold (0.5 and 1 mm).
  const double e_star = 200e9 / (2.0 * (1.0 - 0.3 * 0.3));
  const double delta = std::cbrt(std::pow(3.0 * weight / (4.0 * e_star * std::sqrt(0.0045)), 2));
  EXPECT_NEAR(sim.energies().contact_elastic / (0.4 * weight * delta), 1.0, 1e-3);
}

// A free rigid sphere (boulder) under gravity alone follows z = z0 - g t^2 / 2 exactly
// (velocity Verlet integrates constant acceleration without error).
TEST(RigidBodies, FreeBodyFallsBallistically) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  RigidBodyConfig boulder;
  boulder.name = "boulder";
  boulder.shape = ShapeKind::kSphere;
  boulder.radius = 0.4;
  boulder.position = {0, 0, 3.0};
  boulder.motion = Motion::kFree;
  boulder.mass = 825.0;
  c.rigid_bodies = {boulder};
  SphereConfig far_away;  // one particle so that the time step has a scale
  far_away.position = {10, 0, 0};
  far_away.motion = Motion::kFixed;
  c.spheres = {far_away};
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 1e-4));
  sim.run_steps(5000);
  const double t = sim.time();
  EXPECT_NEAR(sim.model().bodies[0].position.z, 3.0 - 0.5 * 9.81 * t * t, 1e-9);
  EXPECT_NEAR(sim.model().bodies[0].velocity.z, -9.81 * t, 1e-9);
}

// A particle pushed against a fixed cylinder (a pin): contact normal is radial and the pin
// carries the load; the contact history survives neighbour rebuilds.
TEST(RigidBodies, PinCarriesRingWeight) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.damping.global = 0.5;
  c.bonds[0].youngs_modulus = 292e9;
  c.bonds[0].radius_multiplier = 0.43;
  c.rings.push_back(testing::paper_ring());
  RigidBodyConfig pin;
  pin.name = "pin";
  pin.shape = ShapeKind::kCylinder;
  pin.axis = {0, 1, 0};
  pin.radius = 0.01;
  pin.length = 0.1;
  pin.position = {0, 0, 0.15 - 0.0101};  // 0.1 mm below the ring's inner surface
  c.rigid_bodies = {pin};
  const Communicator comm = self_comm();
  Simulation sim(build_model(c, comm), comm, settings_at(c, 0.0));
  sim.run_steps(200000);
  double weight = 0.0;
  for (double m : sim.model().particles.mass)
    weight += m * 9.81;
  const Vec3 f = sim.model().bodies[0].force;
  EXPECT_NEAR(f.z / -weight, 1.0, 1e-3);
  EXPECT_NEAR(f.x / weight, 0.0, 1e-3);
  EXPECT_NEAR(f.y / weight, 0.0, 1e-9);
}

}  // namespace
}  // namespace ringdem

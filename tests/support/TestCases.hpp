#pragma once

// Small cases built in code, and one tiny rockfall case file, shared by tests and benchmarks.

#include <mpi.h>

#include <cmath>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem::testing {

/// A one-rank communicator; initialises MPI on first use (the test main finalises it).
inline Communicator self_comm() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) MPI_Init(nullptr, nullptr);
  return Communicator(MPI_COMM_SELF);
}

/// Steel (Table 1) and the Table 1 bond, no gravity, no damping.
inline CaseConfig base_case() {
  CaseConfig c;
  c.name = "test";
  c.simulation.gravity = {0, 0, 0};
  c.simulation.end_time = 1.0;
  MaterialConfig steel;
  steel.name = "steel";
  c.materials.push_back(steel);
  BondConfig bond;
  bond.name = "ring";
  c.bonds.push_back(bond);
  return c;
}

/// A steel sphere of 4.5 mm (group "spheres") touching a fixed steel floor plane z = 0 at the
/// origin and sliding along +x at `speed`, under gravity (9.81 m/s^2 along -z); friction
/// `friction`, restitution 1 (no contact damping).
inline CaseConfig sliding_sphere(double friction, double speed) {
  CaseConfig c = base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.materials[0].restitution = 1.0;
  c.materials[0].friction = friction;
  SphereConfig s;
  s.position = {0, 0, s.radius};
  s.velocity = {speed, 0, 0};
  c.spheres = {s};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  c.rigid_bodies = {floor};
  return c;
}

/// One ring of the paper: 300 mm internal diameter, 100 particles of 4.5 mm.
inline RingConfig paper_ring(const Vec3& centre = {}, const Vec3& normal = {0, 1, 0}) {
  RingConfig r;
  r.centre = centre;
  r.normal = normal;
  r.reference = {1, 0, 0};
  return r;
}

/// Soft rock for grain flows (E = 1e8 Pa, for steps of 1e-5 s): 2600 kg/m^3, default friction
/// and restitution unless given.
inline MaterialConfig soft_rock() {
  MaterialConfig rock;
  rock.name = "rock";
  rock.density = 2600;
  rock.youngs_modulus = 1e8;
  return rock;
}

/// A channel bed z = 0 of soft_rock and a vertical post (a fixed cylinder of 0.2 m, its
/// centre at `centre`), the rigid bodies of the flow-against-a-barrier tests.
inline std::vector<RigidBodyConfig> bed_and_post(const Vec3& centre, double radius) {
  RigidBodyConfig bed;
  bed.name = "bed";
  bed.shape = ShapeKind::kPlane;
  bed.material = "rock";
  RigidBodyConfig post;
  post.name = "post";
  post.shape = ShapeKind::kCylinder;
  post.position = centre;
  post.axis = {0, 0, 1};
  post.radius = radius;
  post.length = 0.2;
  post.material = "rock";
  return {bed, post};
}

/// 25 paper rings linked like chain mail (each with its four diagonal neighbours, the layout
/// of scripts/bench/make_ring_grid.py --linked), Table 3 bonds, corner rings fixed, and a free
/// rigid sphere of 400 kg and 0.2 m above the middle, `clearance` above the rings, falling at
/// `speed` without gravity: ring-ring contacts, a particle-body contact history, bond failure.
inline CaseConfig ring_patch_hit_by_sphere(double clearance, double speed, double damping) {
  CaseConfig c = base_case();
  c.bonds[0].youngs_modulus = 292e9;  // Table 3
  c.bonds[0].radius_multiplier = 0.43;
  c.bonds[0].tensile_strength = c.bonds[0].compressive_strength = 41e9;
  c.bonds[0].shear_strength = 12e9;
  c.damping.global = damping;
  c.simulation.dt = 7.87e-7;
  const double step = 0.25 / std::sqrt(2.0);
  const double tilt = 12.0 * M_PI / 180.0;
  for (int n = 0; n < 5; ++n)
    for (int i = 0; i < 5; ++i) {
      const int m = 2 * i + (n % 2 ? 0 : 1);
      auto ring = paper_ring({m * step, n * step, 0.0},
                             {0.0, (n % 2 ? 1.0 : -1.0) * std::sin(tilt), std::cos(tilt)});
      const bool corner = (n == 0 || n == 4) && (i == 0 || i == 4);
      ring.motion = corner ? Motion::kFixed : Motion::kFree;
      c.rings.push_back(ring);
    }
  RigidBodyConfig boulder;
  boulder.name = "boulder";
  boulder.shape = ShapeKind::kSphere;
  boulder.radius = 0.2;
  boulder.mass = 400.0;
  boulder.motion = Motion::kFree;
  boulder.gravity = false;
  boulder.position = {4.5 * step, 2.0 * step, 0.23 + clearance};
  boulder.velocity = {0, 0, -speed};
  c.rigid_bodies = {boulder};
  return c;
}

/// A free run of a small net of the paper's rings (40 beads, 0.647 kg each) and rock grains,
/// as case-file text: `simulation` the keys of its simulation section, `net` the keys of the
/// net entry besides its group, bond, material and rings (rows, columns, shackles, mesh, ...),
/// `grains` the particles section's entries after `nets` (spheres, lattices), `rock_modulus`
/// the rock's Young's modulus (Pa).
inline std::string net_free_run(const std::string& simulation, const std::string& net,
                                const std::string& grains,
                                const std::string& rock_modulus = "30.0e9") {
  return "schema_version: 1\nsimulation: {" + simulation +
         "}\n"
         "materials:\n"
         "  - {name: steel, density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3, "
         "restitution: 0.5, friction: 0.3}\n"
         "  - {name: rock, density: 2600, youngs_modulus: " +
         rock_modulus +
         ", poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}\n"
         "bonds:\n"
         "  - {name: ring, derive_from: {windings: 12, wire_diameter: 0.003}, "
         "radius_multiplier: 0.43}\n"
         "particles:\n"
         "  nets:\n"
         "    - {group: net, bond: ring, material: steel, mass: 0.647, n_particles: 40, " +
         net + "}\n" + grains + "scenario: {type: free_run}\n";
}

/// A 2 x 3 net with its shackles, and two layers of 3 x 2 rock grains of 50 mm (E = 1 GPa), the
/// upper one 0.11 m above the lower and 30 mm aside, falling at 2 m/s onto it (the lower layer
/// meets the net after about 10 ms, the upper one the lower after that), plus `more_lattices`
/// (entries of `particles.lattices`). The net's step is 2 us, in `substeps` sub-steps of each
/// grain step (simulation.substeps).
inline std::string grains_landing_on_a_net(int substeps, const std::string& more_lattices = "") {
  const std::string layer =
      "count: [3, 2, 1], spacing: 0.2, particle_radius: 0.05, material: rock, "
      "velocity: [0.1, 0, -2]}\n";
  return net_free_run(
      "dt: 2.0e-6, end_time: 1.0, gravity: [0, 0, -9.81], substeps: " + std::to_string(substeps),
      "rows: 2, columns: 3, shackles: {n_particles: 12}",
      "  lattices:\n    - {group: grains, origin: [-0.2, -0.1, 0.07], " + layer +
          "    - {group: grains, origin: [-0.17, -0.1, 0.18], " + layer + more_lattices,
      "1.0e9");
}

/// grains_landing_on_a_net(substeps) with a third layer of finer grains (8 x 4 x 2 of 20 mm
/// radius, 50 mm apart, 0.3 m up) that lands on the two coarse ones.
inline std::string three_layers_landing_on_a_net(int substeps) {
  return grains_landing_on_a_net(substeps,
                                 "    - {group: grains, origin: [-0.3, -0.15, 0.3], "
                                 "count: [8, 4, 2], spacing: 0.05, particle_radius: "
                                 "0.02, material: rock, velocity: [0.1, 0, -2]}\n");
}

/// A rockfall case of a 2 x 3 net and a 5 kg boulder: the sag ends after t = 0.01 s, the
/// impact 2 ms after the first contact (a second takes about as long, `impacts: 2`).
inline constexpr const char* kTinyRockfall = R"(schema_version: 1
simulation: {dt: 2.0e-6, end_time: 5.0, progress_interval: 1.0e-3}
materials:
  - {name: steel, density: 7800, youngs_modulus: 200.0e9, poisson_ratio: 0.3, restitution: 0.5, friction: 0.3}
  - {name: rock, density: 2600, youngs_modulus: 30.0e9, poisson_ratio: 0.25, restitution: 0.3, friction: 0.5}
bonds:
  - {name: ring, derive_from: {windings: 12, wire_diameter: 0.003}, radius_multiplier: 0.43}
particles:
  nets:
    - {group: net, rows: 2, columns: 3, bond: ring, material: steel, mass: 0.647, n_particles: 40,
       shackles: {n_particles: 12}}
scenario:
  type: rockfall
  rockfall: {boulder_mass: 5, boulder_density: 2600, boulder_material: rock, drop_height: 0.2,
             sag_damping: 0.9, sag_kinetic_energy: 0.05, sag_min_time: 0.01,
             sag_check_interval: 0.005, duration: 0.002, record_interval: 5.0e-4}
)";

/// Polydisperse steel grains (3 and 6 mm, 40/60 % by volume) thrown at (2, 0, -2) m/s onto a
/// floor, next to the end of an outflow box at x = 0.19 m: grains leave from the first steps
/// on, and contacts, friction and rebuilds go on among those that stay. 15 mm behind them an
/// inlet 12 mm deep shoots batches of the same mix at 10 m/s, one every 1.2 ms, that reach
/// them after about 1.9 ms.
inline CaseConfig grains_entering_and_leaving() {
  CaseConfig c = base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.simulation.dt = 1e-6;
  c.simulation.skin = 0.0005;
  GrainsConfig g;
  g.material = "steel";
  g.box_min = {0.0, 0.0, 0.0};
  g.box_max = {0.2, 0.1, 0.05};
  g.sizes.distribution = GrainDistribution::kFractions;
  g.sizes.fractions = {{0.003, 0.4}, {0.006, 0.6}};
  g.velocity = {2.0, 0.0, -2.0};
  c.grains = {g};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  floor.position = {0, 0, 0};
  c.rigid_bodies = {floor};
  OutflowConfig out;
  out.name = "edge";
  out.box_min = {-1, -1, -1};
  out.box_max = {0.19, 1, 1};
  c.outflow = {out};
  InflowConfig in;
  in.name = "inlet";
  in.material = "steel";
  in.box_min = {-0.027, 0.0, 0.0};
  in.box_max = {-0.015, 0.1, 0.05};
  in.velocity = {10.0, 0.0, 0.0};
  in.discharge = 0.25 * 0.012 * 0.1 * 0.05 / 0.0012;  // solid fraction 0.25 in the box
  in.sizes = g.sizes;
  c.inflow = {in};
  return c;
}

/// Two clouds of grains_entering_and_leaving()'s grains (no inlet, no outlet) thrown at each
/// other and onto the floor: many contacts, lists rebuilt often, grains that mix.
inline CaseConfig colliding_clouds() {
  CaseConfig c = grains_entering_and_leaving();
  c.outflow.clear();
  c.inflow.clear();
  c.grains[0].box_max = {0.05, 0.06, 0.03};
  c.grains[0].velocity = {4.0, 0.0, -3.0};
  c.grains.push_back(c.grains[0]);
  c.grains[1].box_min = {0.05, 0.0, 0.0};
  c.grains[1].box_max = {0.1, 0.06, 0.03};
  c.grains[1].velocity = {-4.0, 0.0, -3.0};
  return c;
}

}  // namespace ringdem::testing

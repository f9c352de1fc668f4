// Rank-count independence (DESIGN §4, issue 4): the state after N steps on this run's
// ranks equals, bit for bit, the state after N steps on one rank. Every rank also runs the
// one-rank reference (on Communicator::self()) and compares the gathered state by gid.
// On one rank the compared run would be a copy of the reference, so there it takes another
// path instead (compared_skin): results must not depend on that path either.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/TensileTest.hpp"
#include "domain/PairStore.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"

namespace ringdem {
namespace {

struct ParticleRecord {
  std::int64_t gid;
  Vec3 position, velocity, omega;
  Quat orientation;
};

struct BondRecord {
  std::int64_t gid_a, gid_b;
  std::uint8_t broken;
  double break_time;
  /// The bond model's state columns (plastic elongation, strain, work), zero-padded.
  std::array<double, BondTimoshenkoPlastic::State::kSize> state;
  /// The end frames (a plastic bond's hinges are re-based into them).
  Quat frame_a, frame_b;
};

struct State {
  std::vector<ParticleRecord> particles;
  std::vector<BondRecord> bonds;
  std::vector<Vec3> body_positions, body_forces;
};

/// The global state of a simulation, on every rank, ordered by gid.
State gather_state(const Simulation& sim) {
  const ParticleStore& p = sim.model().particles;
  std::vector<ParticleRecord> mine;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    mine.push_back({p.gid[k], p.position[k], p.velocity[k], p.omega[k],
                    p.tracks_orientation() ? p.orientation[k] : Quat{}});
  State s;
  s.particles = sim.comm().allgather(mine);
  std::sort(s.particles.begin(), s.particles.end(),
            [](const auto& a, const auto& b) { return a.gid < b.gid; });
  const BondStore& bonds = sim.model().bonds;
  std::vector<BondRecord> my_bonds;
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (const std::int64_t a = p.index_of(bonds.gid_a[k]);
        a >= 0 && static_cast<std::size_t>(a) < p.n_local())  // listed once, by the owner of a
    {
      BondRecord r{bonds.gid_a[k],   bonds.gid_b[k],  bonds.broken[k], bonds.break_time[k], {},
                   bonds.frame_a[k], bonds.frame_b[k]};
      for (std::size_t c = 0; c < std::min(bonds.n_model_columns(), r.state.size()); ++c)
        r.state[c] = bonds.model_column(c)[k];
      my_bonds.push_back(r);
    }
  s.bonds = sim.comm().allgather(my_bonds);
  std::sort(s.bonds.begin(), s.bonds.end(), [](const auto& a, const auto& b) {
    return a.gid_a < b.gid_a || (a.gid_a == b.gid_a && a.gid_b < b.gid_b);
  });
  for (const auto& b : sim.model().bodies) {
    s.body_positions.push_back(b.position);
    s.body_forces.push_back(b.force);
  }
  return s;
}

void expect_identical(const State& ref, const State& got) {
  ASSERT_EQ(ref.particles.size(), got.particles.size());
  std::size_t mismatches = 0;
  for (std::size_t k = 0; k < ref.particles.size(); ++k) {
    const auto& a = ref.particles[k];
    const auto& b = got.particles[k];
    const bool same = a.gid == b.gid && a.position == b.position && a.velocity == b.velocity &&
                      a.omega == b.omega && a.orientation == b.orientation;
    if (!same && ++mismatches <= 3)
      ADD_FAILURE() << "particle gid " << a.gid << " differs (position, velocity, omega, "
                    << "orientation equal: " << (a.position == b.position)
                    << (a.velocity == b.velocity) << (a.omega == b.omega)
                    << (a.orientation == b.orientation)
                    << "), x - x_ref = " << b.position.x - a.position.x;
  }
  EXPECT_EQ(mismatches, 0u);
  ASSERT_EQ(ref.bonds.size(), got.bonds.size());
  for (std::size_t k = 0; k < ref.bonds.size(); ++k) {
    EXPECT_EQ(ref.bonds[k].gid_a, got.bonds[k].gid_a);
    EXPECT_EQ(ref.bonds[k].broken, got.bonds[k].broken);
    EXPECT_EQ(ref.bonds[k].break_time, got.bonds[k].break_time);
    EXPECT_TRUE(ref.bonds[k].state == got.bonds[k].state)
        << "model state of bond " << ref.bonds[k].gid_a << "-" << ref.bonds[k].gid_b;
    EXPECT_TRUE(ref.bonds[k].frame_a == got.bonds[k].frame_a &&
                ref.bonds[k].frame_b == got.bonds[k].frame_b)
        << "end frames of bond " << ref.bonds[k].gid_a << "-" << ref.bonds[k].gid_b;
  }
  EXPECT_EQ(ref.body_positions, got.body_positions);
  EXPECT_EQ(ref.body_forces, got.body_forces);
}

/// The energies both runs report: every term is summed exactly (the energy ledger's tallies and
/// each particle's share of its contacts' elastic energy included), so it is the same to the bit.
void expect_identical_energies(const Energies& ref, const Energies& got) {
  EXPECT_EQ(ref.kinetic, got.kinetic);
  EXPECT_EQ(ref.contact_elastic, got.contact_elastic);
  EXPECT_EQ(ref.potential, got.potential);
  EXPECT_EQ(ref.bond_elastic, got.bond_elastic);
  EXPECT_EQ(ref.contact_damping, got.contact_damping);
  EXPECT_EQ(ref.friction, got.friction);
  EXPECT_EQ(ref.global_damping, got.global_damping);
  EXPECT_EQ(ref.broken_bonds, got.broken_bonds);
  EXPECT_EQ(ref.boundary_work, got.boundary_work);
  EXPECT_EQ(ref.plastic_work, got.plastic_work);
  EXPECT_EQ(ref.outflow, got.outflow);
  EXPECT_EQ(ref.inflow, got.inflow);
}

int world_size() {
  int n = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &n);
  return n;
}

/// The Verlet skin of the compared run. On several ranks it is the reference's: the runs
/// differ in the rank count only. On one rank it is half of it, so the compared run rebuilds
/// more often and at other steps (each rebuild re-sorts the particles, redistributes the
/// blocks, which are narrower, and hands the contact history to new neighbour lists) and its
/// lists hold other candidate pairs. None of it may change a bit of the results.
double compared_skin(double reference_skin) {
  return world_size() > 1 ? reference_skin : 0.5 * reference_skin;
}

struct EquivalenceResult {
  State reference, parallel;
  State reference_start;  ///< the one-rank run before its first step
  Energies reference_energies, parallel_energies;
  std::int64_t cut_bonds = 0;
  /// Bonds with a non-zero model state (yielded plastic bonds) whose ends are owned by two
  /// ranks at the end of the run.
  std::int64_t cut_bonds_with_state = 0;
  std::int64_t ghosts = 0;
  std::int64_t repartitions = 0;
  std::int64_t broken = 0;
  std::int64_t reference_rebuilds = 0, parallel_rebuilds = 0;
};

/// On one rank, the compared run must really have rebuilt on another schedule.
void expect_other_path(const EquivalenceResult& r) {
  if (world_size() == 1) {
    EXPECT_NE(r.parallel_rebuilds, r.reference_rebuilds)
        << "the one-rank comparison should rebuild at other steps than its reference";
  }
}

EquivalenceResult run_both(const CaseConfig& c, std::int64_t steps,
                           double imbalance_threshold = 0.1) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  EquivalenceResult r;
  {
    const Communicator comm(world);
    SimulationSettings s = settings_from_case(c);
    s.imbalance_threshold = imbalance_threshold;
    SimulationSettings compared = s;
    compared.skin = compared_skin(s.skin);
    Simulation parallel(build_scenario_model(c, comm), comm, compared);
    for (const auto& rank :
         parallel.decomposition().report(parallel.model().particles, parallel.model().bonds)) {
      r.cut_bonds += rank.cut_bonds;
    }
    parallel.run_steps(steps);
    for (const auto& rank :
         parallel.decomposition().report(parallel.model().particles, parallel.model().bonds))
      r.ghosts += rank.ghosts;  // at the end: contacts made during the run cross ranks
    r.parallel = gather_state(parallel);
    {
      const ParticleStore& p = parallel.model().particles;
      const BondStore& bonds = parallel.model().bonds;
      std::int64_t mine = 0;
      for (std::size_t k = 0; k < bonds.size(); ++k) {
        const std::int64_t b = p.index_of(bonds.gid_b[k]);
        const bool cut = b < 0 || static_cast<std::size_t>(b) >= p.n_local();
        bool state = false;
        for (std::size_t col = 0; col < bonds.n_model_columns(); ++col)
          state = state || bonds.model_column(col)[k] != 0.0;
        mine += counted_here(p, bonds, k) && cut && state;
      }
      r.cut_bonds_with_state = comm.sum(mine);
    }
    r.parallel_energies = parallel.energies();
    r.repartitions = parallel.decomposition().repartitions();
    r.broken = parallel.global_broken_bonds();
    r.parallel_rebuilds = parallel.rebuilds();

    const Communicator self = Communicator::self();
    Simulation serial(build_scenario_model(c, self), self, s);
    r.reference_start = gather_state(serial);
    serial.run_steps(steps);
    r.reference = gather_state(serial);
    r.reference_energies = serial.energies();
    r.reference_rebuilds = serial.rebuilds();
  }
  return r;
}

// (a) The 4-pin tensile test through its bending stage (pins moving at 0.5 m/s, 8 mm).
// The ring is cut between ranks, so bonds cross the cut (e) and ring–pin contacts carry
// tangential history.
TEST(Equivalence, Ring4TensileBendingStage) {
  CaseConfig c =
      load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_calibrated.yaml",
                {"scenario.tensile_test.loading_rate=0.5"});
  const auto r = run_both(c, 16000);
  if (world_size() > 1) {
    EXPECT_GT(r.cut_bonds, 0) << "the ring should be split between ranks";
  }
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.boundary_work, 0.0) << "the pins should do work";
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// (a') The same test with the elastoplastic bond (model timoshenko_plastic), its wire made
// weak (f_y = 15 MPa) so that most bonds yield within the first millimetres: the plastic state of
// the bonds that cross the cut is computed on both ranks that hold them, and moves with them.
// Particles, every bond's plastic state and the plastic-work total: the same bits.
TEST(Equivalence, Ring4PlasticTensileYields) {
  const CaseConfig c =
      load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_plastic.yaml",
                {"scenario.tensile_test.loading_rate=0.5", "bonds[0].plastic.yield_stress=15e6"});
  const auto r = run_both(c, 16000);
  if (world_size() > 1) {
    EXPECT_GT(r.cut_bonds, 0) << "the ring should be split between ranks";
  }
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  const auto& names = BondTimoshenkoPlastic::State::kNames;
  const std::size_t work = static_cast<std::size_t>(
      std::find(names.begin(), names.end(), "plastic_work") - names.begin());
  ASSERT_LT(work, names.size());
  std::size_t yielded = 0, hinged = 0;
  for (std::size_t k = 0; k < r.reference.bonds.size(); ++k) {
    yielded += r.reference.bonds[k].state[work] > 0.0;
    // Frames away from their creation values: a hinge was re-based into them.
    hinged += r.reference.bonds[k].frame_b != r.reference_start.bonds[k].frame_b;
  }
  EXPECT_GT(hinged, 10u) << "hinges should have formed";
  EXPECT_GT(yielded, 40u) << "most bonds should have yielded";
  if (world_size() > 1) {
    EXPECT_GT(r.cut_bonds_with_state, 0) << "a yielded bond should cross the cut";
  }
  EXPECT_GT(r.reference_energies.plastic_work, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// The tensile driver on this run's ranks (on one rank: with half the skin): the same curve,
// bit for bit, as on one rank, through failure (its stop rule and bookkeeping make collective
// calls that every rank must reach).
TEST(Equivalence, TensileDriverToFailure) {
  const CaseConfig c =
      load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_calibrated.yaml",
                {"scenario.tensile_test.loading_rate=0.5"});
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  TensileRunOptions quiet;
  quiet.verbose = false;
  CaseConfig compared = c;
  compared.simulation.skin = compared_skin(c.simulation.skin);
  TensileResult parallel, serial;
  {
    const Communicator comm(world);
    parallel = run_tensile_test(compared, quiet, comm);
    serial = run_tensile_test(c, quiet, Communicator::self());
  }
  EXPECT_EQ(parallel.stop_reason, TensileStopRule::Reason::kFailure);
  EXPECT_GT(parallel.broken_bonds, 0);
  ASSERT_EQ(parallel.curve.size(), serial.curve.size());
  for (std::size_t k = 0; k < serial.curve.size(); ++k) {
    EXPECT_EQ(parallel.curve[k].displacement, serial.curve[k].displacement);
    EXPECT_EQ(parallel.curve[k].load, serial.curve[k].load);
    EXPECT_EQ(parallel.curve[k].broken_bonds, serial.curve[k].broken_bonds);
  }
  EXPECT_EQ(parallel.elongation_at_failure, serial.elongation_at_failure);
  EXPECT_EQ(parallel.first_bond_break_time, serial.first_bond_break_time);
}

// The tensile driver's unloading (unload_at) on this run's ranks: the 4-pin plastic ring with a
// weak wire (hinges within the first millimetres) pulled 8 mm and driven back until the load is
// zero. The turn, the rows of both branches and the residual displacement: the same bits as on
// one rank (the decisions read the pins' load, reduced over the ranks).
TEST(Equivalence, TensileDriverUnloading) {
  const CaseConfig c =
      load_case(std::string(RINGDEM_SOURCE_DIR) + "/inputs/tensile/ring4_plastic.yaml",
                {"scenario.tensile_test.loading_rate=0.5", "scenario.tensile_test.unload_at=0.008",
                 "bonds[0].plastic.yield_stress=15e6"});
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  TensileRunOptions quiet;
  quiet.verbose = false;
  CaseConfig compared = c;
  compared.simulation.skin = compared_skin(c.simulation.skin);
  TensileResult parallel, serial;
  {
    const Communicator comm(world);
    parallel = run_tensile_test(compared, quiet, comm);
    serial = run_tensile_test(c, quiet, Communicator::self());
  }
  EXPECT_EQ(parallel.stop_reason, TensileStopRule::Reason::kUnloaded);
  ASSERT_TRUE(serial.residual_displacement.has_value());
  EXPECT_GT(*serial.residual_displacement, 0.0);
  ASSERT_EQ(parallel.curve.size(), serial.curve.size());
  for (std::size_t k = 0; k < serial.curve.size(); ++k) {
    EXPECT_EQ(parallel.curve[k].displacement, serial.curve[k].displacement);
    EXPECT_EQ(parallel.curve[k].load, serial.curve[k].load);
  }
  EXPECT_EQ(parallel.turn_displacement, serial.turn_displacement);
  EXPECT_EQ(parallel.residual_displacement, serial.residual_displacement);
}

// (b) A 5 x 5 patch of interlinked rings (chain mail: each ring linked with its four
// diagonal neighbours, the layout of scripts/bench/make_ring_grid.py --linked), corner rings
// fixed, hit by a fast rigid sphere until bonds break: ring-ring contacts, bond failure
// decided on both holders of a cut bond, and the sphere's load reduced over ranks.
TEST(Equivalence, RingPatchHitBySphereUntilBondsBreak) {
  // 2 cm clear of the rings, at 60 m/s, Table 1 damping. The sphere touches at step 423 and
  // the first bond breaks at step 541; by step 3000 (2.4 ms) 28 have broken and the pieces fly
  // apart (measured at 1, 2 and 3 ranks, 2026-12-02; 6000 steps before then, twice the time).
  const CaseConfig c = testing::ring_patch_hit_by_sphere(0.02, 60.0, 0.95);
  const auto r = run_both(c, 3000);
  EXPECT_GT(r.broken, 0) << "the impact should break bonds";
  if (world_size() > 1) {
    // METIS cuts between rings (no bond crosses), so the ring-ring contacts do, via ghosts.
    EXPECT_GT(r.ghosts, 0) << "the patch should be split between ranks";
  }
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.broken_bonds, 0.0);
  EXPECT_GT(r.reference_energies.contact_damping, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// (c) Free spheres poured onto a plane; repartitioning at every rebuild (threshold 0) makes
// particles cross between ranks many times, with their contact history (d).
TEST(Equivalence, PouredSpheresCrossRanksManyTimes) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.simulation.dt = 2e-6;
  c.simulation.skin = 0.0005;
  LatticeConfig lat;
  lat.origin = {0, 0, 0.006};
  lat.count = {17, 17, 17};
  lat.spacing = 0.0095;
  lat.particle_radius = 0.0045;
  lat.velocity = {0.2, 0.1, -1.0};
  lat.jitter = 0.3;
  c.lattices = {lat};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  floor.position = {0, 0, 0};
  c.rigid_bodies = {floor};
  const auto r = run_both(c, 2500, /*imbalance_threshold=*/0.0);
  if (world_size() > 1) {
    EXPECT_GT(r.repartitions, 3);
  }
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.friction, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// Polydisperse grains from the per-rank source (sparse gids, cells built by the rank whose
// slice holds them), falling onto a floor: the same bits as one rank.
TEST(Equivalence, PolydisperseGrainsSettleOnAnyRankCount) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.inflow.clear();
  c.outflow.clear();
  c.grains[0].velocity = {0.3, 0.0, -2.0};
  const auto r = run_both(c, 3000, /*imbalance_threshold=*/0.0);
  EXPECT_GT(r.reference.particles.size(), 400u);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.friction, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// Grains entering through an inlet and leaving through an outflow box while they settle: the
// same grains enter and leave at the same steps, and the rest ends the same bits, on any rank
// count; what crossed is counted alike.
/// Runs `c` (grains entering and leaving) for `steps` steps on both paths: more than 300 grains
/// at the end, some in and some out, the same bits.
void expect_grains_enter_and_leave_alike(const CaseConfig& c, std::int64_t steps) {
  const auto r = run_both(c, steps, /*imbalance_threshold=*/0.0);
  EXPECT_GT(r.reference.particles.size(), 300u);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.outflow, 0.0);
  EXPECT_GT(r.reference_energies.inflow, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

TEST(Equivalence, GrainsEnteringAndLeaving) {
  expect_grains_enter_and_leave_alike(testing::grains_entering_and_leaving(), 3000);
}

// Coarse grains falling onto a net whose rings carry a secondary mesh (engine/RingMeshTerm):
// each mesh contact's loads on the grain and on every bead of its ring are computed wherever
// one of them is owned, from the same inputs, so the run is the same bits on any rank count.
TEST(Equivalence, AMeshedNetCatchesGrainsOnAnyRankCount) {
  const CaseConfig c = load_case_from_string(
      testing::net_free_run("dt: 2.0e-6, end_time: 1.0, gravity: [0, 0, -9.81]",
                            "rows: 2, columns: 3, shackles: {n_particles: 12}, "
                            "mesh: {opening: 0.06, stiffness: 2.0e5}",
                            "  lattices:\n"
                            "    - {group: grains, origin: [-0.2, -0.1, 0.07], count: [3, 2, 1], "
                            "spacing: 0.2, particle_radius: 0.05, material: rock, "
                            "velocity: [0.1, 0, -2]}\n",
                            "1.0e9"),
      "meshed.yaml");
  const auto r = run_both(c, 30000, /*imbalance_threshold=*/0.0);
  // The mesh held grains: their speed down, summed over the six (which come last in gid
  // order), is at least 1 m/s less than over the bare net's rings in the same time.
  CaseConfig bare_case = c;
  bare_case.nets[0].mesh.reset();
  const Communicator self = Communicator::self();
  Simulation bare(build_scenario_model(bare_case, self), self, settings_from_case(bare_case));
  bare.run_steps(30000);
  const State bare_end = gather_state(bare);
  ASSERT_EQ(bare_end.particles.size(), r.reference.particles.size());
  double meshed_down = 0.0, bare_down = 0.0;
  for (std::size_t k = r.reference.particles.size() - 6; k < r.reference.particles.size(); ++k) {
    meshed_down -= r.reference.particles[k].velocity.z;
    bare_down -= bare_end.particles[k].velocity.z;
  }
  EXPECT_LT(meshed_down, bare_down - 1.0) << meshed_down << " vs " << bare_down;
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// Multi-rate stepping (simulation.substeps): the net's contacts and bonds at every sub-step, the
// grains' contacts with each other at every fourth, with their ghosts refreshed at both rates:
// the same bits on any rank count.
TEST(Equivalence, ASubsteppedNetCatchesGrainsOnAnyRankCount) {
  // A third layer of finer grains lands on the two of coarse ones.
  const CaseConfig c =
      load_case_from_string(testing::three_layers_landing_on_a_net(4), "substepped.yaml");
  const auto r = run_both(c, 15000, /*imbalance_threshold=*/0.0);  // 0.12 s
  expect_other_path(r);
  expect_identical(r.reference, r.parallel);
  EXPECT_GT(r.reference_energies.friction, 0.0);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// A layer of grains 0.1 mm apart lands on the sub-stepped net and is pressed together as it
// sags: grains that the net kicks at every sub-step (their contacts with it are fast) touch
// their neighbours, often across a rank boundary, through slow contacts whose damping reads
// both velocities. Each rank that holds such a pair must read the velocity of the last fast
// kick, so the ghosts are refreshed again before the slow evaluation (engine/
// SimulationSubsteps.cpp); without that refresh this run differs from one rank at 2 and 3 ranks.
TEST(Equivalence, GrainsPressedTogetherOnASubsteppedNet) {
  const CaseConfig c = load_case_from_string(
      testing::net_free_run("dt: 2.0e-6, end_time: 1.0, gravity: [0, 0, -9.81], substeps: 4",
                            "rows: 2, columns: 3, shackles: {n_particles: 12}",
                            "  lattices:\n"
                            "    - {group: grains, origin: [-0.25, -0.15, 0.05], count: [16, 10, "
                            "1], spacing: 0.0301, particle_radius: 0.015, material: rock, "
                            "velocity: [0.1, 0, -2]}\n",
                            "1.0e9"),
      "pressed.yaml");
  const auto r = run_both(c, 6000, /*imbalance_threshold=*/0.0);  // 0.048 s
  expect_other_path(r);
  EXPECT_GT(r.reference_energies.friction, 0.0);
  expect_identical(r.reference, r.parallel);
  expect_identical_energies(r.reference_energies, r.parallel_energies);
}

// Grains entering and leaving with every interaction slow (no net): the grain steps' ghosts,
// inlets and outflow on any rank count.
TEST(Equivalence, SubsteppedGrainsEnteringAndLeaving) {
  CaseConfig c = testing::grains_entering_and_leaving();
  c.simulation.substeps = 3;
  expect_grains_enter_and_leave_alike(c, 1000);
}

}  // namespace
}  // namespace ringdem

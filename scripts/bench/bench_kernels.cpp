// Micro-benchmarks of the hot kernels and of whole steps (issue: foundation, item 8).
// Run: scripts/bench/run.sh  (builds the "native" preset and runs this binary).
#include <benchmark/benchmark.h>
#include <mpi.h>

#include <memory>
#include <random>

#include "../../tests/support/TestCases.hpp"
#include "engine/ForceTerm.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "engine/TimoshenkoPlasticBondTerm.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/HertzMindlin.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {
namespace {

// One scalar bond evaluation (forces, stresses, failure check) on a bent, stretched, twisted
// state: the latency of a single call, not what the vectorised bond loop achieves.
void BM_BondKernel(benchmark::State& state) {
  BondTimoshenko::Params params;
  params.youngs_modulus = 292e9;
  params.radius_multiplier = 0.43;
  params.tensile_strength = params.compressive_strength = 41e9;
  params.shear_strength = 12e9;
  const double l0 = 0.0097;
  const auto section = BondTimoshenko::Section::make(params, 0.0045, 0.0045, l0);
  const Quat identity;
  const auto ref = BondTimoshenko::Reference::make({0, 0, 0}, identity, {l0, 0, 0}, identity);
  constexpr int kStates = 256;
  std::vector<Vec3> xb(kStates);
  std::vector<Quat> ra(kStates), rb(kStates);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3);
  for (int k = 0; k < kStates; ++k) {
    xb[k] = {l0 * (1 + u(rng)), l0 * u(rng), l0 * u(rng)};
    ra[k] = quat_from_rotation_vector({u(rng), u(rng), u(rng)});
    rb[k] = quat_from_rotation_vector({u(rng), u(rng), u(rng)});
  }
  const BondTimoshenko::Strength strength{41e9, 41e9, 12e9};
  int k = 0;
  for (auto _ : state) {
    const auto r = BondTimoshenko::compute(section, ref, {0, 0, 0}, ra[k], xb[k], rb[k]);
    const auto st = BondTimoshenko::stresses(section, r);
    benchmark::DoNotOptimize(BondTimoshenko::check_failure(st, strength));
    benchmark::DoNotOptimize(r);
    k = (k + 1) & (kStates - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_BondKernel);

// The bond loop as the step runs it (vectorised over bonds): 100 rings, 10 000 bonds, each
// ring bent a little so that no bond is at its reference state. `Term` is the bond model's
// force term, `configure` sets the case's bond model.
template <class Term, class Configure, class MakeTerm>
void bond_loop(benchmark::State& state, Configure&& configure, MakeTerm&& make_term) {
  CaseConfig c = testing::base_case();
  c.bonds[0].youngs_modulus = 292e9;
  c.bonds[0].radius_multiplier = 0.43;
  configure(c.bonds[0]);
  for (int r = 0; r < 100; ++r)
    c.rings.push_back(testing::paper_ring({0.4 * (r % 10), 0.4 * (r / 10), 0}));
  Model model = build_model(c);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1e-5, 1e-5);
  for (auto& x : model.particles.position)
    x += Vec3{u(rng), u(rng), u(rng)};
  model.particles.rebuild_index();
  Term bonds = make_term(model);
  std::vector<ExcludedPair> excluded;
  SlotAllocator allocator;
  GatherMap gather;
  gather.begin(model.particles.n_local());
  RebuildContext rebuild{model.particles, model.bodies, 0.001, excluded, allocator, gather, 0};
  bonds.rebuild(rebuild);
  ForceSlots slots;
  slots.assign(allocator.size());
  EnergyLedger ledger;
  ComputeContext ctx{model.particles, model.bodies, model.materials, slots, ledger, 0.0, 0.0, {}};
  for (auto _ : state)
    bonds.compute(ctx);
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * model.bonds.size()));
}

void BM_BondLoop(benchmark::State& state) {
  bond_loop<TimoshenkoBondTerm>(
      state, [](BondConfig&) {},
      [](Model& m) { return TimoshenkoBondTerm(m.bonds, m.bond_types); });
}
BENCHMARK(BM_BondLoop)->Unit(benchmark::kMicrosecond);

// The same with the elastoplastic bond of inputs/rockfall/r12_plastic.yaml, every bond inside
// its yield surface (as most are, most steps): the vector pass alone.
void BM_PlasticBondLoop(benchmark::State& state) {
  bond_loop<TimoshenkoPlasticBondTerm>(
      state,
      [](BondConfig& b) {
        b.model = "timoshenko_plastic";
        BondPlasticConfig plastic;
        plastic.yield_stress = 1504.5e6;
        plastic.hardening_ratio = 0.036543;
        plastic.failure_strain = 0.035;
        plastic.windings = 12;
        plastic.wire_diameter = 0.003;
        b.plastic = plastic;
      },
      [](Model& m) { return TimoshenkoPlasticBondTerm(m.bonds, m.plastic_bond_types); });
}
BENCHMARK(BM_PlasticBondLoop)->Unit(benchmark::kMicrosecond);

// One Hertz–Mindlin contact evaluation with tangential history.
void BM_ContactKernel(benchmark::State& state) {
  const auto params = HertzMindlin::Params::mix(200e9, 0.3, 200e9, 0.3, 0.5, 1.0, 0.0);
  constexpr int kStates = 256;
  std::vector<HertzMindlin::Input> inputs(kStates);
  std::vector<Vec3> springs(kStates);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (auto& in : inputs) {
    in.normal = normalized(Vec3{u(rng), u(rng), u(rng)});
    in.overlap = 1e-6 * (1.5 + u(rng));
    in.r_star = 0.00225;
    in.m_star = 1.5e-3;
    in.v_rel = Vec3{u(rng), u(rng), u(rng)} * 0.01;
    in.dt = 7.87e-7;
    in.arm_i = in.arm_j = 0.0045;
  }
  int k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(HertzMindlin::compute(params, inputs[k], springs[k]));
    k = (k + 1) & (kStates - 1);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_ContactKernel);

// n_rings separate paper rings (100 particles each) on a square grid, falling and swinging
// under gravity with global damping `damping`, calibrated bonds, dt of the paper, stepped 100
// times (loads, velocities and spins of moving, bending rings).
std::unique_ptr<Simulation> moving_rings(int n_rings, double damping, const Communicator& comm) {
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {0, 0, -9.81};
  c.bonds[0].youngs_modulus = 292e9;
  c.bonds[0].radius_multiplier = 0.43;
  c.damping.global = damping;
  const int side = static_cast<int>(std::ceil(std::sqrt(n_rings)));
  for (int r = 0; r < n_rings; ++r) {
    auto ring = testing::paper_ring({0.4 * (r % side), 0.4 * (r / side), 0.0});
    ring.velocity = {0.01 * (r % 3), 0.0, 0.05};
    c.rings.push_back(ring);
  }
  SimulationSettings s;
  s.dt = 7.87e-7;
  s.gravity = c.simulation.gravity;
  auto sim = std::make_unique<Simulation>(build_model(c, comm), comm, s);
  sim->run_steps(100);
  return sim;
}

void count_particle_steps(benchmark::State& state, double particles) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * particles));
  state.counters["time_per_particle_step"] =
      benchmark::Counter(particles * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

// Whole steps of the moving rings with the paper's global damping.
void BM_StepRings(benchmark::State& state) {
  const Communicator comm(MPI_COMM_SELF);
  const auto sim = moving_rings(static_cast<int>(state.range(0)), 0.95, comm);
  for (auto _ : state)
    sim->step();
  count_particle_steps(state, static_cast<double>(sim->model().particles.n_local()));
}
BENCHMARK(BM_StepRings)->Arg(1)->Arg(100)->Unit(benchmark::kMicrosecond);

// The integrator's two passes alone (drift with orientations, damped second half kick) over
// the moving rings with the net's impact damping, loads as a step leaves them: the part of
// the net's step that issue 12 bounds at 10 ns per particle-step. Arg 0: 10 rings (about
// 1 000 particles, in the first-level caches) and 100 (a rank's share of r12, from the last
// level): equal times say the passes are bound by their arithmetic, not by memory. Arg 1: the
// two passes apart (0) or the fused pass that a run's step batches take (1, with the ledger's
// booking left out).
void BM_IntegrateRings(benchmark::State& state) {
  const Communicator comm(MPI_COMM_SELF);
  const auto sim = moving_rings(static_cast<int>(state.range(0)), 0.2, comm);
  ParticleStore p = sim->model().particles;
  const double dt = sim->dt();
  const Vec3 gravity = sim->settings().gravity;
  const std::vector<Vec3> force = p.force, torque = p.torque;
  const bool fused = state.range(1) != 0;
  // The bond loads a step would add, so that the kick and the damping see real loads.
  const auto add_bond_loads = [&] {
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      p.force[k] += force[k];
      p.torque[k] += torque[k];
    }
  };
  if (fused) {
    benchmark::DoNotOptimize(Integrator::first_half(p, dt, gravity, 1e-4, 0.1, true));
    add_bond_loads();
  }
  for (auto _ : state) {
    if (fused) {
      benchmark::DoNotOptimize(
          Integrator::second_then_first_half(p, dt, gravity, 1e-4, 0.1, true, [](std::size_t) {}));
    } else {
      benchmark::DoNotOptimize(Integrator::first_half(p, dt, gravity, 1e-4, 0.1, true));
    }
    add_bond_loads();
    if (!fused) Integrator::second_half(p, dt);
  }
  count_particle_steps(state, static_cast<double>(p.n_local()));
}
BENCHMARK(BM_IntegrateRings)
    ->Args({10, 0})
    ->Args({100, 0})
    ->Args({10, 1})
    ->Args({100, 1})
    ->Unit(benchmark::kMicrosecond);

// The integrator alone on free grains (no damping, no orientations), as the grain flows step:
// separate passes (second half kick, then drift: Arg 0) or one fused pass (Arg 1, the batches
// of Simulation::run_steps), for 4 096 particles (in cache) and 2^20 (from memory).
/// n free rock grains in a row, moving; radius 5 mm, or 5-9 mm where `mixed_radii`.
ParticleStore free_grains(std::size_t n, bool mixed_radii) {
  ParticleStore p;
  p.reserve(n);
  for (std::size_t k = 0; k < n; ++k) {
    ParticleStore::NewParticle np;
    np.gid = static_cast<std::int64_t>(k);
    np.position = {0.01 * static_cast<double>(k), 0.0, 0.0};
    np.velocity = {1.0, 0.1 * static_cast<double>(k % 7), 0.0};
    np.radius = 0.005 + (mixed_radii ? 0.001 * static_cast<double>(k % 5) : 0.0);
    np.density = 2600.0;
    p.add(np);
  }
  return p;
}

void BM_IntegrateGrains(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  ParticleStore p = free_grains(n, false);
  p.force.assign(n, Vec3{0.01, 0.02, -0.01});
  const Vec3 gravity{5.6, 0.0, -8.0};
  const double dt = 1.31e-5;
  const bool fused = state.range(1) != 0;
  for (auto _ : state) {
    if (fused) {
      benchmark::DoNotOptimize(
          Integrator::second_then_first_half(p, dt, gravity, 1e-4, 0.1, false, [](std::size_t) {}));
    } else {
      Integrator::second_half(p, dt);
      benchmark::DoNotOptimize(Integrator::first_half(p, dt, gravity, 1e-4, 0.1, false));
    }
  }
  count_particle_steps(state, static_cast<double>(p.n_local()));
}
BENCHMARK(BM_IntegrateGrains)
    ->Args({4096, 0})
    ->Args({4096, 1})
    ->Args({1 << 20, 0})
    ->Args({1 << 20, 1})
    ->Unit(benchmark::kMicrosecond);

// Multi-rate stepping's slow half kick (Integrator::kick from ParticleStore::slow_force), which
// opens and closes every grain step over all owned particles, for 4 096 particles (in cache)
// and 2^20 (from memory).
void BM_SlowKick(benchmark::State& state) {
  const std::size_t n = static_cast<std::size_t>(state.range(0));
  ParticleStore p = free_grains(n, true);
  p.slow_force.assign(n, Vec3{0.01, 0.02, -0.01});
  p.slow_torque.assign(n, Vec3{1e-5, 0.0, -2e-5});
  for (auto _ : state) {
    Integrator::kick(p, p.slow_force, p.slow_torque, 0.5e-5);
    benchmark::DoNotOptimize(p.velocity.data());
  }
  count_particle_steps(state, static_cast<double>(p.n_local()));
}
BENCHMARK(BM_SlowKick)->Arg(4096)->Arg(1 << 20)->Unit(benchmark::kMicrosecond);

// A packing in contact, as the peers' `dense` bed (docs/performance.md) at a size that fits
// a benchmark: n^3 rock spheres of 5 mm on a 9.98 mm lattice (each presses 20 um into its
// neighbours, the bottom layer 10 um into a floor), sliding at 1 m/s down a 35-degree incline,
// stepped in batches of 10 as a run steps them (Simulation::run_steps). Arg 0: spheres a side
// (20: 8 000 grains, in cache; 64: 262 144, from memory); Arg 1: the energy ledger off (0) or
// on (1), whose cost on a packing is what the seventeenth and nineteenth rounds measured.
void BM_StepPacking(benchmark::State& state) {
  const int side = static_cast<int>(state.range(0));
  CaseConfig c = testing::base_case();
  c.simulation.gravity = {5.626784840603762, 0.0, -8.03588155447501};
  c.simulation.allow_initial_overlap = true;
  c.simulation.energy_ledger = state.range(1) != 0;
  c.simulation.skin = 0.001;
  MaterialConfig& rock = c.materials[0];
  rock.density = 2600.0;
  rock.youngs_modulus = 1e9;
  rock.poisson_ratio = 0.25;
  rock.restitution = 0.3;
  rock.friction = 0.5;
  LatticeConfig grains;
  grains.group = "grains";
  grains.origin = {0.005, 0.005, 0.00499};
  grains.count = {side, side, side};
  grains.spacing = 0.00998;
  grains.particle_radius = 0.005;
  grains.velocity = {1.0, 0.0, 0.0};
  c.lattices = {grains};
  RigidBodyConfig floor;
  floor.name = "floor";
  floor.shape = ShapeKind::kPlane;
  c.rigid_bodies = {floor};
  const Communicator comm(MPI_COMM_SELF);
  SimulationSettings settings = settings_from_case(c);
  settings.dt = 1.31e-5;
  Simulation sim(build_model(c, comm), comm, settings);
  sim.run_steps(10);
  for (auto _ : state)
    sim.run_steps(10);
  count_particle_steps(state, 10.0 * static_cast<double>(sim.model().particles.n_local()));
}
BENCHMARK(BM_StepPacking)
    ->Args({20, 0})
    ->Args({20, 1})
    ->Args({64, 0})
    ->Args({64, 1})
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace ringdem

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  MPI_Finalize();
  return 0;
}

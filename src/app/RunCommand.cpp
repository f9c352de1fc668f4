#include "app/RunCommand.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>

#include "app/ScenarioRunner.hpp"
#include "comm/ExactSum.hpp"
#include "core/Version.hpp"
#include "domain/RingGenerator.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/SizeEstimate.hpp"

namespace ringdem {

std::string format_duration(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  const auto total = static_cast<long long>(s + 0.5);
  if (total >= 3600) return fmt::format("{}h{:02}m", total / 3600, (total % 3600) / 60);
  if (total >= 60) return fmt::format("{}m{:02}s", total / 60, total % 60);
  return fmt::format("{}s", total);
}

void print_banner(const CaseConfig& config, const std::string& out_dir, const Communicator& comm) {
  fmt::print("ringdem {} — discrete elements for flexible ring nets\n", kVersion);
  fmt::print("case {} ({}), {} MPI rank{}, output in {}\n", config.name, config.source_path,
             comm.size(), comm.size() == 1 ? "" : "s", out_dir.empty() ? "(none)" : out_dir);
  fmt::print("--- resolved configuration ---\n{}--- end of configuration ---\n", dump_case(config));
}

void print_preflight(const Simulation& sim, const CaseConfig& config, std::int64_t planned_steps,
                     bool print, const std::string& time_step_origin) {
  const std::int64_t particles = sim.global_particles();
  const std::int64_t bonds = sim.global_bonds();
  const auto ranks = sim.decomposition().report(sim.model().particles, sim.model().bonds);
  const double imbalance = sim.decomposition().imbalance(sim.model().particles);
  // What the partition balances: a bond weighs as what it costs (more with sub-steps), so a
  // rank with the net holds fewer particles on purpose.
  const double weighted = ranks.size() > 1 ? sim.partition_imbalance() : 0.0;
  if (!print) return;
  if (ranks.size() > 1) {
    const DomainDecomposition& d = sim.decomposition();
    fmt::print(
        "partition: {} ranks, block size {:.4g} m, cells of {}^3 blocks, imbalance {:.1f} % by "
        "weight, {:.1f} % by particles\n",
        ranks.size(), d.block_size(), d.cell_blocks(), 100.0 * weighted, 100.0 * imbalance);
    fmt::print("  {:>4} {:>10} {:>10} {:>10} {:>10} {:>8}\n", "rank", "particles", "ghosts",
               "bonds", "cut bonds", "cells");
    for (std::size_t r = 0; r < ranks.size(); ++r)
      fmt::print("  {:>4} {:>10} {:>10} {:>10} {:>10} {:>8}\n", r, ranks[r].particles,
                 ranks[r].ghosts, ranks[r].bonds, ranks[r].cut_bonds, ranks[r].cells);
  }
  fmt::print("pre-flight: {} particles, {} bonds, {} rigid bodies, {} contact candidates\n",
             particles, bonds, sim.model().bodies.size(), sim.n_contact_candidates());
  for (const BondConfig& b : config.bonds) {
    if (!b.derive_from || b.derived_particle_radius <= 0.0) continue;
    const RingReductionFactors f = ring_reduction_factors(
        b.derive_from->windings, 0.5 * b.derive_from->wire_diameter, b.derived_particle_radius,
        b.radius_multiplier, b.derive_from->steel_youngs_modulus);
    fmt::print(
        "bond {}: {} windings of {:.4g} mm wire, R_eq = {:.4g} mm, r_eq = {:.4g} mm, lambda = "
        "{:.4g}: gamma = {:.4f}, eta = {:.4f}, eta*gamma^4 = {:.4g}, E_b = {:.4g} GPa\n",
        b.name, b.derive_from->windings, 1e3 * b.derive_from->wire_diameter,
        1e3 * f.equivalent_radius, 1e3 * b.derived_particle_radius, b.radius_multiplier, f.gamma,
        f.eta, f.bending_reduction(), 1e-9 * f.bond_youngs_modulus);
  }
  const Model& model = sim.model();
  for (std::size_t t = 0; t < model.plastic_bond_types.size(); ++t) {
    const BondTimoshenkoPlastic::Params& p = model.plastic_bond_types[t];
    fmt::print(
        "bond {} ({}): N_p = {:.4g} kN, M_y = {:.4g} N m, M_p = {:.4g} N m, hardening h = {:.4g}, "
        "plastic strain limit {}\n",
        model.bond_type_names[t], model.bond_model, 1e-3 * p.axial_yield, p.yield_moment,
        p.plastic_moment, p.hardening,
        p.failure_strain > 0.0 ? fmt::format("{:.4g}", p.failure_strain) : std::string("none"));
  }
  const std::string origin = config.simulation.dt
                                 ? std::string("fixed")
                                 : fmt::format("auto, safety {}", config.simulation.dt_safety);
  // A driver that ends the run by what happens (the rockfall's phases) cannot know its steps:
  // say what bounds them rather than "0 steps planned".
  const std::string steps =
      planned_steps > 0
          ? fmt::format("{} steps planned", planned_steps)
          : fmt::format("the scenario's phases set the steps (at most {} to end_time {:g} s)",
                        sim.steps_until(config.simulation.end_time) - sim.steps(),
                        config.simulation.end_time);
  const std::string how = time_step_origin.empty() ? origin : origin + ", " + time_step_origin;
  const auto substeps = sim.settings().substeps;
  if (substeps > 1)
    fmt::print("grain step {:.4g} s, {} sub-steps of {:.4g} s ({}), {}\n", sim.dt(), substeps,
               sim.substep(), how, steps);
  else
    fmt::print("time step {:.4g} s ({}), {}\n", sim.dt(), how, steps);
  // With sub-steps every limit is the fast interactions' (the net's, and those of the grains
  // that touch it); the grains' contacts with each other take the grain step.
  const char* step_name = substeps > 1 ? "the sub-step" : "dt";
  for (const auto& [name, limit] : sim.limits().named())
    if (std::isfinite(limit))
      fmt::print("  {:<14} limit {:.4g} s: {} is {:.3f} of it\n", name, limit, step_name,
                 sim.substep() / limit);
  if (sim.substep() > sim.limits().min())
    fmt::print("WARNING: {} exceeds the smallest stability limit; the run may blow up\n",
               step_name);
  if (substeps > 1 && std::isfinite(sim.grain_rayleigh_limit())) {
    fmt::print("  {:<14} limit {:.4g} s: the grain step is {:.3f} of it\n", "grains' Rayleigh",
               sim.grain_rayleigh_limit(), sim.dt() / sim.grain_rayleigh_limit());
    if (sim.dt() > sim.grain_rayleigh_limit())
      fmt::print(
          "WARNING: the grain step exceeds the grains' Rayleigh limit; lower "
          "simulation.substeps\n");
  }
}

MemoryUse measure_memory_use(const CaseConfig& config, const Communicator& comm) {
  MemoryUse m;
  m.peak_largest_rank = comm.max(peak_resident_bytes());
  m.shared_largest_rank = comm.max(shared_resident_bytes());
  m.estimate_per_rank = estimate_size(config).bytes_per_rank(comm.size());
  return m;
}

void set_memory_use(JsonObject& summary, const MemoryUse& memory) {
  summary.set("peak_memory_largest_rank_bytes", memory.peak_largest_rank)
      .set("shared_memory_largest_rank_bytes", memory.shared_largest_rank)
      .set("estimated_memory_per_rank_bytes", memory.estimate_per_rank);
}

PhaseSpread measure_phases(const Simulation& sim) {
  const Communicator& comm = sim.comm();
  constexpr std::size_t n = Simulation::kPhaseCount;
  const std::array<double, n>& mine = sim.phase_seconds();
  std::array<double, n> negated{};
  std::vector<ExactSum> partial(n);
  for (std::size_t ph = 0; ph < n; ++ph) {
    negated[ph] = -mine[ph];
    partial[ph].add(mine[ph]);
  }
  const std::array<double, n> most = comm.max(mine);
  const std::array<double, n> least = comm.max(negated);
  const std::vector<double> total = comm.sum_exact(partial);
  PhaseSpread s;
  for (std::size_t ph = 0; ph < n; ++ph) {
    s.names.emplace_back(Simulation::phase_name(static_cast<int>(ph)));
    s.min.push_back(-least[ph]);
    s.mean.push_back(total[ph] / comm.size());
    s.max.push_back(most[ph]);
  }
  return s;
}

JsonObject phase_spread_json(const PhaseSpread& phases) {
  JsonObject all;
  for (std::size_t ph = 0; ph < phases.names.size(); ++ph) {
    JsonObject one;
    one.set("min", phases.min[ph]).set("mean", phases.mean[ph]).set("max", phases.max[ph]);
    all.set(phases.names[ph], one);
  }
  return all;
}

void print_timing(const Simulation& sim, double loop_seconds, double particle_steps_per_s,
                  int ranks, const MemoryUse& memory, const PhaseSpread& phases) {
  fmt::print("done: {} steps in {} ({:.3g} particle-steps/s, {:.1f} ns per particle-step)\n",
             sim.steps(), format_duration(loop_seconds), particle_steps_per_s,
             particle_steps_per_s > 0 ? 1e9 / particle_steps_per_s * ranks : 0.0);
  double sum = 0;
  for (double s : phases.mean)
    sum += s;
  const std::string title =
      fmt::format("time per phase over {} rank{}:", ranks, ranks == 1 ? "" : "s");
  fmt::print("{:<29} {:>9} {:>9} {:>9}  of mean\n", title, "min", "mean", "max");
  for (std::size_t ph = 0; ph < phases.names.size(); ++ph)
    fmt::print("  {:<27} {:8.2f}s {:8.2f}s {:8.2f}s  {:5.1f} %\n", phases.names[ph], phases.min[ph],
               phases.mean[ph], phases.max[ph], sum > 0 ? 100.0 * phases.mean[ph] / sum : 0.0);
  constexpr double kMiB = 1024.0 * 1024.0;
  if (memory.peak_largest_rank > 0.0)
    fmt::print("peak memory: {:.0f} MiB on the largest rank (start-up estimate {:.0f} MiB)\n",
               memory.peak_largest_rank / kMiB, memory.estimate_per_rank / kMiB);
  // At 16 ranks of one node Open MPI's segments were 25 MiB of a 139 MiB peak with its
  // single-copy path off, 2 MiB with it on (docs/scaling.md): say what is the model's.
  if (memory.shared_largest_rank >= kMiB)
    fmt::print(
        "  of it shared: at most {:.0f} MiB on a rank (MPI's on-node buffers, mapped by "
        "every rank that reads them)\n",
        memory.shared_largest_rank / kMiB);
}

int run_case(const CaseConfig& config, const RunOptions& options, const Communicator& comm) {
  ScenarioRunOptions run;
  run.output_dir = options.output_dir.empty() ? "results/" + config.name : options.output_dir;
  run.verbose = !options.quiet;
  run.restart = options.restart;
  run.max_walltime = options.max_walltime;
  run.force_size = options.force_size;
  run.break_lock = options.break_lock;
  run.allow_changes = options.allow_changes;
  std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(config);
  return run_scenario(*driver, run, comm);
}

}  // namespace ringdem

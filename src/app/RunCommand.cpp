#include "app/RunCommand.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>

#include "app/RockfallTest.hpp"
#include "app/RunControl.hpp"
#include "app/TensileTest.hpp"
#include "core/Version.hpp"
#include "domain/RingGenerator.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/CaseLoader.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

namespace {
using Clock = std::chrono::steady_clock;
}  // namespace

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
                     bool print) {
  const std::int64_t particles = sim.global_particles();
  const std::int64_t bonds = sim.global_bonds();
  const auto ranks = sim.decomposition().report(sim.model().particles, sim.model().bonds);
  const double imbalance = sim.decomposition().imbalance(sim.model().particles);
  if (!print) return;
  if (ranks.size() > 1) {
    fmt::print("partition: {} ranks, block size {:.4g} m, particle imbalance {:.1f} %\n",
               ranks.size(), sim.decomposition().block_size(), 100.0 * imbalance);
    fmt::print("  {:>4} {:>10} {:>10} {:>10} {:>10} {:>8}\n", "rank", "particles", "ghosts",
               "bonds", "cut bonds", "blocks");
    for (std::size_t r = 0; r < ranks.size(); ++r)
      fmt::print("  {:>4} {:>10} {:>10} {:>10} {:>10} {:>8}\n", r, ranks[r].particles,
                 ranks[r].ghosts, ranks[r].bonds, ranks[r].cut_bonds, ranks[r].blocks);
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
  fmt::print(
      "time step {:.4g} s ({}), {} steps planned\n", sim.dt(),
      config.simulation.dt ? "fixed" : fmt::format("auto, safety {}", config.simulation.dt_safety),
      planned_steps);
  for (const auto& [name, limit] : sim.limits().named())
    if (std::isfinite(limit))
      fmt::print("  {:<14} limit {:.4g} s: dt is {:.3f} of it\n", name, limit, sim.dt() / limit);
  if (sim.dt() > sim.limits().min())
    fmt::print("WARNING: dt exceeds the smallest stability limit; the run may blow up\n");
}

void print_timing(const Simulation& sim, double loop_seconds, double particle_steps_per_s,
                  int ranks) {
  fmt::print("done: {} steps in {} ({:.3g} particle-steps/s, {:.1f} ns per particle-step)\n",
             sim.steps(), format_duration(loop_seconds), particle_steps_per_s,
             particle_steps_per_s > 0 ? 1e9 / particle_steps_per_s * ranks : 0.0);
  fmt::print("time per phase (rank 0):\n");
  double sum = 0;
  for (double s : sim.phase_seconds())
    sum += s;
  for (int ph = 0; ph < Simulation::kPhaseCount; ++ph)
    fmt::print("  {:<10} {:8.2f} s  {:5.1f} %\n", Simulation::phase_name(ph),
               sim.phase_seconds()[ph], sum > 0 ? 100.0 * sim.phase_seconds()[ph] / sum : 0.0);
}

RunControlOptions run_control_options(const RunOptions& options, const std::string& out_dir) {
  RunControlOptions o;
  o.output_dir = out_dir;
  o.restart = options.restart;
  o.max_walltime = options.max_walltime;
  o.verbose = !options.quiet;
  return o;
}

int run_case(const CaseConfig& config, const RunOptions& options, const Communicator& comm) {
  const bool root = comm.is_root() && !options.quiet;
  const auto wall_start = Clock::now();
  const std::string out_dir =
      options.output_dir.empty() ? "results/" + config.name : options.output_dir;
  if (comm.is_root()) std::filesystem::create_directories(out_dir);

  if (config.scenario.type == "tensile_test") {
    if (!options.restart.empty() || options.max_walltime > 0.0)
      throw std::runtime_error(
          "--restart and --max-walltime are not available for tensile tests (they run in "
          "minutes); run the case again");
    TensileRunOptions tensile;
    tensile.output_dir = out_dir;
    tensile.verbose = !options.quiet;
    run_tensile_test(config, tensile, comm);
    return 0;
  }
  if (config.scenario.type == "rockfall") return run_rockfall(config, options, out_dir, comm);
  if (root) print_banner(config, out_dir, comm);

  RunControl control(config, run_control_options(options, out_dir), comm);
  std::unique_ptr<Simulation> sim_ptr = control.make_simulation(settings_from_case(config));
  Simulation& sim = *sim_ptr;
  const Model& model = sim.model();
  const double end_time = config.simulation.end_time;
  const auto total_steps = static_cast<std::int64_t>(std::ceil(end_time / sim.dt() - 1e-9));

  print_preflight(sim, config, total_steps - sim.steps(), root);

  // series.csv columns: energies, broken bonds, and the contact force on each rigid body.
  std::vector<std::string> columns{"time_s",        "kinetic_energy_J", "potential_energy_J",
                                   "bond_energy_J", "contact_energy_J", "broken_bonds"};
  for (const auto& b : model.bodies)
    for (const char* c : {"fx_N", "fy_N", "fz_N"})
      columns.push_back(b.name + "_" + c);
  SeriesWriter series;
  if (comm.is_root())
    series = control.restarted()
                 ? SeriesWriter::resume(out_dir + "/series.csv", columns, control.restart_time())
                 : SeriesWriter(out_dir + "/series.csv", columns);

  const DriverState& restored = control.driver_state();
  double max_kinetic = restored.get("max_kinetic_energy", 0.0);
  double max_util = restored.get("max_bond_utilisation", 0.0);
  double next_record = restored.get("next_record_time", config.simulation.series_interval);
  auto record = [&]() {
    const Energies e = sim.energies();
    const std::int64_t broken = sim.global_broken_bonds();
    max_kinetic = std::max(max_kinetic, e.kinetic);
    double util = 0.0;
    for (double u : sim.model().bonds.utilisation)
      util = std::max(util, u);
    max_util = std::max(max_util, comm.max(util));
    if (!comm.is_root()) return;
    std::vector<double> row{sim.time(),     e.kinetic,         e.potential,
                            e.bond_elastic, e.contact_elastic, static_cast<double>(broken)};
    for (const auto& b : sim.model().bodies) {
      row.push_back(b.force.x);
      row.push_back(b.force.y);
      row.push_back(b.force.z);
    }
    series.row(row);
  };
  const std::function<DriverState()> driver_state = [&]() {
    DriverState d;
    d.set("max_kinetic_energy", max_kinetic);
    d.set("max_bond_utilisation", max_util);
    d.set("next_record_time", next_record);
    return d;
  };

  if (!control.restarted()) {
    record();
    control.write_frame(sim);
  }
  auto last_progress = Clock::now();
  const auto loop_start = Clock::now();
  const std::int64_t first_step = sim.steps();
  bool stopped = false;
  while (sim.steps() < total_steps) {
    control.before_step(sim);
    sim.step();
    if (sim.time() + 1e-12 >= next_record || sim.steps() == total_steps) {
      record();
      next_record += config.simulation.series_interval;
    }
    if (control.after_step(sim, driver_state)) {
      stopped = true;
      break;
    }
    const auto now = Clock::now();
    if (root && std::chrono::duration<double>(now - last_progress).count() >=
                    config.simulation.progress_interval) {
      last_progress = now;
      const double elapsed = std::chrono::duration<double>(now - loop_start).count();
      const double rate = static_cast<double>(sim.steps() - first_step) / elapsed;
      fmt::print("step {:>10} t = {:.5f} s  {:>9.0f} steps/s  ETA {:>7}  broken bonds {}\n",
                 sim.steps(), sim.time(), rate, format_duration((total_steps - sim.steps()) / rate),
                 sim.model().bonds.count_broken());
      std::fflush(stdout);
    }
  }
  if (stopped) return kExitCheckpointed;
  control.write_frame(sim);
  const double loop_seconds = std::chrono::duration<double>(Clock::now() - loop_start).count();
  const double wall = std::chrono::duration<double>(Clock::now() - wall_start).count();

  const Energies e = sim.energies();
  const std::int64_t n_particles = sim.global_particles();
  const std::int64_t n_bonds = sim.global_bonds();
  const std::int64_t n_broken = sim.global_broken_bonds();
  const double particle_steps_per_s =
      loop_seconds > 0 ? static_cast<double>(n_particles) *
                             static_cast<double>(sim.steps() - first_step) / loop_seconds
                       : 0.0;

  if (comm.is_root()) {
    JsonObject summary;
    summary.set("ringdem_version", kVersion)
        .set("case", config.name)
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(n_particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("broken_bonds", static_cast<long long>(n_broken))
        .set("dt_s", sim.dt())
        .set("end_time_s", sim.time())
        .set("steps", static_cast<long long>(sim.steps()))
        .set("neighbour_rebuilds", static_cast<long long>(sim.rebuilds()))
        .set("wall_time_s", wall)
        .set("particle_steps_per_s", particle_steps_per_s)
        .set("final_kinetic_energy_J", e.kinetic)
        .set("max_kinetic_energy_J", max_kinetic)
        .set("final_bond_energy_J", e.bond_elastic)
        .set("max_bond_utilisation", max_util)
        .set("restarted", control.restarted())
        .set("frames", static_cast<long long>(control.frames() ? control.frames()->frames() : 0))
        .set("frame_output_s", control.frames() ? control.frames()->seconds() : 0.0);
    JsonObject bodies;
    for (const auto& b : model.bodies) {
      JsonObject one;
      one.set("contact_force_N", std::vector<double>{b.force.x, b.force.y, b.force.z})
          .set("contact_torque_Nm", std::vector<double>{b.torque.x, b.torque.y, b.torque.z})
          .set("position_m", std::vector<double>{b.position.x, b.position.y, b.position.z});
      bodies.set(b.name, one);
    }
    summary.set("rigid_bodies", bodies);
    summary.write(out_dir + "/summary.json");
  }

  if (root) {
    print_timing(sim, loop_seconds, particle_steps_per_s, comm.size());
    fmt::print("results: {}/summary.json, {}/series.csv\n", out_dir, out_dir);
    if (control.frames())
      fmt::print("frames: {} ({} frames, {:.2f} s writing); open {} in ParaView\n",
                 control.frames()->h5_path(), control.frames()->frames(),
                 control.frames()->seconds(), control.frames()->xdmf_path());
  }
  return 0;
}

}  // namespace ringdem

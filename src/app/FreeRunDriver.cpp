#include "app/FreeRunDriver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "core/Version.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

std::int64_t FreeRunDriver::total_steps(const Simulation& sim) const {
  return sim.steps_until(config_.simulation.end_time);
}

std::int64_t FreeRunDriver::planned_steps(const Simulation& sim) const {
  return total_steps(sim) - sim.steps();
}

bool FreeRunDriver::start(Simulation& sim, const ScenarioContext& context) {
  control_ = &context.control;
  output_dir_ = context.output_dir;
  verbose_ = context.verbose;
  total_steps_ = total_steps(sim);

  // series.csv columns: energies, broken bonds, and the contact force on each rigid body.
  std::vector<std::string> columns{"time_s",        "kinetic_energy_J", "potential_energy_J",
                                   "bond_energy_J", "contact_energy_J", "broken_bonds"};
  for (const auto& b : sim.model().bodies)
    for (const char* c : {"fx_N", "fy_N", "fz_N"})
      columns.push_back(b.name + "_" + c);
  columns.push_back("plastic_work_J");  // appended: the columns before it stay where they were
  // What left through the outflow boxes and came in through the inlets (docs/physics.md
  // "Outflow", "Inflow"), cumulative.
  for (const char* c : {"outflow_grains", "outflow_mass_kg", "outflow_energy_J", "inflow_grains",
                        "inflow_mass_kg", "inflow_energy_J"})
    columns.push_back(c);
  // The momentum balance of the free particles (docs/physics.md "Momentum balance"): their
  // change (with what went out and came in) against the impulse of the reported loads.
  for (const char* c : {"momentum_change_x_N_s", "momentum_change_y_N_s", "momentum_change_z_N_s",
                        "impulse_x_N_s", "impulse_y_N_s", "impulse_z_N_s", "momentum_residual_N_s"})
    columns.push_back(c);
  // The barrier in a flow (scenario.barrier; docs/debris.md "Barrier measures").
  if (config_.scenario.barrier) {
    barrier_.emplace(*config_.scenario.barrier, sim);
    for (const char* c :
         {"barrier_net_force_N", "barrier_posts_force_N", "barrier_force_N", "flow_depth_m",
          "flow_depth_centroid_m", "flow_velocity_m_s", "bulk_density_kg_m3", "front_m",
          "front_velocity_m_s", "retained_mass_kg", "overflow_mass_kg", "net_deflection_m",
          "net_max_utilisation", "net_max_utilisation_x_m", "net_max_utilisation_y_m",
          "net_max_utilisation_z_m", "barrier_mean_net_force_N", "barrier_mean_posts_force_N",
          "barrier_mean_force_N"})
      columns.push_back(c);
  }
  // The energy ledger (docs/physics.md "Energy ledger"): what the dissipative loads took out
  // and the driven bodies put in, cumulative, and how far the balance moved since the start.
  for (const char* c : {"contact_damping_J", "friction_J", "global_damping_J", "broken_bonds_J",
                        "boundary_work_J", "energy_balance_error_J"})
    columns.push_back(c);
  if (sim.comm().is_root() && !output_dir_.empty())
    series_ = control_->restarted() ? SeriesWriter::resume(output_dir_ + "/series.csv", columns,
                                                           control_->restart_time())
                                    : SeriesWriter(output_dir_ + "/series.csv", columns);

  const DriverState& restored = control_->driver_state();
  max_kinetic_ = restored.get("max_kinetic_energy", 0.0);
  max_utilisation_ = restored.get("max_bond_utilisation", 0.0);
  next_record_ = restored.get("next_record_time", config_.simulation.series_interval);
  max_balance_error_ = restored.get("max_energy_balance_error", 0.0);
  // Collective, on every rank alike. A checkpoint of an older version holds no start, and
  // one written with the ledger switched the other way booked other terms: the balance then
  // counts from the restart.
  const bool ledger_on = config_.simulation.energy_ledger;
  ledger_start_ = restored.get("ledger_start", std::nan(""));
  if (!std::isfinite(ledger_start_) || (restored.get("energy_ledger", 1.0) != 0.0) != ledger_on) {
    ledger_start_ = sim.energies().ledger();
    max_balance_error_ = 0.0;
  }
  if (barrier_) {
    barrier_record_.for_each([&](const char* name, double& v) { v = restored.get(name, v); });
    if (!control_->restarted()) {
      const double reach = barrier_->sample(sim).net_reach;
      barrier_record_.initial_net_reach = std::isfinite(reach) ? reach : 0.0;
    }
  }
  if (!control_->restarted()) {
    record(sim);
    control_->write_frame(sim);
  }
  return sim.steps() >= total_steps_;
}

void FreeRunDriver::record(Simulation& sim) {
  const Energies e = sim.energies();
  const std::int64_t broken = sim.global_broken_bonds();
  const Simulation::GrainFlux out = sim.outflow_totals();
  const Simulation::GrainFlux in = sim.inflow_totals();
  const MomentumBalance momentum = sim.momentum_balance();
  max_kinetic_ = std::max(max_kinetic_, e.kinetic);
  const bool ledger_on = config_.simulation.energy_ledger;
  const double balance = e.ledger() - ledger_start_;
  if (ledger_on) max_balance_error_ = std::max(max_balance_error_, std::abs(balance));
  double util = 0.0;
  for (double u : sim.model().bonds.utilisation)
    util = std::max(util, u);
  max_utilisation_ = std::max(max_utilisation_, sim.comm().max(util));
  // Collective: every rank samples the barrier and keeps the same peaks.
  std::vector<double> barrier_row;
  if (barrier_) record_barrier(sim, momentum, barrier_row);
  if (!sim.comm().is_root() || output_dir_.empty()) return;
  std::vector<double> row{sim.time(),
                          e.kinetic,
                          e.potential,
                          e.bond_elastic,
                          ledger_on ? e.contact_elastic : std::nan(""),  // the ledger books it
                          static_cast<double>(broken)};
  for (const auto& b : sim.model().bodies) {
    row.push_back(b.force.x);
    row.push_back(b.force.y);
    row.push_back(b.force.z);
  }
  row.push_back(e.plastic_work);
  row.push_back(static_cast<double>(out.grains));
  row.push_back(out.mass);
  row.push_back(ledger_on ? e.outflow : std::nan(""));  // with the contacts' share: the ledger's
  row.push_back(static_cast<double>(in.grains));
  row.push_back(in.mass);
  row.push_back(e.inflow);
  const Vec3 change = momentum.momentum - momentum.initial + momentum.outflow - momentum.inflow;
  const Vec3 impulse = momentum.impulse();
  row.insert(row.end(), {change.x, change.y, change.z, impulse.x, impulse.y, impulse.z,
                         norm(momentum.residual())});
  row.insert(row.end(), barrier_row.begin(), barrier_row.end());
  if (ledger_on)
    row.insert(row.end(), {e.contact_damping, e.friction, e.global_damping, e.broken_bonds,
                           e.boundary_work, balance});
  else  // not booked: null, not zeros
    row.insert(row.end(), 6, std::nan(""));
  series_.row(row);
}

void FreeRunDriver::record_barrier(const Simulation& sim, const MomentumBalance& momentum,
                                   std::vector<double>& row) {
  const BarrierSample b = barrier_->sample(sim);
  last_barrier_ = b;
  BarrierRecord& r = barrier_record_;
  // Mean forces since the record before, from the impulses of every step (NaN at the first).
  const BarrierMonitor::Impulse impulse = barrier_->impulse(momentum);
  double mean_net = std::nan(""), mean_posts = std::nan("");
  if (r.last_impulse_time >= 0.0 && sim.time() > r.last_impulse_time) {
    const double interval = sim.time() - r.last_impulse_time;
    mean_net = (impulse.net - r.last_net_impulse) / interval;
    mean_posts = (impulse.posts - r.last_posts_impulse) / interval;
    if (mean_net + mean_posts > r.peak_mean_force) {
      r.peak_mean_force = mean_net + mean_posts;
      r.peak_mean_time = sim.time();
    }
    r.peak_mean_net_force = std::max(r.peak_mean_net_force, mean_net);
    r.peak_mean_posts_force = std::max(r.peak_mean_posts_force, mean_posts);
  }
  r.last_net_impulse = impulse.net;
  r.last_posts_impulse = impulse.posts;
  r.last_impulse_time = sim.time();
  const double total = b.net_force + b.posts_force;
  // The front's speed since the record before (NaN at the first record or without grains).
  double front_velocity = std::nan("");
  if (std::isfinite(b.front)) {
    if (r.last_front_time >= 0.0 && sim.time() > r.last_front_time)
      front_velocity = (b.front - r.last_front) / (sim.time() - r.last_front_time);
    r.last_front = b.front;
    r.last_front_time = sim.time();
  }
  const double deflection = std::isfinite(b.net_reach) ? b.net_reach - r.initial_net_reach : 0.0;
  if (total > r.peak_force) {
    r.peak_force = total;
    r.peak_time = sim.time();
  }
  r.peak_net_force = std::max(r.peak_net_force, b.net_force);
  r.peak_posts_force = std::max(r.peak_posts_force, b.posts_force);
  r.peak_depth = std::max(r.peak_depth, b.flow_depth);
  r.peak_velocity = std::max(r.peak_velocity, b.flow_velocity);
  r.largest_gauge_grain_diameter =
      std::max(r.largest_gauge_grain_diameter, 2.0 * b.largest_gauge_radius);
  r.max_deflection = std::max(r.max_deflection, deflection);
  if (b.max_utilisation > r.max_utilisation) {
    r.max_utilisation = b.max_utilisation;
    r.max_utilisation_x = b.utilisation_at.x;
    r.max_utilisation_y = b.utilisation_at.y;
    r.max_utilisation_z = b.utilisation_at.z;
  }
  for (const double v :
       {b.net_force, b.posts_force, total, b.flow_depth, b.flow_depth_centroid, b.flow_velocity,
        b.bulk_density, std::isfinite(b.front) ? b.front : std::nan(""), front_velocity,
        b.retained_mass, b.overflow_mass, deflection, b.max_utilisation, b.utilisation_at.x,
        b.utilisation_at.y, b.utilisation_at.z, mean_net, mean_posts, mean_net + mean_posts})
    row.push_back(v);
}

std::int64_t FreeRunDriver::steps_to_advance(const Simulation& sim) const {
  // after_steps() records once the time is within 1e-12 s of next_record_.
  return std::max<std::int64_t>(
      1, std::min(total_steps_ - sim.steps(), sim.steps_short_of(next_record_, 1e-12)));
}

bool FreeRunDriver::after_steps(Simulation& sim) {
  if (sim.time() + 1e-12 >= next_record_ || sim.steps() == total_steps_) {
    record(sim);
    next_record_ += config_.simulation.series_interval;
  }
  return sim.steps() >= total_steps_;
}

DriverState FreeRunDriver::state() const {
  DriverState d;
  d.set("max_kinetic_energy", max_kinetic_);
  d.set("max_bond_utilisation", max_utilisation_);
  d.set("next_record_time", next_record_);
  d.set("ledger_start", ledger_start_);
  d.set("energy_ledger", config_.simulation.energy_ledger ? 1.0 : 0.0);
  d.set("max_energy_balance_error", max_balance_error_);
  if (barrier_) {
    BarrierRecord record = barrier_record_;
    record.for_each([&](const char* name, double& v) { d.set(name, v); });
  }
  return d;
}

std::string FreeRunDriver::progress(const Simulation& sim, double rate) const {
  return fmt::format("step {:>10} t = {:.5f} s  {:>9.0f} steps/s  ETA {:>7}  broken bonds {}",
                     sim.steps(), sim.time(), rate,
                     format_duration(static_cast<double>(total_steps_ - sim.steps()) / rate),
                     sim.model().bonds.count_broken());
}

void FreeRunDriver::finish(Simulation& sim, const LoopTimes& times) {
  const Communicator& comm = sim.comm();
  control_->write_frame(sim);
  const Model& model = sim.model();
  const Energies e = sim.energies();
  const std::int64_t n_particles = sim.global_particles();
  const std::int64_t n_bonds = sim.global_bonds();
  const std::int64_t n_broken = sim.global_broken_bonds();
  const Simulation::GrainFlux out = sim.outflow_totals();
  const Simulation::GrainFlux in = sim.inflow_totals();
  const MomentumBalance momentum = sim.momentum_balance();
  const double particle_steps_per_s =
      times.loop_seconds > 0
          ? static_cast<double>(n_particles) * static_cast<double>(sim.steps() - times.first_step) /
                times.loop_seconds
          : 0.0;
  const FrameWriter* frames = control_->frames();
  const MemoryUse memory = measure_memory_use(config_, comm);  // collective
  const PhaseSpread phases = measure_phases(sim);              // collective

  if (comm.is_root() && !output_dir_.empty()) {
    JsonObject summary;
    summary.set("ringdem_version", kVersion)
        .set("case", config_.name)
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(n_particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("broken_bonds", static_cast<long long>(n_broken))
        .set("dt_s", sim.dt())
        .set("end_time_s", sim.time())
        .set("steps", static_cast<long long>(sim.steps()))
        .set("neighbour_rebuilds", static_cast<long long>(sim.rebuilds()))
        .set("wall_time_s", times.wall_seconds)
        .set("particle_steps_per_s", particle_steps_per_s)
        .set("final_kinetic_energy_J", e.kinetic)
        .set("max_kinetic_energy_J", max_kinetic_)
        .set("final_bond_energy_J", e.bond_elastic)
        .set("final_plastic_work_J", e.plastic_work)
        .set("max_bond_utilisation", max_utilisation_)
        .set("restarted", control_->restarted())
        .set("frames", static_cast<long long>(frames ? frames->frames() : 0))
        .set("frame_output_s", frames ? frames->seconds() : 0.0)
        .set("time_per_phase_s", phase_spread_json(phases));
    set_memory_use(summary, memory);
    JsonObject bodies;
    for (const auto& b : model.bodies) {
      JsonObject one;
      one.set("contact_force_N", std::vector<double>{b.force.x, b.force.y, b.force.z})
          .set("contact_torque_Nm", std::vector<double>{b.torque.x, b.torque.y, b.torque.z})
          .set("position_m", std::vector<double>{b.position.x, b.position.y, b.position.z});
      bodies.set(b.name, one);
    }
    summary.set("rigid_bodies", bodies);
    const auto flux = [](const Simulation::GrainFlux& f, double energy) {
      JsonObject o;
      o.set("grains", static_cast<long long>(f.grains))
          .set("mass_kg", f.mass)
          .set("momentum_kg_m_s", std::vector<double>{f.momentum.x, f.momentum.y, f.momentum.z})
          .set("energy_J", energy);
      return o;
    };
    // The energy ledger at the end (docs/physics.md "Energy ledger"; docs/output.md).
    const double energy_balance = e.ledger() - ledger_start_;
    JsonObject ledger;
    ledger.set("booked", config_.simulation.energy_ledger);
    if (config_.simulation.energy_ledger)
      ledger.set("kinetic_J", e.kinetic)
          .set("potential_J", e.potential)
          .set("bond_elastic_J", e.bond_elastic)
          .set("contact_elastic_J", e.contact_elastic)
          .set("contact_damping_J", e.contact_damping)
          .set("friction_J", e.friction)
          .set("global_damping_J", e.global_damping)
          .set("broken_bonds_J", e.broken_bonds)
          .set("plastic_work_J", e.plastic_work)
          .set("boundary_work_J", e.boundary_work)
          .set("outflow_J", e.outflow)
          .set("inflow_J", e.inflow)
          .set("balance_error_J", energy_balance)
          .set("largest_balance_error_J", std::max(max_balance_error_, std::abs(energy_balance)));
    summary.set("energy_ledger", ledger);
    summary.set("outflow", flux(out, config_.simulation.energy_ledger ? e.outflow : std::nan("")));
    summary.set("inflow", flux(in, e.inflow));
    const auto vec = [](const Vec3& v) { return std::vector<double>{v.x, v.y, v.z}; };
    JsonObject impulses;
    impulses.set("gravity_N_s", vec(momentum.gravity))
        .set("point_loads_N_s", vec(momentum.point_loads))
        .set("held_particles_N_s", vec(momentum.held))
        .set("outflow_inflow_kicks_N_s", vec(momentum.exchange));
    for (std::size_t b = 0; b < model.bodies.size(); ++b)
      impulses.set(model.bodies[b].name + "_N_s", vec(momentum.bodies[b]));
    JsonObject balance;
    balance.set("momentum_kg_m_s", vec(momentum.momentum))
        .set("initial_momentum_kg_m_s", vec(momentum.initial))
        .set("outflow_momentum_kg_m_s", vec(momentum.outflow))
        .set("inflow_momentum_kg_m_s", vec(momentum.inflow))
        .set("impulse_N_s", vec(momentum.impulse()))
        .set("impulses", impulses)
        .set("residual_N_s", vec(momentum.residual()));
    summary.set("momentum_balance", balance);
    if (barrier_) {
      const BarrierRecord& r = barrier_record_;
      JsonObject b;
      b.set("peak_force_N", r.peak_force)
          .set("peak_force_time_s", r.peak_time)
          .set("peak_net_force_N", r.peak_net_force)
          .set("peak_posts_force_N", r.peak_posts_force)
          .set("peak_flow_depth_m", r.peak_depth)
          .set("peak_flow_velocity_m_s", r.peak_velocity)
          .set("final_retained_mass_kg", last_barrier_.retained_mass)
          .set("final_overflow_mass_kg", last_barrier_.overflow_mass)
          .set("max_net_deflection_m", r.max_deflection)
          .set("max_net_utilisation", r.max_utilisation)
          .set("max_net_utilisation_at_m",
               std::vector<double>{r.max_utilisation_x, r.max_utilisation_y, r.max_utilisation_z})
          .set("peak_mean_force_N", r.peak_mean_force)
          .set("peak_mean_force_time_s", r.peak_mean_time)
          .set("peak_mean_net_force_N", r.peak_mean_net_force)
          .set("peak_mean_posts_force_N", r.peak_mean_posts_force)
          .set("largest_gauge_grain_diameter_m", r.largest_gauge_grain_diameter);
      summary.set("barrier", b);
    }
    summary.write(output_dir_ + "/summary.json");
  }

  if (comm.is_root() && verbose_) {
    print_timing(sim, times.loop_seconds, particle_steps_per_s, comm.size(), memory, phases);
    fmt::print("results: {}/summary.json, {}/series.csv\n", output_dir_, output_dir_);
    if (frames)
      fmt::print("frames: {} ({} frames, {:.2f} s writing); open {} in ParaView\n",
                 frames->h5_path(), frames->frames(), frames->seconds(), frames->xdmf_path());
  }
}

}  // namespace ringdem

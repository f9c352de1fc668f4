#include "app/RockfallTest.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <stdexcept>

#include "app/RunControl.hpp"
#include "core/Version.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/ResultsWriter.hpp"

namespace ringdem {

namespace {

using Clock = std::chrono::steady_clock;
constexpr const char* kBoulderName = "boulder";

double seconds_since(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

/// Extent of a particle group over all ranks (owned particles), and the top of the group
/// within a horizontal distance of an axis.
struct GroupExtent {
  Vec3 lo, hi;
  double top_near_axis = -std::numeric_limits<double>::infinity();
  double lowest_near_axis = std::numeric_limits<double>::infinity();
};

GroupExtent group_extent(const Simulation& sim, int group, double axis_x, double axis_y,
                         double axis_radius) {
  const ParticleStore& p = sim.model().particles;
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  double top = -inf, low = inf;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.group[k] != group) continue;
    const Vec3& x = p.position[k];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z - p.radius[k])};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z + p.radius[k])};
    const double dx = x.x - axis_x, dy = x.y - axis_y;
    if (dx * dx + dy * dy <= axis_radius * axis_radius) {
      top = std::max(top, x.z + p.radius[k]);
      low = std::min(low, x.z - p.radius[k]);
    }
  }
  const Communicator& c = sim.comm();
  const auto maxima = c.max(std::array<double, 6>{-lo.x, -lo.y, -lo.z, hi.x, hi.y, hi.z});
  const auto near = c.max(std::array<double, 2>{top, -low});
  GroupExtent e;
  e.lo = {-maxima[0], -maxima[1], -maxima[2]};
  e.hi = {maxima[3], maxima[4], maxima[5]};
  e.top_near_axis = near[0];
  e.lowest_near_axis = -near[1];
  return e;
}

/// Contact load on the particles of a group (their total force less gravity), summed by gid
/// so that it does not depend on the rank count.
Vec3 group_contact_load(const Simulation& sim, int group, const Vec3& gravity) {
  const ParticleStore& p = sim.model().particles;
  std::vector<std::int64_t> keys;
  std::vector<double> fx, fy, fz;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.group[k] != group) continue;
    const Vec3 f = p.force[k] - p.mass[k] * gravity;
    keys.push_back(p.gid[k]);
    fx.push_back(f.x);
    fy.push_back(f.y);
    fz.push_back(f.z);
  }
  const Communicator& c = sim.comm();
  return {c.sum_by_key(keys, fx), c.sum_by_key(keys, fy), c.sum_by_key(keys, fz)};
}

int group_or_throw(const Model& m, const std::string& name, const char* key) {
  const int g = m.group_id(name);
  if (g < 0)
    throw std::runtime_error(
        fmt::format("scenario.rockfall.{}: no particle group '{}' in the case (groups: {})", key,
                    name, fmt::join(m.group_names, ", ")));
  return g;
}

}  // namespace

double sphere_radius(double mass, double density) {
  return std::cbrt(3.0 * mass / (4.0 * M_PI * density));
}

int run_rockfall(const CaseConfig& input, const RunOptions& options, const std::string& out_dir,
                 const Communicator& comm) {
  const RockfallConfig& rf = input.scenario.rockfall;
  const bool root = comm.is_root() && !options.quiet;
  const auto wall_start = Clock::now();

  // The boulder is a free rigid sphere; until the release it is parked far above, motion
  // prescribed at rest, so it neither moves nor touches anything.
  CaseConfig config = input;
  for (const auto& b : config.rigid_bodies)
    if (b.name == kBoulderName)
      throw std::runtime_error(
          "a rockfall case makes its own rigid body 'boulder': rename the one in rigid_bodies");
  const double radius = sphere_radius(rf.boulder_mass, rf.boulder_density);
  {
    RigidBodyConfig boulder;
    boulder.name = kBoulderName;
    boulder.shape = ShapeKind::kSphere;
    boulder.radius = radius;
    boulder.material = rf.boulder_material;
    boulder.motion = MotionKind::kPrescribed;
    boulder.mass = rf.boulder_mass;
    boulder.gravity = true;
    boulder.position = {0, 0, 1e3};
    config.rigid_bodies.push_back(boulder);
  }
  if (root) print_banner(config, out_dir, comm);

  RunControl control(config, run_control_options(options, out_dir), comm);
  const SimulationSettings settings = settings_from_case(config);
  std::unique_ptr<Simulation> sim_ptr = control.make_simulation(settings);
  Simulation& sim = *sim_ptr;
  const Model& model = sim.model();
  const int net = group_or_throw(model, rf.net_group, "net_group");
  const int frame = group_or_throw(model, rf.frame_group, "frame_group");
  const std::size_t boulder = model.bodies.size() - 1;
  const double g = norm(settings.gravity);
  if (!(g > 0.0)) throw std::runtime_error("a rockfall test needs gravity");
  const Vec3 down = settings.gravity / g;
  if (std::abs(down.z + 1.0) > 1e-12)
    throw std::runtime_error("a rockfall test expects gravity along -z");
  const double impact_energy = rf.boulder_mass * g * rf.drop_height;
  const double impact_velocity = std::sqrt(2.0 * g * rf.drop_height);
  print_preflight(sim, config, 0, root);

  // ---- driver state (saved in checkpoints) ----
  const DriverState& restored = control.driver_state();
  int phase = static_cast<int>(restored.get("phase", 0.0));  // 0 sag, 1 impact
  double next_sag_check = restored.get("next_sag_check", rf.sag_min_time);
  double sag_end_time = restored.get("sag_end_time", -1.0);
  double contact_time = restored.get("contact_time", -1.0);
  double ledger_start = restored.get("ledger_start", 0.0);
  double energy_added = restored.get("energy_added", 0.0);
  double contact_z = restored.get("contact_z", 0.0);
  double net_top_initial = restored.get("net_top_initial", 0.0);
  double net_top_sagged = restored.get("net_top_sagged", 0.0);
  double drop_x = restored.get("drop_x", 0.0), drop_y = restored.get("drop_y", 0.0);
  double next_record = restored.get("next_record", 0.0);
  double peak_acceleration = restored.get("peak_acceleration", 0.0);
  double time_of_peak = restored.get("time_of_peak", 0.0);
  double peak_instant = restored.get("peak_instant", 0.0);
  double lowest_z = restored.get("lowest_z", std::numeric_limits<double>::infinity());
  double stopping_time = restored.get("stopping_time", -1.0);
  double max_frame_force = restored.get("max_frame_force", 0.0);
  double max_balance_error = restored.get("max_balance_error", 0.0);
  double free_fall_time = restored.get("free_fall_time", 0.0);
  double peak_sag_kinetic = restored.get("peak_sag_kinetic", 0.0);
  // Boulder contact load summed over the steps since the last row (row means).
  double sum_steps = restored.get("sum_steps", 0.0);
  Vec3 sum_force{restored.get("sum_fx", 0.0), restored.get("sum_fy", 0.0),
                 restored.get("sum_fz", 0.0)};
  auto driver_state = [&]() {
    DriverState d;
    d.set("phase", phase);
    d.set("next_sag_check", next_sag_check);
    d.set("sag_end_time", sag_end_time);
    d.set("contact_time", contact_time);
    d.set("ledger_start", ledger_start);
    d.set("energy_added", energy_added);
    d.set("contact_z", contact_z);
    d.set("net_top_initial", net_top_initial);
    d.set("net_top_sagged", net_top_sagged);
    d.set("drop_x", drop_x);
    d.set("drop_y", drop_y);
    d.set("next_record", next_record);
    d.set("peak_acceleration", peak_acceleration);
    d.set("time_of_peak", time_of_peak);
    d.set("peak_instant", peak_instant);
    d.set("lowest_z", lowest_z);
    d.set("stopping_time", stopping_time);
    d.set("max_frame_force", max_frame_force);
    d.set("max_balance_error", max_balance_error);
    d.set("free_fall_time", free_fall_time);
    d.set("peak_sag_kinetic", peak_sag_kinetic);
    d.set("sum_steps", sum_steps);
    d.set("sum_fx", sum_force.x);
    d.set("sum_fy", sum_force.y);
    d.set("sum_fz", sum_force.z);
    return d;
  };

  std::vector<std::string> columns{"time_s",
                                   "time_from_contact_s",
                                   "boulder_x_m",
                                   "boulder_y_m",
                                   "boulder_z_m",
                                   "boulder_vz_m_s",
                                   "boulder_speed_m_s",
                                   "acceleration_m_s2",
                                   "acceleration_g",
                                   "boulder_az_m_s2",
                                   "frame_force_N",
                                   "frame_fz_N",
                                   "broken_bonds",
                                   "kinetic_J",
                                   "potential_J",
                                   "bond_elastic_J",
                                   "contact_elastic_J",
                                   "contact_damping_J",
                                   "friction_J",
                                   "global_damping_J",
                                   "broken_bonds_J",
                                   "boundary_work_J",
                                   "balance_error_J"};
  SeriesWriter series, sag_series;
  if (comm.is_root()) {
    const double until = control.restarted() ? control.restart_time() : -1.0;
    series = SeriesWriter::resume(out_dir + "/series.csv", columns, until);
    sag_series = SeriesWriter::resume(out_dir + "/sag.csv",
                                      {"time_s", "kinetic_J", "net_top_near_axis_m"}, until);
  }

  if (!control.restarted()) {
    // Centre of the net, its initial top, and the reference of the energy ledger.
    const GroupExtent e = group_extent(sim, net, 0, 0, 0);
    drop_x = rf.drop_point ? rf.drop_point->x : 0.5 * (e.lo.x + e.hi.x);
    drop_y = rf.drop_point ? rf.drop_point->y : 0.5 * (e.lo.y + e.hi.y);
    net_top_initial = group_extent(sim, net, drop_x, drop_y, radius).top_near_axis;
    ledger_start = sim.energies().ledger();
    if (rf.sag_damping) sim.set_group_damping(net, *rf.sag_damping);
    control.write_frame(sim);
    if (root)
      fmt::print(
          "rockfall: boulder {:.4g} kg, radius {:.4g} m, drop {:.4g} m ({:.4g} kJ, {:.4g} "
          "m/s at contact) on ({:.4g}, {:.4g}); sag phase first\n",
          rf.boulder_mass, radius, rf.drop_height, 1e-3 * impact_energy, impact_velocity, drop_x,
          drop_y);
  }

  auto record = [&]() {
    const Energies e = sim.energies();
    const RigidBody& b = sim.model().bodies[boulder];
    const Vec3 mean_force = sum_steps > 0 ? sum_force / sum_steps : b.force;
    sum_force = {};
    sum_steps = 0;
    const double accel = norm(mean_force) / rf.boulder_mass;
    const double az = mean_force.z / rf.boulder_mass - g;
    const Vec3 frame_load = group_contact_load(sim, frame, settings.gravity);
    const std::int64_t broken = sim.global_broken_bonds();
    const double balance = e.ledger() - (ledger_start + energy_added);
    max_balance_error = std::max(max_balance_error, std::abs(balance));
    if (contact_time >= 0.0) {
      if (accel > peak_acceleration) {
        peak_acceleration = accel;
        time_of_peak = sim.time() - contact_time;
      }
      max_frame_force = std::max(max_frame_force, norm(frame_load));
    }
    if (!comm.is_root()) return;
    series.row({sim.time(),
                contact_time >= 0 ? sim.time() - contact_time : std::nan(""),
                b.position.x,
                b.position.y,
                b.position.z,
                b.velocity.z,
                norm(b.velocity),
                accel,
                accel / g,
                az,
                norm(frame_load),
                frame_load.z,
                static_cast<double>(broken),
                e.kinetic,
                e.potential,
                e.bond_elastic,
                e.contact_elastic,
                e.contact_damping,
                e.friction,
                e.global_damping,
                e.broken_bonds,
                e.boundary_work,
                balance});
  };

  auto last_progress = Clock::now();
  const auto loop_start = Clock::now();
  const std::int64_t first_step = sim.steps();
  double sag_wall = restored.get("sag_wall", 0.0), impact_wall = 0.0;
  // `extra` formats the end of the line: called only when a line is due, not every step.
  auto progress = [&](const char* what, const auto& extra) {
    if (!root || seconds_since(last_progress) < config.simulation.progress_interval) return;
    last_progress = Clock::now();
    const double rate = static_cast<double>(sim.steps() - first_step) / seconds_since(loop_start);
    fmt::print("{} step {:>9} t = {:.5f} s  {:>7.0f} steps/s  {}\n", what, sim.steps(), sim.time(),
               rate, extra());
    std::fflush(stdout);
  };
  // Built once: after_step takes them every step.
  const std::function<DriverState()> impact_state = driver_state;

  // ---- phase 1: the net sags to rest ----
  if (phase == 0) {
    const auto sag_start = Clock::now();
    double kinetic = std::numeric_limits<double>::infinity();
    const std::function<DriverState()> sag_state = [&] {
      DriverState d = driver_state();
      d.set("sag_wall", sag_wall + seconds_since(sag_start));
      return d;
    };
    while (true) {
      if (sim.time() + 0.5 * sim.dt() >= next_sag_check) {
        next_sag_check += rf.sag_check_interval;
        kinetic = sim.energies().kinetic;
        const double top = group_extent(sim, net, drop_x, drop_y, radius).top_near_axis;
        if (comm.is_root()) sag_series.row({sim.time(), kinetic, top});
        peak_sag_kinetic = std::max(peak_sag_kinetic, kinetic);
        // The net starts at rest: it is at rest again once its kinetic energy has fallen below
        // the threshold and to half its peak (or, if it barely moves, after a while).
        const bool decayed =
            kinetic < 0.5 * peak_sag_kinetic ||
            (peak_sag_kinetic < rf.sag_kinetic_energy && sim.time() >= 10.0 * rf.sag_min_time);
        if (sim.time() >= rf.sag_min_time && kinetic < rf.sag_kinetic_energy && decayed) break;
        if (sim.time() > rf.sag_max_time)
          throw std::runtime_error(fmt::format(
              "the net is not at rest after {:.4g} s of sag (kinetic energy {:.4g} J > "
              "scenario.rockfall.sag_kinetic_energy {:.4g} J): raise sag_max_time, sag_damping "
              "or the threshold",
              sim.time(), kinetic, rf.sag_kinetic_energy));
      }
      control.before_step(sim);
      sim.step();
      if (control.after_step(sim, sag_state)) return kExitCheckpointed;
      progress("sag   ", [&] {
        return fmt::format("net kinetic energy {:.4g} J (rest below {:.3g} J)", kinetic,
                           rf.sag_kinetic_energy);
      });
    }
    sag_wall += seconds_since(sag_start);

    // ---- release ----
    sag_end_time = sim.time();
    const GroupExtent e = group_extent(sim, net, drop_x, drop_y, radius);
    net_top_sagged = e.top_near_axis;
    if (rf.impact_damping) sim.set_group_damping(net, *rf.impact_damping);
    const double bottom_at_rest = net_top_sagged + rf.drop_height;
    double z_centre, vz;
    if (rf.integrate_free_fall) {
      z_centre = bottom_at_rest + radius;
      vz = 0.0;
    } else {
      // Free fall in vacuum, exactly: from rest at bottom_at_rest down to release_gap above
      // the net, v = sqrt(2 g (h - gap)); the net is at rest meanwhile.
      const double fall = rf.drop_height - rf.release_gap;
      z_centre = net_top_sagged + rf.release_gap + radius;
      vz = -std::sqrt(2.0 * g * fall);
      free_fall_time = -vz / g;
    }
    const Energies before = sim.energies();
    sim.place_body(boulder, {drop_x, drop_y, z_centre}, {0, 0, vz}, Motion::kFree);
    energy_added = sim.energies().ledger() - before.ledger();
    phase = 1;
    next_record = sim.time();
    if (root)
      fmt::print(
          "sag done at t = {:.4f} s ({} wall): net top under the drop axis {:.4f} m (sagged {:.4f} "
          "m), "
          "kinetic energy {:.3g} J; boulder released {:.4g} m above the net{}\n",
          sim.time(), format_duration(sag_wall), net_top_sagged, net_top_initial - net_top_sagged,
          kinetic, rf.drop_height,
          rf.integrate_free_fall
              ? ""
              : fmt::format(" (free fall of {:.4f} s advanced analytically to {:.3g} m above, "
                            "{:.4g} m/s)",
                            free_fall_time, rf.release_gap, -vz));
  }

  // ---- phase 2: the impact ----
  const auto impact_start = Clock::now();
  const double no_contact_limit =
      sim.time() + std::sqrt(2.0 * (rf.drop_height + 1.0) / g) + 1.0;  // generous
  while (contact_time < 0.0 || sim.time() < contact_time + rf.duration - 0.5 * sim.dt()) {
    if (sim.time() + 0.5 * sim.dt() >= next_record) {
      record();
      next_record += rf.record_interval;
    }
    control.before_step(sim);
    sim.step();
    const RigidBody& b = sim.model().bodies[boulder];
    sum_force += b.force;
    sum_steps += 1.0;
    if (contact_time < 0.0) {
      if (norm2(b.force) > 0.0) {
        contact_time = sim.time();
        contact_z = b.position.z;
        if (root)
          fmt::print("first contact at t = {:.5f} s, boulder speed {:.4g} m/s\n", contact_time,
                     norm(b.velocity));
      } else if (sim.time() > no_contact_limit) {
        throw std::runtime_error("the boulder never touched the net: check drop_point");
      }
    } else {
      peak_instant = std::max(peak_instant, norm(b.force) / rf.boulder_mass);
      if (b.position.z < lowest_z) lowest_z = b.position.z;
      if (stopping_time < 0.0 && b.velocity.z >= 0.0) stopping_time = sim.time() - contact_time;
    }
    if (control.after_step(sim, impact_state)) return kExitCheckpointed;
    progress("impact", [&] {
      return contact_time < 0 ? std::string("falling")
                              : fmt::format("{:.4f} s after contact, boulder vz {:.3f} m/s",
                                            sim.time() - contact_time, b.velocity.z);
    });
  }
  record();
  control.write_frame(sim);
  impact_wall = seconds_since(impact_start);

  const double loop_seconds = seconds_since(loop_start);
  const std::int64_t n_particles = sim.global_particles();
  const double particle_steps_per_s =
      loop_seconds > 0 ? static_cast<double>(n_particles) *
                             static_cast<double>(sim.steps() - first_step) / loop_seconds
                       : 0.0;
  // Collective calls first: never inside rank-0-only code.
  const Energies e = sim.energies();
  const std::int64_t broken = sim.global_broken_bonds();
  const std::int64_t n_bonds = sim.global_bonds();
  if (comm.is_root()) {
    JsonObject s;
    s.set("ringdem_version", kVersion)
        .set("case", config.name)
        .set("scenario", "rockfall")
        .set("peak_acceleration_m_s2", peak_acceleration)
        .set("peak_acceleration_g", peak_acceleration / g)
        .set("time_of_peak_s", time_of_peak)
        .set("peak_acceleration_single_step_m_s2", peak_instant)
        .set("max_deflection_m", contact_z - lowest_z)
        .set("stopping_time_s", stopping_time)
        .set("broken_bonds", static_cast<long long>(broken))
        .set("max_frame_force_N", max_frame_force)
        .set("energy_balance_error", max_balance_error / impact_energy)
        .set("energy_balance_error_final",
             std::abs(e.ledger() - ledger_start - energy_added) / impact_energy)
        .set("impact_energy_J", impact_energy)
        .set("impact_velocity_m_s", impact_velocity)
        .set("boulder_mass_kg", rf.boulder_mass)
        .set("boulder_radius_m", radius)
        .set("drop_height_m", rf.drop_height)
        .set("free_fall_time_s", free_fall_time)
        .set("free_fall_integrated", rf.integrate_free_fall)
        .set("sag_time_s", sag_end_time)
        .set("net_sag_m", net_top_initial - net_top_sagged)
        .set("first_contact_time_s", contact_time)
        .set("energy_dissipated_J",
             std::vector<double>{e.contact_damping, e.friction, e.global_damping, e.broken_bonds})
        .set("energy_dissipated_order", "contact_damping, friction, global_damping, broken_bonds")
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(n_particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("dt_s", sim.dt())
        .set("steps", static_cast<long long>(sim.steps()))
        .set("neighbour_rebuilds", static_cast<long long>(sim.rebuilds()))
        .set("wall_time_s", seconds_since(wall_start))
        .set("sag_wall_time_s", sag_wall)
        .set("impact_wall_time_s", impact_wall)
        .set("particle_steps_per_s", particle_steps_per_s)
        .set("particle_steps_per_s_per_rank", particle_steps_per_s / comm.size())
        .set("restarted", control.restarted())
        .set("frames", static_cast<long long>(control.frames() ? control.frames()->frames() : 0))
        .set("frame_output_s", control.frames() ? control.frames()->seconds() : 0.0);
    JsonObject phases;
    for (int ph = 0; ph < Simulation::kPhaseCount; ++ph)
      phases.set(Simulation::phase_name(ph), sim.phase_seconds()[ph]);
    s.set("time_per_phase_s", phases);
    s.write(out_dir + "/summary.json");
  }
  if (root) {
    print_timing(sim, loop_seconds, particle_steps_per_s, comm.size());
    fmt::print(
        "rockfall: peak acceleration {:.4g} m/s^2 ({:.3g} g) at {:.4f} s after contact, "
        "deflection {:.4f} m, stopped after {:.4f} s, {} broken bonds, frame force up to {:.4g} "
        "kN, energy balance within {:.3g} % of the impact energy\n",
        peak_acceleration, peak_acceleration / g, time_of_peak, contact_z - lowest_z, stopping_time,
        broken, 1e-3 * max_frame_force, 100.0 * max_balance_error / impact_energy);
    fmt::print("results: {0}/summary.json, {0}/series.csv, {0}/sag.csv\n", out_dir);
    if (control.frames())
      fmt::print("frames: open {} in ParaView ({} frames)\n", control.frames()->xdmf_path(),
                 control.frames()->frames());
  }
  return 0;
}

}  // namespace ringdem

// RockfallDriver's reports: a series row every series_interval, the progress line, and the
// summary at the end of the run. Split from RockfallDriver.cpp, which steps the scenario.
#include "app/RockfallDriver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "app/GroupExtent.hpp"
#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "app/WallClock.hpp"
#include "core/Version.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

void RockfallDriver::record(Simulation& sim) {
  const Energies e = sim.energies();
  const RigidBody& b = sim.model().bodies[boulder_];
  const Vec3 mean_force = sum_steps_ > 0 ? sum_force_ / sum_steps_ : b.force;
  sum_force_ = {};
  sum_steps_ = 0;
  const double accel = norm(mean_force) / rf_.boulder_mass;
  const double az = mean_force.z / rf_.boulder_mass - g_;
  const Vec3 frame = frame_load(sim, frame_, sim.settings().gravity);
  const double rope_tension = restraint_totals(sim.model()).largest_tension;  // replicated
  const std::int64_t broken = sim.global_broken_bonds();
  const double balance = e.ledger() - (ledger_start_ + energy_added_);
  max_balance_error_ = std::max(max_balance_error_, std::abs(balance));
  if (contact_time_ >= 0.0) {
    if (accel > peak_acceleration_) {
      peak_acceleration_ = accel;
      time_of_peak_ = sim.time() - contact_time_;
    }
    max_frame_force_ = std::max(max_frame_force_, norm(frame));
    max_rope_tension_ = std::max(max_rope_tension_, rope_tension);
  }
  if (!sim.comm().is_root() || output_dir_.empty()) return;
  series_.row({sim.time(),
               contact_time_ >= 0 ? sim.time() - contact_time_ : std::nan(""),
               b.position.x,
               b.position.y,
               b.position.z,
               b.velocity.z,
               norm(b.velocity),
               accel,
               accel / g_,
               az,
               norm(frame),
               frame.z,
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
               balance,
               e.plastic_work,
               static_cast<double>(impact_),
               e.brake_work,
               e.brake_elastic,
               rope_tension});
}

std::string RockfallDriver::progress(const Simulation& sim, double rate) const {
  std::string extra;
  if (phase_ != kImpact && !std::isfinite(kinetic_))  // no rest check yet in this run segment
    extra = fmt::format("net kinetic energy: first rest check at t = {:.4g} s", next_sag_check_);
  else if (phase_ != kImpact)
    extra = fmt::format("net kinetic energy {:.4g} J (rest below {:.3g} J)", kinetic_,
                        rf_.sag_kinetic_energy);
  else if (contact_time_ < 0)
    extra = "falling";
  else
    extra = fmt::format("{:.4f} s after contact, boulder vz {:.3f} m/s", sim.time() - contact_time_,
                        sim.model().bodies[boulder_].velocity.z);
  if (rf_.impacts > 1 && phase_ != kSag)
    extra += fmt::format(" (impact {} of {})", impact_, rf_.impacts);
  const char* label = phase_ == kSag ? "sag   " : phase_ == kResettle ? "settle" : "impact";
  return fmt::format("{} step {:>9} t = {:.5f} s  {:>7.0f} steps/s  {}", label, sim.steps(),
                     sim.time(), rate, extra);
}

void RockfallDriver::finish(Simulation& sim, const LoopTimes& times) {
  const Communicator& comm = sim.comm();
  control_->write_frame(sim);
  const double impact_wall = seconds_since(impact_start_);
  const std::int64_t n_particles = sim.global_particles();
  const double particle_steps_per_s =
      times.loop_seconds > 0
          ? static_cast<double>(n_particles) * static_cast<double>(sim.steps() - times.first_step) /
                times.loop_seconds
          : 0.0;
  // Collective calls first: never inside rank-0-only code.
  const Energies e = sim.energies();
  const RestraintTotals restraints = restraint_totals(sim.model());
  const std::int64_t broken = sim.global_broken_bonds();
  const std::int64_t n_bonds = sim.global_bonds();
  const FrameWriter* frames = control_->frames();
  const MemoryUse memory = measure_memory_use(config_, comm);
  const PhaseSpread phases = measure_phases(sim);  // collective
  // Every impact, the one cut off by simulation.end_time included.
  std::vector<ImpactRecord> impacts = impacts_;
  if (phase_ == kImpact && impacts.size() < static_cast<std::size_t>(impact_))
    impacts.push_back(impact_record(e, restraints.friction_work, broken));
  // The keys of one impact describe the first (with a single impact, as they always have).
  ImpactRecord first = impact_record(e, restraints.friction_work, broken);
  first.deflection = contact_z_ - lowest_z_;
  first.stopping_time = stopping_time_ >= 0.0 ? stopping_time_ : std::nan("");
  first.contact_time = contact_time_;
  if (rf_.impacts > 1 && !impacts_.empty()) first = impacts_[0];
  if (comm.is_root() && !output_dir_.empty()) {
    JsonObject s;
    s.set("ringdem_version", kVersion)
        .set("case", config_.name)
        .set("scenario", scenario_name(ScenarioKind::kRockfall))
        .set("peak_acceleration_m_s2", first.peak_acceleration)
        .set("peak_acceleration_g", first.peak_acceleration / g_)
        .set("time_of_peak_s", first.time_of_peak)
        .set("peak_acceleration_single_step_m_s2", first.peak_instant)
        .set("max_deflection_m", first.deflection)
        // null (NaN) while the boulder had not turned by the end of the run.
        .set("stopping_time_s", first.stopping_time)
        .set("broken_bonds", static_cast<long long>(broken))  // the whole run
        .set("max_frame_force_N", first.max_frame_force)
        .set("max_rope_tension_N", first.max_rope_tension)
        .set("energy_balance_error", max_balance_error_ / impact_energy_)
        .set("energy_balance_error_final",
             std::abs(e.ledger() - ledger_start_ - energy_added_) / impact_energy_)
        .set("impact_energy_J", impact_energy_)
        .set("impact_velocity_m_s", impact_velocity_)
        .set("boulder_mass_kg", rf_.boulder_mass)
        .set("boulder_radius_m", radius_)
        .set("drop_height_m", rf_.drop_height)
        .set("free_fall_time_s", free_fall_time_)
        .set("free_fall_integrated", rf_.integrate_free_fall)
        .set("sag_time_s", sag_end_time_)
        .set("net_sag_m", net_top_initial_ - net_top_sagged_)
        .set("first_contact_time_s", first.contact_time)
        .set("stopped_at_end_time", reached_end_time_)
        .set("energy_dissipated_J",
             std::vector<double>{e.contact_damping, e.friction, e.global_damping, e.broken_bonds,
                                 e.plastic_work, e.brake_work})
        .set("energy_dissipated_order",
             "contact_damping, friction, global_damping, broken_bonds, plastic_work, brake_work")
        .set("brake_largest_travel_m", restraints.largest_travel)
        .set("brakes_used_up", restraints.used_up)
        .set("ranks", comm.size())
        .set("particles", static_cast<long long>(n_particles))
        .set("bonds", static_cast<long long>(n_bonds))
        .set("dt_s", sim.case_time_step())
        .set("sag_dt_s", rf_.sag_dt ? *rf_.sag_dt : sim.case_time_step())
        .set("steps", static_cast<long long>(sim.steps()))
        .set("neighbour_rebuilds", static_cast<long long>(sim.rebuilds()))
        .set("wall_time_s", times.wall_seconds)
        .set("sag_wall_time_s", sag_wall_)
        .set("impact_wall_time_s", impact_wall)
        .set("particle_steps_per_s", particle_steps_per_s)
        .set("particle_steps_per_s_per_rank", particle_steps_per_s / comm.size())
        .set("restarted", control_->restarted())
        .set("frames", static_cast<long long>(frames ? frames->frames() : 0))
        .set("frame_output_s", frames ? frames->seconds() : 0.0);
    s.set("time_per_phase_s", phase_spread_json(phases));
    set_memory_use(s, memory);
    s.set("impacts_planned", rf_.impacts);
    set_impacts(s, impacts, g_, impact_energy_);
    s.write(output_dir_ + "/summary.json");
  }
  if (print_) {
    print_timing(sim, times.loop_seconds, particle_steps_per_s, comm.size(), memory, phases);
    if (reached_end_time_)
      fmt::print(
          "rockfall: stopped at simulation.end_time = {:.6g} s, {}\n", config_.simulation.end_time,
          phase_ == kSag        ? std::string("still in the sag phase (no impact)")
          : phase_ == kResettle ? fmt::format("while the net re-settled after impact {}", impact_)
          : contact_time_ < 0.0 ? std::string("before the boulder reached the net")
                                : std::string("before scenario.rockfall.duration after "
                                              "contact"));
    if (rf_.impacts > 1) {
      print_impacts(impacts, g_, impact_energy_);
    } else if (phase_ == kImpact && contact_time_ >= 0.0) {
      // stopping_time_ stays negative while the boulder still moves down: it never turned within
      // `duration`, so there is no stopping time to report.
      const std::string stopped =
          stopping_time_ >= 0.0
              ? fmt::format("stopped after {:.4f} s", stopping_time_)
              : fmt::format(
                    "still moving down at the end ({:.4g} s after contact, vz {:.3f} m/s; "
                    "raise scenario.rockfall.duration to see it stop)",
                    sim.time() - contact_time_, sim.model().bodies[boulder_].velocity.z);
      fmt::print(
          "rockfall: peak acceleration {:.4g} m/s^2 ({:.3g} g) at {:.4f} s after contact, "
          "deflection {:.4f} m, {}, {} broken bonds, frame force up to {:.4g} kN, energy balance "
          "within {:.3g} % of the impact energy\n",
          peak_acceleration_, peak_acceleration_ / g_, time_of_peak_, contact_z_ - lowest_z_,
          stopped, broken, 1e-3 * max_frame_force_, 100.0 * max_balance_error_ / impact_energy_);
    }
    fmt::print("results: {0}/summary.json, {0}/series.csv, {0}/sag.csv{1}\n", output_dir_,
               rf_.impacts > 1 ? fmt::format(", {}/resettle.csv", output_dir_) : "");
    if (frames)
      fmt::print("frames: open {} in ParaView ({} frames)\n", frames->xdmf_path(),
                 frames->frames());
  }
}

}  // namespace ringdem

#include "app/RockfallDriver.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "app/GroupExtent.hpp"
#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "app/WallClock.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

namespace {

constexpr const char* kBoulderName = "boulder";

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

RockfallDriver::RockfallDriver(const CaseConfig& input)
    : config_(input),
      rf_(config_.scenario.rockfall),
      radius_(sphere_radius(rf_.boulder_mass, rf_.boulder_density)) {
  // The boulder is a free rigid sphere; until the release it is parked far above, motion
  // prescribed at rest, so it neither moves nor touches anything (where it will be released
  // is known only once the net has sagged). It is marked out of play meanwhile (start()).
  for (const auto& b : config_.rigid_bodies)
    if (b.name == kBoulderName)
      throw std::runtime_error(
          "a rockfall case makes its own rigid body 'boulder': rename the one in rigid_bodies");
  RigidBodyConfig boulder;
  boulder.name = kBoulderName;
  boulder.shape = ShapeKind::kSphere;
  boulder.radius = radius_;
  boulder.material = rf_.boulder_material;
  boulder.motion = Motion::kPrescribed;
  boulder.mass = rf_.boulder_mass;
  boulder.gravity = true;
  boulder.position = {0, 0, 1e3};
  config_.rigid_bodies.push_back(boulder);
}

bool RockfallDriver::start(Simulation& sim, const ScenarioContext& context) {
  control_ = &context.control;
  output_dir_ = context.output_dir;
  const Communicator& comm = sim.comm();
  print_ = comm.is_root() && context.verbose;
  const Model& model = sim.model();
  net_ = group_or_throw(model, rf_.net_group, "net_group");
  frame_ = group_or_throw(model, rf_.frame_group, "frame_group");
  boulder_ = model.bodies.size() - 1;
  g_ = norm(sim.settings().gravity);
  if (!(g_ > 0.0)) throw std::runtime_error("a rockfall test needs gravity");
  const Vec3 down = sim.settings().gravity / g_;
  if (std::abs(down.z + 1.0) > 1e-12)
    throw std::runtime_error("a rockfall test expects gravity along -z");
  impact_energy_ = rf_.boulder_mass * g_ * rf_.drop_height;
  impact_velocity_ = std::sqrt(2.0 * g_ * rf_.drop_height);
  if (rf_.sag_dt && *rf_.sag_dt > sim.limits().min())
    throw std::runtime_error(fmt::format(
        "scenario.rockfall.sag_dt {:.4g} s is {:.3g} times the smallest stability limit {:.4g} "
        "s: the sag would blow up; lower it (0.3 of the limit is the automatic step's rule)",
        *rf_.sag_dt, *rf_.sag_dt / sim.limits().min(), sim.limits().min()));
  restore(control_->driver_state());
  // Out of play while parked: the frames leave it out of the scene (docs/output.md).
  sim.model().bodies[boulder_].active = phase_ == kImpact;

  static const std::vector<std::string> columns{"time_s",
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
                                                "balance_error_J",
                                                "plastic_work_J",
                                                "impact",
                                                "brake_work_J",
                                                "brake_elastic_J",
                                                "rope_tension_N"};
  if (comm.is_root() && !output_dir_.empty()) {
    const double until = control_->restarted() ? control_->restart_time() : -1.0;
    series_ = SeriesWriter::resume(output_dir_ + "/series.csv", columns, until);
    sag_series_ = SeriesWriter::resume(output_dir_ + "/sag.csv",
                                       {"time_s", "kinetic_J", "net_top_near_axis_m"}, until);
    if (rf_.impacts > 1)
      resettle_series_ = SeriesWriter::resume(
          output_dir_ + "/resettle.csv",
          {"time_s", "after_impact", "kinetic_J", "net_top_near_axis_m"}, until);
  }
  segment_start_ = impact_start_ = WallClock::now();

  if (control_->restarted()) {
    // The net's damping of this phase, from the case (a restart may have applied a change).
    if (const std::optional<double> damping = net_damping()) sim.set_group_damping(net_, *damping);
    apply_phase_time_step(sim);
    // The checkpoint was written after between_steps(): nothing is due before the next step.
    return finished_ || (phase_ == kImpact && impact_over(sim));
  }

  // Centre of the net, its initial top, and the reference of the energy ledger.
  const GroupExtent e = group_extent(sim, net_, 0, 0, 0);
  drop_x_ = rf_.drop_point ? rf_.drop_point->x : 0.5 * (e.lo.x + e.hi.x);
  drop_y_ = rf_.drop_point ? rf_.drop_point->y : 0.5 * (e.lo.y + e.hi.y);
  net_top_initial_ = net_top_under_drop_axis(sim, "at the start");
  sim.hold_restrained_bodies(true);  // until the release
  ledger_start_ = sim.energies().ledger();
  if (rf_.sag_damping) sim.set_group_damping(net_, *rf_.sag_damping);
  apply_phase_time_step(sim);
  control_->write_frame(sim);
  if (print_)
    fmt::print(
        "rockfall: boulder {:.4g} kg, radius {:.4g} m, drop {:.4g} m ({:.4g} kJ, {:.4g} "
        "m/s at contact) on ({:.4g}, {:.4g}); sag phase first{}\n",
        rf_.boulder_mass, radius_, rf_.drop_height, 1e-3 * impact_energy_, impact_velocity_,
        drop_x_, drop_y_,
        rf_.sag_dt ? fmt::format(", in steps of {:.4g} s (sag_dt) until the release", *rf_.sag_dt)
                   : std::string());
  return between_steps(sim);
}

template <class Self, class F>
void RockfallDriver::for_each_saved(Self& s, F&& f) {
  const double inf = std::numeric_limits<double>::infinity();
  f("next_sag_check", s.next_sag_check_, s.rf_.sag_min_time);
  f("sag_end_time", s.sag_end_time_, -1.0);
  f("contact_time", s.contact_time_, -1.0);
  f("ledger_start", s.ledger_start_, 0.0);
  f("energy_added", s.energy_added_, 0.0);
  f("contact_z", s.contact_z_, 0.0);
  f("net_top_initial", s.net_top_initial_, 0.0);
  f("net_top_sagged", s.net_top_sagged_, 0.0);
  f("drop_x", s.drop_x_, 0.0);
  f("drop_y", s.drop_y_, 0.0);
  f("next_record", s.next_record_, 0.0);
  f("peak_acceleration", s.peak_acceleration_, 0.0);
  f("time_of_peak", s.time_of_peak_, 0.0);
  f("peak_instant", s.peak_instant_, 0.0);
  f("lowest_z", s.lowest_z_, inf);
  f("stopping_time", s.stopping_time_, -1.0);
  f("max_frame_force", s.max_frame_force_, 0.0);
  f("max_rope_tension", s.max_rope_tension_, 0.0);
  f("max_balance_error", s.max_balance_error_, 0.0);
  f("free_fall_time", s.free_fall_time_, 0.0);
  f("peak_sag_kinetic", s.peak_sag_kinetic_, 0.0);
  f("no_contact_limit", s.no_contact_limit_, inf);
  f("sum_steps", s.sum_steps_, 0.0);
  f("sum_fx", s.sum_force_.x, 0.0);
  f("sum_fy", s.sum_force_.y, 0.0);
  f("sum_fz", s.sum_force_.z, 0.0);
  f("rest_start", s.rest_start_, 0.0);
  f("rebound_speed", s.rebound_speed_, 0.0);
  f("release_time", s.release_time_, 0.0);
  f("release_top", s.release_top_, 0.0);
  f("ledger_before_removal", s.ledger_before_removal_, -inf);
  f("release_broken", s.release_broken_, 0.0);
}

void RockfallDriver::restore(const DriverState& d) {
  for_each_saved(*this,
                 [&](const char* name, double& v, double absent) { v = d.get(name, absent); });
  phase_ = static_cast<int>(d.get("phase", 0.0));
  sag_wall_ = d.get("sag_wall", 0.0);
  finished_ = d.get("finished", 0.0) != 0.0;
  impact_ = static_cast<int>(d.get("impact", 0.0));
  for (std::size_t i = 0; i < release_dissipated_.size(); ++i)
    release_dissipated_[i] = d.get(fmt::format("release_dissipated{}", i), 0.0);
  impacts_.clear();
  const int ended = static_cast<int>(d.get("impacts_ended", 0.0));
  for (int i = 1; i <= ended; ++i)
    impacts_.push_back(ImpactRecord::load(d, i));
}

DriverState RockfallDriver::state() const {
  DriverState d;
  for_each_saved(*this, [&](const char* name, const double& v, double) { d.set(name, v); });
  d.set("phase", static_cast<double>(phase_));
  d.set("sag_wall", phase_ == kSag ? sag_wall_ + seconds_since(segment_start_) : sag_wall_);
  d.set("finished", finished_ ? 1.0 : 0.0);
  d.set("impact", static_cast<double>(impact_));
  for (std::size_t i = 0; i < release_dissipated_.size(); ++i)
    d.set(fmt::format("release_dissipated{}", i), release_dissipated_[i]);
  d.set("impacts_ended", static_cast<double>(impacts_.size()));
  for (std::size_t i = 0; i < impacts_.size(); ++i)
    impacts_[i].save(d, static_cast<int>(i + 1));
  return d;
}

bool RockfallDriver::net_at_rest(Simulation& sim) {
  if (sim.time() + 0.5 * sim.dt() < next_sag_check_) return false;
  next_sag_check_ += rf_.sag_check_interval;
  kinetic_ = sim.energies().kinetic;
  const double top = group_extent(sim, net_, drop_x_, drop_y_, radius_).top_near_axis;
  if (sim.comm().is_root() && !output_dir_.empty()) {
    if (phase_ == kSag)
      sag_series_.row({sim.time(), kinetic_, top});
    else
      resettle_series_.row({sim.time(), static_cast<double>(impact_), kinetic_, top});
  }
  peak_sag_kinetic_ = std::max(peak_sag_kinetic_, kinetic_);
  // The net starts at rest (or moves once the boulder is removed): it is at rest (again) once
  // its kinetic energy has fallen below the threshold and to half its peak since the start of
  // the phase (or, if it barely moves, after a while). rest_start_ is 0 in the sag phase.
  const double since = sim.time() - rest_start_;
  const bool decayed =
      kinetic_ < 0.5 * peak_sag_kinetic_ ||
      (peak_sag_kinetic_ < rf_.sag_kinetic_energy && since >= 10.0 * rf_.sag_min_time);
  if (since >= rf_.sag_min_time && kinetic_ < rf_.sag_kinetic_energy && decayed) return true;
  if (phase_ == kSag && since > rf_.sag_max_time) {
    // Say which half of the rest test failed: a net still gathering speed is below the
    // threshold but not yet below half its peak.
    const std::string why =
        kinetic_ >= rf_.sag_kinetic_energy
            ? fmt::format(
                  "kinetic energy {:.4g} J, not below scenario.rockfall.sag_kinetic_energy "
                  "{:.4g} J",
                  kinetic_, rf_.sag_kinetic_energy)
            : fmt::format(
                  "kinetic energy {:.4g} J, below sag_kinetic_energy {:.4g} J but not "
                  "yet half its peak {:.4g} J: the net is still falling",
                  kinetic_, rf_.sag_kinetic_energy, peak_sag_kinetic_);
    throw std::runtime_error(fmt::format(
        "the net is not at rest after {:.4g} s of sag ({}): raise sag_max_time, sag_damping "
        "or the threshold",
        sim.time(), why));
  }
  if (phase_ == kResettle && since > rf_.resettle_max_time)
    throw std::runtime_error(fmt::format(
        "the net is not at rest {:.4g} s after the boulder of impact {} was removed (kinetic "
        "energy {:.4g} J > scenario.rockfall.sag_kinetic_energy {:.4g} J): raise "
        "resettle_max_time, sag_damping or the threshold",
        since, impact_, kinetic_, rf_.sag_kinetic_energy));
  return false;
}

std::optional<double> RockfallDriver::net_damping() const {
  // The sag's damping in the sag and re-settle phases, the impact's from a release on; where
  // one is not given, the net keeps what it had.
  const std::optional<double>& sag = rf_.sag_damping;
  const std::optional<double>& impact = rf_.impact_damping;
  if (phase_ == kSag) return sag;
  if (phase_ == kResettle) return sag ? sag : impact;
  return impact ? impact : sag;
}

void RockfallDriver::apply_phase_time_step(Simulation& sim) const {
  const bool settling = phase_ == kSag || phase_ == kResettle;
  const double dt = settling && rf_.sag_dt ? *rf_.sag_dt : sim.case_time_step();
  if (sim.dt() != dt) sim.change_time_step(dt);
}

double RockfallDriver::net_top_under_drop_axis(const Simulation& sim, const char* when) const {
  const GroupExtent e = group_extent(sim, net_, drop_x_, drop_y_, radius_);
  // The boulder is released above the net's top near the drop axis: with no net particle there
  // (a drop point off the net, or over a ring's opening wider than the boulder) there is none.
  if (!std::isfinite(e.top_near_axis))
    throw std::runtime_error(fmt::format(
        "scenario.rockfall.{}: no particle of the net group '{}' lies within the boulder's "
        "radius {:.4g} m of the drop axis at ({:.4g}, {:.4g}) {} (the net spans x {:.4g} to "
        "{:.4g}, y {:.4g} to {:.4g}): the boulder would miss the net or pass through a ring; move "
        "the drop point onto the net's wires or make the boulder larger",
        rf_.drop_point ? "drop_point" : "net_group", rf_.net_group, radius_, drop_x_, drop_y_, when,
        e.lo.x, e.hi.x, e.lo.y, e.hi.y));
  return e.top_near_axis;
}

void RockfallDriver::release(Simulation& sim) {
  const int previous = phase_;
  if (previous == kSag) sag_wall_ += seconds_since(segment_start_);
  const double top = net_top_under_drop_axis(sim, "at the release");
  if (previous == kSag) {
    sag_end_time_ = sim.time();
    net_top_sagged_ = top;
  }
  // The results of this impact start here (no-ops before the first).
  ++impact_;
  contact_time_ = -1.0;
  contact_z_ = 0.0;
  peak_acceleration_ = time_of_peak_ = peak_instant_ = 0.0;
  lowest_z_ = std::numeric_limits<double>::infinity();
  stopping_time_ = -1.0;
  max_frame_force_ = max_rope_tension_ = 0.0;
  rebound_speed_ = 0.0;
  release_time_ = sim.time();
  release_top_ = top;
  const Energies before = sim.energies();
  release_dissipated_ = {before.plastic_work,    before.friction,
                         before.contact_damping, before.global_damping,
                         before.brake_work,      restraint_totals(sim.model()).friction_work};
  release_broken_ = static_cast<double>(sim.global_broken_bonds());
  if (rf_.impact_damping) sim.set_group_damping(net_, *rf_.impact_damping);
  const double bottom_at_rest = top + rf_.drop_height;
  double z_centre, vz;
  if (rf_.integrate_free_fall) {
    z_centre = bottom_at_rest + radius_;
    vz = 0.0;
  } else {
    // Free fall in vacuum, exactly: from rest at bottom_at_rest down to release_gap above
    // the net, v = sqrt(2 g (h - gap)); the net is at rest meanwhile.
    const double fall = rf_.drop_height - rf_.release_gap;
    z_centre = top + rf_.release_gap + radius_;
    vz = -std::sqrt(2.0 * g_ * fall);
    free_fall_time_ = -vz / g_;
  }
  sim.hold_restrained_bodies(false);
  sim.place_body(boulder_, {drop_x_, drop_y_, z_centre}, {0, 0, vz}, Motion::kFree);
  sim.model().bodies[boulder_].active = true;
  energy_added_ += sim.energies().ledger() - before.ledger();
  phase_ = kImpact;
  apply_phase_time_step(sim);
  next_record_ = sim.time();
  no_contact_limit_ = sim.time() + std::sqrt(2.0 * (rf_.drop_height + 1.0) / g_) + 1.0;  // generous
  impact_start_ = WallClock::now();
  if (!print_) return;
  const std::string fall =
      rf_.integrate_free_fall
          ? ""
          : fmt::format(
                " (free fall of {:.4f} s advanced analytically to {:.3g} m above, "
                "{:.4g} m/s)",
                free_fall_time_, rf_.release_gap, -vz);
  if (previous == kSag)
    fmt::print(
        "sag done at t = {:.4f} s ({} wall): net top under the drop axis {:.4f} m (sagged {:.4f} "
        "m), "
        "kinetic energy {:.3g} J; boulder released {:.4g} m above the net{}\n",
        sim.time(), format_duration(sag_wall_), net_top_sagged_, net_top_initial_ - net_top_sagged_,
        kinetic_, rf_.drop_height, fall);
  else
    fmt::print(
        "impact {} of {}: boulder released {:.4g} m above the net top {:.4f} m at t = "
        "{:.4f} s{}\n",
        impact_, rf_.impacts, rf_.drop_height, top, sim.time(), fall);
}

bool RockfallDriver::impact_over(const Simulation& sim) const {
  return contact_time_ >= 0.0 && sim.time() >= contact_time_ + rf_.duration - 0.5 * sim.dt();
}

ImpactRecord RockfallDriver::impact_record(const Energies& e, double rope_friction_work,
                                           std::int64_t broken) const {
  ImpactRecord r;
  r.release_time = release_time_;
  r.release_net_top = release_top_;
  r.contact_time = contact_time_ >= 0.0 ? contact_time_ : ImpactRecord::kNone;
  r.peak_acceleration = peak_acceleration_;
  r.time_of_peak = time_of_peak_;
  r.peak_instant = peak_instant_;
  r.deflection = contact_time_ >= 0.0 ? contact_z_ - lowest_z_ : ImpactRecord::kNone;
  r.stopping_time = stopping_time_ >= 0.0 ? stopping_time_ : ImpactRecord::kNone;
  r.rebound_speed = rebound_speed_;
  r.max_frame_force = max_frame_force_;
  r.max_rope_tension = max_rope_tension_;
  r.broken_bonds = static_cast<double>(broken) - release_broken_;
  r.plastic_work = e.plastic_work - release_dissipated_[0];
  r.friction = e.friction - release_dissipated_[1];
  r.contact_damping = e.contact_damping - release_dissipated_[2];
  r.global_damping = e.global_damping - release_dissipated_[3];
  r.brake_work = e.brake_work - release_dissipated_[4];
  r.rope_friction = rope_friction_work - release_dissipated_[5];
  return r;
}

bool RockfallDriver::close_impact(Simulation& sim) {
  const Energies e = sim.energies();
  ImpactRecord r =
      impact_record(e, restraint_totals(sim.model()).friction_work, sim.global_broken_bonds());
  impacts_.push_back(r);
  if (rf_.impacts == 1) return true;  // a single impact ends with the boulder in the net
  if (print_)
    fmt::print(
        "impact {} of {} over at t = {:.4f} s: peak acceleration {:.4g} m/s^2, deflection "
        "{:.4f} m, rebound {:.4g} m/s, {} bonds broken; boulder removed, the net "
        "re-settles\n",
        impact_, rf_.impacts, sim.time(), r.peak_acceleration, r.deflection, r.rebound_speed,
        static_cast<long long>(r.broken_bonds));
  // The boulder goes back where it waited before the first release, at rest, out of play. A
  // body with prescribed motion is outside the energy ledger: its kinetic and potential energy
  // leave with it, and so does the elastic energy of its contacts with the net, which the
  // contact forces drop at the next step. after_steps() books the difference then.
  ledger_before_removal_ = e.ledger();
  sim.place_body(boulder_, config_.rigid_bodies.back().position, {0, 0, 0}, Motion::kPrescribed);
  sim.hold_restrained_bodies(true);
  sim.model().bodies[boulder_].active = false;
  phase_ = kResettle;
  apply_phase_time_step(sim);
  rest_start_ = sim.time();
  peak_sag_kinetic_ = 0.0;
  next_sag_check_ = sim.time() + rf_.sag_check_interval;
  if (const std::optional<double> damping = net_damping()) sim.set_group_damping(net_, *damping);
  return false;
}

void RockfallDriver::resettled(Simulation& sim) {
  const double top = group_extent(sim, net_, drop_x_, drop_y_, radius_).top_near_axis;
  ImpactRecord& r = impacts_.back();
  r.residual_height = top - net_top_initial_;
  if (print_)
    fmt::print(
        "net at rest again at t = {:.4f} s, {:.4f} s after impact {}: net top under the "
        "drop axis {:.4f} m, residual height {:.4f} m from the initial top\n",
        sim.time(), sim.time() - rest_start_, impact_, top, r.residual_height);
}

bool RockfallDriver::between_steps(Simulation& sim) {
  // simulation.end_time caps the whole scenario (sag, fall and impact), as for every scenario.
  if (sim.time() + 0.5 * sim.dt() >= config_.simulation.end_time) {
    reached_end_time_ = true;
    if (phase_ == kImpact) record(sim);  // the final state
    return true;
  }
  if (phase_ == kSag || phase_ == kResettle) {
    if (!net_at_rest(sim)) return false;
    if (phase_ == kResettle) {
      resettled(sim);
      if (impact_ >= rf_.impacts) return finished_ = true;
    }
    release(sim);
  }
  if (impact_over(sim)) {
    record(sim);  // the final state of the impact
    if (close_impact(sim)) return finished_ = true;
    return false;
  }
  if (sim.time() + 0.5 * sim.dt() >= next_record_) {
    record(sim);
    next_record_ += rf_.record_interval;
  }
  return false;
}

std::int64_t RockfallDriver::steps_to_advance(const Simulation& sim) const {
  if (std::isfinite(ledger_before_removal_)) return 1;  // after_steps() books the removal
  // between_steps() tests each time t against an event time T as t + dt/2 >= T.
  const double half = 0.5 * sim.dt();
  const auto short_of = [&sim, half](double event) {
    return sim.steps_short_of(event - half, 0.0);
  };
  std::int64_t n = short_of(config_.simulation.end_time);
  if (phase_ == kSag || phase_ == kResettle) return std::min(n, short_of(next_sag_check_));
  n = std::min(n, short_of(next_record_));
  // Before the first contact, impact_over() cannot come within this batch: it is a whole
  // duration after the contact, and a batch ends at the next row.
  if (contact_time_ >= 0.0) n = std::min(n, short_of(contact_time_ + rf_.duration));
  return n;
}

void RockfallDriver::observe_step(const std::vector<RigidBody>& bodies, double time) {
  if (phase_ != kImpact) return;
  const RigidBody& b = bodies[boulder_];
  sum_force_ += b.force;
  sum_steps_ += 1.0;
  if (contact_time_ < 0.0) {
    if (norm2(b.force) > 0.0) {
      contact_time_ = time;
      contact_z_ = b.position.z;
      if (print_)
        fmt::print("first contact at t = {:.5f} s, boulder speed {:.4g} m/s\n", contact_time_,
                   norm(b.velocity));
    } else if (time > no_contact_limit_) {
      throw std::runtime_error("the boulder never touched the net: check drop_point");
    }
  } else {
    peak_instant_ = std::max(peak_instant_, norm(b.force) / rf_.boulder_mass);
    if (b.position.z < lowest_z_) lowest_z_ = b.position.z;
    if (stopping_time_ < 0.0 && b.velocity.z >= 0.0) stopping_time_ = time - contact_time_;
    rebound_speed_ = std::max(rebound_speed_, b.velocity.z);
  }
}

bool RockfallDriver::after_steps(Simulation& sim) {
  if (std::isfinite(ledger_before_removal_)) {
    // The step after the removal: what left the ledger with the boulder.
    energy_added_ += sim.energies().ledger() - ledger_before_removal_;
    ledger_before_removal_ = -std::numeric_limits<double>::infinity();
  }
  return between_steps(sim);
}

}  // namespace ringdem

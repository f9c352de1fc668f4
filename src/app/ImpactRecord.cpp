#include "app/ImpactRecord.hpp"

#include <fmt/format.h>

#include <cmath>
#include <string>
#include <utility>

namespace ringdem {

namespace {

/// The fields a checkpoint holds, by name: one list for save() and load().
template <class Record, class F>
void for_each_field(Record& r, F&& f) {
  f("release_time", r.release_time);
  f("release_net_top", r.release_net_top);
  f("contact_time", r.contact_time);
  f("peak_acceleration", r.peak_acceleration);
  f("time_of_peak", r.time_of_peak);
  f("peak_instant", r.peak_instant);
  f("deflection", r.deflection);
  f("stopping_time", r.stopping_time);
  f("rebound_speed", r.rebound_speed);
  f("max_frame_force", r.max_frame_force);
  f("max_rope_tension", r.max_rope_tension);
  f("broken_bonds", r.broken_bonds);
  f("plastic_work", r.plastic_work);
  f("friction", r.friction);
  f("contact_damping", r.contact_damping);
  f("global_damping", r.global_damping);
  f("brake_work", r.brake_work);
  f("rope_friction", r.rope_friction);
  f("residual_height", r.residual_height);
}

}  // namespace

void ImpactRecord::save(DriverState& state, int number) const {
  for_each_field(*this, [&](const char* name, const double& v) {
    state.set(fmt::format("impact{}.{}", number, name), v);
  });
}

ImpactRecord ImpactRecord::load(const DriverState& state, int number) {
  ImpactRecord r;
  for_each_field(r, [&](const char* name, double& v) {
    v = state.get(fmt::format("impact{}.{}", number, name), v);
  });
  return r;
}

JsonObject ImpactRecord::json(int number, double g, double impact_energy) const {
  JsonObject o;
  o.set("impact", number)
      .set("release_time_s", release_time)
      .set("release_net_top_m", release_net_top)
      .set("first_contact_time_s", contact_time)
      .set("peak_acceleration_m_s2", peak_acceleration)
      .set("peak_acceleration_g", peak_acceleration / g)
      .set("time_of_peak_s", time_of_peak)
      .set("peak_acceleration_single_step_m_s2", peak_instant)
      .set("max_deflection_m", deflection)
      .set("stopping_time_s", stopping_time)
      .set("rebound_speed_m_s", rebound_speed)
      .set("max_frame_force_N", max_frame_force)
      .set("max_rope_tension_N", max_rope_tension)
      .set("broken_bonds", static_cast<long long>(broken_bonds))
      .set("plastic_work_share", plastic_work / impact_energy)
      .set("friction_share", friction / impact_energy)
      .set("contact_damping_share", contact_damping / impact_energy)
      .set("global_damping_share", global_damping / impact_energy)
      .set("brake_work_share", brake_work / impact_energy)
      .set("rope_friction_share", rope_friction / impact_energy)  // part of friction_share
      .set("residual_height_m", residual_height);                 // null: not re-settled
  return o;
}

void set_impacts(JsonObject& summary, const std::vector<ImpactRecord>& impacts, double g,
                 double impact_energy) {
  std::vector<JsonObject> list;
  for (std::size_t i = 0; i < impacts.size(); ++i)
    list.push_back(impacts[i].json(static_cast<int>(i + 1), g, impact_energy));
  summary.set("impacts", list);
}

std::string ImpactRecord::log_line(int number, double g, double impact_energy) const {
  return fmt::format(
      "rockfall impact {}: peak acceleration {:.4g} m/s^2 ({:.3g} g), deflection {:.4f} m, "
      "rebound {:.4g} m/s, {} bonds broken, frame force up to {:.4g} kN, plastic work "
      "{:.3g} %, friction {:.3g} %{}, contact damping {:.3g} %, global damping {:.3g} %, brakes "
      "{:.3g} % of the impact energy, residual height {}",
      number, peak_acceleration, peak_acceleration / g, deflection, rebound_speed,
      static_cast<long long>(broken_bonds), 1e-3 * max_frame_force,
      100.0 * plastic_work / impact_energy, 100.0 * friction / impact_energy,
      rope_friction > 0.0
          ? fmt::format(" ({:.3g} % on the ropes)", 100.0 * rope_friction / impact_energy)
          : std::string(),
      100.0 * contact_damping / impact_energy, 100.0 * global_damping / impact_energy,
      100.0 * brake_work / impact_energy,
      std::isnan(residual_height) ? std::string("not measured")
                                  : fmt::format("{:.4f} m", residual_height));
}

void print_impacts(const std::vector<ImpactRecord>& impacts, double g, double impact_energy) {
  for (std::size_t i = 0; i < impacts.size(); ++i)
    fmt::print("{}\n", impacts[i].log_line(static_cast<int>(i) + 1, g, impact_energy));
}

}  // namespace ringdem

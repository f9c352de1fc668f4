// Derived quantities of a case, checked for range and finiteness (see CaseMagnitudes.hpp).
// The formulas are the model builder's and the time-step estimate's (physics.md §1, §4):
// particle mass rho 4/3 pi r^3 and moment of inertia 2/5 m r^2, the Timoshenko bond section
// (BondTimoshenko::Section::make) on the chord 2 R_c sin(pi / n) of a ring, the Rayleigh and
// spring limits of physics/TimeStep.hpp.

#include "io/CaseMagnitudes.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "io/GrainsInput.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/TimeStep.hpp"

namespace ringdem {

namespace {

using schema::Context;
using schema::format_number;

constexpr double kLightSpeed = 299792458.0;  // m/s
// Atomic nuclei are about 2.3e17 kg/m^3; no material (scaled masses included) is denser.
constexpr double kMaxDensity = 1e18;  // kg/m^3

/// A value the computation can go on with: finite and at least the smallest normal double.
bool usable(double v) {
  return std::isfinite(v) && v >= std::numeric_limits<double>::min();
}

/// A derived value to 4 significant digits, written like the keys' values (1.234e-5).
std::string short_number(double v) {
  return format_number(std::stod(fmt::format("{:.4g}", v)));
}

/// The value, or what went wrong with it.
std::string describe(double v) {
  if (std::isnan(v)) return "not a number";
  if (std::isinf(v)) return "infinite (overflow)";
  if (v == 0.0) return "0 (underflow)";
  if (std::abs(v) < std::numeric_limits<double>::min())
    return short_number(v) + " (below the smallest normal double)";
  return short_number(v);
}

/// `key` where it was given, else `fallback`'s location (both reported under `key`).
void report(Context& ctx, const std::string& key, const std::string& fallback,
            std::string message) {
  ctx.error(ctx.where(key, fallback), key, std::move(message));
}

/// The given one of `keys` (the first if none was given): where a derived value is reported.
std::string given_or_first(const Context& ctx, const std::vector<std::string>& keys) {
  for (const std::string& k : keys)
    if (ctx.given(k)) return k;
  return keys.front();
}

const MaterialConfig* find_material(const CaseConfig& c, const std::string& name) {
  for (const MaterialConfig& m : c.materials)
    if (m.name == name) return &m;
  return nullptr;
}

std::optional<std::size_t> find_bond(const CaseConfig& c, const std::string& name) {
  for (std::size_t i = 0; i < c.bonds.size(); ++i)
    if (c.bonds[i].name == name) return i;
  return std::nullopt;
}

double shear_modulus(const MaterialConfig& m) {
  return m.youngs_modulus / (2.0 * (1.0 + m.poisson_ratio));
}

double largest_abs(const Vec3& v) {
  return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
}

/// The particles one generator entry makes (a ring or net also its bonds), as the builder
/// will compute them.
struct Kind {
  std::string path;          ///< e.g. particles.rings[0], particles.nets[0].shackles
  std::string radius_key;    ///< key path of the particle radius
  std::string position_key;  ///< key path of the centre / origin / position
  double radius = 0.0;
  const MaterialConfig* material = nullptr;
  std::optional<double> ring_mass;  ///< a given mass of one ring (sets the density)
  int per_ring = 0;                 ///< particles of one ring
  std::optional<std::size_t> bond;  ///< index into CaseConfig::bonds
  double chord = 0.0;               ///< bond length between neighbours of a ring
  double reach = 0.0;               ///< bound of |coordinate| of its particles
  Vec3 velocity;                    ///< initial (or prescribed) velocity
};

double ring_chord(double internal_diameter, double radius, int n) {
  const double centreline = 0.5 * internal_diameter + radius;
  return 2.0 * centreline * std::sin(M_PI / n);
}

std::vector<Kind> particle_kinds(const CaseConfig& c, const Context& ctx) {
  std::vector<Kind> kinds;
  const auto add = [&](Kind k, const std::string& material) {
    k.material = find_material(c, material);
    if (k.material == nullptr || ctx.failed(k.path)) return;  // reported elsewhere
    kinds.push_back(std::move(k));
  };
  for (std::size_t i = 0; i < c.rings.size(); ++i) {
    const RingConfig& r = c.rings[i];
    Kind k;
    k.path = schema::index_path("particles.rings", i);
    k.radius_key = k.path + ".particle_radius";
    k.position_key = k.path + ".centre";
    k.radius = r.particle_radius;
    k.ring_mass = r.mass;
    k.per_ring = r.n_particles;
    k.bond = find_bond(c, r.bond);
    k.chord = ring_chord(r.internal_diameter, r.particle_radius, r.n_particles);
    k.reach = largest_abs(r.centre) + 0.5 * r.internal_diameter + 2.0 * r.particle_radius;
    k.velocity = r.velocity;
    add(k, r.material);
  }
  for (std::size_t i = 0; i < c.nets.size(); ++i) {
    const RingNetConfig& n = c.nets[i];
    Kind k;
    k.path = schema::index_path("particles.nets", i);
    k.radius_key = k.path + ".particle_radius";
    k.position_key = k.path + ".centre";
    k.radius = n.particle_radius;
    k.ring_mass = n.mass;
    k.per_ring = n.n_particles;
    k.bond = find_bond(c, n.bond);
    k.chord = ring_chord(n.internal_diameter, n.particle_radius, n.n_particles);
    // Ring centres lie within rows (columns) x link_distance / sqrt(2) of the centre; rings and
    // shackles add their size. A bound, not the extent.
    const double span = static_cast<double>(std::max(n.rows, n.columns)) * n.link_distance;
    const double shackle =
        n.shackles.enabled ? 2.0 * (n.shackles.internal_diameter + 2.0 * n.shackles.particle_radius)
                           : 0.0;
    k.reach =
        largest_abs(n.centre) + span + n.internal_diameter + 2.0 * n.particle_radius + shackle;
    const double reach = k.reach;
    add(k, n.material);
    if (n.shackles.enabled) {
      Kind s;
      s.path = k.path + ".shackles";
      s.radius_key = s.path + ".particle_radius";
      s.position_key = k.position_key;
      s.radius = n.shackles.particle_radius;
      s.reach = reach;
      add(s, n.shackles.material);
    }
  }
  for (std::size_t i = 0; i < c.lattices.size(); ++i) {
    const LatticeConfig& l = c.lattices[i];
    Kind k;
    k.path = schema::index_path("particles.lattices", i);
    k.radius_key = k.path + ".particle_radius";
    k.position_key = k.path + ".origin";
    k.radius = l.particle_radius;
    const double o[3] = {l.origin.x, l.origin.y, l.origin.z};
    for (int a = 0; a < 3; ++a) {
      const double last =
          o[a] + static_cast<double>(l.count[static_cast<std::size_t>(a)] - 1) * l.spacing;
      k.reach = std::max({k.reach, std::abs(o[a]), std::abs(last)});
    }
    k.reach += l.spacing + l.particle_radius;  // jitter moves a sphere by less than a gap
    k.velocity = l.velocity;
    add(k, l.material);
  }
  for (std::size_t i = 0; i < c.grains.size(); ++i) {
    const GrainsConfig& g = c.grains[i];
    Kind k;
    k.path = schema::index_path("particles.grains", i);
    // The smallest grain sets the contact time step (Rayleigh: proportional to the radius).
    k.radius_key = k.path + ".sizes";
    k.position_key = k.path + ".box_min";
    k.radius = smallest_grain_radius(g.sizes);
    if (!(k.radius > 0.0)) continue;  // no size class: reported by validate_grains
    k.reach = std::max(largest_abs(g.box_min), largest_abs(g.box_max));
    k.velocity = g.velocity;
    add(k, g.material);
  }
  for (std::size_t i = 0; i < c.spheres.size(); ++i) {
    const SphereConfig& s = c.spheres[i];
    Kind k;
    k.path = schema::index_path("particles.spheres", i);
    k.radius_key = k.path + ".radius";
    k.position_key = k.path + ".position";
    k.radius = s.radius;
    k.reach = largest_abs(s.position) + s.radius;
    k.velocity = s.velocity;
    add(k, s.material);
  }
  return kinds;
}

/// The smallest stability limit found so far and where it comes from.
struct Limit {
  double value = std::numeric_limits<double>::infinity();
  std::string what;
  void offer(double v, const std::string& description) {
    if (v < value) {
      value = v;
      what = description;
    }
  }
};

/// Initial and prescribed speeds (of a point on a spinning body too) below the speed of light.
void check_speeds(const CaseConfig& c, const std::vector<Kind>& kinds, Context& ctx) {
  const auto check = [&](const std::string& key, const std::string& fallback, double speed) {
    if (speed <= kLightSpeed || ctx.failed(key)) return;
    report(ctx, key, fallback,
           fmt::format("a speed of {} m/s is faster than light", describe(speed)));
  };
  for (const Kind& k : kinds)
    check(k.path + ".velocity", k.path, norm(k.velocity));
  for (std::size_t i = 0; i < c.spheres.size(); ++i) {
    const std::string p = schema::index_path("particles.spheres", i);
    check(p + ".omega", p, norm(c.spheres[i].omega) * c.spheres[i].radius);
  }
  for (std::size_t i = 0; i < c.rigid_bodies.size(); ++i) {
    const RigidBodyConfig& b = c.rigid_bodies[i];
    const std::string p = schema::index_path("rigid_bodies", i);
    check(p + ".velocity", p, norm(b.velocity));
    if (b.shape != ShapeKind::kPlane)
      check(p + ".omega", p, norm(b.omega) * std::max(b.radius, 0.5 * b.length));
  }
}

/// Elastic wave speed sqrt(G / rho) of every material below the speed of light: beyond it the
/// modulus (or density) is no material's, and the stability limits underflow. Returns the
/// names of the materials that failed.
std::set<std::string> check_materials(const CaseConfig& c, Context& ctx) {
  std::set<std::string> bad;
  for (std::size_t i = 0; i < c.materials.size(); ++i) {
    const MaterialConfig& m = c.materials[i];
    const std::string p = schema::index_path("materials", i);
    if (ctx.failed(p)) {
      bad.insert(m.name);
      continue;
    }
    if (m.density > kMaxDensity) {
      bad.insert(m.name);
      report(ctx, p + ".density", p,
             fmt::format("{} kg/m^3 is denser than an atomic nucleus (2.3e17 kg/m^3): at most {}",
                         format_number(m.density), format_number(kMaxDensity)));
      continue;
    }
    const double g = shear_modulus(m);
    const double speed = std::sqrt(g / m.density);
    if (usable(g) && speed <= kLightSpeed) continue;
    bad.insert(m.name);
    report(ctx, given_or_first(ctx, {p + ".youngs_modulus", p + ".density", p + ".poisson_ratio"}),
           p,
           fmt::format("youngs_modulus {} Pa, poisson_ratio {} and density {} kg/m^3 give a shear "
                       "modulus of {} Pa and an elastic wave speed sqrt(G / density) of {} m/s, "
                       "faster than light: no material is that stiff or that light (steel: "
                       "about 3200 m/s)",
                       format_number(m.youngs_modulus), format_number(m.poisson_ratio),
                       format_number(m.density), describe(g), describe(speed)));
  }
  return bad;
}

/// Mass, moment of inertia and (for rings) bonds of one kind of particle; offers its stability
/// limits. Returns false if something was reported.
bool check_kind(const CaseConfig& c, const Kind& k, std::set<std::size_t>& bad_bonds, Limit& limit,
                Context& ctx) {
  const double volume = 4.0 / 3.0 * M_PI * k.radius * k.radius * k.radius;
  if (!usable(volume)) {
    report(ctx, k.radius_key, k.path,
           fmt::format("a particle radius of {} m gives a particle volume 4/3 pi r^3 of {} m^3",
                       format_number(k.radius), describe(volume)));
    return false;
  }
  double density = k.material->density;
  if (k.ring_mass) {
    density = *k.ring_mass / (k.per_ring * volume);
    if (!usable(density) || density > kMaxDensity) {
      report(ctx, k.path + ".mass", k.path,
             fmt::format("a ring of {} kg in {} particles of {} m^3 gives a particle density of "
                         "{} kg/m^3 (at most {})",
                         format_number(*k.ring_mass), k.per_ring, short_number(volume),
                         describe(density), format_number(kMaxDensity)));
      return false;
    }
  }
  const double mass = density * volume;
  const double inertia = 0.4 * mass * k.radius * k.radius;
  if (!usable(mass) || !usable(inertia)) {
    report(ctx, k.ring_mass ? k.path + ".mass" : k.radius_key, k.path,
           fmt::format("particles of radius {} m and density {} kg/m^3 have a mass of {} kg and "
                       "a moment of inertia 2/5 m r^2 of {} kg m^2",
                       format_number(k.radius), short_number(density), describe(mass),
                       describe(inertia)));
    return false;
  }
  const MaterialConfig& m = *k.material;
  const double rayleigh =
      rayleigh_time_step(k.radius, m.density, shear_modulus(m), m.poisson_ratio);
  if (!usable(rayleigh)) {
    report(ctx, k.radius_key, k.path,
           fmt::format("the Rayleigh time-step limit pi r sqrt(rho / G) / (0.1631 nu + 0.8766) of "
                       "these particles (material '{}') is {} s",
                       m.name, describe(rayleigh)));
    return false;
  }
  limit.offer(rayleigh, fmt::format("the Rayleigh limit of {} (particle radius {} m, material "
                                    "'{}')",
                                    k.path, format_number(k.radius), m.name));
  if (!k.bond || bad_bonds.count(*k.bond) != 0) return true;

  const BondConfig& b = c.bonds[*k.bond];
  const std::string bp = schema::index_path("bonds", *k.bond);
  if (ctx.failed(bp)) return true;
  const std::string bond_key = b.derive_from ? bp + ".derive_from" : bp + ".youngs_modulus";
  const auto bond_error = [&](const std::string& message) {
    bad_bonds.insert(*k.bond);
    report(ctx, bond_key, bp,
           fmt::format("bond '{}' on {} (particle radius {} m, bond length {} m): {}", b.name,
                       k.path, format_number(k.radius), short_number(k.chord), message));
    return false;
  };
  if (!usable(b.youngs_modulus))
    return bond_error(
        fmt::format("the derived modulus youngs_modulus is {} Pa", describe(b.youngs_modulus)));
  if (!usable(k.chord)) {
    report(ctx, k.path + ".n_particles", k.path,
           fmt::format("{} particles on this ring are {} m apart", k.per_ring, describe(k.chord)));
    return false;
  }
  const double speed = std::sqrt(b.youngs_modulus / density);
  if (!(speed <= kLightSpeed))
    return bond_error(fmt::format(
        "youngs_modulus {} Pa on particles of {} kg/m^3 gives a wave speed sqrt(E / density) of "
        "{} m/s, faster than light",
        short_number(b.youngs_modulus), short_number(density), describe(speed)));
  BondTimoshenko::Params params;
  params.youngs_modulus = b.youngs_modulus;
  params.poisson_ratio = b.poisson_ratio;
  params.radius_multiplier = b.radius_multiplier;
  const auto s = BondTimoshenko::Section::make(params, k.radius, k.radius, k.chord);
  const std::pair<const char*, double> stiffnesses[] = {{"axial stiffness E A / L", s.k_axial},
                                                        {"shear stiffness 12 c / L^3", s.k_shear},
                                                        {"bending stiffness", s.k_bend_self},
                                                        {"torsion stiffness G J / L", s.k_torsion}};
  for (const auto& [name, value] : stiffnesses)
    if (!usable(value)) return bond_error(fmt::format("its {} is {}", name, describe(value)));
  const double rotation = std::max(s.k_bend_self, s.k_torsion);
  const std::pair<const char*, double> limits[] = {
      {"bond axial", spring_time_step(mass, s.k_axial)},
      {"bond shear", spring_time_step(mass, s.k_shear)},
      {"bond rotation", spring_time_step(inertia, rotation)}};
  for (const auto& [name, value] : limits) {
    if (!usable(value))
      return bond_error(fmt::format("its {} time-step limit is {} s", name, describe(value)));
    limit.offer(value, fmt::format("the {} limit of bond '{}' on {}", name, b.name, k.path));
  }
  return true;
}

/// Masses and moments of inertia of the free rigid bodies and of the rockfall boulder.
void check_bodies(const CaseConfig& c, const std::set<std::string>& bad_materials, Context& ctx) {
  for (std::size_t i = 0; i < c.rigid_bodies.size(); ++i) {
    const RigidBodyConfig& b = c.rigid_bodies[i];
    const std::string p = schema::index_path("rigid_bodies", i);
    if (b.motion != Motion::kFree || b.shape == ShapeKind::kPlane || ctx.failed(p)) continue;
    const MaterialConfig* m = find_material(c, b.material);
    if (!b.mass && (m == nullptr || bad_materials.count(b.material) != 0)) continue;
    // As the model builder: a cylinder's principal moments about its diameter and its axis.
    const double r2 = b.radius * b.radius;
    double mass = 0.0, inertia = 0.0, inertia_axis = 0.0;
    if (b.shape == ShapeKind::kCylinder) {
      mass = b.mass.value_or(m ? m->density * M_PI * r2 * b.length : 0.0);
      inertia = mass * (3.0 * r2 + b.length * b.length) / 12.0;
      inertia_axis = 0.5 * mass * r2;
    } else {
      mass = b.mass.value_or(m ? m->density * 4.0 / 3.0 * M_PI * r2 * b.radius : 0.0);
      inertia = inertia_axis = 0.4 * mass * r2;
    }
    if (usable(mass) && usable(inertia) && usable(inertia_axis)) continue;
    if (usable(inertia)) inertia = inertia_axis;  // report the moment out of range
    report(ctx, given_or_first(ctx, {p + ".mass", p + ".radius", p + ".length"}), p,
           fmt::format("the free body '{}' has a mass of {} kg and a moment of inertia of {} "
                       "kg m^2",
                       b.name, describe(mass), describe(inertia)));
  }
  if (c.scenario.type != "rockfall" || ctx.failed("scenario.rockfall")) return;
  const RockfallConfig& rf = c.scenario.rockfall;
  const double radius = std::cbrt(3.0 * rf.boulder_mass / (4.0 * M_PI * rf.boulder_density));
  const double inertia = 0.4 * rf.boulder_mass * radius * radius;
  if (usable(radius) && usable(inertia)) return;
  const std::string p = "scenario.rockfall";
  report(ctx, given_or_first(ctx, {p + ".boulder_mass", p + ".boulder_density"}),
         ctx.given(p) ? p : "scenario",
         fmt::format("a boulder of {} kg and {} kg/m^3 has a radius (3 m / (4 pi rho))^(1/3) of "
                     "{} m and a moment of inertia of {} kg m^2",
                     format_number(rf.boulder_mass), format_number(rf.boulder_density),
                     describe(radius), describe(inertia)));
}

}  // namespace

std::pair<double, std::string> run_duration(const CaseConfig& c) {
  if (c.scenario.type == "tensile_test") {
    const TensileTestConfig& t = c.scenario.tensile_test;
    const double travel = t.max_displacement / t.loading_rate;
    if (travel < c.simulation.end_time) return {travel, "scenario.tensile_test.max_displacement"};
  }
  if (c.scenario.type == "rockfall") {
    // The sag (at most sag_max_time), the fall (the driver gives up after
    // sqrt(2 (drop_height + 1) / g) + 1 s without contact) and `duration` after the contact.
    const RockfallConfig& rf = c.scenario.rockfall;
    const double g = std::abs(c.simulation.gravity.z);
    const double fall = std::sqrt(2.0 * (rf.drop_height + 1.0) / g) + 1.0;
    const std::string p = "scenario.rockfall.";
    std::string key = p + "sag_max_time";
    if (fall > std::max(rf.sag_max_time, rf.duration)) key = p + "drop_height";
    if (rf.duration > std::max(rf.sag_max_time, fall)) key = p + "duration";
    if (rf.impacts > 1) {
      // Each further impact: a re-settle (at most resettle_max_time), a fall and `duration`.
      const double more = static_cast<double>(rf.impacts - 1);
      return {
          rf.sag_max_time + fall + rf.duration + more * (rf.resettle_max_time + fall + rf.duration),
          key};
    }
    return {rf.sag_max_time + fall + rf.duration, key};
  }
  return {c.simulation.end_time, "simulation.end_time"};
}

namespace {

/// The smallest stability limit over the particle kinds (check_kind reports what is out of
/// range); `ok` is false where a kind could not be checked.
struct KindLimits {
  Limit limit;
  double largest_radius = 0.0;
  bool ok = true;
};
KindLimits kind_limits(const CaseConfig& c, const std::vector<Kind>& kinds,
                       const std::set<std::string>& bad_materials, Context& ctx) {
  KindLimits out;
  std::set<std::size_t> bad_bonds;
  for (const Kind& k : kinds) {
    if (bad_materials.count(k.material->name) != 0) {
      out.ok = false;
      continue;
    }
    out.ok = check_kind(c, k, bad_bonds, out.limit, ctx) && out.ok;
    out.largest_radius = std::max(out.largest_radius, k.radius);
  }
  return out;
}

}  // namespace

std::string fixed_step_above_limit(double dt, double limit, const std::string& what) {
  return fmt::format(
      "the fixed time step {} s is {:.3g} times the smallest stability limit, {} s ({}): the "
      "run may diverge; lower it, or leave it out to take dt_safety x that limit",
      format_number(dt), dt / limit, short_number(limit), what);
}

void TimeStepPlan::tighten(double smaller, const std::string& what, double dt_safety) {
  if (!(smaller < limit)) return;
  limit = smaller;
  limit_what = what;
  if (!fixed) dt = dt_safety * limit;
  steps = duration / dt;
}

std::optional<TimeStepPlan> plan_time_steps(const CaseConfig& c) {
  Context ctx(c.name);  // a loaded case: nothing to report
  const std::set<std::string> bad_materials = check_materials(c, ctx);
  const std::vector<Kind> kinds = particle_kinds(c, ctx);
  const KindLimits k = kind_limits(c, kinds, bad_materials, ctx);
  if (!k.ok || kinds.empty() || !std::isfinite(k.limit.value)) return std::nullopt;
  TimeStepPlan plan;
  plan.fixed = c.simulation.dt.has_value();
  plan.dt = plan.fixed ? *c.simulation.dt : c.simulation.dt_safety * k.limit.value;
  plan.limit = k.limit.value;
  plan.limit_what = k.limit.what;
  std::tie(plan.duration, plan.duration_key) = run_duration(c);
  plan.steps = plan.duration / plan.dt;
  return plan;
}

void check_case_magnitudes(const CaseConfig& c, Context& ctx) {
  const std::set<std::string> bad_materials = check_materials(c, ctx);
  check_bodies(c, bad_materials, ctx);
  std::vector<Kind> kinds = particle_kinds(c, ctx);
  check_speeds(c, kinds, ctx);
  const KindLimits kind = kind_limits(c, kinds, bad_materials, ctx);
  if (!kind.ok || kinds.empty()) return;
  const Limit& limit = kind.limit;
  const double largest_radius = kind.largest_radius;

  // Steps: a run needs duration / dt of them, with dt the fixed one (at most the smallest
  // stability limit, or the run is unstable) or dt_safety times that limit.
  const SimulationConfig& s = c.simulation;
  const auto [duration, duration_key] = run_duration(c);
  if (s.dt && *s.dt > limit.value && !ctx.failed("simulation.dt"))
    ctx.warn(ctx.where("simulation.dt", "simulation"), "simulation.dt",
             fixed_step_above_limit(*s.dt, limit.value, limit.what));
  if (!ctx.failed("simulation") && !ctx.failed(duration_key) && std::isfinite(limit.value)) {
    const double dt = s.dt ? std::min(*s.dt, limit.value) : s.dt_safety * limit.value;
    const double steps = duration / dt;
    // A fixed dt far below what stability asks for is the cause when a run at the stable dt
    // would be countable.
    const bool dt_too_small =
        s.dt && *s.dt <= limit.value && duration / limit.value <= kMaxStepsPerRun;
    if (!(steps <= kMaxStepsPerRun) && dt_too_small) {
      report(ctx, "simulation.dt", "simulation",
             fmt::format("a run of {} s at dt {} s takes {} steps, more than the {} one run can "
                         "count; stability allows dt up to {} s ({})",
                         short_number(duration), format_number(*s.dt), describe(steps),
                         format_number(kMaxStepsPerRun), short_number(limit.value), limit.what));
    } else if (!(steps <= kMaxStepsPerRun)) {
      const std::string how =
          !s.dt ? fmt::format("dt auto = dt_safety {} x {}, {} s", format_number(s.dt_safety),
                              limit.what, short_number(limit.value))
          : *s.dt <= limit.value ? fmt::format("the fixed dt {} s", format_number(*s.dt))
                                 : fmt::format("dt at most {}, {} s, for a stable run", limit.what,
                                               format_number(limit.value));
      report(ctx, duration_key, "simulation",
             fmt::format("a run of {} s at {} takes {} steps, more than the {} one run can "
                         "count: shorten the run or make the time step larger",
                         short_number(duration), how, describe(steps),
                         format_number(kMaxStepsPerRun)));
    } else {
      // Frames and checkpoints by simulated time: each due time is found by adding the
      // interval, which must move it.
      for (const auto& [key, interval] :
           {std::pair<std::string, double>{"output.frame_interval", c.output.frame_interval},
            {"output.checkpoint_interval", c.output.checkpoint_interval}}) {
        if (interval <= 0.0 || ctx.failed(key)) continue;
        const double count = duration / interval;
        if (count <= kMaxStepsPerRun) continue;
        report(ctx, key, "output",
               fmt::format("{} s in a run of {} s is {} of them, more than the {} one run can "
                           "count",
                           format_number(interval), short_number(duration), describe(count),
                           format_number(kMaxStepsPerRun)));
      }
    }
  }

  // Lengths: every particle within kMaxCellsFromOrigin cells of the neighbour search (and
  // blocks of the decomposition, which are at least as large) from the origin.
  if (ctx.failed("simulation.skin")) return;
  const double cell = 2.0 * largest_radius + s.skin;
  for (const Kind& k : kinds) {
    const double cells = k.reach / cell;
    if (cells <= kMaxCellsFromOrigin) continue;
    report(ctx, k.position_key, k.path,
           fmt::format("particles reach {} m from the origin, {} cells of 2 x largest particle "
                       "radius + skin = {} m; the neighbour search and the domain decomposition "
                       "number at most {} each way: place the model near the origin",
                       describe(k.reach), describe(cells), short_number(cell),
                       format_number(kMaxCellsFromOrigin)));
    return;
  }
}

}  // namespace ringdem

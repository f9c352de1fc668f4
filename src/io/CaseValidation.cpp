// Cross-key validation of a parsed case (see CaseValidation.hpp).
//
// This is the one file of the loader that depends on domain/: a net's geometry can only be
// judged on the net itself (rings that touch at creation, linked rings that are not linked, a
// shackle that does not hold its ring), so validate_net runs the ring-net generator and the
// Gauss linking number; and a bond with `derive_from` gets its modulus from the ring reduction
// factors (domain/RingGenerator.hpp, physics.md §2 Eq. 17), which need the particle radius of
// the rings that use it. Doing it here makes a bad net or bond an input error with its line
// instead of a failure after the build. Besides this file, only io/GrainsInput (the grain
// size distributions of domain/GrainSizeDistribution) calls into domain/.

#include "io/CaseValidation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "domain/LinkingNumber.hpp"
#include "domain/RingGenerator.hpp"
#include "domain/RingNet.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/ModelTable.hpp"
#include "io/CaseMagnitudes.hpp"
#include "io/DebrisValidation.hpp"
#include "io/GrainsInput.hpp"
#include "io/ReferenceChecks.hpp"
#include "io/SizeEstimate.hpp"
#include "io/SphereFile.hpp"

namespace ringdem {

namespace {

using schema::Context;
using schema::Location;

/// Bonds with `derive_from`: E_b = eta E with eta = 1 / (5 gamma^2), gamma = lambda r_eq / R_eq
/// (physics.md §2, Eq. 17), r_eq the particle radius of the rings that use the bond.
void derive_bond_moduli(CaseConfig& c, Context& ctx) {
  for (std::size_t i = 0; i < c.bonds.size(); ++i) {
    BondConfig& b = c.bonds[i];
    const std::string p = schema::index_path("bonds", i);
    if (!b.derive_from || ctx.failed(p + ".derive_from")) continue;
    if (ctx.given(p + ".youngs_modulus")) {
      ctx.error(ctx.where(p + ".youngs_modulus"), p + ".youngs_modulus",
                "give either youngs_modulus or derive_from, not both (derive_from sets it)");
      continue;
    }
    std::optional<double> particle_radius;
    std::string first_ring;
    // Rings and nets using the bond; rp is the entry's key path.
    const auto use = [&](const std::string& bond, double radius, const std::string& rp) {
      if (bond != b.name || ctx.failed(rp + ".particle_radius")) return;
      if (!particle_radius) {
        particle_radius = radius;
        first_ring = rp;
      } else if (radius != *particle_radius) {
        ctx.error(ctx.where(rp + ".particle_radius", rp), rp + ".particle_radius",
                  fmt::format("bond '{}' derives its modulus from the particle radius, so every "
                              "ring using it needs the same particle_radius: {} has {} m, got {}",
                              b.name, first_ring, schema::format_number(*particle_radius),
                              schema::format_number(radius)));
      }
    };
    for (std::size_t k = 0; k < c.rings.size(); ++k)
      use(c.rings[k].bond, c.rings[k].particle_radius, schema::index_path("particles.rings", k));
    for (std::size_t k = 0; k < c.nets.size(); ++k)
      use(c.nets[k].bond, c.nets[k].particle_radius, schema::index_path("particles.nets", k));
    if (!particle_radius) continue;  // unused bond: nothing to derive from
    const BondDerivationConfig& d = *b.derive_from;
    const RingReductionFactors f =
        ring_reduction_factors(d.windings, 0.5 * d.wire_diameter, *particle_radius,
                               b.radius_multiplier, d.steel_youngs_modulus);
    b.youngs_modulus = f.bond_youngs_modulus;
    b.derived_particle_radius = *particle_radius;
  }
}

/// `bonds[].plastic`: required by a plastic bond model (the table's `plastic` flag), refused by
/// the others; the wire bundle from the section or from derive_from, not from both.
void check_plastic_limits(const CaseConfig& c, Context& ctx) {
  std::vector<std::string> plastic_models;
  for (const auto& m : bond_models())
    if (m.plastic) plastic_models.emplace_back(m.name);
  for (std::size_t i = 0; i < c.bonds.size(); ++i) {
    const BondConfig& b = c.bonds[i];
    const std::string p = schema::index_path("bonds", i);
    const BondModelEntry* model = find_bond_model(b.model);
    if (model == nullptr || ctx.failed(p + ".model") || ctx.failed(p + ".plastic")) continue;
    if (!model->plastic) {
      if (b.plastic)
        ctx.error(ctx.where(p + ".plastic"), p + ".plastic",
                  fmt::format("model '{}' is elastic and reads no plastic limits; use model {} "
                              "or remove this section",
                              b.model, schema::join_names(plastic_models)));
      continue;
    }
    if (!b.plastic) {
      ctx.error(ctx.where(p + ".model", p), p + ".plastic",
                fmt::format("model '{}' needs the section {}.plastic (yield_stress, "
                            "hardening_ratio, failure_strain; windings and wire_diameter unless "
                            "derive_from gives them)",
                            b.model, p));
      continue;
    }
    const std::string q = p + ".plastic";
    for (const char* key : {"windings", "wire_diameter", "steel_youngs_modulus"}) {
      const std::string k = q + "." + key;
      if (b.derive_from && ctx.given(k))
        ctx.error(ctx.where(k), k,
                  fmt::format("{}.derive_from gives {}: give it in one place only", p, key));
      else if (!b.derive_from && !ctx.given(k) && std::string(key) != "steel_youngs_modulus")
        ctx.error(
            ctx.where(q), k,
            fmt::format("missing key '{}' (the bond has no derive_from to take it from)", key));
    }
  }
}

std::string describe_net_ring(const RingNetLayout& net, std::size_t index) {
  static const char* const side_names[] = {"-x", "+x", "-y", "+y"};
  if (index < net.rings.size())
    return fmt::format("ring (row {}, column {})", net.rings[index].row, net.rings[index].column);
  const ShacklePlacement& s = net.shackles[index - net.rings.size()];
  return fmt::format("the {} shackle of ring (row {}, column {})",
                     side_names[static_cast<int>(s.side)], net.rings[s.net_ring].row,
                     net.rings[s.net_ring].column);
}

/// Resolves width / length into columns / rows, checks references and the geometry: that the
/// rings can interlink, that shackle particles neither overlap nor let a wire through, and, on
/// the generated net, that no two rings touch at creation and that linked rings are linked.
/// Returns the number of particles the net creates (0 if its geometry is invalid).
long long validate_net(RingNetConfig& n, const std::string& p,
                       const std::vector<std::string>& materials, bool materials_ok,
                       const std::vector<std::string>& bonds, bool bonds_ok, Context& ctx) {
  const std::string sp = p + ".shackles";
  check_reference(n.material, materials, materials_ok, p + ".material", p, "material", "materials",
                  ctx);
  check_reference(n.bond, bonds, bonds_ok, p + ".bond", p, "bond", "bonds", ctx);
  if (n.shackles.enabled)
    check_reference(n.shackles.material, materials, materials_ok, sp + ".material",
                    ctx.given(sp) ? sp : p, "material", "materials", ctx);
  if (n.shackles.brake && n.shackles.ropes)
    ctx.error(ctx.where(sp + ".ropes"), sp + ".ropes",
              "give either brake or ropes, not both (a braked shackle is held at its place, a "
              "roped one slides on its rope)");
  if (!n.shackles.enabled && n.shackles.rigid_tori())
    ctx.error(ctx.where(sp + ".enabled"), sp + ".enabled",
              fmt::format("must be true with {} (they hold the shackles)",
                          n.shackles.brake ? "brake" : "ropes"));
  if (!ctx.given(p + ".contact_radius")) {
    n.contact_radius = std::max(0.008, n.particle_radius);
  } else if (!ctx.failed(p + ".contact_radius") && !ctx.failed(p + ".particle_radius") &&
             n.contact_radius < n.particle_radius) {
    ctx.error(ctx.where(p + ".contact_radius"), p + ".contact_radius",
              fmt::format("must be >= particle_radius ({} m), got {}",
                          schema::format_number(n.particle_radius),
                          schema::format_number(n.contact_radius)));
  }
  if (n.mesh && !ctx.failed(p + ".mesh") && !ctx.failed(p + ".internal_diameter") &&
      n.mesh->opening >= n.internal_diameter)
    ctx.warn(ctx.where(p + ".mesh.opening", p), p + ".mesh.opening",
             fmt::format("the mesh holds grains of {} m or more, which the rings' {} m openings "
                         "hold anyway: it adds cost and no retention; lower it to the mesh's "
                         "opening",
                         schema::format_number(n.mesh->opening),
                         schema::format_number(n.internal_diameter)));
  for (const auto& [target, count] : {std::pair{"width", "columns"}, std::pair{"length", "rows"}}) {
    if (ctx.given(p + "." + target) && ctx.given(p + "." + count))
      ctx.error(
          ctx.where(p + "." + count), p + "." + count,
          fmt::format("give either {} or {}, not both ({} sets {})", count, target, target, count));
  }
  for (const char* key :
       {"rows", "columns", "width", "length", "link_distance", "tilt", "centre", "normal", "x_axis",
        "internal_diameter", "n_particles", "particle_radius", "contact_radius", "shackles"}) {
    if (ctx.failed(p + "." + key)) return 0;
  }
  // The net's frame: x_axis projected onto the plane, as a ring's reference; not given and
  // parallel to the normal (a net normal to x), the world y instead.
  n.normal = normalized(n.normal);
  Vec3 in_plane = n.x_axis - dot(n.x_axis, n.normal) * n.normal;
  if (!(norm(in_plane) > 1e-9 * norm(n.x_axis)) && !ctx.given(p + ".x_axis")) {
    n.x_axis = {0, 1, 0};
    in_plane = n.x_axis - dot(n.x_axis, n.normal) * n.normal;
  }
  if (!(norm(in_plane) > 1e-9 * norm(n.x_axis))) {
    ctx.error(ctx.where(p + ".x_axis", p), p + ".x_axis",
              fmt::format("must not be parallel to normal {}, got {}",
                          schema::format_vec3(n.normal), schema::format_vec3(n.x_axis)));
    return 0;
  }
  n.x_axis = normalized(in_plane);

  RingNetParameters g = net_parameters(n);
  if (n.width || n.length) {
    const LatticeSize size = lattice_size_for(n.width.value_or(0.0), n.length.value_or(0.0), g);
    if (n.width) n.columns = g.columns = size.columns;
    if (n.length) n.rows = g.rows = size.rows;
  }

  bool geometry_ok = true;
  const double centreline_diameter = 2.0 * g.centreline_radius();
  if (g.link_distance >= centreline_diameter) {
    ctx.error(ctx.where(p + ".link_distance", p), p + ".link_distance",
              fmt::format("must be < internal_diameter + 2 * particle_radius = {} m (rings "
                          "farther apart cannot interlink), got {}",
                          schema::format_number(centreline_diameter),
                          schema::format_number(g.link_distance)));
    geometry_ok = false;
  }
  if (g.shackles) {
    // Bond-free rigid shackles: neighbours must not press on each other, and the gap between
    // them must stay narrower than a net particle (contact radius) plus the shackle particles.
    const double rs = g.shackle_particle_radius;
    const auto spacing = [&](int count) {
      return 2.0 * g.shackle_centreline_radius() * std::sin(M_PI / count);
    };
    const double too_wide = 2.0 * (rs + n.contact_radius);
    const std::string key = sp + ".n_particles";
    const Location at = ctx.where(key, ctx.given(sp) ? sp : p);
    if (spacing(g.shackle_n_particles) < 2.0 * rs) {
      int most = 3;
      while (spacing(most + 1) >= 2.0 * rs)
        ++most;
      ctx.error(
          at, key,
          fmt::format("shackle particles would overlap: spacing {} m < 2 * particle_radius "
                      "= {} m{}",
                      schema::format_number(spacing(g.shackle_n_particles)),
                      schema::format_number(2.0 * rs),
                      spacing(3) >= 2.0 * rs ? fmt::format("; use at most {} particles", most)
                                             : std::string("; use a larger internal_diameter")));
      geometry_ok = false;
    } else if (spacing(g.shackle_n_particles) >= too_wide) {
      int fewest = g.shackle_n_particles;
      while (spacing(fewest) >= too_wide)
        ++fewest;
      ctx.error(at, key,
                fmt::format("net particles (contact_radius {} m) could slip between shackle "
                            "particles: spacing {} m >= 2 * (particle_radius + net "
                            "contact_radius) = {} m; use at least {} particles",
                            schema::format_number(n.contact_radius),
                            schema::format_number(spacing(g.shackle_n_particles)),
                            schema::format_number(too_wide), fewest));
      geometry_ok = false;
    }
  }
  if (!geometry_ok) return 0;

  // The layout repeats every two rows and columns, so for a large net a patch of the same
  // row and column parity (the same corners and edges) has every configuration of
  // neighbouring rings and shackles: checking it instead keeps `check` fast for any size.
  RingNetParameters checked = g;
  const auto patch = [](int count) { return count <= 5 ? count : (count % 2 == 0 ? 4 : 5); };
  if (static_cast<long long>(g.rows) * g.columns > 400) {
    checked.rows = patch(g.rows);
    checked.columns = patch(g.columns);
  }
  const RingNetLayout net = generate_ring_net(checked);
  const RingNetClearance clearance =
      smallest_clearance(net, n.contact_radius, g.shackle_particle_radius, 0.0);
  if (clearance.gap < 0.0) {
    ctx.error(ctx.where(p), p,
              fmt::format("rings touch at creation: particles of {} and {} overlap by {} m "
                          "(contact radii); change tilt or link_distance",
                          describe_net_ring(net, clearance.ring_a),
                          describe_net_ring(net, clearance.ring_b),
                          schema::format_number(-clearance.gap)));
  } else {
    // Clear of each other, linked pairs are linked exactly when their linking number is +-1
    // (domain/LinkingNumber.hpp); unlinked rings would fall apart.
    const auto linked = [](const RingGeometry& a, const RingGeometry& b) {
      return std::lround(std::abs(gauss_linking_number(a.positions(), b.positions()))) == 1;
    };
    for (const auto& [a, b] : net.links) {
      if (linked(net.ring_geometry(a), net.ring_geometry(b))) continue;
      ctx.error(ctx.where(p + ".link_distance", p), p + ".link_distance",
                fmt::format("neighbouring {} and {} are not linked; decrease link_distance or "
                            "change tilt",
                            describe_net_ring(net, a), describe_net_ring(net, b)));
      break;
    }
    for (std::size_t k = 0; k < net.shackles.size(); ++k) {
      if (linked(net.shackle_geometry(k), net.ring_geometry(net.shackles[k].net_ring))) continue;
      ctx.error(ctx.where(sp, p), sp,
                fmt::format("{} does not hold its ring; enlarge internal_diameter",
                            describe_net_ring(net, net.rings.size() + k)));
      break;
    }
  }
  RingNetConfig resolved = n;
  resolved.rows = g.rows;
  resolved.columns = g.columns;
  CaseConfig just_the_net;
  just_the_net.nets.push_back(resolved);
  return static_cast<long long>(estimate_size(just_the_net).particles);
}

void validate_scenario(CaseConfig& c, Context& ctx, bool bodies_ok) {
  // The rockfall and tensile tests report the ledger's shares and check their balance.
  if (!c.simulation.energy_ledger && c.scenario.type != "free_run" && !ctx.failed("scenario.type"))
    ctx.error(ctx.where("simulation.energy_ledger", "simulation"), "simulation.energy_ledger",
              fmt::format("false applies to scenario type free_run only; a {} reports the "
                          "energy ledger",
                          c.scenario.type));
  // Multi-rate stepping runs free runs only (a rockfall's boulder is a free body, a tensile
  // test's calibration asks for one rate).
  if (c.simulation.substeps > 1 && c.scenario.type != "free_run" && !ctx.failed("scenario.type"))
    ctx.error(
        ctx.where("simulation.substeps", "simulation"), "simulation.substeps",
        fmt::format("more than 1 applies to scenario type free_run only, not {}", c.scenario.type));
  if (c.scenario.type != "tensile_test" || ctx.failed("scenario.type")) return;
  const std::string p = "scenario.tensile_test";
  if (!ctx.given(p)) {
    ctx.error(ctx.where("scenario.type", "scenario"), p,
              "missing section 'tensile_test', required when scenario.type is tensile_test");
    return;
  }
  TensileTestConfig& t = c.scenario.tensile_test;
  if (!ctx.failed(p + ".pull_direction")) t.pull_direction = normalized(t.pull_direction);
  // The plate must turn before the test would stop at max_displacement.
  if (t.unload_at && !ctx.failed(p + ".unload_at") && !ctx.failed(p + ".max_displacement") &&
      *t.unload_at >= t.max_displacement)
    ctx.error(ctx.where(p + ".unload_at"), p + ".unload_at",
              fmt::format("unload_at ({:g} m) must be below {}.max_displacement ({:g} m): the "
                          "test stops there before the plate would turn",
                          *t.unload_at, p, t.max_displacement));
  if (ctx.failed(p + ".moving_bodies")) return;
  std::vector<std::string> names;
  for (const auto& b : c.rigid_bodies)
    names.push_back(b.name);
  for (std::size_t k = 0; k < t.moving_bodies.size(); ++k) {
    const std::string key = schema::index_path(p + ".moving_bodies", k);
    const std::string& name = t.moving_bodies[k];
    const auto it = std::find(names.begin(), names.end(), name);
    if (it == names.end()) {
      check_reference(name, names, bodies_ok, key, p + ".moving_bodies", "rigid body",
                      "rigid_bodies", ctx);
      continue;
    }
    const std::size_t index = static_cast<std::size_t>(it - names.begin());
    RigidBodyConfig& body = c.rigid_bodies[index];
    const std::string bp = schema::index_path("rigid_bodies", index);
    if (body.motion != Motion::kPrescribed && !ctx.failed(bp + ".motion")) {
      ctx.error(ctx.where(bp + ".motion", bp), bp + ".motion",
                fmt::format("rigid body '{}' is on the moving plate ({}) and must have motion: "
                            "prescribed",
                            name, key));
    }
    // The velocity comes from loading_rate and pull_direction (build_model sets it); a zero
    // vector is accepted so that dumps of the resolved case load again.
    if (ctx.given(bp + ".velocity") && !ctx.failed(bp + ".velocity") &&
        norm2(body.velocity) != 0.0) {
      ctx.error(ctx.where(bp + ".velocity"), bp + ".velocity",
                fmt::format("rigid body '{}' is on the moving plate: its velocity is set by "
                            "{}.loading_rate and pull_direction (remove it)",
                            name, p));
    }
  }
}

/// The rockfall driver's references (groups, boulder material) and its gravity, checked here
/// so that a wrong name is an input error with its line, not a failure after the build.
void validate_rockfall(const CaseConfig& c, Context& ctx, const std::set<std::string>& groups,
                       const std::vector<std::string>& materials, bool materials_ok) {
  if (c.scenario.type != "rockfall" || ctx.failed("scenario.type")) return;
  const std::string p = "scenario.rockfall";
  const std::string fallback = ctx.given(p) ? p : "scenario.type";
  const RockfallConfig& rf = c.scenario.rockfall;
  check_group(rf.net_group, groups, p + ".net_group", fallback, ctx);
  check_group(rf.frame_group, groups, p + ".frame_group", fallback, ctx);
  check_reference(rf.boulder_material, materials, materials_ok, p + ".boulder_material", fallback,
                  "material", "materials", ctx);
  const Vec3 g = c.simulation.gravity;
  if (!ctx.failed("simulation.gravity") && !(g.z < 0.0 && g.x == 0.0 && g.y == 0.0)) {
    ctx.error(
        ctx.where("simulation.gravity", "simulation"), "simulation.gravity",
        fmt::format("a rockfall test needs gravity along -z, got {}{}", schema::format_vec3(g),
                    ctx.given("simulation.gravity") ? "" : " (the default, key not given)"));
  }
}

}  // namespace

void cross_validate_case(CaseConfig& c, Context& ctx) {
  // The name is the output folder results/<name>: it must stay inside results/.
  if (ctx.given("name") && !ctx.failed("name")) {
    const std::string problem = schema::folder_name_problem(c.name);
    if (!problem.empty())
      ctx.error(ctx.where("name"), "name",
                fmt::format("'{}' {}: the name is the output folder results/<name>, so it may "
                            "not contain '/' or '\\' nor be '.' or '..'",
                            c.name, problem));
  }
  // Names and references.
  bool materials_ok = true, bonds_ok = true, bodies_ok = true;
  const auto materials =
      unique_names(c.materials, &MaterialConfig::name, "materials", "material", ctx, &materials_ok);
  const auto bonds = unique_names(c.bonds, &BondConfig::name, "bonds", "bond", ctx, &bonds_ok);
  unique_names(c.rigid_bodies, &RigidBodyConfig::name, "rigid_bodies", "rigid body", ctx,
               &bodies_ok);
  if (c.materials.empty() && ctx.given("materials") && !ctx.failed("materials"))
    ctx.error(ctx.where("materials"), "materials", "must define at least one material, got none");

  // One bond model per case: every bond of the model lives in one store, evaluated by one
  // term (engine/ModelTable.hpp).
  for (std::size_t i = 1; i < c.bonds.size(); ++i) {
    const std::string key = schema::index_path("bonds", i) + ".model";
    if (c.bonds[i].model != c.bonds[0].model && !ctx.failed(key))
      ctx.error(ctx.where(key, schema::index_path("bonds", i)), key,
                fmt::format("'{}' differs from bonds[0].model '{}': one bond model per case",
                            c.bonds[i].model, c.bonds[0].model));
  }

  std::map<std::pair<std::string, std::string>, std::size_t> pairs;
  for (std::size_t i = 0; i < c.interactions.size(); ++i) {
    const InteractionConfig& in = c.interactions[i];
    const std::string p = schema::index_path("interactions", i);
    if (ctx.failed(p + ".materials") || !ctx.given(p + ".materials")) continue;
    for (int k = 0; k < 2; ++k) {
      const std::string& m = k == 0 ? in.material_a : in.material_b;
      check_reference(m, materials, materials_ok, fmt::format("{}.materials[{}]", p, k),
                      p + ".materials", "material", "materials", ctx);
    }
    const auto key = std::minmax(in.material_a, in.material_b);
    const auto [it, inserted] = pairs.emplace(std::make_pair(key.first, key.second), i);
    if (!inserted)
      ctx.error(ctx.where(p + ".materials", p), p + ".materials",
                fmt::format("pair [{}, {}] is already defined by {}", in.material_a, in.material_b,
                            schema::index_path("interactions", it->second)));
  }

  std::set<std::string> groups;
  long long total_particles = 0;
  for (std::size_t i = 0; i < c.rings.size(); ++i) {
    RingConfig& r = c.rings[i];
    const std::string p = schema::index_path("particles.rings", i);
    groups.insert(r.group);
    total_particles += r.n_particles;
    check_reference(r.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
    check_reference(r.bond, bonds, bonds_ok, p + ".bond", p, "bond", "bonds", ctx);
    if (!ctx.given(p + ".contact_radius")) {
      r.contact_radius = std::max(0.008, r.particle_radius);
    } else if (!ctx.failed(p + ".contact_radius") && !ctx.failed(p + ".particle_radius") &&
               r.contact_radius < r.particle_radius) {
      ctx.error(ctx.where(p + ".contact_radius"), p + ".contact_radius",
                fmt::format("must be >= particle_radius ({} m), got {}",
                            schema::format_number(r.particle_radius),
                            schema::format_number(r.contact_radius)));
    }
    if (!ctx.failed(p + ".normal") && !ctx.failed(p + ".reference")) {
      r.normal = normalized(r.normal);
      const Vec3 in_plane = r.reference - dot(r.reference, r.normal) * r.normal;
      if (norm(in_plane) > 1e-9 * norm(r.reference)) {
        r.reference = normalized(in_plane);
      } else if (!ctx.given(p + ".reference")) {
        r.reference = any_perpendicular(r.normal);
      } else {
        ctx.error(ctx.where(p + ".reference", p), p + ".reference",
                  fmt::format("must not be parallel to normal {}, got {}",
                              schema::format_vec3(r.normal), schema::format_vec3(r.reference)));
      }
    }
  }
  for (std::size_t i = 0; i < c.nets.size(); ++i) {
    RingNetConfig& n = c.nets[i];
    groups.insert(n.group);
    if (n.shackles.enabled) groups.insert(n.shackles.group);
    total_particles += validate_net(n, schema::index_path("particles.nets", i), materials,
                                    materials_ok, bonds, bonds_ok, ctx);
  }
  derive_bond_moduli(c, ctx);
  check_plastic_limits(c, ctx);
  for (std::size_t i = 0; i < c.lattices.size(); ++i) {
    LatticeConfig& l = c.lattices[i];
    const std::string p = schema::index_path("particles.lattices", i);
    groups.insert(l.group);
    total_particles += static_cast<long long>(l.count[0]) * l.count[1] * l.count[2];
    check_reference(l.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
    if (!ctx.failed(p + ".spacing") && !ctx.failed(p + ".particle_radius") &&
        l.spacing < 2.0 * l.particle_radius) {
      ctx.error(ctx.where(p + ".spacing", p), p + ".spacing",
                fmt::format("must be >= 2 * particle_radius = {} m (spheres would overlap), got {}",
                            schema::format_number(2.0 * l.particle_radius),
                            schema::format_number(l.spacing)));
    }
  }
  for (std::size_t i = 0; i < c.grains.size(); ++i) {
    const GrainsConfig& g = c.grains[i];
    const std::string p = schema::index_path("particles.grains", i);
    groups.insert(g.group);
    total_particles += std::llround(validate_grains(g, p, ctx));
    check_reference(g.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
  }
  for (std::size_t i = 0; i < c.spheres.size(); ++i) {
    const SphereConfig& s = c.spheres[i];
    const std::string p = schema::index_path("particles.spheres", i);
    groups.insert(s.group);
    total_particles += 1;
    check_reference(s.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
  }
  for (std::size_t i = 0; i < c.sphere_files.size(); ++i) {
    SphereFileConfig& f = c.sphere_files[i];
    const std::string p = schema::index_path("particles.sphere_files", i);
    groups.insert(f.group);
    check_reference(f.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
    if (ctx.failed(p + ".path")) continue;
    try {  // reads the file through once: every row's fault is reported before a run starts
      f.count = SphereFile(SphereFile::resolve(f.path, c.source_path)).count();
      total_particles += f.count;
    } catch (const std::runtime_error& e) {
      ctx.error(ctx.where(p + ".path", p), p + ".path", e.what());
    }
  }
  if (total_particles == 0 && ctx.given("particles") && !ctx.failed("particles")) {
    ctx.error(ctx.where("particles"), "particles",
              "no particles: add at least one entry to rings, nets, lattices, grains, spheres "
              "or sphere_files");
  }

  for (const InflowConfig& in : c.inflow)
    groups.insert(in.group);
  for (const DampingGroupConfig& g : c.damping.groups)
    check_group(g.group, groups, "damping.groups." + g.group, "damping.groups", ctx);

  bool inflow_ok = true;
  unique_names(c.inflow, &InflowConfig::name, "inflow", "inlet", ctx, &inflow_ok);
  for (std::size_t i = 0; i < c.inflow.size(); ++i) {
    const InflowConfig& in = c.inflow[i];
    const std::string p = schema::index_path("inflow", i);
    validate_inflow(in, p, run_duration(c).first, ctx);
    check_reference(in.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
  }
  bool outflow_ok = true;
  unique_names(c.outflow, &OutflowConfig::name, "outflow", "outflow box", ctx, &outflow_ok);
  for (std::size_t i = 0; i < c.outflow.size(); ++i) {
    const OutflowConfig& o = c.outflow[i];
    const std::string p = schema::index_path("outflow", i);
    for (std::size_t k = 0; k < o.groups.size(); ++k)
      check_group(o.groups[k], groups, fmt::format("{}.groups[{}]", p, k), p + ".groups", ctx);
    validate_outflow(c, i, ctx);
  }

  for (std::size_t i = 0; i < c.rigid_bodies.size(); ++i) {
    RigidBodyConfig& b = c.rigid_bodies[i];
    const std::string p = schema::index_path("rigid_bodies", i);
    check_reference(b.material, materials, materials_ok, p + ".material", p, "material",
                    "materials", ctx);
    if (!ctx.given(p + ".shape") || ctx.failed(p + ".shape")) continue;
    std::vector<std::string> needs, unused;
    std::string shape_name;
    switch (b.shape) {
      case ShapeKind::kPlane:
        shape_name = "plane";
        unused = {"axis", "radius", "length", "mass"};
        break;
      case ShapeKind::kCylinder:
        shape_name = "cylinder";
        needs = {"radius", "length"};
        unused = {"normal"};
        break;
      case ShapeKind::kSphere:
        shape_name = "sphere";
        needs = {"radius"};
        unused = {"normal", "axis", "length"};
        break;
    }
    for (const std::string& k : needs) {
      if (!ctx.given(p + "." + k))
        ctx.error(ctx.where(p), p + "." + k,
                  fmt::format("missing key '{}', required for shape '{}'", k, shape_name));
    }
    for (const std::string& k : unused) {
      if (ctx.given(p + "." + k))
        ctx.error(ctx.where(p + "." + k), p + "." + k,
                  fmt::format("does not apply to shape '{}' (remove it)", shape_name));
    }
    if (b.shape == ShapeKind::kPlane && b.motion == Motion::kFree && !ctx.failed(p + ".motion")) {
      ctx.error(ctx.where(p + ".motion", p), p + ".motion",
                "'free' is not allowed for a plane (allowed: fixed, prescribed)");
    }
    b.normal = normalized(b.normal);
    b.axis = normalized(b.axis);
  }
  validate_scenario(c, ctx, bodies_ok);
  validate_rockfall(c, ctx, groups, materials, materials_ok);
  validate_barrier(c, ctx, groups, bodies_ok);
  // Last: it computes from the values the checks above resolved (bond moduli, net sizes).
  check_case_magnitudes(c, ctx);
}

}  // namespace ringdem

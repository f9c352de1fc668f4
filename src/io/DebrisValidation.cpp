#include "io/DebrisValidation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <set>
#include <vector>

#include "core/Vec3.hpp"
#include "io/GrainsInput.hpp"
#include "io/ReferenceChecks.hpp"

namespace ringdem {

void validate_inflow(const InflowConfig& in, const std::string& p, double run_duration,
                     schema::Context& ctx) {
  // Before the batch's own checks: at zero velocity the batch has no interval, hence no solid
  // fraction and no grains, which validate_grains() takes for a box it has reported.
  if (!ctx.failed(p + ".velocity") && norm2(in.velocity) == 0.0) {
    ctx.error(ctx.where(p + ".velocity", p), p + ".velocity",
              "must not be zero: the grains enter at this velocity");
    return;
  }
  if (validate_grains(inflow_fill(in), p, ctx) == 0.0) return;
  if (ctx.failed(p + ".velocity") || ctx.failed(p + ".discharge")) return;
  const InflowBatch b = inflow_batch(in);
  if (b.solid_fraction > 0.35)
    ctx.error(ctx.where(p + ".discharge", p), p + ".discharge",
              fmt::format("needs a solid fraction of {:.3g} in the inlet box, above the 0.35 that "
                          "random sequential addition reaches: raise the velocity or widen the "
                          "box across the flow",
                          b.solid_fraction));
  if (in.end_time && !(*in.end_time > in.start_time))
    ctx.error(ctx.where(p + ".end_time", p), p + ".end_time",
              fmt::format("must be after start_time = {}", schema::format_number(in.start_time)));
  if (in.start_time >= run_duration && !ctx.failed(p + ".start_time"))
    ctx.warn(ctx.where(p + ".start_time", p), p + ".start_time",
             fmt::format("the inlet '{}' opens at {} s, when the run has ended (at {} s at the "
                         "latest): it adds no grains",
                         in.name, schema::format_number(in.start_time),
                         schema::format_number(run_duration)));
}

namespace {

void check_outflow_groups(const CaseConfig& c, std::size_t i, schema::Context& ctx) {
  const auto groups_of = [](std::set<std::string>& to, const auto& entries) {
    for (const auto& e : entries)
      to.insert(e.group);
  };
  std::set<std::string> loose, in_rings;
  groups_of(loose, c.grains);
  groups_of(loose, c.lattices);
  groups_of(loose, c.spheres);
  groups_of(loose, c.sphere_files);
  groups_of(loose, c.inflow);
  groups_of(in_rings, c.rings);
  groups_of(in_rings, c.nets);
  for (const RingNetConfig& n : c.nets)
    if (n.shackles.enabled) in_rings.insert(n.shackles.group);
  const std::string p = schema::index_path("outflow", i);
  const std::vector<std::string>& groups = c.outflow[i].groups;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    const std::string key = fmt::format("{}.groups[{}]", p, k);
    if (!ctx.failed(key) && loose.count(groups[k]) == 0 && in_rings.count(groups[k]) != 0)
      ctx.error(ctx.where(key, p + ".groups"), key,
                fmt::format("particle group '{}' holds only ring particles, which an outflow box "
                            "never takes",
                            groups[k]));
  }
}

/// A box of grain centres to be: a release volume or an inlet.
struct GrainSourceBox {
  std::string path;  ///< particles.grains[i] or inflow[i]
  std::string what;  ///< for messages: "the inlet 'x'", "the release box"
  std::string group;
  Vec3 box_min, box_max;
};

void check_sources_within_outflow(const CaseConfig& c, std::size_t i, schema::Context& ctx) {
  const OutflowConfig& o = c.outflow[i];
  std::vector<GrainSourceBox> sources;
  for (std::size_t k = 0; k < c.grains.size(); ++k)
    sources.push_back({schema::index_path("particles.grains", k), "the release box",
                       c.grains[k].group, c.grains[k].box_min, c.grains[k].box_max});
  for (std::size_t k = 0; k < c.inflow.size(); ++k)
    sources.push_back({schema::index_path("inflow", k),
                       fmt::format("the inlet '{}'", c.inflow[k].name), c.inflow[k].group,
                       c.inflow[k].box_min, c.inflow[k].box_max});
  const auto box = [](const Vec3& lo, const Vec3& hi) {
    return schema::format_vec3(lo) + " to " + schema::format_vec3(hi);
  };
  for (const GrainSourceBox& s : sources) {
    const bool takes =
        o.groups.empty() || std::find(o.groups.begin(), o.groups.end(), s.group) != o.groups.end();
    if (!takes || ctx.failed(s.path + ".box_min") || ctx.failed(s.path + ".box_max")) continue;
    bool overlaps = true, inside = true;
    for (int a = 0; a < 3; ++a) {
      overlaps = overlaps && s.box_min[a] < o.box_max[a] && s.box_max[a] > o.box_min[a];
      inside = inside && s.box_min[a] >= o.box_min[a] && s.box_max[a] <= o.box_max[a];
    }
    const std::string where =
        fmt::format("{} ({}) {} the outflow box '{}' ({}), which takes its group '{}'", s.what,
                    box(s.box_min, s.box_max), overlaps ? "reaches out of" : "lies wholly outside",
                    o.name, box(o.box_min, o.box_max), s.group);
    if (!overlaps)
      ctx.error(ctx.where(s.path + ".box_min", s.path), s.path + ".box_min",
                where + ": every grain it makes would be taken out at its first step");
    else if (!inside)
      ctx.warn(ctx.where(s.path + ".box_min", s.path), s.path + ".box_min",
               where + ": grains it makes out there are taken out at their first step");
  }
}

}  // namespace

void validate_outflow(const CaseConfig& c, std::size_t i, schema::Context& ctx) {
  const OutflowConfig& o = c.outflow[i];
  const std::string p = schema::index_path("outflow", i);
  check_outflow_groups(c, i, ctx);
  const Vec3 e = o.box_max - o.box_min;
  if (ctx.failed(p + ".box_min") || ctx.failed(p + ".box_max")) return;
  if (!(e.x > 0.0 && e.y > 0.0 && e.z > 0.0)) {
    ctx.error(ctx.where(p + ".box_max", p), p + ".box_max",
              fmt::format("must be above box_min on every axis (box {} to {})",
                          schema::format_vec3(o.box_min), schema::format_vec3(o.box_max)));
    return;
  }
  check_sources_within_outflow(c, i, ctx);
}

void validate_barrier(CaseConfig& c, schema::Context& ctx, const std::set<std::string>& groups,
                      bool bodies_ok) {
  if (!c.scenario.barrier) return;
  const std::string p = "scenario.barrier";
  BarrierConfig& b = *c.scenario.barrier;
  if (c.scenario.type != "free_run" && !ctx.failed("scenario.type"))
    ctx.error(ctx.where(p), p,
              fmt::format("applies to scenario type free_run only, not {}", c.scenario.type));
  if (!ctx.failed(p + ".direction")) b.direction = normalized(b.direction);
  for (std::size_t k = 0; k < b.grain_groups.size(); ++k)
    check_group(b.grain_groups[k], groups, fmt::format("{}.grain_groups[{}]", p, k),
                p + ".grain_groups", ctx);
  for (const auto& [key, group] :
       {std::pair{".net_group", &b.net_group}, std::pair{".frame_group", &b.frame_group}})
    if (!group->empty()) check_group(*group, groups, p + key, p, ctx);
  std::vector<std::string> names;
  for (const auto& body : c.rigid_bodies)
    names.push_back(body.name);
  for (std::size_t k = 0; k < b.posts.size(); ++k)
    check_reference(b.posts[k], names, bodies_ok, fmt::format("{}.posts[{}]", p, k), p + ".posts",
                    "rigid body", "rigid_bodies", ctx);
  check_reference(b.bed, names, bodies_ok, p + ".bed", p, "rigid body", "rigid_bodies", ctx);
  // The barrier's load sums its posts' contact loads along the flow: the bed among them would
  // add the flow's friction on the bed. (A name given twice is the schema's error.)
  for (std::size_t k = 0; k < b.posts.size(); ++k) {
    const std::string key = fmt::format("{}.posts[{}]", p, k);
    if (b.posts[k] == b.bed && !ctx.failed(key))
      ctx.error(ctx.where(key, p + ".posts"), key,
                fmt::format("rigid body '{}' is the bed: the flow's friction on it would count as "
                            "load on the barrier",
                            b.posts[k]));
  }
  // The net's deflection and load are its own particles', never the flow's.
  for (const auto& [key, group] :
       {std::pair{".net_group", &b.net_group}, std::pair{".frame_group", &b.frame_group}})
    if (!group->empty() && !ctx.failed(p + key) &&
        std::find(b.grain_groups.begin(), b.grain_groups.end(), *group) != b.grain_groups.end())
      ctx.error(ctx.where(p + key, p), p + key,
                fmt::format("particle group '{}' is one of grain_groups too: a group is the "
                            "flow's or the barrier's, not both",
                            *group));
  const auto bed = std::find(names.begin(), names.end(), b.bed);
  if (bed != names.end() &&
      c.rigid_bodies[static_cast<std::size_t>(bed - names.begin())].shape != ShapeKind::kPlane)
    ctx.error(ctx.where(p + ".bed", p), p + ".bed",
              fmt::format("rigid body '{}' must be a plane (the bed the flow runs on)", b.bed));
}

}  // namespace ringdem

#include "io/GrainsInput.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <vector>

namespace ringdem {

GrainSizeDistribution grain_size_distribution(const GrainSizesConfig& s) {
  switch (s.distribution) {
    case GrainDistribution::kUniform:
      return GrainSizeDistribution::uniform(s.min_radius, s.max_radius);
    case GrainDistribution::kLogNormal:
      return GrainSizeDistribution::log_normal(s.median_radius, s.sigma, s.min_radius,
                                               s.max_radius);
    case GrainDistribution::kFractions: {
      std::vector<GrainSizeDistribution::SizeClass> classes;
      for (const GrainFractionConfig& f : s.fractions)
        classes.push_back({f.radius, f.fraction});
      return GrainSizeDistribution::fractions(std::move(classes));
    }
  }
  return GrainSizeDistribution::uniform(s.min_radius, s.max_radius);
}

double expected_grain_count(const GrainsConfig& g) {
  const Vec3 e = g.box_max - g.box_min;
  if (!(e.x > 0.0 && e.y > 0.0 && e.z > 0.0)) return 0.0;
  try {
    return g.solid_fraction * e.x * e.y * e.z / grain_size_distribution(g.sizes).mean_volume();
  } catch (const std::invalid_argument&) {
    return 0.0;  // reported by validate_grains
  }
}

double smallest_grain_radius(const GrainSizesConfig& s) {
  if (s.distribution != GrainDistribution::kFractions) return s.min_radius;
  double r = 0.0;
  for (const GrainFractionConfig& f : s.fractions)
    r = r == 0.0 ? f.radius : std::min(r, f.radius);
  return r;
}

double largest_grain_radius(const GrainSizesConfig& s) {
  if (s.distribution != GrainDistribution::kFractions) return s.max_radius;
  double r = 0.0;
  for (const GrainFractionConfig& f : s.fractions)
    r = std::max(r, f.radius);
  return r;
}

double validate_grains(const GrainsConfig& g, const std::string& p, schema::Context& ctx) {
  const std::size_t errors_before = ctx.diagnostics().size();
  const GrainSizesConfig& s = g.sizes;
  const std::string sp = p + ".sizes";
  const auto error = [&](const std::string& key, const std::string& message) {
    ctx.error(ctx.where(key, ctx.given(sp) ? sp : p), key, message);
  };
  // A key the schema refused already has its error; check only what rests on sound keys.
  if (ctx.failed(sp)) return 0.0;

  // The keys each distribution reads; any other is a mistake the user should hear about.
  const char* name = s.distribution == GrainDistribution::kUniform     ? "uniform"
                     : s.distribution == GrainDistribution::kLogNormal ? "log_normal"
                                                                       : "fractions";
  const bool fractions = s.distribution == GrainDistribution::kFractions;
  const bool log_normal = s.distribution == GrainDistribution::kLogNormal;
  const struct {
    const char* key;
    bool used;
    bool needed;  ///< no default that makes sense
  } keys[] = {{"min_radius", !fractions, false},
              {"max_radius", !fractions, false},
              {"median_radius", log_normal, log_normal},
              {"sigma", log_normal, log_normal},
              {"fractions", fractions, fractions}};
  for (const auto& k : keys) {
    const std::string key = sp + "." + k.key;
    if (!k.used && ctx.given(key))
      error(key, fmt::format("does not apply to distribution '{}' (remove it)", name));
    if (k.needed && !ctx.given(key))
      error(key, fmt::format("missing key '{}' (distribution '{}' needs it)", k.key, name));
  }
  if (!fractions && (log_normal ? !(s.max_radius > s.min_radius) : s.max_radius < s.min_radius))
    error(sp + ".max_radius",
          fmt::format("must be {} min_radius = {}, got {}", log_normal ? ">" : ">=",
                      schema::format_number(s.min_radius), schema::format_number(s.max_radius)));
  if (log_normal && s.median_radius > 0.0 && s.sigma > 0.0 && s.max_radius > s.min_radius) {
    const double kept = GrainSizeDistribution::kept_log_normal_fraction(s.median_radius, s.sigma,
                                                                        s.min_radius, s.max_radius);
    if (kept < 0.01)
      error(sp + ".median_radius",
            fmt::format("[min_radius, max_radius] keeps {:.3g} % of this log-normal distribution; "
                        "it must keep at least 1 % (move median_radius into the range or widen it)",
                        100.0 * kept));
  }
  if (fractions && ctx.given(sp + ".fractions") && !ctx.failed(sp + ".fractions")) {
    double total = 0.0;
    for (const GrainFractionConfig& f : s.fractions)
      total += f.fraction;
    if (s.fractions.empty())
      error(sp + ".fractions", "needs at least one size class");
    else if (std::abs(total - 1.0) > 1e-6)
      error(sp + ".fractions",
            fmt::format("the fractions must sum to 1, got {}", schema::format_number(total)));
  }

  if (ctx.failed(p + ".box_min") || ctx.failed(p + ".box_max")) return 0.0;
  const double e[3] = {g.box_max.x - g.box_min.x, g.box_max.y - g.box_min.y,
                       g.box_max.z - g.box_min.z};
  const double largest = largest_grain_radius(s);
  for (int a = 0; a < 3; ++a) {
    if (!(e[a] > 0.0)) {
      error(p + ".box_max",
            fmt::format("must be above box_min along {} (box {} to {})", "xyz"[a],
                        schema::format_vec3(g.box_min), schema::format_vec3(g.box_max)));
      break;
    }
    if (e[a] < 2.0 * largest) {
      error(
          p + ".box_max",
          fmt::format("the box is {} m wide along {}, less than the largest grain's diameter {} m",
                      schema::format_number(e[a]), "xyz"[a], schema::format_number(2.0 * largest)));
      break;
    }
  }
  if (ctx.diagnostics().size() != errors_before) return 0.0;
  return expected_grain_count(g);
}

InflowBatch inflow_batch(const InflowConfig& in) {
  const Vec3 e = in.box_max - in.box_min;
  const double extent[3] = {e.x, e.y, e.z};
  const double v[3] = {std::abs(in.velocity.x), std::abs(in.velocity.y), std::abs(in.velocity.z)};
  const int axis = static_cast<int>(std::max_element(v, v + 3) - v);
  InflowBatch b;
  if (!(v[axis] > 0.0)) return b;
  b.interval = extent[axis] / v[axis];
  const double volume = e.x * e.y * e.z;
  if (volume > 0.0) b.solid_fraction = in.discharge * b.interval / volume;
  return b;
}

GrainsConfig inflow_fill(const InflowConfig& in) {
  GrainsConfig g;
  g.group = in.group;
  g.material = in.material;
  g.box_min = in.box_min;
  g.box_max = in.box_max;
  g.solid_fraction = inflow_batch(in).solid_fraction;
  g.sizes = in.sizes;
  g.velocity = in.velocity;
  g.seed = in.seed;
  return g;
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

}  // namespace ringdem

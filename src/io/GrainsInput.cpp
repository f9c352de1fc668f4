#include "io/GrainsInput.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
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

}  // namespace ringdem

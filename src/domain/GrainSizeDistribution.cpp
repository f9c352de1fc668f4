#include "domain/GrainSizeDistribution.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ringdem {
namespace {

double sphere_volume(double r) {
  return 4.0 / 3.0 * M_PI * r * r * r;
}

/// A standard normal deviate by Box-Muller from two unit draws (the cosine branch only, so
/// that every deviate costs exactly two draws whatever came before).
double standard_normal(std::mt19937_64& rng) {
  const double u1 = 1.0 - unit_draw(rng);  // (0, 1]: log is finite
  const double u2 = unit_draw(rng);
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
}

}  // namespace

double GrainSizeDistribution::kept_log_normal_fraction(double median, double sigma,
                                                       double min_radius, double max_radius) {
  // Phi(z) = erfc(-z / sqrt 2) / 2 for the standard normal CDF.
  const auto cdf = [](double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); };
  const double lo = std::log(min_radius / median) / sigma;
  const double hi = std::log(max_radius / median) / sigma;
  return cdf(hi) - cdf(lo);
}

GrainSizeDistribution GrainSizeDistribution::uniform(double min_radius, double max_radius) {
  if (!(min_radius > 0.0) || !(max_radius >= min_radius))
    throw std::invalid_argument("uniform grain sizes need 0 < min <= max");
  GrainSizeDistribution d;
  d.kind_ = Kind::kUniform;
  d.min_ = min_radius;
  d.max_ = max_radius;
  // E[r^3] for r uniform in [a, b]: (b^4 - a^4) / (4 (b - a)), or a^3 when a = b.
  const double a = min_radius, b = max_radius;
  const double mean_r3 = b > a ? (b * b * b * b - a * a * a * a) / (4.0 * (b - a)) : a * a * a;
  d.mean_volume_ = 4.0 / 3.0 * M_PI * mean_r3;
  return d;
}

GrainSizeDistribution GrainSizeDistribution::log_normal(double median, double sigma,
                                                        double min_radius, double max_radius) {
  if (!(min_radius > 0.0) || !(max_radius > min_radius) || !(sigma > 0.0) || !(median > 0.0))
    throw std::invalid_argument("log-normal grain sizes need 0 < min < max, median > 0, sigma > 0");
  GrainSizeDistribution d;
  d.kind_ = Kind::kLogNormal;
  d.min_ = min_radius;
  d.max_ = max_radius;
  d.log_median_ = std::log(median);
  d.sigma_ = sigma;
  // E[v] of the truncated distribution, by the midpoint rule in ln r (the integrand is smooth;
  // 4096 intervals give far more digits than an estimate of the grain count needs).
  const int n = 4096;
  const double lo = std::log(min_radius), hi = std::log(max_radius);
  double weight = 0.0, volume = 0.0;
  for (int i = 0; i < n; ++i) {
    const double x = lo + (hi - lo) * (i + 0.5) / n;
    const double z = (x - d.log_median_) / sigma;
    const double w = std::exp(-0.5 * z * z);
    weight += w;
    volume += w * sphere_volume(std::exp(x));
  }
  d.mean_volume_ = hi > lo ? volume / weight : sphere_volume(min_radius);
  const double kept = kept_log_normal_fraction(median, sigma, min_radius, max_radius);
  if (!(kept >= 0.01))
    throw std::invalid_argument(
        "log-normal grain sizes: [min, max] keeps less than 1 % of the distribution");
  return d;
}

GrainSizeDistribution GrainSizeDistribution::fractions(std::vector<SizeClass> classes) {
  if (classes.empty()) throw std::invalid_argument("grain size fractions need at least one class");
  std::sort(classes.begin(), classes.end(),
            [](const SizeClass& a, const SizeClass& b) { return a.radius < b.radius; });
  double total = 0.0;
  for (const SizeClass& c : classes) {
    if (!(c.radius > 0.0) || !(c.volume_fraction > 0.0))
      throw std::invalid_argument("grain size classes need radius > 0 and fraction > 0");
    total += c.volume_fraction;
  }
  GrainSizeDistribution d;
  d.kind_ = Kind::kFractions;
  d.min_ = classes.front().radius;
  d.max_ = classes.back().radius;
  // Number of grains of class i per unit solid volume: f_i / v_i (f normalised).
  double number = 0.0;
  for (const SizeClass& c : classes) {
    number += c.volume_fraction / total / sphere_volume(c.radius);
    d.radii_.push_back(c.radius);
    d.number_cdf_.push_back(number);
  }
  for (double& p : d.number_cdf_)
    p /= number;
  d.number_cdf_.back() = 1.0;
  d.mean_volume_ = 1.0 / number;
  return d;
}

double GrainSizeDistribution::draw(std::mt19937_64& rng) const {
  switch (kind_) {
    case Kind::kUniform:
      return min_ + (max_ - min_) * unit_draw(rng);
    case Kind::kLogNormal:
      // Rejection of the tails: log_normal() refuses a truncation that keeps less than 1 % of
      // the distribution, so this loop takes at most about a hundred draws on average.
      for (;;) {
        const double r = std::exp(log_median_ + sigma_ * standard_normal(rng));
        if (r >= min_ && r <= max_) return r;
      }
    case Kind::kFractions: {
      const double u = unit_draw(rng);
      const auto it = std::upper_bound(number_cdf_.begin(), number_cdf_.end(), u);
      const auto i = static_cast<std::size_t>(std::min<std::ptrdiff_t>(
          it - number_cdf_.begin(), static_cast<std::ptrdiff_t>(radii_.size()) - 1));
      return radii_[i];
    }
  }
  return min_;
}

}  // namespace ringdem

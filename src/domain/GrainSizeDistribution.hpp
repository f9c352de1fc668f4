#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace ringdem {

/// The radii of a polydisperse grain mix, as a distribution to draw from (docs/physics.md
/// "Debris grains"). Three forms, as grading curves are given in practice:
///  - uniform: radius uniform in [min, max] by number;
///  - log_normal: ln r normal with mean ln(median) and standard deviation sigma, by number,
///    truncated to [min, max] (rejection);
///  - fractions: discrete radii, each with its fraction of the solid volume (a sieve
///    analysis's mass fractions at one density); by number, class i has probability
///    proportional to f_i / r_i^3.
/// draw() uses only the generator it is given, so a stream seeded per packing cell gives the
/// same radii on any rank.
class GrainSizeDistribution {
 public:
  enum class Kind { kUniform, kLogNormal, kFractions };
  struct SizeClass {
    double radius = 0.0;
    double volume_fraction = 0.0;
  };

  static GrainSizeDistribution uniform(double min_radius, double max_radius);
  static GrainSizeDistribution log_normal(double median, double sigma, double min_radius,
                                          double max_radius);
  /// The share of the untruncated log-normal that [min, max] keeps (the loader asks >= 1 %).
  static double kept_log_normal_fraction(double median, double sigma, double min_radius,
                                         double max_radius);
  /// Fractions that do not sum to 1 are normalised (the loader refuses sums off by > 1e-6).
  static GrainSizeDistribution fractions(std::vector<SizeClass> classes);

  Kind kind() const { return kind_; }
  double min_radius() const { return min_; }
  double max_radius() const { return max_; }
  /// Mean grain volume by number, E[4/3 pi r^3]: grains per unit solid volume is its inverse.
  double mean_volume() const { return mean_volume_; }

  double draw(std::mt19937_64& rng) const;

 private:
  Kind kind_ = Kind::kUniform;
  double min_ = 0.0, max_ = 0.0;
  double log_median_ = 0.0, sigma_ = 0.0;
  std::vector<double> radii_;       ///< fractions: the classes, ascending
  std::vector<double> number_cdf_;  ///< fractions: cumulative number probability
  double mean_volume_ = 0.0;
};

/// A uniform double in [0, 1) from one 64-bit draw (53 bits), the same on every platform.
inline double unit_draw(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace ringdem

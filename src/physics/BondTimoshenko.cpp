#include "physics/BondTimoshenko.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace ringdem {

BondTimoshenko::Section BondTimoshenko::Section::make(const Params& p, double radius_a,
                                                      double radius_b, double length0) {
  Section s;
  s.r_b = p.radius_multiplier * std::min(radius_a, radius_b);  // Eq. 11
  s.area = M_PI * s.r_b * s.r_b;
  s.inertia = M_PI * s.r_b * s.r_b * s.r_b * s.r_b / 4.0;
  s.length0 = length0;
  const double e = p.youngs_modulus;
  const double g = e / (2.0 * (1.0 + p.poisson_ratio));
  const double nu = p.poisson_ratio;
  const double form_factor = (7.0 + 6.0 * nu) / (6.0 * (1.0 + nu));  // Cowper, solid circle
  const double l = length0;
  const double phi = 12.0 * e * s.inertia * form_factor / (g * s.area * l * l);
  const double c = e * s.inertia / (1.0 + phi);
  s.k_axial = e * s.area / l;
  s.k_torsion = g * 2.0 * s.inertia / l;
  s.k_shear = 12.0 * c / (l * l * l);
  s.k_couple = 6.0 * c / (l * l);
  s.k_bend_self = (4.0 + phi) * c / l;
  s.k_bend_cross = (2.0 - phi) * c / l;
  s.inv_area = 1.0 / s.area;
  s.bend_factor = s.r_b / s.inertia;
  return s;
}

BondTimoshenko::Failure BondTimoshenko::check_failure(const Stresses& st,
                                                      const Strength& strength) {
  if (st.tensile > strength.tensile) return Failure::kTensile;
  if (st.compressive > strength.compressive) return Failure::kCompressive;
  if (st.shear > strength.shear) return Failure::kShear;
  return Failure::kNone;
}

double BondTimoshenko::utilisation(const Stresses& st, const Strength& strength) {
  return std::max({st.tensile / strength.tensile, st.compressive / strength.compressive,
                   st.shear / strength.shear});
}

BondTimoshenko::Strength BondTimoshenko::draw_strength(const Params& p, std::uint64_t seed,
                                                       std::int64_t gid_a, std::int64_t gid_b) {
  Strength s{p.tensile_strength, p.compressive_strength, p.shear_strength};
  if (p.strength_cov <= 0.0) return s;
  // SplitMix64 of (seed, gid pair): a fixed stream per bond, independent of ranks.
  auto mix = [](std::uint64_t z) {
    z += 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  };
  const std::uint64_t key =
      mix(mix(mix(seed) ^ static_cast<std::uint64_t>(gid_a)) ^ static_cast<std::uint64_t>(gid_b));
  std::uint64_t state = key;
  auto uniform = [&]() {
    state = mix(state);
    return (static_cast<double>(state >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  };
  // Box–Muller, written out so the result does not depend on the standard library.
  auto normal = [&]() {
    const double u1 = uniform(), u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
  };
  // Strengths stay positive: a draw below 1 % of the mean is clamped there.
  auto vary = [&](double mean) { return mean * std::max(0.01, 1.0 + p.strength_cov * normal()); };
  s.tensile = vary(s.tensile);
  s.compressive = vary(s.compressive);
  s.shear = vary(s.shear);
  return s;
}

}  // namespace ringdem

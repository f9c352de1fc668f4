#include "physics/MaterialTable.hpp"

#include <algorithm>
#include <cstring>

namespace ringdem {

MaterialTable::MaterialTable(std::vector<Material> materials,
                             const std::vector<PairOverride>& overrides)
    : materials_(std::move(materials)) {
  const std::size_t n = materials_.size();
  pair_.resize(n * n);
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      const Material& ma = materials_[a];
      const Material& mb = materials_[b];
      // Pairs without an explicit interaction use the mean of the two materials' coefficients.
      double e = 0.5 * (ma.restitution + mb.restitution);
      double mu = 0.5 * (ma.friction + mb.friction);
      double mu_r = 0.5 * (ma.rolling_friction + mb.rolling_friction);
      for (const auto& o : overrides) {
        const bool match = (o.a == static_cast<int>(a) && o.b == static_cast<int>(b)) ||
                           (o.a == static_cast<int>(b) && o.b == static_cast<int>(a));
        if (!match) continue;
        if (o.restitution >= 0.0) e = o.restitution;
        if (o.friction >= 0.0) mu = o.friction;
        if (o.rolling_friction >= 0.0) mu_r = o.rolling_friction;
      }
      pair_[a * n + b] = HertzMindlin::Params::mix(
          ma.youngs_modulus, ma.poisson_ratio, mb.youngs_modulus, mb.poisson_ratio, e, mu, mu_r);
    }
  const auto same = [](const HertzMindlin::Params& x, const HertzMindlin::Params& y) {
    return std::memcmp(&x, &y, sizeof(HertzMindlin::Params)) == 0;
  };
  uniform_ = !pair_.empty() && std::all_of(pair_.begin(), pair_.end(),
                                           [&](const auto& q) { return same(q, pair_.front()); });
}

int MaterialTable::find(const std::string& name) const {
  for (std::size_t k = 0; k < materials_.size(); ++k)
    if (materials_[k].name == name) return static_cast<int>(k);
  return -1;
}

}  // namespace ringdem

#pragma once

#include <string>
#include <vector>

#include "physics/HertzMindlin.hpp"

namespace ringdem {

struct Material {
  std::string name;
  double density = 7800.0;
  double youngs_modulus = 200e9;
  double poisson_ratio = 0.3;
  double restitution = 0.5;
  double friction = 1.0;
  double rolling_friction = 0.0;

  double shear_modulus() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
};

/// Materials and the precomputed contact parameters of every material pair.
class MaterialTable {
 public:
  struct PairOverride {
    int a = 0, b = 0;
    double restitution = -1.0, friction = -1.0, rolling_friction = -1.0;  ///< < 0: not set
  };

  MaterialTable() = default;
  MaterialTable(std::vector<Material> materials, const std::vector<PairOverride>& overrides);

  std::size_t size() const { return materials_.size(); }
  const Material& operator[](std::size_t k) const { return materials_[k]; }
  const HertzMindlin::Params& pair(int a, int b) const {
    return pair_[static_cast<std::size_t>(a) * materials_.size() + static_cast<std::size_t>(b)];
  }
  /// The parameters that every material pair has, where they all have the same (one material,
  /// as a granular bed of one rock); nullptr otherwise. Compared bit for bit.
  const HertzMindlin::Params* uniform_pair() const { return uniform_ ? &pair_.front() : nullptr; }
  int find(const std::string& name) const;
  /// Whether some material pair has rolling friction.
  bool any_rolling_friction() const {
    for (const HertzMindlin::Params& p : pair_)
      if (p.rolling_friction > 0.0) return true;
    return false;
  }

 private:
  std::vector<Material> materials_;
  std::vector<HertzMindlin::Params> pair_;
  bool uniform_ = false;
};

}  // namespace ringdem

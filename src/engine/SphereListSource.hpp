#pragma once

#include <cstdint>
#include <vector>

#include "engine/ParticleSource.hpp"

namespace ringdem {

/// Spheres listed one by one: item i is the i-th.
class SphereListSource final : public ParticleSource {
 public:
  explicit SphereListSource(std::vector<ParticleStore::NewParticle> spheres)
      : spheres_(std::move(spheres)) {}

  std::string describe() const override { return "spheres"; }
  std::int64_t count() const override { return static_cast<std::int64_t>(spheres_.size()); }
  void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
            Model& model) const override;

 private:
  std::vector<ParticleStore::NewParticle> spheres_;  ///< gid unset
};

}  // namespace ringdem

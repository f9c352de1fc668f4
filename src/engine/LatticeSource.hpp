#pragma once

#include <array>
#include <cstdint>

#include "core/Motion.hpp"
#include "core/Vec3.hpp"
#include "engine/ParticleSource.hpp"

namespace ringdem {

/// Spheres on a cubic lattice, optionally jittered: item (i n_y + j) n_z + k sits at
/// origin + spacing (i, j, k) plus a uniform offset in [-jitter gap / 2, jitter gap / 2]^3
/// (gap = spacing - 2 r). The offsets are three consecutive draws of one seeded stream per
/// lattice, so a slice starting at item m skips 3 m draws: the positions do not depend on
/// the rank count.
class LatticeSource final : public ParticleSource {
 public:
  struct Spec {
    Vec3 origin;
    std::array<int, 3> count{1, 1, 1};
    double spacing = 0.01;
    double radius = 0.0045;
    double jitter = 0.0;
    std::uint64_t seed = 1;
    Vec3 velocity;
    double density = 0.0;
    double damping = 0.0;
    std::int32_t material = 0;
    std::int32_t group = 0;
  };
  explicit LatticeSource(const Spec& spec) : spec_(spec) {}

  std::string describe() const override { return "lattice"; }
  std::int64_t count() const override {
    return std::int64_t{spec_.count[0]} * spec_.count[1] * spec_.count[2];
  }
  void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
            Model& model) const override;

 private:
  Spec spec_;
};

}  // namespace ringdem

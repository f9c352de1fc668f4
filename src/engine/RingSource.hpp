#pragma once

#include <cstdint>
#include <vector>

#include "core/Motion.hpp"
#include "domain/RingGenerator.hpp"
#include "engine/ParticleSource.hpp"

namespace ringdem {

/// One ring of a RingSource: its geometry and the particles' attributes.
struct RingSpec {
  RingGeometry geometry;
  double density = 0.0;  ///< particle density (a ring mass spread over the particles)
  double damping = 0.0;
  std::int32_t material = 0;
  std::int32_t group = 0;
  Motion motion = Motion::kFree;
  Vec3 velocity;
  /// Bond type of the consecutive particles (k, k+1 mod n), or kNoBond.
  std::int32_t bond_type = kNoBond;
  std::uint64_t bond_seed = 0;
  static constexpr std::int32_t kNoBond = -1;
};

/// Rings of bonded particles (physics.md §5): the `rings` entries of a case, or the rings and
/// shackles of one net. Items run ring by ring, particle by particle; each ring is a body of
/// its own; bond k of a bonded ring joins its particles k and k+1 mod n and has the id
/// bases.bond_id + (bonds of the rings before) + k.
class RingSource final : public ParticleSource {
 public:
  RingSource(std::string description, std::vector<RingSpec> rings);

  std::string describe() const override { return description_; }
  std::int64_t count() const override { return first_item_.back(); }
  std::int64_t bond_count() const override { return first_bond_.back(); }
  std::int32_t body_count() const override { return static_cast<std::int32_t>(rings_.size()); }
  void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
            Model& model) const override;

 private:
  std::string description_;
  std::vector<RingSpec> rings_;
  std::vector<std::int64_t> first_item_;  ///< per ring, and the total at the end
  std::vector<std::int64_t> first_bond_;  ///< per ring, and the total at the end
};

}  // namespace ringdem

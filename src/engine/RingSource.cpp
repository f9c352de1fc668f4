#include "engine/RingSource.hpp"

#include <algorithm>
#include <cmath>

#include "engine/ModelBuilder.hpp"

namespace ringdem {

RingSource::RingSource(std::string description, std::vector<RingSpec> rings)
    : description_(std::move(description)), rings_(std::move(rings)) {
  first_item_.reserve(rings_.size() + 1);
  first_bond_.reserve(rings_.size() + 1);
  first_item_.push_back(0);
  first_bond_.push_back(0);
  for (const RingSpec& r : rings_) {
    first_item_.push_back(first_item_.back() + r.geometry.n_particles);
    first_bond_.push_back(first_bond_.back() +
                          (r.bond_type == RingSpec::kNoBond ? 0 : r.geometry.n_particles));
  }
}

void RingSource::emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                      Model& model) const {
  if (first >= last) return;
  // The first ring with an item in [first, last).
  auto ring = static_cast<std::size_t>(
      std::upper_bound(first_item_.begin(), first_item_.end(), first) - first_item_.begin() - 1);
  const auto in_slice = [&](std::int64_t item) { return item >= first && item < last; };
  for (; ring < rings_.size() && first_item_[ring] < last; ++ring) {
    const RingSpec& spec = rings_[ring];
    const int n = spec.geometry.n_particles;
    const std::int64_t item0 = first_item_[ring];
    const std::vector<Vec3> x = spec.geometry.positions();
    const double radius = spec.geometry.particle_radius;
    const auto body = static_cast<std::int32_t>(bases.body + static_cast<std::int32_t>(ring));
    for (int k = 0; k < n; ++k) {
      if (!in_slice(item0 + k)) continue;
      ParticleStore::NewParticle np;
      np.gid = bases.gid + item0 + k;
      np.position = x[static_cast<std::size_t>(k)];
      np.velocity = spec.velocity;
      np.radius = radius;
      np.density = spec.density;
      np.damping = spec.damping;
      np.material = spec.material;
      np.body = body;
      np.group = spec.group;
      np.motion = spec.motion;
      model.particles.add(np);
    }
    if (spec.bond_type == RingSpec::kNoBond) continue;
    // Bond k joins particles k and k + 1 mod n and comes with particle k.
    for (int k = 0; k < n; ++k) {
      const int next = (k + 1) % n;
      if (!in_slice(item0 + k)) continue;
      const auto end = [&](int m) {
        BondEnd e;
        e.gid = bases.gid + item0 + m;
        e.position = x[static_cast<std::size_t>(m)];
        e.radius = radius;
        return e;
      };
      add_bond(model, bases.bond_id + first_bond_[ring] + k, end(k), end(next), spec.bond_type,
               spec.bond_seed);
    }
  }
}

}  // namespace ringdem

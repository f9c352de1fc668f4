#include "engine/LatticeSource.hpp"

#include <random>

namespace ringdem {

void LatticeSource::emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                         Model& model) const {
  if (first >= last) return;
  const std::int64_t ny = spec_.count[1], nz = spec_.count[2];
  std::mt19937_64 rng(spec_.seed);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  const bool jitter = spec_.jitter > 0.0;
  // Three draws per item before this slice (one 64-bit draw per double with this engine).
  if (jitter) rng.discard(static_cast<unsigned long long>(3 * first));
  const double gap = spec_.spacing - 2.0 * spec_.radius;
  for (std::int64_t item = first; item < last; ++item) {
    const std::int64_t i = item / (ny * nz), j = (item / nz) % ny, k = item % nz;
    ParticleStore::NewParticle np;
    np.gid = bases.gid + item;
    np.position = spec_.origin + Vec3{static_cast<double>(i) * spec_.spacing,
                                      static_cast<double>(j) * spec_.spacing,
                                      static_cast<double>(k) * spec_.spacing};
    // Braced initialisation evaluates the draws left to right.
    if (jitter) np.position += Vec3{u(rng), u(rng), u(rng)} * (spec_.jitter * gap);
    np.velocity = spec_.velocity;
    np.radius = spec_.radius;
    np.density = spec_.density;
    np.damping = spec_.damping;
    np.material = spec_.material;
    np.group = spec_.group;
    model.particles.add(np);
  }
}

}  // namespace ringdem

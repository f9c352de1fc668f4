#include "engine/SphereListSource.hpp"

namespace ringdem {

void SphereListSource::emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                            Model& model) const {
  for (std::int64_t item = first; item < last; ++item) {
    ParticleStore::NewParticle np = spheres_[static_cast<std::size_t>(item)];
    np.gid = bases.gid + item;
    model.particles.add(np);
  }
}

}  // namespace ringdem

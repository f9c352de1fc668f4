#include "engine/SphereFileSource.hpp"

namespace ringdem {

void SphereFileSource::emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                            Model& model) const {
  std::int64_t item = first;
  file_.read(first, last, [&](double x, double y, double z, double radius) {
    ParticleStore::NewParticle np = prototype_;
    np.gid = bases.gid + item++;
    np.position = {x, y, z};
    np.radius = radius;
    model.particles.add(np);
  });
}

}  // namespace ringdem

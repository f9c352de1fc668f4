#pragma once

#include <cstdint>
#include <string>

#include "engine/ParticleSource.hpp"
#include "io/SphereFile.hpp"

namespace ringdem {

/// Free spheres read from a CSV packing (io/SphereFile.hpp): item i is the file's i-th sphere.
/// A rank reads only its slice of the lines, so no rank holds the whole packing, unlike a list
/// of spheres in the case file.
class SphereFileSource final : public ParticleSource {
 public:
  /// `prototype`: group, material, density, damping and velocity of every sphere.
  SphereFileSource(SphereFile file, const ParticleStore::NewParticle& prototype)
      : file_(std::move(file)), prototype_(prototype) {}

  std::string describe() const override { return "spheres from " + file_.path(); }
  std::int64_t count() const override { return file_.count(); }
  void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
            Model& model) const override;

 private:
  SphereFile file_;
  ParticleStore::NewParticle prototype_;
};

}  // namespace ringdem

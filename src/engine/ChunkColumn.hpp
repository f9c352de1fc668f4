#pragma once

#include <cstddef>

#include "core/Vec3.hpp"

namespace ringdem {

/// One Vec3 column of a contact kernel's chunk (PairContactChunk, BodyContactChunk): kSize x,
/// then y, then z, so that the contact law's loop over the chunk reads each component as a
/// vector.
template <std::size_t kSize>
struct ChunkColumn {
  alignas(64) double v[3][kSize];
  Vec3 get(std::size_t c) const { return {v[0][c], v[1][c], v[2][c]}; }
  /// out = get(c), written component by component (see PairContactTerm::compute_pairs).
  void copy_to(std::size_t c, Vec3& out) const {
    out.x = v[0][c];
    out.y = v[1][c];
    out.z = v[2][c];
  }
  void set(std::size_t c, const Vec3& x) {
    v[0][c] = x.x;
    v[1][c] = x.y;
    v[2][c] = x.z;
  }
  /// Lane `to` = lane `from`.
  void copy_lane(std::size_t from, std::size_t to) {
    v[0][to] = v[0][from];
    v[1][to] = v[1][from];
    v[2][to] = v[2][from];
  }
};

}  // namespace ringdem

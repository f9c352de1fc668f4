#pragma once

#include "core/Vec3.hpp"

namespace ringdem {

/// A 3-vector of floats for sums that are only ever read into a product with doubles: the
/// energy ledger's per-particle contact loads (engine/EnergyLedger.hpp, ContactMoments), where
/// half the bytes of a Vec3 bring an entry into one cache line. A Vec3 is added in double and
/// rounded once to float, so a sum in a fixed order is the same bits wherever it is taken.
struct Vec3f {
  float x = 0.0f, y = 0.0f, z = 0.0f;

  Vec3f& operator+=(const Vec3& o) {
    x = static_cast<float>(static_cast<double>(x) + o.x);
    y = static_cast<float>(static_cast<double>(y) + o.y);
    z = static_cast<float>(static_cast<double>(z) + o.z);
    return *this;
  }
};

/// The product in double.
inline double dot(const Vec3f& a, const Vec3& b) {
  return static_cast<double>(a.x) * b.x + static_cast<double>(a.y) * b.y +
         static_cast<double>(a.z) * b.z;
}

}  // namespace ringdem

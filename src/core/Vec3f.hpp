#pragma once

#include "core/Vec3.hpp"

namespace ringdem {

/// A 3-vector of floats for values that are only ever read into a product with doubles: the
/// energy ledger's per-particle contact loads (engine/EnergyLedger.hpp, ContactMoments), where
/// half the bytes of a Vec3 bring an entry into one cache line, and the damping force a contact
/// carries to the next step (SpringSlots). A Vec3 is added in double and rounded once to float,
/// so a sum in a fixed order is the same bits wherever it is taken.
struct Vec3f {
  float x = 0.0f, y = 0.0f, z = 0.0f;

  Vec3f& operator+=(const Vec3& o) {
    x = static_cast<float>(static_cast<double>(x) + o.x);
    y = static_cast<float>(static_cast<double>(y) + o.y);
    z = static_cast<float>(static_cast<double>(z) + o.z);
    return *this;
  }
};

/// Each component rounded once to float.
inline Vec3f to_vec3f(const Vec3& v) {
  return {static_cast<float>(v.x), static_cast<float>(v.y), static_cast<float>(v.z)};
}
/// Exact.
inline Vec3 to_vec3(const Vec3f& v) {
  return {static_cast<double>(v.x), static_cast<double>(v.y), static_cast<double>(v.z)};
}

/// The product in double.
inline double dot(const Vec3f& a, const Vec3& b) {
  return static_cast<double>(a.x) * b.x + static_cast<double>(a.y) * b.y +
         static_cast<double>(a.z) * b.z;
}

}  // namespace ringdem

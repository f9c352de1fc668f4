#pragma once

#include <cstring>

#include "core/Vec3.hpp"

namespace ringdem::testing {

/// Whether two doubles are the same bits (what rank independence promises; 0.0 and -0.0
/// differ, as do two NaNs of different payloads).
inline bool same_bits(double a, double b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
inline bool same_bits(const Vec3& a, const Vec3& b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

}  // namespace ringdem::testing

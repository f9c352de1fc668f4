#pragma once

#include <cstdint>
#include <cstring>

#include "core/Lanes4.hpp"

// Eight lanes a register, not for the ABI (see core/Lanes4.hpp on -Wpsabi).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace ringdem::lanes8 {

// Eight particles side by side, as core/Lanes4.hpp has four: one AVX-512 register where the
// build has it (GCC's vector extension lowers them to two or four narrower registers
// elsewhere, with the same operations). Where the 512-bit units are as wide as their
// registers, eight lanes do the arithmetic of eight particles in the instructions of four, and
// a transpose of eight rows takes as many shuffles as one of four.
//
// Each operation is one IEEE operation per lane, in the order the scalar code writes it
// (-ffp-contract=off): eight lanes give the bits of eight scalar evaluations.

using V8 = double __attribute__((vector_size(64)));
using Mask8 = std::int64_t __attribute__((vector_size(64)));  ///< a comparison's result

inline V8 load(const double* p) {
  V8 r;
  std::memcpy(&r, p, sizeof r);
  return r;
}
inline void store(double* p, const V8& v) {
  std::memcpy(p, &v, sizeof v);
}
inline V8 splat(double a) {
  return V8{a, a, a, a, a, a, a, a};
}
/// |a| by clearing the sign bit, as std::abs.
inline V8 abs(const V8& a) {
  constexpr std::int64_t kMagnitude = 0x7fffffffffffffffLL;
  return reinterpret_cast<V8>(reinterpret_cast<Mask8>(a) & kMagnitude);
}
/// Two fours side by side: a in lanes 0-3, b in lanes 4-7.
inline V8 join(const lanes::V4& a, const lanes::V4& b) {
  return __builtin_shufflevector(a, b, 0, 1, 2, 3, 4, 5, 6, 7);
}
inline lanes::V4 low(const V8& a) {
  return __builtin_shufflevector(a, a, 0, 1, 2, 3);
}
inline lanes::V4 high(const V8& a) {
  return __builtin_shufflevector(a, a, 4, 5, 6, 7);
}
/// Eight bytes from p as the doubles 0-255 in eight lanes (lanes::from_bytes twice).
inline V8 from_bytes(const std::uint8_t* p) {
  return join(lanes::from_bytes(p), lanes::from_bytes(p + 4));
}

/// Eight Vec3 rows as they lie in memory: a = (x0 y0 z0 x1 y1 z1 x2 y2),
/// b = (z2 x3 y3 z3 x4 y4 z4 x5), c = (y5 z5 x6 y6 z6 x7 y7 z7).
struct Rows3 {
  V8 a, b, c;
};
/// The same eight vectors as columns: x = (x0 ... x7), and so on.
struct Columns3 {
  V8 x, y, z;
};

inline Rows3 load_rows(const Vec3* r) {
  const double* const p = &r->x;
  return {load(p), load(p + 8), load(p + 16)};
}
inline void store_rows(Vec3* r, const Rows3& v) {
  double* const p = &r->x;
  store(p, v.a);
  store(p + 8, v.b);
  store(p + 16, v.c);
}

/// Each lane's factor spread over its row's three components.
inline Rows3 spread(const V8& f) {
  return {__builtin_shufflevector(f, f, 0, 0, 0, 1, 1, 1, 2, 2),
          __builtin_shufflevector(f, f, 2, 3, 3, 3, 4, 4, 4, 5),
          __builtin_shufflevector(f, f, 5, 5, 6, 6, 6, 7, 7, 7)};
}

/// A vector's components in the layout of eight rows.
inline Rows3 rows_of(const Vec3& v) {
  return {V8{v.x, v.y, v.z, v.x, v.y, v.z, v.x, v.y}, V8{v.z, v.x, v.y, v.z, v.x, v.y, v.z, v.x},
          V8{v.y, v.z, v.x, v.y, v.z, v.x, v.y, v.z}};
}

inline Columns3 columns(const Rows3& r) {
  // The first six of each column lie in a and b, the last two in c.
  const V8 x = __builtin_shufflevector(r.a, r.b, 0, 3, 6, 9, 12, 15, 15, 15);
  const V8 y = __builtin_shufflevector(r.a, r.b, 1, 4, 7, 10, 13, 13, 13, 13);
  const V8 z = __builtin_shufflevector(r.a, r.b, 2, 5, 8, 11, 14, 14, 14, 14);
  return {__builtin_shufflevector(x, r.c, 0, 1, 2, 3, 4, 5, 10, 13),
          __builtin_shufflevector(y, r.c, 0, 1, 2, 3, 4, 8, 11, 14),
          __builtin_shufflevector(z, r.c, 0, 1, 2, 3, 4, 9, 12, 15)};
}

/// Per lane: x^2 + y^2 + z^2 of its row, in norm2's order.
inline V8 norm2(const Columns3& c) {
  return c.x * c.x + c.y * c.y + c.z * c.z;
}

/// Per lane: x + y + z of its row, left to right (lanes::component_sum).
inline V8 component_sum(const Rows3& r) {
  const Columns3 c = columns(r);
  return c.x + c.y + c.z;
}

/// Eight quaternions as columns.
struct Columns4 {
  V8 w, x, y, z;
};

/// Eight quaternions, loaded as rows (two a register) and turned into columns.
inline Columns4 load_quats(const Quat* q) {
  const double* const p = &q->w;
  const V8 q01 = load(p), q23 = load(p + 8), q45 = load(p + 16), q67 = load(p + 24);
  const V8 wx0123 = __builtin_shufflevector(q01, q23, 0, 4, 8, 12, 1, 5, 9, 13);
  const V8 yz0123 = __builtin_shufflevector(q01, q23, 2, 6, 10, 14, 3, 7, 11, 15);
  const V8 wx4567 = __builtin_shufflevector(q45, q67, 0, 4, 8, 12, 1, 5, 9, 13);
  const V8 yz4567 = __builtin_shufflevector(q45, q67, 2, 6, 10, 14, 3, 7, 11, 15);
  return {__builtin_shufflevector(wx0123, wx4567, 0, 1, 2, 3, 8, 9, 10, 11),
          __builtin_shufflevector(wx0123, wx4567, 4, 5, 6, 7, 12, 13, 14, 15),
          __builtin_shufflevector(yz0123, yz4567, 0, 1, 2, 3, 8, 9, 10, 11),
          __builtin_shufflevector(yz0123, yz4567, 4, 5, 6, 7, 12, 13, 14, 15)};
}
inline void store_quats(Quat* q, const Columns4& c) {
  const V8 wx0123 = __builtin_shufflevector(c.w, c.x, 0, 1, 2, 3, 8, 9, 10, 11);
  const V8 wx4567 = __builtin_shufflevector(c.w, c.x, 4, 5, 6, 7, 12, 13, 14, 15);
  const V8 yz0123 = __builtin_shufflevector(c.y, c.z, 0, 1, 2, 3, 8, 9, 10, 11);
  const V8 yz4567 = __builtin_shufflevector(c.y, c.z, 4, 5, 6, 7, 12, 13, 14, 15);
  double* const p = &q->w;
  store(p, __builtin_shufflevector(wx0123, yz0123, 0, 4, 8, 12, 1, 5, 9, 13));
  store(p + 8, __builtin_shufflevector(wx0123, yz0123, 2, 6, 10, 14, 3, 7, 11, 15));
  store(p + 16, __builtin_shufflevector(wx4567, yz4567, 0, 4, 8, 12, 1, 5, 9, 13));
  store(p + 24, __builtin_shufflevector(wx4567, yz4567, 2, 6, 10, 14, 3, 7, 11, 15));
}

}  // namespace ringdem::lanes8

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

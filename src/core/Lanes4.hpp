#pragma once

#include <cstdint>
#include <cstring>
#if defined(__AVX__) && defined(__SSE4_1__)
#include <immintrin.h>
#endif

#include "core/Quat.hpp"
#include "core/Vec3.hpp"

// Without AVX, GCC notes that passing these 32-byte vectors by value has another ABI than with
// it (-Wpsabi). The functions here and the passes that use them are inline in one translation
// unit, compiled with one set of flags; no such value crosses a library boundary.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace ringdem::lanes {

// Four particles side by side: one value of each in a vector of four doubles (GCC's vector
// extension, lowered to what the target has: one AVX register, two SSE2 registers). The
// integrator's columns are rows of Vec3 or Quat, x, y, z of a particle next to each other; a
// loop over them that the compiler vectorises takes every row apart and back with shuffles,
// and spreads each particle's factors over its components through memory. Here four rows are
// loaded as they lie and only the few operations that mix a particle's components (norms,
// quaternion products) see them turned into columns, with a fixed handful of shuffles.
//
// Each operation is one IEEE operation per lane, in the order the scalar code writes it, and
// the build does not contract multiply-adds (-ffp-contract=off): four lanes give the bits of
// four scalar evaluations.

using V4 = double __attribute__((vector_size(32)));
using Mask4 = std::int64_t __attribute__((vector_size(32)));  ///< a comparison's result

inline V4 load(const double* p) {
  V4 r;
  std::memcpy(&r, p, sizeof r);
  return r;
}
inline void store(double* p, const V4& v) {
  std::memcpy(p, &v, sizeof v);
}
inline V4 splat(double a) {
  return V4{a, a, a, a};
}
/// Four bytes from p as the doubles 0-255 in four lanes. GCC lowers the vector extension's
/// conversion of four bytes (__builtin_convertvector) to four scalar conversions and inserts,
/// some fifteen instructions where AVX has two (a zero-extending load and a conversion): the
/// integrator reads its motion kinds so three times a step for every four particles. Either
/// way the values are exact, so the same bits.
inline V4 from_bytes(const std::uint8_t* p) {
#if defined(__AVX__) && defined(__SSE4_1__)
  std::int32_t word;
  std::memcpy(&word, p, sizeof word);
  return reinterpret_cast<V4>(_mm256_cvtepi32_pd(_mm_cvtepu8_epi32(_mm_cvtsi32_si128(word))));
#else
  using Bytes4 = std::uint8_t __attribute__((vector_size(4)));
  Bytes4 bytes;
  std::memcpy(&bytes, p, sizeof bytes);
  return __builtin_convertvector(bytes, V4);
#endif
}
/// |a| by clearing the sign bit, as std::abs.
inline V4 abs(const V4& a) {
  constexpr std::int64_t kMagnitude = 0x7fffffffffffffffLL;
  return reinterpret_cast<V4>(reinterpret_cast<Mask4>(a) &
                              Mask4{kMagnitude, kMagnitude, kMagnitude, kMagnitude});
}
/// c ? yes : no per lane.
inline V4 select(const Mask4& c, const V4& yes, const V4& no) {
  return c ? yes : no;
}
/// Largest lane.
inline double max_lane(const V4& a) {
  const double m01 = a[0] > a[1] ? a[0] : a[1];
  const double m23 = a[2] > a[3] ? a[2] : a[3];
  return m01 > m23 ? m01 : m23;
}

/// Four Vec3 rows as they lie in memory: a = (x0 y0 z0 x1), b = (y1 z1 x2 y2),
/// c = (z2 x3 y3 z3).
struct Rows3 {
  V4 a, b, c;
};
/// The same four vectors as columns: x = (x0 x1 x2 x3), and so on.
struct Columns3 {
  V4 x, y, z;
};
/// Four quaternions as columns.
struct Columns4 {
  V4 w, x, y, z;
};

static_assert(sizeof(Vec3) == 3 * sizeof(double) && sizeof(Quat) == 4 * sizeof(double),
              "rows must be runs of doubles");

inline Rows3 load_rows(const Vec3* r) {
  const double* const p = &r->x;
  return {load(p), load(p + 4), load(p + 8)};
}
inline void store_rows(Vec3* r, const Rows3& v) {
  double* const p = &r->x;
  store(p, v.a);
  store(p + 4, v.b);
  store(p + 8, v.c);
}

/// Each lane's factor spread over its row's three components.
inline Rows3 spread(const V4& f) {
  return {__builtin_shufflevector(f, f, 0, 0, 0, 1), __builtin_shufflevector(f, f, 1, 1, 2, 2),
          __builtin_shufflevector(f, f, 2, 3, 3, 3)};
}

inline Columns3 columns(const Rows3& r) {
  const V4 x = __builtin_shufflevector(r.a, r.b, 0, 3, 6, 6);
  const V4 y = __builtin_shufflevector(r.a, r.b, 1, 4, 7, 7);
  const V4 z = __builtin_shufflevector(r.a, r.b, 2, 5, 5, 5);
  return {__builtin_shufflevector(x, r.c, 0, 1, 2, 5), __builtin_shufflevector(y, r.c, 0, 1, 2, 6),
          __builtin_shufflevector(z, r.c, 0, 1, 4, 7)};
}

/// Per lane: x^2 + y^2 + z^2 of its row, in norm2's order.
inline V4 norm2(const Columns3& c) {
  return c.x * c.x + c.y * c.y + c.z * c.z;
}

/// Per lane: x + y + z of its row, left to right.
inline V4 component_sum(const Rows3& r) {
  const Columns3 c = columns(r);
  return c.x + c.y + c.z;
}

/// Four quaternions, loaded as rows and turned into columns (a 4 x 4 transpose).
inline Columns4 load_quats(const Quat* q) {
  const double* const p = &q->w;
  const V4 q0 = load(p), q1 = load(p + 4), q2 = load(p + 8), q3 = load(p + 12);
  const V4 wy01 = __builtin_shufflevector(q0, q1, 0, 4, 2, 6);
  const V4 xz01 = __builtin_shufflevector(q0, q1, 1, 5, 3, 7);
  const V4 wy23 = __builtin_shufflevector(q2, q3, 0, 4, 2, 6);
  const V4 xz23 = __builtin_shufflevector(q2, q3, 1, 5, 3, 7);
  return {__builtin_shufflevector(wy01, wy23, 0, 1, 4, 5),
          __builtin_shufflevector(xz01, xz23, 0, 1, 4, 5),
          __builtin_shufflevector(wy01, wy23, 2, 3, 6, 7),
          __builtin_shufflevector(xz01, xz23, 2, 3, 6, 7)};
}
inline void store_quats(Quat* q, const Columns4& c) {
  const V4 wx01 = __builtin_shufflevector(c.w, c.x, 0, 4, 1, 5);
  const V4 wx23 = __builtin_shufflevector(c.w, c.x, 2, 6, 3, 7);
  const V4 yz01 = __builtin_shufflevector(c.y, c.z, 0, 4, 1, 5);
  const V4 yz23 = __builtin_shufflevector(c.y, c.z, 2, 6, 3, 7);
  double* const p = &q->w;
  store(p, __builtin_shufflevector(wx01, yz01, 0, 1, 4, 5));
  store(p + 4, __builtin_shufflevector(wx01, yz01, 2, 3, 6, 7));
  store(p + 8, __builtin_shufflevector(wx23, yz23, 0, 1, 4, 5));
  store(p + 12, __builtin_shufflevector(wx23, yz23, 2, 3, 6, 7));
}

}  // namespace ringdem::lanes

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// The particle integrator's vector passes (physics/Integrator.cpp's drift and
// physics/IntegratorKicks.cpp's kicks): the columns they read, the lanes of four and eight
// particles, and the kick factors both halves of a step share. Included by those two files
// only.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>

#include "core/Lanes4.hpp"
#include "core/Lanes8.hpp"
#include "physics/Integrator.hpp"

// The passes hand vectors of four doubles between inline functions (see core/Lanes4.hpp on
// -Wpsabi).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace ringdem::integrator_lanes {

// The particle passes run four particles at a time (core/Lanes4.hpp): the Vec3 columns are
// loaded as they lie, each particle's factors (dt/2m, ...) are spread over its components in
// registers, and only the norms and the quaternion update see the rows as columns. Motion
// kinds become 0/1 factors, so that nothing branches per particle. A fixed particle has zero
// velocity and angular velocity (the model builder sets them), so scaling its drift by 0 only
// guards against stray values. A pass's last particles, fewer than four, are copied into four
// lanes padded with fixed particles at rest (TailLanes), so that every particle goes through
// the same operations.

using lanes::Columns3;
using lanes::Columns4;
using lanes::Rows3;
using lanes::V4;

struct DriftMaxima {
  double max_v2 = 0.0;  ///< infinite for a non-finite velocity
  double max_w2 = 0.0;
  Integrator::VelocityBox velocities;
};

/// A drift pass's box of velocities in lanes of four, each component's minimum and maximum
/// (the eight-lane passes fold their halves into them), folded into a VelocityBox at the end.
struct VelocityLanes {
  V4 low_x, low_y, low_z, high_x, high_y, high_z;
  VelocityLanes() {
    const V4 empty = lanes::splat(Integrator::VelocityBox::kEmptyLow);
    low_x = low_y = low_z = empty;
    high_x = high_y = high_z = -empty;
  }
  /// Widens the box by four velocities, given as columns (a NaN component is left out).
  void widen(const V4& x, const V4& y, const V4& z) {
    low_x = x < low_x ? x : low_x;
    low_y = y < low_y ? y : low_y;
    low_z = z < low_z ? z : low_z;
    high_x = x > high_x ? x : high_x;
    high_y = y > high_y ? y : high_y;
    high_z = z > high_z ? z : high_z;
  }
  void fold_into(Integrator::VelocityBox& box) const {
    for (int i = 0; i < 4; ++i) {
      Integrator::VelocityBox lane;
      lane.low = {low_x[i], low_y[i], low_z[i]};
      lane.high = {high_x[i], high_y[i], high_z[i]};
      box.add(lane);
    }
  }
};

// motion_lanes() reads the kinds as these numbers.
static_assert(static_cast<int>(Motion::kFree) == 0 && static_cast<int>(Motion::kFixed) == 1 &&
              static_cast<int>(Motion::kPrescribed) == 2);
static_assert(sizeof(Motion) == 1, "motion_lanes() reads a motion kind as one byte");
/// The motion kinds of four particles from k as factors in lanes: free (1 for a free particle,
/// else 0) and moving (1 for one that moves, free or driven, else 0). In vector registers: one
/// particle at a time, the byte-to-double conversions were some forty scalar instructions per
/// four particles in each pass (8 % of the net's integrator).
struct MotionLanes {
  V4 free, moving;
};
inline MotionLanes motion_lanes(const Motion* motion) {
  const V4 kind = lanes::from_bytes(reinterpret_cast<const std::uint8_t*>(motion));
  const V4 zero{}, one = lanes::splat(1.0);
  return {lanes::select(kind == zero, one, zero), lanes::select(kind != one, one, zero)};
}

/// The columns the passes read and write, from some particle on.
struct ParticleRows {
  Vec3* x;
  Vec3* v;
  Vec3* w;
  Quat* q;  ///< null where the store keeps no orientations (nothing bonded)
  Vec3* force;
  Vec3* torque;
  const double* mass;
  const double* radius;
  const Motion* motion;
  const double* alpha;  ///< null where nothing in the model is damped
  double* dissipated;   ///< the ledger's global-damping columns, null where it keeps none
  double* power;
  const std::uint8_t* turning = nullptr;  ///< Integrator::Turning::only, null: all turn
};

inline ParticleRows rows_of(ParticleStore& p) {
  const bool ledger = p.books_global_damping();
  return {p.position.data(),
          p.velocity.data(),
          p.omega.data(),
          p.tracks_orientation() ? p.orientation.data() : nullptr,
          p.force.data(),
          p.torque.data(),
          p.mass.data(),
          p.radius.data(),
          p.motion.data(),
          p.tracks_damping() ? p.damping.data() : nullptr,
          ledger ? p.dissipated_global.data() : nullptr,
          ledger ? p.power_global.data() : nullptr,
          nullptr};
}

/// The last n < 4 particles of a pass in four lanes; the others are fixed particles at rest
/// with unit mass and radius, which neither move nor raise the largest speeds.
struct TailLanes {
  Vec3 x[4]{}, v[4]{}, w[4]{}, force[4]{}, torque[4]{};
  Quat q[4]{};
  double mass[4]{1.0, 1.0, 1.0, 1.0}, radius[4]{1.0, 1.0, 1.0, 1.0};
  Motion motion[4]{Motion::kFixed, Motion::kFixed, Motion::kFixed, Motion::kFixed};
  double alpha[4]{}, dissipated[4]{}, power[4]{};
  std::uint8_t turning[4]{};

  TailLanes(const ParticleRows& r, std::size_t k, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      x[i] = r.x[k + i];
      v[i] = r.v[k + i];
      w[i] = r.w[k + i];
      if (r.q) q[i] = r.q[k + i];
      force[i] = r.force[k + i];
      torque[i] = r.torque[k + i];
      mass[i] = r.mass[k + i];
      radius[i] = r.radius[k + i];
      motion[i] = r.motion[k + i];
      if (r.alpha) alpha[i] = r.alpha[k + i];
      if (r.dissipated) dissipated[i] = r.dissipated[k + i];
      if (r.power) power[i] = r.power[k + i];
      if (r.turning) turning[i] = r.turning[k + i];
    }
  }
  ParticleRows rows(const ParticleRows& like) {
    return {x,
            v,
            w,
            like.q ? q : nullptr,
            force,
            torque,
            mass,
            radius,
            motion,
            like.alpha ? alpha : nullptr,
            like.dissipated ? dissipated : nullptr,
            like.power ? power : nullptr,
            like.turning ? turning : nullptr};
  }
  void write_back(const ParticleRows& r, std::size_t k, std::size_t n) const {
    for (std::size_t i = 0; i < n; ++i) {
      r.x[k + i] = x[i];
      r.v[k + i] = v[i];
      r.w[k + i] = w[i];
      if (r.q) r.q[k + i] = q[i];
      r.force[k + i] = force[i];
      r.torque[k + i] = torque[i];
      if (r.dissipated) r.dissipated[k + i] = dissipated[i];
      if (r.power) r.power[k + i] = power[i];
    }
  }
};

/// Runs kernel(rows, k, group) over particles [begin, end) four at a time, the last ones in
/// TailLanes; `group` counts the fours from begin (the tail's too).
template <class Kernel>
inline void for_each_four(const ParticleRows& r, std::size_t begin, std::size_t end,
                          Kernel&& kernel) {
  std::size_t k = begin;
  for (; k + 4 <= end; k += 4)
    kernel(r, k, (k - begin) / 4);
  if (k == end) return;
  TailLanes tail(r, k, end - k);
  kernel(tail.rows(r), 0, (k - begin) / 4);
  tail.write_back(r, k, end - k);
}

/// The half-kick factors of four particles: free (1 for a free particle, else 0),
/// kick = free dt/2m and turn = free dt/2I.
struct KickFactors {
  V4 free, kick, turn;
};
inline KickFactors kick_factors(const ParticleRows& r, std::size_t k, double half) {
  const V4 free = motion_lanes(r.motion + k).free;
  const V4 mass = lanes::load(r.mass + k), radius = lanes::load(r.radius + k);
  const V4 free_half = free * half;
  // ParticleStore::sphere_inertia, 0.4 m r^2, in its order.
  return {free, free_half / mass, free_half / (0.4 * mass * radius * radius)};
}

/// A step's two half kicks of a particle have the same factors (the step's dt, its mass,
/// radius and motion): the fused pass (Integrator::second_then_first_half) keeps those of the
/// second for the first, so that the drift does not divide again (two divisions of four lanes
/// per four particles: 4 % of the fused pass on grains in cache).
struct HalfKicks {
  V4 kick, turn;
};

/// a += b s, register by register: Vec3 rows a += b * factor, component by component.
inline void add_scaled(Rows3& a, const Rows3& b, const Rows3& s) {
  a.a += b.a * s.a;
  a.b += b.b * s.b;
  a.c += b.c * s.c;
}

/// The operations the drift and the damped kick need, on four lanes (core/Lanes4.hpp) or eight
/// (core/Lanes8.hpp), so that each is written once for both widths.
struct FourLanes {
  using V = V4;
  using Rows = Rows3;
  static V load(const double* p) { return lanes::load(p); }
  static void store(double* p, const V& v) { lanes::store(p, v); }
  static V kinds(const Motion* m) {
    return lanes::from_bytes(reinterpret_cast<const std::uint8_t*>(m));
  }
  static Rows load_rows(const Vec3* p) { return lanes::load_rows(p); }
  static void store_rows(Vec3* p, const Rows& r) { lanes::store_rows(p, r); }
  static Rows spread(const V& f) { return lanes::spread(f); }
  static V component_sum(const Rows& r) { return lanes::component_sum(r); }
  using Columns = Columns3;
  static Columns columns(const Rows& r) { return lanes::columns(r); }
  static V norm2(const Columns& c) { return lanes::norm2(c); }
  /// The components of a vector in the layout of the rows.
  static Rows rows_of(const Vec3& g) {
    return {V4{g.x, g.y, g.z, g.x}, V4{g.y, g.z, g.x, g.y}, V4{g.z, g.x, g.y, g.z}};
  }
  /// The kick's factors for the drift, one HalfKicks a four, and back.
  static void keep(HalfKicks* keep, const V& kick, const V& turn) { *keep = {kick, turn}; }
  static void kept(const HalfKicks* kept, V& kick, V& turn) {
    kick = kept->kick;
    turn = kept->turn;
  }
  /// kick_factors() of the lanes from k.
  static void factors(const ParticleRows& r, std::size_t k, double half, V& kick, V& turn) {
    const KickFactors f = kick_factors(r, k, half);
    kick = f.kick;
    turn = f.turn;
  }
  /// Raises the largest squared speeds of four lanes by the lanes' (NaN: infinite).
  static void raise(V4& max, const V& a) {
    const V4 infinite = lanes::splat(std::numeric_limits<double>::infinity());
    max = lanes::select(a <= max, max, lanes::select(a == a, a, infinite));
  }
  /// The half turns for the orientation pass, one Columns3 a four.
  static void hand_turns(Columns3* turn, const V& hx, const V& hy, const V& hz) {
    *turn = {hx, hy, hz};
  }
  static void widen(VelocityLanes& box, const Columns& v) { box.widen(v.x, v.y, v.z); }
};
struct EightLanes {
  using V = lanes8::V8;
  using Rows = lanes8::Rows3;
  static V load(const double* p) { return lanes8::load(p); }
  static void store(double* p, const V& v) { lanes8::store(p, v); }
  static V kinds(const Motion* m) {
    return lanes8::from_bytes(reinterpret_cast<const std::uint8_t*>(m));
  }
  static Rows load_rows(const Vec3* p) { return lanes8::load_rows(p); }
  static void store_rows(Vec3* p, const Rows& r) { lanes8::store_rows(p, r); }
  static Rows spread(const V& f) { return lanes8::spread(f); }
  static V component_sum(const Rows& r) { return lanes8::component_sum(r); }
  using Columns = lanes8::Columns3;
  static Columns columns(const Rows& r) { return lanes8::columns(r); }
  static V norm2(const Columns& c) { return lanes8::norm2(c); }
  static Rows rows_of(const Vec3& g) { return lanes8::rows_of(g); }
  static void keep(HalfKicks* keep, const V& kick, const V& turn) {
    keep[0] = {lanes8::low(kick), lanes8::low(turn)};
    keep[1] = {lanes8::high(kick), lanes8::high(turn)};
  }
  static void kept(const HalfKicks* kept, V& kick, V& turn) {
    kick = lanes8::join(kept[0].kick, kept[1].kick);
    turn = lanes8::join(kept[0].turn, kept[1].turn);
  }
  static void factors(const ParticleRows& r, std::size_t k, double half, V& kick, V& turn) {
    const KickFactors first = kick_factors(r, k, half), second = kick_factors(r, k + 4, half);
    kick = lanes8::join(first.kick, second.kick);
    turn = lanes8::join(first.turn, second.turn);
  }
  /// One four after the other, as FourLanes::raise().
  static void raise(V4& max, const V& a) {
    FourLanes::raise(max, lanes8::low(a));
    FourLanes::raise(max, lanes8::high(a));
  }
  static void hand_turns(Columns3* turn, const V& hx, const V& hy, const V& hz) {
    turn[0] = {lanes8::low(hx), lanes8::low(hy), lanes8::low(hz)};
    turn[1] = {lanes8::high(hx), lanes8::high(hy), lanes8::high(hz)};
  }
  /// One four after the other, as raise().
  static void widen(VelocityLanes& box, const Columns& v) {
    box.widen(lanes8::low(v.x), lanes8::low(v.y), lanes8::low(v.z));
    box.widen(lanes8::high(v.x), lanes8::high(v.y), lanes8::high(v.z));
  }
};

/// The second half kick of owned particles [begin, end), one chunk of Integrator::kChunk; the
/// factors of each four from begin go to `keep` where it is not null (IntegratorKicks.cpp).
void second_half_chunk(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                       HalfKicks* keep);

}  // namespace ringdem::integrator_lanes

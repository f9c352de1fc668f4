#include "physics/Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <limits>

#include "core/Lanes4.hpp"
#include "core/Lanes8.hpp"
#include "core/Select.hpp"

// The passes hand vectors of four doubles between inline functions of this file (see
// core/Lanes4.hpp on -Wpsabi).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wpsabi"
#endif

namespace ringdem {

namespace {

/// The Cundall damping load alpha |f| sign(v) of one component, taken off f.
inline double damping_component(double f, double v, double alpha) {
  // sign(0) = 0: a particle at rest is not pushed. The passes' damp_and_kick() does the same
  // lane by lane.
  const double s = select_bits(v > 0.0, 1.0, 0.0) - select_bits(v < 0.0, 1.0, 0.0);
  return alpha * std::abs(f) * s;
}

/// Cundall damping load of one vector load against its velocity: the damped load is
/// f - damping_load(f, v, alpha); alpha = 0 leaves f bit for bit.
inline Vec3 damping_load(const Vec3& f, const Vec3& v, double alpha) {
  return {damping_component(f.x, v.x, alpha), damping_component(f.y, v.y, alpha),
          damping_component(f.z, v.z, alpha)};
}

}  // namespace

// The particle passes run four particles at a time (core/Lanes4.hpp): the Vec3 columns are
// loaded as they lie, each particle's factors (dt/2m, ...) are spread over its components in
// registers, and only the norms and the quaternion update see the rows as columns. Motion
// kinds become 0/1 factors, so that nothing branches per particle. A fixed particle has zero
// velocity and angular velocity (the model builder sets them), so scaling its drift by 0 only
// guards against stray values. A pass's last particles, fewer than four, are copied into four
// lanes padded with fixed particles at rest (TailLanes), so that every particle goes through
// the same operations.

namespace {

using lanes::Columns3;
using lanes::Columns4;
using lanes::Rows3;
using lanes::V4;

struct DriftMaxima {
  double max_v2 = 0.0;  ///< infinite for a non-finite velocity
  double max_w2 = 0.0;
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

ParticleRows rows_of(ParticleStore& p) {
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
void for_each_four(const ParticleRows& r, std::size_t begin, std::size_t end, Kernel&& kernel) {
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
};

/// The drift of the four or eight particles (Lanes) from k: v += F dt/2m, omega += T dt/2I,
/// x += v dt, the next step's initial loads (F = m g, T = 0; GatherMap::initialise_loads) and
/// the largest squared speeds per lane of four.
/// `kept`: the factors of this step's second half kick, one HalfKicks a four (kick_factors()
/// otherwise). `turn`, where not null, gets the half turns h = omega moving dt/2 as columns
/// for the orientation pass, one Columns3 a four.
template <class Lanes>
inline void drift(const ParticleRows& r, std::size_t k, double dt,
                  const typename Lanes::Rows& gravity, const HalfKicks* kept, V4& max_v2,
                  V4& max_w2, Columns3* turn) {
  using V = typename Lanes::V;
  using Rows = typename Lanes::Rows;
  const double half = 0.5 * dt;
  V kick, spin;
  if (kept)
    Lanes::kept(kept, kick, spin);
  else
    Lanes::factors(r, k, half, kick, spin);
  const V zero{}, one = zero + 1.0;
  const V moving = Lanes::kinds(r.motion + k) != one ? one : zero;  // motion_lanes()
  Rows v = Lanes::load_rows(r.v + k), w = Lanes::load_rows(r.w + k);
  Rows x = Lanes::load_rows(r.x + k);
  const Rows force = Lanes::load_rows(r.force + k), torque = Lanes::load_rows(r.torque + k);
  const Rows kicks = Lanes::spread(kick), spins = Lanes::spread(spin);
  v = {v.a + force.a * kicks.a, v.b + force.b * kicks.b, v.c + force.c * kicks.c};  // F dt/2m
  w = {w.a + torque.a * spins.a, w.b + torque.b * spins.b, w.c + torque.c * spins.c};
  const Rows step = Lanes::spread(moving * dt);
  x = {x.a + v.a * step.a, x.b + v.b * step.b, x.c + v.c * step.c};  // x += v dt
  Lanes::store_rows(r.v + k, v);
  Lanes::store_rows(r.w + k, w);
  Lanes::store_rows(r.x + k, x);
  const Rows mass = Lanes::spread(Lanes::load(r.mass + k));
  Lanes::store_rows(r.force + k, {gravity.a * mass.a, gravity.b * mass.b, gravity.c * mass.c});
  Lanes::store_rows(r.torque + k, {zero, zero, zero});
  // The largest squared speeds, scaled after the pass: scaling by a positive constant keeps the
  // order, so max(scaled) is the scaled max. NaN compares false: it counts as infinite.
  const typename Lanes::Columns wc = Lanes::columns(w);
  Lanes::raise(max_v2, Lanes::norm2(Lanes::columns(v)));
  Lanes::raise(max_w2, Lanes::norm2(wc));
  // The columns of omega are at hand here; the orientation pass would load and transpose them
  // again.
  if (turn)
    Lanes::hand_turns(turn, wc.x * moving * half, wc.y * moving * half, wc.z * moving * half);
}

/// Quaternions as columns of lanes of type V (four or eight).
template <class V>
struct QuatColumns {
  V w, x, y, z;
};

/// cayley_turned() lane by lane, in its order: p = (1, h) q brought to unit norm by
/// inverse_norm_near_one().
template <class V>
inline QuatColumns<V> cayley_lanes(const V& hx, const V& hy, const V& hz, const QuatColumns<V>& b) {
  const V pw = 1.0 * b.w - hx * b.x - hy * b.y - hz * b.z;
  const V px = 1.0 * b.x + hx * b.w + hy * b.z - hz * b.y;
  const V py = 1.0 * b.y - hx * b.z + hy * b.w + hz * b.x;
  const V pz = 1.0 * b.z + hx * b.y - hy * b.x + hz * b.w;
  const V n2 = pw * pw + px * px + py * py + pz * pz;
  const V y = 0.5 * (3.0 - n2);
  const V scale = y * (0.5 * (3.0 - n2 * y * y));
  return {pw * scale, px * scale, py * scale, pz * scale};
}

/// The orientation update of four particles from k with their new angular velocities (after
/// drift(), which left their half turns h = omega moving dt/2 as columns):
/// rotated(q, omega * moving, dt), cayley_turned() in its order: p = (1, h) q brought to unit
/// norm by inverse_norm_near_one().
inline void turn_four(const ParticleRows& r, std::size_t k, const Columns3& h) {
  // Where only some particles turn, four that do not are skipped, and of four that partly do
  // the others keep their orientation (the lanes' select); the ones that turn get the same
  // operations as without flags, so the same bits.
  lanes::Mask4 turns{};
  if (r.turning) {
    std::uint32_t any = 0;
    std::memcpy(&any, r.turning + k, sizeof any);
    if (any == 0) return;
    turns = lanes::from_bytes(r.turning + k) != V4{};
  }
  const Columns4 b = lanes::load_quats(r.q + k);
  const QuatColumns<V4> p = cayley_lanes(h.x, h.y, h.z, QuatColumns<V4>{b.w, b.x, b.y, b.z});
  if (r.turning)
    lanes::store_quats(r.q + k, {lanes::select(turns, p.w, b.w), lanes::select(turns, p.x, b.x),
                                 lanes::select(turns, p.y, b.y), lanes::select(turns, p.z, b.z)});
  else
    lanes::store_quats(r.q + k, {p.w, p.x, p.y, p.z});
}

/// turn_four() of eight particles from k at once (core/Lanes8.hpp), whose half turns are `low`
/// (the first four) and `high`: the same operations lane by lane, the same bits. The
/// transposes of eight quaternions take as many shuffles as those of four.
inline void turn_eight(const ParticleRows& r, std::size_t k, const Columns3& low,
                       const Columns3& high) {
  using lanes8::V8;
  lanes8::Mask8 turns{};
  if (r.turning) {
    std::uint64_t any = 0;
    std::memcpy(&any, r.turning + k, sizeof any);
    if (any == 0) return;
    turns = lanes8::from_bytes(r.turning + k) != V8{};
  }
  const lanes8::Columns4 b = lanes8::load_quats(r.q + k);
  QuatColumns<V8> p =
      cayley_lanes(lanes8::join(low.x, high.x), lanes8::join(low.y, high.y),
                   lanes8::join(low.z, high.z), QuatColumns<V8>{b.w, b.x, b.y, b.z});
  if (r.turning) p = {turns ? p.w : b.w, turns ? p.x : b.x, turns ? p.y : b.y, turns ? p.z : b.z};
  lanes8::store_quats(r.q + k, {p.w, p.x, p.y, p.z});
}

/// The drift over owned particles [begin, end), with the orientation update compiled in or
/// out; raises `m` to the largest squared speeds it saw. `kept`: the second half kick's
/// factors of each four from begin, or null.
template <bool kTurn>
void drift_range(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                 const Vec3& gravity, const std::uint8_t* turning, const HalfKicks* kept,
                 DriftMaxima& m) {
  // The components of gravity in the layout of four rows.
  const Rows3 gravity_rows = FourLanes::rows_of(gravity);
  const lanes8::Rows3 gravity_eight = EightLanes::rows_of(gravity);
  V4 max_v2 = lanes::splat(m.max_v2), max_w2 = lanes::splat(m.max_w2);
  ParticleRows rows = rows_of(p);
  rows.turning = turning;
  // The orientations in a pass of their own over each chunk, after its drift (in cache): the
  // quaternion update of four particles ends in a long chain of dependent operations, which
  // the drift's long iterations could not overlap; in short iterations of its own they do
  // (BM_IntegrateRings 3 % faster, docs/performance.md, twenty-fourth round). The same
  // operations on the same values: the same bits.
  // The drift hands each four's half turns to the orientation pass (6 kB a chunk, in L1).
  constexpr std::size_t kTurnChunk = 256;
  Columns3 turns[kTurnChunk / 4];
  for (std::size_t c = begin; c < end; c += kTurnChunk) {
    const std::size_t c_end = std::min(end, c + kTurnChunk);
    const HalfKicks* const chunk_kept = kept ? kept + (c - begin) / 4 : nullptr;
    std::size_t k = c, group = 0;
    for (; k + 8 <= c_end; k += 8, group += 2)
      drift<EightLanes>(rows, k, dt, gravity_eight, chunk_kept ? chunk_kept + group : nullptr,
                        max_v2, max_w2, kTurn ? turns + group : nullptr);
    for_each_four(rows, k, c_end, [&](const ParticleRows& r, std::size_t four, std::size_t g) {
      drift<FourLanes>(r, four, dt, gravity_rows, chunk_kept ? chunk_kept + group + g : nullptr,
                       max_v2, max_w2, kTurn ? turns + group + g : nullptr);
    });
    if constexpr (kTurn) {
      k = c;
      group = 0;
      for (; k + 8 <= c_end; k += 8, group += 2)
        turn_eight(rows, k, turns[group], turns[group + 1]);
      for_each_four(rows, k, c_end, [&](const ParticleRows& r, std::size_t four, std::size_t g) {
        turn_four(r, four, turns[group + g]);
      });
    }
  }
  m.max_v2 = lanes::max_lane(max_v2);
  m.max_w2 = lanes::max_lane(max_w2);
}

void drift_range(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                 const Vec3& gravity, Integrator::Turning turning, const HalfKicks* kept,
                 DriftMaxima& m) {
  if (turning.orientations)
    drift_range<true>(p, begin, end, dt, gravity, turning.only, kept, m);
  else
    drift_range<false>(p, begin, end, dt, gravity, nullptr, kept, m);
}

/// What the drift passes saw (their largest squared speeds, order-free maxima) as the
/// Integrator's Drift: the worst runaway ratio and, only when something ran away, which
/// particle (of the largest ratio, the lowest gid).
Integrator::Drift drift_result(const ParticleStore& p, const DriftMaxima& m, double dt,
                               double max_step, double max_turn) {
  const double step_scale = dt * dt / (max_step * max_step);
  const double turn_scale = dt * dt / (max_turn * max_turn);
  const double s = m.max_v2 * step_scale, t = m.max_w2 * turn_scale;
  const double worst = std::min(s > t ? s : t, Integrator::kRunaway);
  Integrator::Drift d{std::sqrt(m.max_v2), worst, 0};
  bool found = false;
  if (worst > 1.0)
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      const double sk = norm2(p.velocity[k]) * step_scale, tk = norm2(p.omega[k]) * turn_scale;
      // A non-finite speed is a runaway (NaN compares false, and would lose against tk).
      double r = sk > tk ? sk : tk;
      r = sk == sk && tk == tk && r <= Integrator::kRunaway ? r : Integrator::kRunaway;
      // Of equal ratios (every runaway has kRunaway) the lowest gid, which is the same particle
      // on any rank count whatever the storage order.
      if (r == worst && (!found || p.gid[k] < p.gid[d.worst_index])) {
        d.worst_index = k;
        found = true;
      }
    }
  return d;
}

}  // namespace

Integrator::Drift Integrator::first_half(ParticleStore& p, double dt, const Vec3& gravity,
                                         double max_step, double max_turn, Turning turning) {
  DriftMaxima m;
  drift_range(p, 0, p.n_local(), dt, gravity, turning, nullptr, m);
  return drift_result(p, m, dt, max_step, max_turn);
}

Integrator::Drift Integrator::first_half(ParticleStore& p, double dt, const Vec3& gravity,
                                         double max_step, double max_turn, Turning turning,
                                         const std::vector<Run>& runs,
                                         const SquaredSpeeds& others) {
  // Maxima are order-free: the runs' pass raised from the others' speeds gives the bits of
  // one pass over all of them.
  DriftMaxima m{others.v2, others.w2};
  for (const Run& run : runs)
    drift_range(p, run.begin, run.end, dt, gravity, turning, nullptr, m);
  return drift_result(p, m, dt, max_step, max_turn);
}

Integrator::SquaredSpeeds Integrator::squared_speeds(const ParticleStore& p,
                                                     const std::vector<Run>& runs) {
  // As FourLanes::raise(): a NaN counts as infinite.
  const auto raise = [](double& max, double a) {
    max = a <= max ? max : (a == a ? a : std::numeric_limits<double>::infinity());
  };
  SquaredSpeeds s;
  for (const Run& run : runs)
    for (std::size_t k = run.begin; k < run.end; ++k) {
      raise(s.v2, norm2(p.velocity[k]));
      raise(s.w2, norm2(p.omega[k]));
    }
  return s;
}

void Integrator::drift_unloaded(ParticleStore& p, double dt, const std::vector<Run>& runs,
                                int drifts) {
  // drift() and kick_four() of a free particle whose loads are zero: v + 0 dt/2m (which
  // leaves v, but for a -0 component, as those passes do), x + v dt for each drift.
  // The drifts of a block of particles at once, each step over the whole block: a particle's
  // drifts are a chain of dependent additions, and chained one particle at a time they waited
  // on each other's latency (a tenth of a 10^5-grain channel's run on one rank).
  constexpr std::size_t kBlock = 16;
  double x[3 * kBlock] = {}, step[3 * kBlock] = {};  // a short block leaves old values past n
  for (const Run& run : runs)
    for (std::size_t first = run.begin; first < run.end; first += kBlock) {
      const std::size_t n = std::min(kBlock, run.end - first);
      // Component by component through flat arrays: a Vec3 built in a register pair and read
      // back whole stalled on store forwarding at every particle.
      double* const v = &p.velocity[first].x;
      double* const w = &p.omega[first].x;
      const double* const x0 = &p.position[first].x;
      for (std::size_t c = 0; c < 3 * n; ++c) {
        v[c] = v[c] + 0.0;
        w[c] = w[c] + 0.0;
        x[c] = x0[c];
        step[c] = v[c] * dt;  // each drift's v dt, the same product every time
      }
      for (int d = 0; d < drifts; ++d)
        for (std::size_t c = 0; c < 3 * kBlock; ++c)
          x[c] = x[c] + step[c];
      double* const x1 = &p.position[first].x;
      for (std::size_t c = 0; c < 3 * n; ++c)
        x1[c] = x[c];
    }
}

namespace {

inline V4 magnitude(const V4& a) {
  return lanes::abs(a);
}
inline lanes8::V8 magnitude(const lanes8::V8& a) {
  return lanes8::abs(a);
}

/// The Cundall load of each component of a register of rows of loads against their velocities
/// (damping_component, lane by lane; four lanes or eight), taken off where the particle is
/// damped; the velocities take their kick from the damped loads, and `power` gets each
/// component's damping power at the new velocity.
template <class V>
inline void damp_and_kick(V& load, V& velocity, const V& alpha, const V& factor, V& power) {
  const V zero{}, one = zero + 1.0;
  const V sign = (velocity > zero ? one : zero) - (velocity < zero ? one : zero);
  const V df = alpha * magnitude(load) * sign;
  const V g = alpha != zero ? load - df : load;
  load = g;
  velocity = velocity + g * factor;
  power = df * velocity;
}

/// The damped second half kick of the four or eight particles (Lanes) from k, with the
/// ledger's global-damping columns where the store keeps them; its factors go to `keep` (one
/// HalfKicks a four) where it is not null.
template <class Lanes>
inline void damped_kick(const ParticleRows& r, std::size_t k, double dt, HalfKicks* keep) {
  using V = typename Lanes::V;
  using Rows = typename Lanes::Rows;
  const V zero{}, one = zero + 1.0;
  // kick_factors() lane by lane.
  const V free = Lanes::kinds(r.motion + k) == zero ? one : zero;
  const V mass = Lanes::load(r.mass + k), radius = Lanes::load(r.radius + k);
  const V free_half = free * (0.5 * dt);
  const V kick_factor = free_half / mass;
  const V turn_factor = free_half / (0.4 * mass * radius * radius);  // sphere_inertia's order
  if (keep) Lanes::keep(keep, kick_factor, turn_factor);
  const V alpha_lanes = Lanes::load(r.alpha + k);
  const Rows alpha = Lanes::spread(alpha_lanes), kick = Lanes::spread(kick_factor),
             turn = Lanes::spread(turn_factor);
  Rows force = Lanes::load_rows(r.force + k), v = Lanes::load_rows(r.v + k);
  Rows torque = Lanes::load_rows(r.torque + k), w = Lanes::load_rows(r.w + k);
  Rows force_power, torque_power;
  damp_and_kick(force.a, v.a, alpha.a, kick.a, force_power.a);
  damp_and_kick(force.b, v.b, alpha.b, kick.b, force_power.b);
  damp_and_kick(force.c, v.c, alpha.c, kick.c, force_power.c);
  damp_and_kick(torque.a, w.a, alpha.a, turn.a, torque_power.a);
  damp_and_kick(torque.b, w.b, alpha.b, turn.b, torque_power.b);
  damp_and_kick(torque.c, w.c, alpha.c, turn.c, torque_power.c);
  // The damped loads stay for the next step.
  Lanes::store_rows(r.force + k, force);
  Lanes::store_rows(r.torque + k, torque);
  Lanes::store_rows(r.v + k, v);
  Lanes::store_rows(r.w + k, w);
  if (r.dissipated == nullptr) return;
  // Energy ledger: the power the Cundall loads take out, at the synchronised velocity v^{n+1}
  // just computed (docs/physics.md "Energy ledger").
  const V q = free * (Lanes::component_sum(force_power) + Lanes::component_sum(torque_power));
  const auto on = alpha_lanes != zero;
  const V dissipated = Lanes::load(r.dissipated + k), power = Lanes::load(r.power + k);
  Lanes::store(r.dissipated + k, on ? dissipated + q * dt : dissipated);
  Lanes::store(r.power + k, on ? q : (power != zero ? zero : power));
}

/// The undamped second half kick of four particles from k; its factors go to `keep` where it
/// is not null.
inline void kick_four(const ParticleRows& r, std::size_t k, double dt, HalfKicks* keep) {
  const KickFactors f = kick_factors(r, k, 0.5 * dt);
  if (keep) *keep = {f.kick, f.turn};
  Rows3 v = lanes::load_rows(r.v + k), w = lanes::load_rows(r.w + k);
  add_scaled(v, lanes::load_rows(r.force + k), lanes::spread(f.kick));   // v += F dt/2m
  add_scaled(w, lanes::load_rows(r.torque + k), lanes::spread(f.turn));  // omega += T dt/2I
  lanes::store_rows(r.v + k, v);
  lanes::store_rows(r.w + k, w);
}

/// The second half kick of owned particles [begin, end), one chunk of Integrator::kChunk; the
/// factors of each four from begin go to `keep` where it is not null.
void second_half_chunk(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                       HalfKicks* keep) {
  const auto kept = [keep](std::size_t group) { return keep ? keep + group : nullptr; };
  const ParticleRows r = rows_of(p);
  // Each chunk goes one of two ways: without Cundall arithmetic where no particle of the
  // chunk is damped (most grains), with it elsewhere (the net). An undamped particle gets the
  // same bits either way (its loads stay as they are, its power goes to 0 only if it was not),
  // so the result does not depend on which particles share its chunk, that is on the rank
  // count. Counted in doubles (select_bits), so that the check is a vector loop.
  double damped_count = 0.0, stale_count = 0.0;
  if (r.alpha)
#pragma omp simd reduction(+ : damped_count)
    for (std::size_t k = begin; k < end; ++k)
      damped_count += select_bits(r.alpha[k] != 0.0, 1.0, 0.0);
  if (damped_count > 0.0) {
    std::size_t k = begin, group = 0;
    for (; k + 8 <= end; k += 8, group += 2)
      damped_kick<EightLanes>(r, k, dt, kept(group));
    for_each_four(r, k, end, [&](const ParticleRows& rows, std::size_t four, std::size_t g) {
      damped_kick<FourLanes>(rows, four, dt, kept(group + g));
    });
    return;
  }
  // Only a coefficient that just went to 0 leaves a last power to clear (counted first,
  // read-only: storing back every particle's zero would dirty a cache line per 8 grains in
  // the flows' memory-bound pass).
  if (r.power) {
#pragma omp simd reduction(+ : stale_count)
    for (std::size_t k = begin; k < end; ++k)
      stale_count += select_bits(r.power[k] != 0.0, 1.0, 0.0);
    if (stale_count > 0.0)
      for (std::size_t k = begin; k < end; ++k)
        r.power[k] = r.power[k] != 0.0 ? 0.0 : r.power[k];
  }
  for_each_four(r, begin, end, [&](const ParticleRows& rows, std::size_t k, std::size_t group) {
    kick_four(rows, k, dt, kept(group));
  });
}

}  // namespace

void Integrator::second_half(ParticleStore& p, double dt) {
  const std::size_t n = p.n_local();
  for (std::size_t begin = 0; begin < n; begin += kChunk)
    second_half_chunk(p, begin, std::min(n, begin + kChunk), dt, nullptr);
}

void Integrator::second_half(ParticleStore& p, double dt, const std::vector<Run>& runs) {
  // Which particles share a chunk does not change their bits (second_half_chunk()).
  for (const Run& run : runs)
    for (std::size_t begin = run.begin; begin < run.end; begin += kChunk)
      second_half_chunk(p, begin, std::min(run.end, begin + kChunk), dt, nullptr);
}

Integrator::Drift Integrator::second_then_first_half(
    ParticleStore& p, double dt, const Vec3& gravity, double max_step, double max_turn,
    Turning turning, const std::function<void(std::size_t end)>& between) {
  // Block by block, while a block's particles are in cache: the same operations on each
  // particle in the same order as second_half(), between(), first_half(), so the same bits,
  // with one pass from memory over the particles' columns instead of three.
  // The second half kicks' factors wait in `kept` for the drift (HalfKicks): 256 kB, in the
  // caches with the block.
  static_assert(kBlock % kChunk == 0 && kChunk % 4 == 0);
  static thread_local std::vector<HalfKicks> kept(kBlock / 4);
  const std::size_t n = p.n_local();
  DriftMaxima m;
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t end = std::min(n, begin + kBlock);
    for (std::size_t c = begin; c < end; c += kChunk)
      second_half_chunk(p, c, std::min(end, c + kChunk), dt, kept.data() + (c - begin) / 4);
    between(end);
    drift_range(p, begin, end, dt, gravity, turning, kept.data(), m);
  }
  return drift_result(p, m, dt, max_step, max_turn);
}

void apply_global_damping(ParticleStore& p, double dt) {
  if (!p.tracks_damping()) return;  // nothing in the model is damped
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const Vec3 damping_force = damping_load(p.force[k], p.velocity[k], p.damping[k]);
    const Vec3 damping_torque = damping_load(p.torque[k], p.omega[k], p.damping[k]);
    p.force[k] -= damping_force;
    p.torque[k] -= damping_torque;
    if (!p.books_global_damping()) continue;
    // The ledger's first trapezoid weight: the tally so far is kept and the power of the
    // initial loads enters with dt/2 (see ParticleStore::ledger_value).
    const double q = p.motion[k] == Motion::kFree
                         ? dot(damping_force, p.velocity[k]) + dot(damping_torque, p.omega[k])
                         : 0.0;
    const double tally = ParticleStore::ledger_value(p.dissipated_global[k], p.power_global[k], dt);
    p.power_global[k] = q;
    p.dissipated_global[k] = tally + 0.5 * dt * q;
  }
}

void Integrator::kick(ParticleStore& p, const std::vector<Vec3>& force,
                      const std::vector<Vec3>& torque, double half_dt) {
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.motion[k] != Motion::kFree) continue;
    p.velocity[k] += force[k] * (half_dt / p.mass[k]);
    p.omega[k] += torque[k] * (half_dt / p.inertia(k));
  }
}

}  // namespace ringdem

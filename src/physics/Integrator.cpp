#include "physics/Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

#include "physics/IntegratorLanes.hpp"

// The drift (first half of a step) of the particle passes; the kicks are in
// physics/IntegratorKicks.cpp, the rigid bodies' step in physics/IntegratorBodies.cpp.

namespace ringdem {

namespace integrator_lanes {
namespace {

/// The drift of the four or eight particles (Lanes) from k: v += F dt/2m, omega += T dt/2I,
/// x += v dt, the next step's initial loads (F = m g, T = 0; GatherMap::initialise_loads) and
/// the largest squared speeds per lane of four.
/// `kept`: the factors of this step's second half kick, one HalfKicks a four (kick_factors()
/// otherwise). `turn`, where not null, gets the half turns h = omega moving dt/2 as columns
/// for the orientation pass, one Columns3 a four.
template <class Lanes>
inline void drift(const ParticleRows& r, std::size_t k, double dt,
                  const typename Lanes::Rows& gravity, const HalfKicks* kept, V4& max_v2,
                  V4& max_w2, VelocityLanes* velocities, Columns3* turn) {
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
  const typename Lanes::Columns wc = Lanes::columns(w), vc = Lanes::columns(v);
  Lanes::raise(max_v2, Lanes::norm2(vc));
  if (velocities) Lanes::widen(*velocities, vc);
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
/// out; raises `m` to the largest squared speeds it saw and widens its box of velocities.
/// `kept`: the second half kick's factors of each four from begin, or null.
template <bool kTurn>
void drift_range(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                 const Vec3& gravity, const std::uint8_t* turning, const HalfKicks* kept,
                 DriftMaxima& m) {
  // The components of gravity in the layout of four rows.
  const Rows3 gravity_rows = FourLanes::rows_of(gravity);
  const lanes8::Rows3 gravity_eight = EightLanes::rows_of(gravity);
  V4 max_v2 = lanes::splat(m.max_v2), max_w2 = lanes::splat(m.max_w2);
  VelocityLanes velocities;
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
                        max_v2, max_w2, &velocities, kTurn ? turns + group : nullptr);
    for_each_four(rows, k, c_end, [&](const ParticleRows& r, std::size_t four, std::size_t g) {
      // The last few particles' lanes are padded with fixed particles at rest (TailLanes),
      // which are no particles' velocities: theirs join the box below.
      const bool tail = r.v != rows.v;
      drift<FourLanes>(r, four, dt, gravity_rows, chunk_kept ? chunk_kept + group + g : nullptr,
                       max_v2, max_w2, tail ? nullptr : &velocities,
                       kTurn ? turns + group + g : nullptr);
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
  velocities.fold_into(m.velocities);
  for (std::size_t k = end - (end - begin) % 4; k < end; ++k)
    m.velocities.add(p.velocity[k]);
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
  Integrator::Drift d{std::sqrt(m.max_v2), worst, 0, m.velocities};
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
}  // namespace integrator_lanes

using integrator_lanes::drift_range;
using integrator_lanes::drift_result;
using integrator_lanes::DriftMaxima;
using integrator_lanes::HalfKicks;
using integrator_lanes::second_half_chunk;

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
  DriftMaxima m{others.v2, others.w2, others.velocities};
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
      s.velocities.add(p.velocity[k]);
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

}  // namespace ringdem

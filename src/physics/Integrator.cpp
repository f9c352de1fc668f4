#include "physics/Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "core/Select.hpp"

namespace ringdem {

namespace {

/// The Cundall damping load alpha |f| sign(v) of one component, taken off f.
inline double damping_component(double f, double v, double alpha) {
  // sign(0) = 0: a particle at rest is not pushed. In doubles (an int here would make the
  // vectoriser size the damped kick's vectors by 32-bit lanes, see kick_factors()) and by
  // select_bits (AVX2).
  const double s = select_bits(v > 0.0, 1.0, 0.0) - select_bits(v < 0.0, 1.0, 0.0);
  return alpha * std::abs(f) * s;
}

/// Cundall damping load of one vector load against its velocity: the damped load is
/// f - damping_load(f, v, alpha); alpha = 0 leaves f bit for bit.
inline Vec3 damping_load(const Vec3& f, const Vec3& v, double alpha) {
  return {damping_component(f.x, v.x, alpha), damping_component(f.y, v.y, alpha),
          damping_component(f.z, v.z, alpha)};
}

/// Returns dq(omega dt) q with the Cayley form dq(phi) = (1, phi/2) / sqrt(1 + |phi|^2/4): a unit
/// quaternion of angle 2 atan(|phi|/2) = |phi| (1 - |phi|^2/12 + ...), exactly inverted by
/// dq(-phi), so the update stays time-reversible; for |omega dt| ~ 1e-5 the angle error is
/// ~1e-11 relative, and it needs one square root instead of sin, cos and a norm.
inline Quat rotated(const Quat& q, const Vec3& omega, double dt) {
  const Vec3 h = omega * (0.5 * dt);
  const double s = 1.0 / std::sqrt(1.0 + norm2(h));
  return renormalized(Quat{s, h.x * s, h.y * s, h.z * s} * q);
}

/// Angular velocity update of a rigid body with principal inertia I (body frame).
inline void kick_rotation(RigidBody& b, double half_dt) {
  const Mat3 r = rotation_matrix(b.orientation);
  const Vec3 w_body = r.transpose_times(b.omega);
  const Vec3& i = b.principal_inertia;
  const Vec3 l_body{w_body.x * i.x, w_body.y * i.y, w_body.z * i.z};
  const Vec3 l = r * l_body + b.torque * half_dt;
  const Vec3 l_new = r.transpose_times(l);
  b.omega = r * Vec3{l_new.x / i.x, l_new.y / i.y, l_new.z / i.z};
}

}  // namespace

// The particle loops are branch-free (motion kinds become 0/1 factors) so they vectorise.
// A fixed particle has zero velocity and angular velocity (the model builder sets them), so
// scaling its drift by 0 only guards against stray values.

namespace {

struct DriftMaxima {
  double max_v2 = 0.0;  ///< infinite for a non-finite velocity
  double max_w2 = 0.0;
};

// The kicks and the drift read and write rows of Vec3 (x, y, z of a particle side by side).
// A vector loop over particles has to take such rows apart into x, y and z lanes and put them
// back together, a shuffle per register on the way in and out, and that, not arithmetic or
// memory, was most of the integrator's time. So within a chunk the per-particle factors
// (kick = dt/2m, ...) are spread over the three components once, and the updates run over the
// chunk's rows as one run of doubles, lane for lane: the same operation on each component as
// the Vec3 arithmetic, so the same bits.
static_assert(sizeof(Vec3) == 3 * sizeof(double), "Vec3 rows must be runs of 3 doubles");

/// 1 for a free particle, else 0; 1 for one that moves (free or driven), else 0. In integer
/// arithmetic, not as a select: GCC does not vectorise a select on a byte compare for AVX2
/// (-march=x86-64-v3), only with AVX-512 masks, and the loops that read these stayed scalar.
static_assert(static_cast<int>(Motion::kFree) == 0 && static_cast<int>(Motion::kFixed) == 1 &&
              static_cast<int>(Motion::kPrescribed) == 2);
inline double is_free(Motion m) {
  return static_cast<double>(1 - std::min(static_cast<int>(m), 1));
}
inline double is_moving(Motion m) {
  return static_cast<double>(std::min(std::abs(static_cast<int>(m) - 1), 1));
}

double* run_of(Vec3* rows) {
  return &rows->x;
}

/// out[3 i + c] = f[i] for c = 0, 1, 2 and i < n: a factor per particle for each component.
inline void spread3(const double* __restrict f, std::size_t n, double* __restrict out) {
  for (std::size_t i = 0; i < n; ++i) {
    out[3 * i] = f[i];
    out[3 * i + 1] = f[i];
    out[3 * i + 2] = f[i];
  }
}

/// a[j] += b[j] s[j], j < n: Vec3 rows a += b * factor, component by component.
inline void add_scaled(double* __restrict a, const double* __restrict b, const double* __restrict s,
                       std::size_t n) {
#pragma omp simd
  for (std::size_t j = 0; j < n; ++j)
    a[j] += b[j] * s[j];
}

/// The half-kick factors of particles [begin, begin + n), n <= Integrator::kChunk: free[i] (1
/// for a free particle, else 0), kick[i] = free dt/2m and turn[i] = free dt/2I. The motion
/// kinds are read in a loop of their own: GCC sizes a loop's vectors by its narrowest type, so
/// a byte column among doubles makes it run 64 particles at a time, eight registers a double,
/// and spill them.
inline void kick_factors(const ParticleStore& p, std::size_t begin, std::size_t n, double half,
                         double* __restrict free, double* __restrict kick,
                         double* __restrict turn) {
  const Motion* const motion = p.motion.data() + begin;
  const double* const mass = p.mass.data() + begin;
  const double* const radius = p.radius.data() + begin;
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i)
    free[i] = is_free(motion[i]);
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    kick[i] = free[i] * half / mass[i];
    turn[i] = free[i] * half / ParticleStore::sphere_inertia(mass[i], radius[i]);
  }
}

/// The drift loop over owned particles [begin, end), chunk by chunk, with the orientation
/// update compiled in or out; raises `m` to the largest squared speeds it saw.
template <bool kTurn>
void drift_range(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                 const Vec3& gravity, DriftMaxima& m) {
  constexpr std::size_t kChunk = Integrator::kChunk;
  const double half = 0.5 * dt;
  const Motion* const motion = p.motion.data();
  const double* const mass = p.mass.data();
  Vec3* const v = p.velocity.data();
  Vec3* const w = p.omega.data();
  Quat* const q = p.orientation.data();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  // The components of gravity, repeated along a run.
  double gravity_run[3 * kChunk];
  for (std::size_t j = 0; j < 3 * kChunk; j += 3) {
    gravity_run[j] = gravity.x;
    gravity_run[j + 1] = gravity.y;
    gravity_run[j + 2] = gravity.z;
  }
  double free[kChunk], kick[kChunk], turn[kChunk], step[kChunk], moving[kChunk];
  double kick_run[3 * kChunk], turn_run[3 * kChunk], step_run[3 * kChunk], mass_run[3 * kChunk];
  double max_v2 = m.max_v2, max_w2 = m.max_w2;
  for (std::size_t c = begin; c < end; c += kChunk) {
    const std::size_t n = std::min(end - c, kChunk), n3 = 3 * n;
    kick_factors(p, c, n, half, free, kick, turn);
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i)
      moving[i] = is_moving(motion[c + i]);  // a loop of its own, as in kick_factors()
#pragma omp simd
    for (std::size_t i = 0; i < n; ++i)
      step[i] = moving[i] * dt;
    spread3(kick, n, kick_run);
    spread3(turn, n, turn_run);
    spread3(step, n, step_run);
    spread3(mass + c, n, mass_run);
    double* const vr = run_of(v + c);
    double* const wr = run_of(w + c);
    double* const fr = run_of(p.force.data() + c);
    double* const tr = run_of(p.torque.data() + c);
    add_scaled(vr, fr, kick_run, n3);                             // v += F dt/2m
    add_scaled(wr, tr, turn_run, n3);                             // omega += T dt/2I
    add_scaled(run_of(p.position.data() + c), vr, step_run, n3);  // x += v dt
    // The next step's initial load (GatherMap::initialise_loads): F = m g, T = 0.
#pragma omp simd
    for (std::size_t j = 0; j < n3; ++j) {
      fr[j] = gravity_run[j] * mass_run[j];
      tr[j] = 0.0;
    }
    if constexpr (kTurn)
      for (std::size_t i = 0; i < n; ++i)
        q[c + i] = rotated(q[c + i], w[c + i] * moving[i], dt);
        // The largest squared speeds, scaled after the loop: scaling by a positive constant keeps
        // the order, so max(scaled) is the scaled max. NaN compares false: it counts as infinite.
#pragma omp simd reduction(max : max_v2, max_w2)
    for (std::size_t k = c; k < c + n; ++k) {
      const double v2 = norm2(v[k]), w2 = norm2(w[k]);
      max_v2 = v2 <= max_v2 ? max_v2 : (v2 == v2 ? v2 : kInfinity);
      max_w2 = w2 <= max_w2 ? max_w2 : (w2 == w2 ? w2 : kInfinity);
    }
  }
  m.max_v2 = max_v2;
  m.max_w2 = max_w2;
}

void drift_range(ParticleStore& p, std::size_t begin, std::size_t end, double dt,
                 const Vec3& gravity, bool orientations, DriftMaxima& m) {
  if (orientations)
    drift_range<true>(p, begin, end, dt, gravity, m);
  else
    drift_range<false>(p, begin, end, dt, gravity, m);
}

/// What the drift passes saw (their largest squared speeds, order-free maxima) as the
/// Integrator's Drift: the worst runaway ratio and, only when something ran away, which
/// particle (the first of the largest ratio).
Integrator::Drift drift_result(const ParticleStore& p, const DriftMaxima& m, double dt,
                               double max_step, double max_turn) {
  const double step_scale = dt * dt / (max_step * max_step);
  const double turn_scale = dt * dt / (max_turn * max_turn);
  const double s = m.max_v2 * step_scale, t = m.max_w2 * turn_scale;
  const double worst = std::min(s > t ? s : t, Integrator::kRunaway);
  Integrator::Drift d{std::sqrt(m.max_v2), worst, 0};
  if (worst > 1.0)
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      const double sk = norm2(p.velocity[k]) * step_scale, tk = norm2(p.omega[k]) * turn_scale;
      double r = sk > tk ? sk : tk;
      r = r <= Integrator::kRunaway ? r : Integrator::kRunaway;
      if (r == worst) {
        d.worst_index = k;
        break;
      }
    }
  return d;
}

}  // namespace

Integrator::Drift Integrator::first_half(ParticleStore& p, double dt, const Vec3& gravity,
                                         double max_step, double max_turn, bool orientations) {
  DriftMaxima m;
  drift_range(p, 0, p.n_local(), dt, gravity, orientations, m);
  return drift_result(p, m, dt, max_step, max_turn);
}

namespace {

/// The second half kick of owned particles [begin, end), one chunk of Integrator::kChunk.
void second_half_chunk(ParticleStore& p, std::size_t begin, std::size_t end, double dt) {
  const double half = 0.5 * dt;
  // No coefficients where nothing in the model is damped (ParticleStore::tracks_damping()).
  const double* const alpha = p.tracks_damping() ? p.damping.data() : nullptr;
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  Vec3* const v = p.velocity.data();
  Vec3* const w = p.omega.data();
  // The ledger's columns, or null where the store keeps none (simulation.energy_ledger: false,
  // or nothing damped).
  const bool ledger = p.books_global_damping();
  double* const dissipated = ledger ? p.dissipated_global.data() : nullptr;
  double* const power = ledger ? p.power_global.data() : nullptr;
  // Each chunk goes through one of two branch-free loops that vectorise: without
  // Cundall arithmetic where no particle of the chunk is damped (most grains), with it
  // elsewhere (the net). An undamped particle gets the same bits on either path (its loads stay
  // as they are, its power goes to 0 only if it was not), so the result does not depend on
  // which particles share its chunk, that is on the rank count.
  // Counted in doubles (select_bits), so that the check is a vector loop too.
  double damped_count = 0.0, stale_count = 0.0;
  if (alpha)
#pragma omp simd reduction(+ : damped_count)
    for (std::size_t k = begin; k < end; ++k)
      damped_count += select_bits(alpha[k] != 0.0, 1.0, 0.0);
  if (ledger)
#pragma omp simd reduction(+ : stale_count)
    for (std::size_t k = begin; k < end; ++k)
      stale_count += select_bits(power[k] != 0.0, 1.0, 0.0);
  const bool damped = damped_count > 0.0;
  constexpr std::size_t kChunk = Integrator::kChunk;
  const std::size_t n = end - begin, n3 = 3 * n;
  double free[kChunk], kick[kChunk], turn[kChunk], kick_run[3 * kChunk], turn_run[3 * kChunk];
  kick_factors(p, begin, n, half, free, kick, turn);
  if (!damped) {
    // Only a coefficient that just went to 0 leaves a last power to clear (counted above,
    // read-only: storing back every particle's zero would dirty a cache line per 8 grains in
    // the flows' memory-bound pass).
    if (stale_count > 0.0)
      for (std::size_t k = begin; k < end; ++k)
        power[k] = power[k] != 0.0 ? 0.0 : power[k];
    spread3(kick, n, kick_run);
    spread3(turn, n, turn_run);
    add_scaled(run_of(v + begin), run_of(force + begin), kick_run, 3 * n);   // v += F dt/2m
    add_scaled(run_of(w + begin), run_of(torque + begin), turn_run, 3 * n);  // omega += T dt/2I
    return;
  }
  // Damped: the Cundall load of each component (damping_component) comes off only where the
  // particle is damped, with selects (select_bits) so that the loop stays branch-free.
  double alpha_run[3 * kChunk], force_power[3 * kChunk], torque_power[3 * kChunk];
  spread3(kick, n, kick_run);
  spread3(turn, n, turn_run);
  spread3(alpha + begin, n, alpha_run);
  // One Vec3 row pair (load, velocity) as runs: the damped load stays for the next step, the
  // velocity takes its kick, and each component's damping power at the new velocity is kept.
  const auto damp_and_kick = [n3, &alpha_run](double* __restrict load, double* __restrict vel,
                                              const double* __restrict factor,
                                              double* __restrict power_run) {
#pragma omp simd
    for (std::size_t j = 0; j < n3; ++j) {
      const double a = alpha_run[j];
      const double f = load[j];
      const double df = damping_component(f, vel[j], a);
      const double g = select_bits(a != 0.0, f - df, f);
      load[j] = g;
      const double v_new = vel[j] + g * factor[j];
      vel[j] = v_new;
      power_run[j] = df * v_new;
    }
  };
  damp_and_kick(run_of(force + begin), run_of(v + begin), kick_run, force_power);
  damp_and_kick(run_of(torque + begin), run_of(w + begin), turn_run, torque_power);
  if (!ledger) return;
#pragma omp simd
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t k = begin + i;
    const bool on = alpha[k] != 0.0;
    // Energy ledger: the power the Cundall loads take out, at the synchronised velocity
    // v^{n+1} just computed (docs/physics.md "Energy ledger").
    const double* const fp = force_power + 3 * i;
    const double* const tp = torque_power + 3 * i;
    const double q = free[i] * ((fp[0] + fp[1] + fp[2]) + (tp[0] + tp[1] + tp[2]));
    dissipated[k] = select_bits(on, dissipated[k] + q * dt, dissipated[k]);
    power[k] = select_bits(on, q, select_bits(power[k] != 0.0, 0.0, power[k]));
  }
}

}  // namespace

void Integrator::second_half(ParticleStore& p, double dt) {
  const std::size_t n = p.n_local();
  for (std::size_t begin = 0; begin < n; begin += kChunk)
    second_half_chunk(p, begin, std::min(n, begin + kChunk), dt);
}

Integrator::Drift Integrator::second_then_first_half(
    ParticleStore& p, double dt, const Vec3& gravity, double max_step, double max_turn,
    bool orientations, const std::function<void(std::size_t end)>& between) {
  // Block by block, while a block's particles are in cache: the same operations on each
  // particle in the same order as second_half(), between(), first_half(), so the same bits,
  // with one pass from memory over the particles' columns instead of three.
  const std::size_t n = p.n_local();
  DriftMaxima m;
  for (std::size_t begin = 0; begin < n; begin += kBlock) {
    const std::size_t end = std::min(n, begin + kBlock);
    for (std::size_t c = begin; c < end; c += kChunk)
      second_half_chunk(p, c, std::min(end, c + kChunk), dt);
    between(end);
    drift_range(p, begin, end, dt, gravity, orientations, m);
  }
  return drift_result(p, m, dt, max_step, max_turn);
}

void Integrator::first_half(std::vector<RigidBody>& bodies, double dt, const Vec3& gravity) {
  const double half = 0.5 * dt;
  for (auto& b : bodies) {
    if (b.motion == Motion::kFixed) continue;
    if (b.motion == Motion::kFree) {
      const Vec3 f = b.force + (b.gravity ? gravity * b.mass : Vec3{});
      b.velocity += f * (half / b.mass);
      kick_rotation(b, half);
    }
    b.position += b.velocity * dt;
    b.orientation = rotated(b.orientation, b.omega, dt);
  }
}

void Integrator::second_half(std::vector<RigidBody>& bodies, double dt, const Vec3& gravity) {
  const double half = 0.5 * dt;
  for (auto& b : bodies) {
    if (b.motion != Motion::kFree) continue;
    const Vec3 f = b.force + (b.gravity ? gravity * b.mass : Vec3{});
    b.velocity += f * (half / b.mass);
    kick_rotation(b, half);
  }
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

}  // namespace ringdem

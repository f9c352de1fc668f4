#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "core/Select.hpp"
#include "physics/Integrator.hpp"
#include "physics/IntegratorLanes.hpp"

// The second half kick of the particle passes, the Cundall damping they apply, and the kicks
// of multi-rate stepping; the drift is in physics/Integrator.cpp.

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

namespace integrator_lanes {

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

}  // namespace

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

}  // namespace integrator_lanes

using integrator_lanes::second_half_chunk;

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

void Integrator::kick(ParticleStore& p, std::vector<Vec3>& force, std::vector<Vec3>& torque,
                      double half_dt) {
  // The passes' undamped kick (kick_four) over these loads: per lane v + F (half_dt / m) and
  // omega + T (half_dt / 0.4 m r^2), the operations of one particle at a time in their order,
  // so the same bits; a held particle's factors are zero. One particle at a time, with two
  // divisions each, this was about 4.5 % of the sub-stepped debris demo.
  integrator_lanes::ParticleRows r = integrator_lanes::rows_of(p);
  r.force = force.data();
  r.torque = torque.data();
  // kick_four() kicks by half of the step it is given.
  const double dt = 2.0 * half_dt;
  integrator_lanes::for_each_four(
      r, 0, p.n_local(),
      [dt](const integrator_lanes::ParticleRows& rows, std::size_t k, std::size_t) {
        integrator_lanes::kick_four(rows, k, dt, nullptr);
      });
}

}  // namespace ringdem

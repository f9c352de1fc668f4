#include "physics/Integrator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace ringdem {

namespace {

/// The Cundall damping load alpha |f| sign(v) of one component, taken off f.
inline double damping_component(double f, double v, double alpha) {
  // sign(0) = 0: a particle at rest is not pushed.
  const double s = (v > 0.0) - (v < 0.0);
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
  double worst = 0.0;
};

/// The drift loop, with the orientation update compiled in or out.
template <bool kTurn>
DriftMaxima drift_pass(ParticleStore& p, double dt, const Vec3& gravity, double step_scale,
                       double turn_scale) {
  const double half = 0.5 * dt;
  const std::size_t n = p.n_local();
  const Motion* const motion = p.motion.data();
  const double* const mass = p.mass.data();
  const double* const radius = p.radius.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  Vec3* const v = p.velocity.data();
  Vec3* const w = p.omega.data();
  Vec3* const x = p.position.data();
  Quat* const q = p.orientation.data();
  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  double max_v2 = 0.0, max_w2 = 0.0;
#pragma omp simd reduction(max : max_v2, max_w2)
  for (std::size_t k = 0; k < n; ++k) {
    const double free = motion[k] == Motion::kFree ? 1.0 : 0.0;
    const double moving = motion[k] == Motion::kFixed ? 0.0 : 1.0;
    v[k] += force[k] * (free * half / mass[k]);
    w[k] += torque[k] * (free * half / ParticleStore::sphere_inertia(mass[k], radius[k]));
    x[k] += v[k] * (moving * dt);
    if constexpr (kTurn) q[k] = rotated(q[k], w[k] * moving, dt);
    // The next step's initial load (GatherMap::initialise_loads), component by component so
    // that the loop vectorises.
    force[k].x = gravity.x * mass[k];
    force[k].y = gravity.y * mass[k];
    force[k].z = gravity.z * mass[k];
    torque[k].x = 0.0;
    torque[k].y = 0.0;
    torque[k].z = 0.0;
    // The largest squared speeds, scaled after the loop: scaling by a positive constant keeps
    // the order, so max(scaled) is the scaled max. NaN compares false: it counts as infinite.
    const double v2 = norm2(v[k]), w2 = norm2(w[k]);
    max_v2 = v2 <= max_v2 ? max_v2 : (v2 == v2 ? v2 : kInfinity);
    max_w2 = w2 <= max_w2 ? max_w2 : (w2 == w2 ? w2 : kInfinity);
  }
  const double s = max_v2 * step_scale, t = max_w2 * turn_scale;
  const double worst = std::min(s > t ? s : t, Integrator::kRunaway);
  return {max_v2, worst};
}

}  // namespace

Integrator::Drift Integrator::first_half(ParticleStore& p, double dt, const Vec3& gravity,
                                         double max_step, double max_turn, bool orientations) {
  const std::size_t n = p.n_local();
  const Vec3* const v = p.velocity.data();
  const Vec3* const w = p.omega.data();
  const double step_scale = dt * dt / (max_step * max_step);
  const double turn_scale = dt * dt / (max_turn * max_turn);
  const DriftMaxima m = orientations ? drift_pass<true>(p, dt, gravity, step_scale, turn_scale)
                                     : drift_pass<false>(p, dt, gravity, step_scale, turn_scale);
  const double worst = m.worst;
  Drift d{std::sqrt(m.max_v2), worst, 0};
  // Only when something ran away: which particle (the first of the largest ratio).
  if (worst > 1.0)
    for (std::size_t k = 0; k < n; ++k) {
      const double s = norm2(v[k]) * step_scale, t = norm2(w[k]) * turn_scale;
      double r = s > t ? s : t;
      r = r <= kRunaway ? r : kRunaway;
      if (r == worst) {
        d.worst_index = k;
        break;
      }
    }
  return d;
}

void Integrator::second_half(ParticleStore& p, double dt) {
  const double half = 0.5 * dt;
  const std::size_t n = p.n_local();
  const Motion* const motion = p.motion.data();
  const double* const mass = p.mass.data();
  const double* const radius = p.radius.data();
  const double* const alpha = p.damping.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  Vec3* const v = p.velocity.data();
  Vec3* const w = p.omega.data();
  double* const dissipated = p.dissipated_global.data();
  double* const power = p.power_global.data();
  // Chunks of particles, each through one of two branch-free loops that vectorise: without
  // Cundall arithmetic where no particle of the chunk is damped (most grains), with it
  // elsewhere (the net). An undamped particle gets the same bits on either path (its loads stay
  // as they are, its power goes to 0 only if it was not), so the result does not depend on
  // which particles share its chunk, that is on the rank count.
  constexpr std::size_t kChunk = 64;
  for (std::size_t begin = 0; begin < n; begin += kChunk) {
    const std::size_t end = std::min(n, begin + kChunk);
    bool damped = false;
    for (std::size_t k = begin; k < end; ++k)
      damped = damped || alpha[k] != 0.0;
    if (!damped) {
#pragma omp simd
      for (std::size_t k = begin; k < end; ++k) {
        const double free = motion[k] == Motion::kFree ? 1.0 : 0.0;
        v[k] += force[k] * (free * half / mass[k]);
        w[k] += torque[k] * (free * half / ParticleStore::sphere_inertia(mass[k], radius[k]));
        // Only a coefficient that just went to 0 leaves a last power to clear.
        power[k] = power[k] != 0.0 ? 0.0 : power[k];
      }
      continue;
    }
#pragma omp simd
    for (std::size_t k = begin; k < end; ++k) {
      const double free = motion[k] == Motion::kFree ? 1.0 : 0.0;
      const double a = alpha[k];
      const bool on = a != 0.0;
      // Component by component, with selects, so that the compiler blends them: the Cundall
      // load of each component (damping_component) comes off only where the particle is damped.
      const double fx = force[k].x, fy = force[k].y, fz = force[k].z;
      const double tx = torque[k].x, ty = torque[k].y, tz = torque[k].z;
      const double dfx = damping_component(fx, v[k].x, a), dfy = damping_component(fy, v[k].y, a),
                   dfz = damping_component(fz, v[k].z, a);
      const double dtx = damping_component(tx, w[k].x, a), dty = damping_component(ty, w[k].y, a),
                   dtz = damping_component(tz, w[k].z, a);
      const double gx = on ? fx - dfx : fx, gy = on ? fy - dfy : fy, gz = on ? fz - dfz : fz;
      const double hx = on ? tx - dtx : tx, hy = on ? ty - dty : ty, hz = on ? tz - dtz : tz;
      force[k].x = gx;
      force[k].y = gy;
      force[k].z = gz;
      torque[k].x = hx;
      torque[k].y = hy;
      torque[k].z = hz;
      const double kick = free * half / mass[k],
                   turn = free * half / ParticleStore::sphere_inertia(mass[k], radius[k]);
      const double vx = v[k].x + gx * kick, vy = v[k].y + gy * kick, vz = v[k].z + gz * kick;
      const double wx = w[k].x + hx * turn, wy = w[k].y + hy * turn, wz = w[k].z + hz * turn;
      v[k].x = vx;
      v[k].y = vy;
      v[k].z = vz;
      w[k].x = wx;
      w[k].y = wy;
      w[k].z = wz;
      // Energy ledger: the power the Cundall loads take out, at the synchronised velocity
      // v^{n+1} just computed (docs/physics.md "Energy ledger").
      const double q = free * ((dfx * vx + dfy * vy + dfz * vz) + (dtx * wx + dty * wy + dtz * wz));
      dissipated[k] = on ? dissipated[k] + q * dt : dissipated[k];
      power[k] = on ? q : (power[k] != 0.0 ? 0.0 : power[k]);
    }
  }
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
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const Vec3 damping_force = damping_load(p.force[k], p.velocity[k], p.damping[k]);
    const Vec3 damping_torque = damping_load(p.torque[k], p.omega[k], p.damping[k]);
    p.force[k] -= damping_force;
    p.torque[k] -= damping_torque;
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

// Integrator's halves for the rigid bodies (physics.md §4): few bodies, one at a time, apart
// from the particles' vector passes in Integrator.cpp.
#include <vector>

#include "core/Quat.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {

namespace {

/// q <- dq(omega dt) q, the Cayley update (cayley_turned): for |omega dt| ~ 1e-5 the angle
/// error against the exponential map is ~1e-11 relative; time-reversible.
inline Quat rotated(const Quat& q, const Vec3& omega, double dt) {
  return cayley_turned(q, omega * (0.5 * dt));
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

}  // namespace ringdem

#include "domain/RigidBody.hpp"

#include <cmath>
#include <limits>

namespace ringdem {

double RigidBody::contact_radius() const {
  if (shape == RigidShape::kSphere) return radius;
  if (shape == RigidShape::kTorus) return tube_radius;
  return std::numeric_limits<double>::infinity();
}

double RigidBody::extent() const {
  switch (shape) {
    case RigidShape::kSphere:
      return radius;
    case RigidShape::kCylinder:
      return std::sqrt(radius * radius + half_length * half_length);
    case RigidShape::kTorus:
      return radius + tube_radius;
    case RigidShape::kPlane:
      break;
  }
  return std::numeric_limits<double>::infinity();
}

RigidBody::SurfacePoint RigidBody::closest_curved(const Vec3& p) const {
  const Vec3 d = p - position;
  switch (shape) {
    case RigidShape::kPlane:
      break;  // inline in closest()
    case RigidShape::kSphere: {
      const double r = norm(d);
      const Vec3 n = r > 0.0 ? d / r : Vec3{0, 0, 1};
      return {r - radius, n, position + n * radius};
    }
    case RigidShape::kCylinder: {
      const Vec3 a = rotate(orientation, {0, 0, 1});
      const double t = dot(d, a);
      const Vec3 radial = d - a * t;
      const double rho = norm(radial);
      const Vec3 e_r = rho > 0.0 ? radial / rho : any_perpendicular(a);
      const double cap_sign = t >= 0.0 ? 1.0 : -1.0;
      const bool within_length = std::abs(t) <= half_length;
      const bool within_radius = rho <= radius;
      if (within_length && !within_radius) {  // side
        return {rho - radius, e_r, position + a * t + e_r * radius};
      }
      if (!within_length && within_radius) {  // flat cap
        return {std::abs(t) - half_length, a * cap_sign, p - a * (t - cap_sign * half_length)};
      }
      if (!within_length && !within_radius) {  // rim edge
        const Vec3 rim = position + a * (cap_sign * half_length) + e_r * radius;
        const Vec3 off = p - rim;
        const double dist = norm(off);
        return {dist, dist > 0.0 ? off / dist : e_r, rim};
      }
      // Inside: leave through the nearer face.
      const double to_side = radius - rho;
      const double to_cap = half_length - std::abs(t);
      if (to_side <= to_cap) return {-to_side, e_r, position + a * t + e_r * radius};
      return {-to_cap, a * cap_sign, p + a * (cap_sign * to_cap)};
    }
    case RigidShape::kTorus: {
      // The nearest point of the centreline circle, then the tube around it.
      const Vec3 a = rotate(orientation, {0, 0, 1});
      const Vec3 radial = d - a * dot(d, a);
      const double rho = norm(radial);
      const Vec3 e_r = rho > 0.0 ? radial / rho : any_perpendicular(a);
      const Vec3 centreline = position + e_r * radius;
      const Vec3 off = p - centreline;
      const double dist = norm(off);
      const Vec3 n = dist > 0.0 ? off / dist : a;
      return {dist - tube_radius, n, centreline + n * tube_radius};
    }
  }
  return {std::numeric_limits<double>::infinity(), {0, 0, 1}, p};
}

}  // namespace ringdem

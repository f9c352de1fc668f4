#pragma once

#include <cstdint>
#include <string>

#include "core/Motion.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"

namespace ringdem {

enum class RigidShape : std::uint8_t { kPlane, kCylinder, kSphere, kTorus };

/// A large rigid body in contact with particles (plane, finite capped cylinder, sphere, torus:
/// a net's braked shackle).
/// Rigid bodies are few and replicated on every rank; they are not in the particle grid.
struct RigidBody {
  std::string name;
  RigidShape shape = RigidShape::kPlane;
  Motion motion = Motion::kFixed;
  std::int32_t material = 0;

  // Geometry in the body frame: plane normal and cylinder axis are the body z axis.
  double radius = 0.0;       ///< cylinder, sphere; torus: of its centreline circle
  double half_length = 0.0;  ///< cylinder
  double tube_radius = 0.0;  ///< torus: of its cross-section (the axis is the body z axis)

  // State.
  Vec3 position;  ///< centre (point on the plane)
  Quat orientation;
  Vec3 velocity;
  Vec3 omega;
  double mass = 0.0;       ///< free bodies
  Vec3 principal_inertia;  ///< free bodies, body frame
  bool gravity = true;
  /// False while a scenario holds the body out of play (the rockfall boulder before its
  /// release, parked far away at rest): nothing reads it but the frame output, which leaves
  /// the body out of the scene of such frames (docs/output.md).
  bool active = true;

  // Contact load of the current step, torque about position: the loads the particle contacts
  // put on the body, summed over every rank once the step reduces them. Set anew each step
  // (nothing is accumulated over steps) and without gravity, which the integrator adds.
  Vec3 force;
  Vec3 torque;

  /// Effective contact radius for Hertz (infinite for plane and cylinder: physics.md §3; a
  /// torus's tube radius, the smaller of its two curvature radii, as the shackle spheres').
  double contact_radius() const;
  /// Whether the body has finite mass in contacts.
  bool has_finite_mass() const { return motion == Motion::kFree; }

  /// Signed distance from point p to the surface and the outward unit normal there.
  struct SurfacePoint {
    double distance;  ///< > 0 outside
    Vec3 normal;      ///< outward
    Vec3 point;       ///< closest surface point
  };
  /// closest() of every shape but the plane.
  SurfacePoint closest_curved(const Vec3& p) const;
  /// A plane's outward normal (its local z axis).
  Vec3 plane_normal() const { return rotate(orientation, {0, 0, 1}); }
  /// The plane's case inline: a debris channel's bed and walls are most of the body contacts,
  /// and out of line its result went through the stack in pieces that a wide load read back
  /// (a store-forwarding stall, most of the call's time).
  SurfacePoint closest(const Vec3& p) const {
    if (shape == RigidShape::kPlane) {
      const Vec3 n = plane_normal();
      const double dist = dot(p - position, n);
      return {dist, n, p - n * dist};
    }
    return closest_curved(p);
  }

  /// Velocity of the body's material point at x.
  Vec3 velocity_at(const Vec3& x) const { return velocity + cross(omega, x - position); }

  /// Largest distance from position of any surface point that a particle can touch
  /// (infinite for a plane); used to bound how far the surface moved.
  double extent() const;
};

}  // namespace ringdem

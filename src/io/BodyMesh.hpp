#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/RigidBody.hpp"

namespace ringdem {

/// A triangulated surface of a rigid body for the frame files (docs/output.md, "Rigid
/// bodies"), in the body frame: vertices relative to the body's position, before its
/// orientation. Triangles are counter-clockwise seen from outside (normals point out of the
/// body, along the plane's normal for a plane).
struct BodyMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<std::int64_t, 3>> triangles;  ///< vertex numbers

  /// Sphere: a UV sphere of kStacks bands and kSlices meridians (482 vertices, 960 triangles).
  /// Cylinder: the side between the two rims of kSlices vertices and both flat caps as fans
  /// around their centres (66 vertices, 128 triangles). Plane: a square patch of half width
  /// `plane_half_width` centred at `plane_centre` (a world point, projected onto the plane;
  /// 4 vertices, 2 triangles), since a plane has no extent of its own.
  static BodyMesh of(const RigidBody& body, double plane_half_width, const Vec3& plane_centre);

  static constexpr int kStacks = 16;
  static constexpr int kSlices = 32;
  /// Torus: kTorusRings rings of kTorusTube vertices (128 vertices, 256 triangles).
  static constexpr int kTorusRings = 16;
  static constexpr int kTorusTube = 8;
};

/// World position of a body-frame point of `body`.
inline Vec3 body_to_world(const RigidBody& body, const Vec3& local) {
  return body.position + rotate(body.orientation, local);
}

}  // namespace ringdem

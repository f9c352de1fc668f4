#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <utility>

#include "io/BodyMesh.hpp"

namespace ringdem {
namespace {

RigidBody placed(RigidShape shape) {
  RigidBody b;
  b.shape = shape;
  b.radius = 0.3;
  b.half_length = 0.7;
  b.position = {1.5, -2.0, 0.25};
  b.orientation = quat_from_axis_angle({1, 2, -0.5}, 0.9);  // nothing axis-aligned
  return b;
}

/// Signed volume enclosed by a closed, outward-oriented triangle mesh (divergence theorem),
/// about the origin of the vertices' frame.
double enclosed_volume(const BodyMesh& m) {
  double v = 0.0;
  for (const auto& t : m.triangles)
    v += dot(m.vertices[t[0]], cross(m.vertices[t[1]], m.vertices[t[2]])) / 6.0;
  return v;
}

/// Every directed edge appears once and its reverse once: closed and consistently oriented.
void expect_closed(const BodyMesh& m) {
  std::map<std::pair<std::int64_t, std::int64_t>, int> edges;
  for (const auto& t : m.triangles)
    for (int k = 0; k < 3; ++k)
      ++edges[{t[k], t[(k + 1) % 3]}];
  for (const auto& [e, n] : edges) {
    EXPECT_EQ(n, 1) << e.first << "-" << e.second;
    EXPECT_EQ(edges.count({e.second, e.first}), 1u) << e.first << "-" << e.second;
  }
}

/// On the body's surface (RigidBody::closest, the contact code's own geometry) and facing out.
void expect_on_surface_facing_out(const RigidBody& b, const BodyMesh& m) {
  for (const Vec3& v : m.vertices)
    EXPECT_NEAR(b.closest(body_to_world(b, v)).distance, 0.0, 1e-12);
  for (const auto& t : m.triangles) {
    const Vec3 a = body_to_world(b, m.vertices[t[0]]), c = body_to_world(b, m.vertices[t[1]]),
               d = body_to_world(b, m.vertices[t[2]]);
    const Vec3 n = cross(c - a, d - a);
    ASSERT_GT(norm(n), 0.0);  // no degenerate triangle
    EXPECT_GT(dot(n / norm(n), b.closest((a + c + d) / 3.0).normal), 0.9);
  }
}

TEST(BodyMesh, SphereIsAClosedOutwardSurfaceOfItsRadius) {
  const RigidBody b = placed(RigidShape::kSphere);
  const BodyMesh m = BodyMesh::of(b, 0.0, {});
  EXPECT_EQ(m.vertices.size(), 482u);  // docs/output.md
  EXPECT_EQ(m.triangles.size(), 960u);
  expect_closed(m);
  expect_on_surface_facing_out(b, m);
  // An inscribed polyhedron: a little less than the ball (16 x 32 bands: within 2 %).
  const double ball = 4.0 / 3.0 * M_PI * std::pow(b.radius, 3);
  EXPECT_LT(enclosed_volume(m), ball);
  EXPECT_GT(enclosed_volume(m), 0.98 * ball);
}

TEST(BodyMesh, CylinderIsAClosedOutwardPrismOfItsLength) {
  const RigidBody b = placed(RigidShape::kCylinder);
  const BodyMesh m = BodyMesh::of(b, 0.0, {});
  EXPECT_EQ(m.vertices.size(), 66u);
  EXPECT_EQ(m.triangles.size(), 128u);
  expect_closed(m);
  expect_on_surface_facing_out(b, m);
  // A prism on the inscribed 32-gon, exactly: area (n / 2) r^2 sin(2 pi / n) times 2 h.
  const double n = BodyMesh::kSlices;
  const double prism =
      0.5 * n * b.radius * b.radius * std::sin(2.0 * M_PI / n) * 2.0 * b.half_length;
  EXPECT_NEAR(enclosed_volume(m), prism, 1e-12 * prism);
}

TEST(BodyMesh, PlanePatchLiesInThePlaneAroundTheGivenCentre) {
  const RigidBody b = placed(RigidShape::kPlane);
  const Vec3 centre{3.0, 1.0, -4.0};
  const BodyMesh m = BodyMesh::of(b, 2.5, centre);
  EXPECT_EQ(m.vertices.size(), 4u);
  EXPECT_EQ(m.triangles.size(), 2u);
  expect_on_surface_facing_out(b, m);
  Vec3 mean;
  for (const Vec3& v : m.vertices)
    mean += body_to_world(b, v) / 4.0;
  const RigidBody::SurfacePoint foot = b.closest(centre);
  EXPECT_NEAR(norm(mean - foot.point), 0.0, 1e-12);  // centred at the projection
  // A square of side 5: diagonals of 5 sqrt(2).
  EXPECT_NEAR(norm(body_to_world(b, m.vertices[2]) - body_to_world(b, m.vertices[0])),
              5.0 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(norm(body_to_world(b, m.vertices[3]) - body_to_world(b, m.vertices[1])),
              5.0 * std::sqrt(2.0), 1e-12);
}

}  // namespace
}  // namespace ringdem

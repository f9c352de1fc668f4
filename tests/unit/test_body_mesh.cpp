#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

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

TEST(BodyMesh, TorusIsAClosedOutwardRingOfItsTube) {
  RigidBody b = placed(RigidShape::kTorus);
  b.tube_radius = 0.08;
  const BodyMesh m = BodyMesh::of(b, 0.0, {});
  EXPECT_EQ(m.vertices.size(), 128u);  // docs/output.md
  EXPECT_EQ(m.triangles.size(), 256u);
  expect_closed(m);
  expect_on_surface_facing_out(b, m);
  // A lathe of planar trapezoids: each of the S wedges holds sin(2 pi / S) times the first
  // moment about the axis of the inscribed T-gon, (T / 2) r^2 sin(2 pi / T) R: exactly, and
  // 0.877 of the torus 2 pi^2 R r^2.
  const double s = BodyMesh::kTorusRings, t = BodyMesh::kTorusTube;
  const double lathe = s * std::sin(2.0 * M_PI / s) * 0.5 * t * b.tube_radius * b.tube_radius *
                       std::sin(2.0 * M_PI / t) * b.radius;
  EXPECT_NEAR(enclosed_volume(m), lathe, 1e-12 * lathe);
  EXPECT_LT(lathe, 2.0 * M_PI * M_PI * b.radius * b.tube_radius * b.tube_radius);
}

// RigidBody::closest of a torus against the nearest of 720 x 180 points sampled on its surface:
// no sample is nearer than the closest point, and the nearest sample is within its spacing.
TEST(BodyMesh, TorusClosestPointAgreesWithSampledSurface) {
  RigidBody b = placed(RigidShape::kTorus);
  b.tube_radius = 0.08;
  std::vector<Vec3> surface;
  for (int i = 0; i < 720; ++i)
    for (int j = 0; j < 180; ++j) {
      const double phi = 2.0 * M_PI * i / 720, theta = 2.0 * M_PI * j / 180;
      const double rho = b.radius + b.tube_radius * std::cos(theta);
      surface.push_back(body_to_world(
          b, {rho * std::cos(phi), rho * std::sin(phi), b.tube_radius * std::sin(theta)}));
    }
  const std::vector<Vec3> probes{{1.5, -2.0, 0.25},   {1.9, -2.0, 0.5}, {1.0, -1.5, 0.0},
                                 {1.6, -2.2, 0.3},    {2.2, -2.6, 1.0}, {0.9, -2.3, -0.4},
                                 {1.55, -1.75, 0.22}, {3.0, 0.0, 0.0}};
  for (const Vec3& x : probes) {
    const RigidBody::SurfacePoint c = b.closest(x);
    if (c.distance < 0.0) continue;  // inside the tube: the samples bound only outside points
    double nearest = 1e9;
    for (const Vec3& s : surface)
      nearest = std::min(nearest, norm(x - s));
    EXPECT_GE(nearest, c.distance - 1e-12);
    EXPECT_LE(nearest, c.distance + 2e-3);
    EXPECT_NEAR(norm(c.normal), 1.0, 1e-12);
    EXPECT_NEAR(norm(x - (c.point + c.normal * c.distance)), 0.0, 1e-12);
  }
  EXPECT_EQ(b.extent(), b.radius + b.tube_radius);
  EXPECT_EQ(b.contact_radius(), b.tube_radius);
}

}  // namespace
}  // namespace ringdem

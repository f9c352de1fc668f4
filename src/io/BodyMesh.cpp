#include "io/BodyMesh.hpp"

#include <cmath>

namespace ringdem {

namespace {

BodyMesh sphere(double r) {
  // Vertex 0 the north pole (+z), then the kStacks - 1 rings of kSlices from north to south,
  // then the south pole.
  constexpr int S = BodyMesh::kSlices, N = BodyMesh::kStacks;
  BodyMesh m;
  m.vertices.push_back({0, 0, r});
  for (int i = 1; i < N; ++i) {
    const double theta = M_PI * i / N;
    for (int j = 0; j < S; ++j) {
      const double phi = 2.0 * M_PI * j / S;
      m.vertices.push_back({r * std::sin(theta) * std::cos(phi),
                            r * std::sin(theta) * std::sin(phi), r * std::cos(theta)});
    }
  }
  m.vertices.push_back({0, 0, -r});
  const std::int64_t south = static_cast<std::int64_t>(m.vertices.size()) - 1;
  const auto v = [](int ring, int j) -> std::int64_t { return 1 + (ring - 1) * S + (j % S); };
  for (int j = 0; j < S; ++j) {
    m.triangles.push_back({0, v(1, j), v(1, j + 1)});
    for (int i = 1; i < N - 1; ++i) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
    m.triangles.push_back({v(N - 1, j), south, v(N - 1, j + 1)});
  }
  return m;
}

BodyMesh cylinder(double r, double h) {
  // Vertices: the bottom rim (z = -h), the top rim (z = +h), the bottom and top cap centres.
  constexpr int S = BodyMesh::kSlices;
  BodyMesh m;
  for (const double z : {-h, h})
    for (int j = 0; j < S; ++j) {
      const double phi = 2.0 * M_PI * j / S;
      m.vertices.push_back({r * std::cos(phi), r * std::sin(phi), z});
    }
  m.vertices.push_back({0, 0, -h});
  m.vertices.push_back({0, 0, h});
  const std::int64_t bottom_centre = 2 * S, top_centre = 2 * S + 1;
  const auto bottom = [](int j) -> std::int64_t { return j % S; };
  const auto top = [](int j) -> std::int64_t { return S + j % S; };
  for (int j = 0; j < S; ++j) {
    m.triangles.push_back({bottom(j), bottom(j + 1), top(j + 1)});
    m.triangles.push_back({bottom(j), top(j + 1), top(j)});
    m.triangles.push_back({top_centre, top(j), top(j + 1)});
    m.triangles.push_back({bottom_centre, bottom(j + 1), bottom(j)});
  }
  return m;
}

BodyMesh torus(double big_r, double small_r) {
  // kTorusRings rings of kTorusTube vertices around the tube, one per angle about the axis (z):
  // coarser than a sphere's, since a net has one torus per braked shackle (76 in r12).
  constexpr int S = BodyMesh::kTorusRings, T = BodyMesh::kTorusTube;
  BodyMesh m;
  for (int i = 0; i < S; ++i) {
    const double phi = 2.0 * M_PI * i / S;
    for (int j = 0; j < T; ++j) {
      const double theta = 2.0 * M_PI * j / T;
      const double rho = big_r + small_r * std::cos(theta);
      m.vertices.push_back({rho * std::cos(phi), rho * std::sin(phi), small_r * std::sin(theta)});
    }
  }
  const auto v = [](int i, int j) -> std::int64_t { return (i % S) * T + (j % T); };
  for (int i = 0; i < S; ++i)
    for (int j = 0; j < T; ++j) {
      m.triangles.push_back({v(i, j), v(i + 1, j), v(i + 1, j + 1)});
      m.triangles.push_back({v(i, j), v(i + 1, j + 1), v(i, j + 1)});
    }
  return m;
}

}  // namespace

BodyMesh BodyMesh::of(const RigidBody& body, double plane_half_width, const Vec3& plane_centre) {
  switch (body.shape) {
    case RigidShape::kSphere:
      return sphere(body.radius);
    case RigidShape::kCylinder:
      return cylinder(body.radius, body.half_length);
    case RigidShape::kTorus:
      return torus(body.radius, body.tube_radius);
    case RigidShape::kPlane:
      break;
  }
  Vec3 c = rotate(conjugate(body.orientation), plane_centre - body.position);
  c.z = 0.0;
  const double w = plane_half_width;
  BodyMesh m;
  m.vertices = {c + Vec3{-w, -w, 0}, c + Vec3{w, -w, 0}, c + Vec3{w, w, 0}, c + Vec3{-w, w, 0}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

}  // namespace ringdem

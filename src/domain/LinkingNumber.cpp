#include "domain/LinkingNumber.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace ringdem {

namespace {

/// Unit vector along v, or the zero vector if v vanishes (a degenerate face of the
/// quadrilateral, which then subtends no solid angle through it).
Vec3 unit_or_zero(const Vec3& v) {
  const double n2 = norm2(v);
  return n2 > 0.0 ? v / std::sqrt(n2) : Vec3{};
}

double clamped_asin(double x) {
  return std::asin(std::clamp(x, -1.0, 1.0));
}

/// Signed solid angle subtended by the quadrilateral of segment p1->p2 (first curve) and
/// segment p3->p4 (second curve): the spherical quadrilateral with corners r13, r14, r24, r23
/// (the differences between the segments' end points) seen from the origin, whose four edge
/// planes have the normals n1..n4 (Klenin & Langowski 2000).
double segment_pair_solid_angle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& p4) {
  const Vec3 r13 = p3 - p1, r14 = p4 - p1, r23 = p3 - p2, r24 = p4 - p2;
  const Vec3 r12 = p2 - p1, r34 = p4 - p3;
  const double orientation = dot(cross(r34, r12), r13);
  // Coplanar segments (to rounding): the quadrilateral is flat and seen edge-on.
  const double scale = norm(r34) * norm(r12) * norm(r13);
  if (!(std::abs(orientation) > 1e-13 * scale)) return 0.0;
  const Vec3 n1 = unit_or_zero(cross(r13, r14));
  const Vec3 n2 = unit_or_zero(cross(r14, r24));
  const Vec3 n3 = unit_or_zero(cross(r24, r23));
  const Vec3 n4 = unit_or_zero(cross(r23, r13));
  const double unsigned_angle = clamped_asin(dot(n1, n2)) + clamped_asin(dot(n2, n3)) +
                                clamped_asin(dot(n3, n4)) + clamped_asin(dot(n4, n1));
  return orientation > 0.0 ? unsigned_angle : -unsigned_angle;
}

}  // namespace

double gauss_linking_number(const std::vector<Vec3>& a, const std::vector<Vec3>& b) {
  if (a.size() < 3 || b.size() < 3)
    throw std::invalid_argument("the linking number needs two closed polygons of >= 3 vertices");
  double total = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const Vec3& p1 = a[i];
    const Vec3& p2 = a[(i + 1) % a.size()];
    for (std::size_t j = 0; j < b.size(); ++j)
      total += segment_pair_solid_angle(p1, p2, b[j], b[(j + 1) % b.size()]);
  }
  return total / (4.0 * M_PI);
}

}  // namespace ringdem

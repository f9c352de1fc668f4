// Unit tests of the rotation helpers in core/Quat.hpp against closed-form expectations
// (Rodrigues' rotation formula, orthonormality, composition).

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/Quat.hpp"
#include "core/Vec3.hpp"

namespace ringdem {
namespace {

// Rodrigues: v' = v cos a + (k x v) sin a + k (k . v)(1 - cos a), k unit.
Vec3 rodrigues_rotate(const Vec3& phi, const Vec3& v) {
  const double a = norm(phi);
  if (a == 0.0) return v;
  const Vec3 k = phi / a;
  return v * std::cos(a) + cross(k, v) * std::sin(a) + k * (dot(k, v) * (1.0 - std::cos(a)));
}

Vec3 random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n01(0.0, 1.0);
  return normalized(Vec3{n01(rng), n01(rng), n01(rng)});
}

// Rotation vector with angle uniform in (0, pi - 1e-3) and a random axis. The inverse map is
// ill-conditioned at exactly pi (phi and -phi are the same rotation), hence the margin.
Vec3 random_rotation_vector(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> angle(1e-3, M_PI - 1e-3);
  return random_unit(rng) * angle(rng);
}

TEST(QuatMath, DefaultsAreIdentity) {
  const Mat3 m;
  const Vec3 v{0.3, -0.4, 1.2};
  EXPECT_EQ(m * v, v);
  const Quat q;
  EXPECT_EQ(rotate(q, v), v);
}

TEST(QuatMath, RotationVectorInvertsExpMap) {
  std::mt19937_64 rng(1);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 phi = random_rotation_vector(rng);
    const Quat q = quat_from_rotation_vector(phi);
    // Unit quaternion: rounding only.
    EXPECT_NEAR(q.w * q.w + norm2(q.vec()), 1.0, 1e-14);
    // Inverse map, 1e-12 absolute (rad): atan2 and the normalisation are well conditioned
    // away from angle pi.
    const Vec3 back = rotation_vector(q);
    EXPECT_NEAR(back.x, phi.x, 1e-12);
    EXPECT_NEAR(back.y, phi.y, 1e-12);
    EXPECT_NEAR(back.z, phi.z, 1e-12);
    // q and -q are the same rotation: same rotation vector.
    const Vec3 back_neg = rotation_vector(Quat{-q.w, -q.x, -q.y, -q.z});
    EXPECT_NEAR(norm(back_neg - phi), 0.0, 1e-12);
  }
  // Tiny angles keep full relative precision (no 1 - cos cancellation).
  for (const double a : {1e-8, 1e-12, 1e-15}) {
    const Vec3 phi = Vec3{0.6, 0.0, -0.8} * a;
    const Vec3 back = rotation_vector(quat_from_rotation_vector(phi));
    EXPECT_NEAR(norm(back - phi), 0.0, 1e-12 * a) << "angle " << a;
  }
  EXPECT_EQ(norm(rotation_vector(Quat{})), 0.0);
}

TEST(QuatMath, ExpMapRotatesLikeRodrigues) {
  std::mt19937_64 rng(2);
  for (int i = 0; i < 500; ++i) {
    const Vec3 phi = random_rotation_vector(rng);
    const Vec3 v = random_unit(rng) * 2.5;
    const Vec3 want = rodrigues_rotate(phi, v);
    // Both closed forms: rounding only, 1e-13 of |v|.
    EXPECT_NEAR(norm(rotate(quat_from_rotation_vector(phi), v) - want), 0.0, 1e-13 * 2.5);
  }
  // Right-handedness: +90 degrees about z takes x to y.
  const Vec3 y = rotate(quat_from_axis_angle(Vec3{0, 0, 2}, 0.5 * M_PI), Vec3{1, 0, 0});
  EXPECT_NEAR(y.x, 0.0, 1e-15);
  EXPECT_NEAR(y.y, 1.0, 1e-15);
  EXPECT_NEAR(y.z, 0.0, 1e-15);
}

TEST(QuatMath, RotationMatrixIsOrthonormalWithUnitDeterminant) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int i = 0; i < 500; ++i) {
    const Quat q = normalized(Quat{n01(rng), n01(rng), n01(rng), n01(rng)});
    const Mat3 r = rotation_matrix(q);
    // R^T R = I column by column; rounding only, 1e-14.
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        EXPECT_NEAR(dot(r.column(a), r.column(b)), a == b ? 1.0 : 0.0, 1e-14);
      }
    }
    const double det = dot(r.column(0), cross(r.column(1), r.column(2)));
    EXPECT_NEAR(det, 1.0, 1e-14);  // proper rotation, not a reflection
    // transpose_times is the inverse.
    const Vec3 v{0.1, -2.0, 0.7};
    EXPECT_NEAR(norm(r.transpose_times(r * v) - v), 0.0, 1e-14 * norm(v));
  }
}

TEST(QuatMath, ProductComposesRotations) {
  std::mt19937_64 rng(4);
  for (int i = 0; i < 200; ++i) {
    const Vec3 p1 = random_rotation_vector(rng), p2 = random_rotation_vector(rng);
    const Vec3 v = random_unit(rng);
    // (q1 * q2) v = q1 (q2 v): apply p2 first, then p1. Rounding only.
    const Vec3 want = rodrigues_rotate(p1, rodrigues_rotate(p2, v));
    const Quat q = quat_from_rotation_vector(p1) * quat_from_rotation_vector(p2);
    EXPECT_NEAR(norm(rotate(q, v) - want), 0.0, 1e-13);
    // conjugate is the inverse rotation.
    EXPECT_NEAR(norm(rotate(conjugate(q), rotate(q, v)) - v), 0.0, 1e-13);
  }
}

TEST(QuatMath, QuatBetweenMapsAToB) {
  std::mt19937_64 rng(5);
  for (int i = 0; i < 1000; ++i) {
    const Vec3 a = random_unit(rng), b = random_unit(rng);
    const Quat q = quat_between(a, b);
    // Maps a onto b; 1e-12 absolute for unit vectors (normalisation of 1 + c loses a few
    // digits only when a and b are nearly opposite, which random pairs rarely are).
    EXPECT_NEAR(norm(rotate(q, a) - b), 0.0, 1e-12) << "i = " << i;
    // Shortest rotation: angle = angle between a and b, axis along a x b.
    const double angle = std::atan2(norm(cross(a, b)), dot(a, b));
    EXPECT_NEAR(norm(rotation_vector(q)), angle, 1e-12);
  }
  // Parallel: identity.
  const Vec3 a = normalized(Vec3{1.0, -2.0, 0.5});
  EXPECT_NEAR(norm(rotation_vector(quat_between(a, a))), 0.0, 1e-15);
  // Antiparallel: a half turn that takes a to -a.
  const Quat q = quat_between(a, -a);
  EXPECT_NEAR(norm(rotate(q, a) + a), 0.0, 1e-12);
  EXPECT_NEAR(norm(rotation_vector(q)), M_PI, 1e-12);
  // Nearly antiparallel (just above the special-case threshold): still maps a to b.
  const Vec3 perp = any_perpendicular(a);
  const Vec3 b = normalized(-a + perp * 1e-5);
  EXPECT_NEAR(norm(rotate(quat_between(a, b), a) - b), 0.0, 1e-9);
}

// The Cayley turn is the exponential map's rotation about the same axis by 2 atan(|phi|/2)
// (Rodrigues), a unit quaternion, and the opposite turn undoes it (the bond terms' step back).
TEST(QuatMath, CayleyTurnRotatesByItsAngleAndIsUndoneByTheOppositeTurn) {
  const Quat q = normalized(Quat{0.9, -0.2, 0.3, 0.1});
  const Vec3 axis = Vec3{0.3, 0.5, -0.8} * (1.0 / std::sqrt(0.98));
  for (const double phi : {1e-7, 1e-4, 0.01, 0.2, 0.5}) {
    const Vec3 h = axis * (0.5 * phi);
    // Within the norm error of the two Newton steps, 0.21 e^4 with e = |h|^2.
    const double e = 0.25 * phi * phi, tolerance = 1e-15 + 0.25 * std::pow(e, 4);
    const Quat turned = cayley_turned(q, h);
    const Quat expected = quat_from_rotation_vector(axis * (2.0 * std::atan(0.5 * phi))) * q;
    EXPECT_NEAR(turned.w, expected.w, tolerance) << phi;
    EXPECT_NEAR(turned.x, expected.x, tolerance) << phi;
    EXPECT_NEAR(turned.y, expected.y, tolerance) << phi;
    EXPECT_NEAR(turned.z, expected.z, tolerance) << phi;
    const Quat back = cayley_turned(turned, h * -1.0);
    EXPECT_NEAR(back.w, q.w, 2.0 * tolerance) << phi;
    EXPECT_NEAR(back.x, q.x, 2.0 * tolerance) << phi;
    EXPECT_NEAR(back.y, q.y, 2.0 * tolerance) << phi;
    EXPECT_NEAR(back.z, q.z, 2.0 * tolerance) << phi;
  }
}

}  // namespace
}  // namespace ringdem

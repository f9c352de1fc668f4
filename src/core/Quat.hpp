#pragma once

#include <cmath>

#include "core/Vec3.hpp"

namespace ringdem {

/// Row-major 3x3 matrix, used for rotation matrices built once per particle per step.
struct Mat3 {
  double m[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};

  constexpr Vec3 operator*(const Vec3& v) const {
    return {m[0] * v.x + m[1] * v.y + m[2] * v.z, m[3] * v.x + m[4] * v.y + m[5] * v.z,
            m[6] * v.x + m[7] * v.y + m[8] * v.z};
  }
  /// Transpose times vector (the inverse rotation).
  constexpr Vec3 transpose_times(const Vec3& v) const {
    return {m[0] * v.x + m[3] * v.y + m[6] * v.z, m[1] * v.x + m[4] * v.y + m[7] * v.z,
            m[2] * v.x + m[5] * v.y + m[8] * v.z};
  }
  constexpr Vec3 column(int j) const { return {m[j], m[3 + j], m[6 + j]}; }
};

/// Unit quaternion w + (x, y, z), rotating body-frame vectors into the world frame.
struct Quat {
  double w = 1.0, x = 0.0, y = 0.0, z = 0.0;

  constexpr Quat() = default;
  constexpr Quat(double w_, double x_, double y_, double z_) : w(w_), x(x_), y(y_), z(z_) {}
  constexpr bool operator==(const Quat&) const = default;

  constexpr Vec3 vec() const { return {x, y, z}; }
};

constexpr Quat operator*(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
constexpr Quat conjugate(const Quat& q) {
  return {q.w, -q.x, -q.y, -q.z};
}

inline Quat normalized(const Quat& q) {
  const double inv = 1.0 / std::sqrt(q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z);
  return {q.w * inv, q.x * inv, q.y * inv, q.z * inv};
}

/// 1/sqrt(n2) for n2 near 1, by two Newton steps from 1, with no square root or division:
/// the relative error is about 0.21 e^4 for n2 = 1 + e.
inline double inverse_norm_near_one(double n2) {
  const double y = 0.5 * (3.0 - n2);
  return y * (0.5 * (3.0 - n2 * y * y));
}

/// dq(phi) q for the Cayley form dq(phi) = (1, phi/2) / sqrt(1 + |phi|^2/4), given h = phi/2:
/// a unit quaternion of angle 2 atan(|phi|/2) = |phi| (1 - |phi|^2/12 + ...), exactly inverted
/// by dq(-phi). Computed as the product p = (1, h) q brought to unit norm: |p|^2 =
/// (1 + |h|^2) |q|^2, so p/|p| is dq q for a unit q, and |q| drifts by round-off only. With
/// e = |p|^2 - 1 (|h|^2 plus earlier round-off) the norm comes out within 0.21 e^4 of 1:
/// round-off for |phi| < 0.02, 3e-6 at |phi| = 0.5, and the next update takes that out again.
/// One quaternion product and a few multiplications, no square root or division.
inline Quat cayley_turned(const Quat& q, const Vec3& h) {
  const Quat p = Quat{1.0, h.x, h.y, h.z} * q;
  const double f = inverse_norm_near_one(p.w * p.w + p.x * p.x + p.y * p.y + p.z * p.z);
  return {p.w * f, p.x * f, p.y * f, p.z * f};
}

/// Rotation by the rotation vector phi (axis * angle), exact exponential map.
inline Quat quat_from_rotation_vector(const Vec3& phi) {
  const double angle = norm(phi);
  if (angle < 1e-300) return {};
  const double half = 0.5 * angle;
  const double s = std::sin(half) / angle;
  return {std::cos(half), phi.x * s, phi.y * s, phi.z * s};
}

inline Quat quat_from_axis_angle(const Vec3& axis, double angle) {
  return quat_from_rotation_vector(normalized(axis) * angle);
}

/// Rotation vector of q (inverse of quat_from_rotation_vector), angle in [0, pi].
inline Vec3 rotation_vector(const Quat& q) {
  const Quat p = q.w < 0 ? Quat{-q.w, -q.x, -q.y, -q.z} : q;
  const double s = norm(p.vec());
  if (s < 1e-300) return {};
  return p.vec() * (2.0 * std::atan2(s, p.w) / s);
}

constexpr Mat3 rotation_matrix(const Quat& q) {
  const double xx = q.x * q.x, yy = q.y * q.y, zz = q.z * q.z;
  const double xy = q.x * q.y, xz = q.x * q.z, yz = q.y * q.z;
  const double wx = q.w * q.x, wy = q.w * q.y, wz = q.w * q.z;
  return Mat3{{1 - 2 * (yy + zz), 2 * (xy - wz), 2 * (xz + wy),  //
               2 * (xy + wz), 1 - 2 * (xx + zz), 2 * (yz - wx),  //
               2 * (xz - wy), 2 * (yz + wx), 1 - 2 * (xx + yy)}};
}

/// Rotates v by the unit quaternion q: v + w t + q_v x t with t = 2 q_v x v (no matrix).
constexpr Vec3 rotate(const Quat& q, const Vec3& v) {
  const Vec3 qv{q.x, q.y, q.z};
  const Vec3 t = cross(qv, v) * 2.0;
  return v + t * q.w + cross(qv, t);
}

/// Unit quaternion of a rotation matrix (Shepperd: pivot on the largest diagonal term).
inline Quat quat_from_matrix(const Mat3& r) {
  const double* m = r.m;
  const double tr = m[0] + m[4] + m[8];
  Quat q;
  if (tr >= m[0] && tr >= m[4] && tr >= m[8]) {
    const double s = 2.0 * std::sqrt(1.0 + tr);
    q = {0.25 * s, (m[7] - m[5]) / s, (m[2] - m[6]) / s, (m[3] - m[1]) / s};
  } else if (m[0] >= m[4] && m[0] >= m[8]) {
    const double s = 2.0 * std::sqrt(1.0 + m[0] - m[4] - m[8]);
    q = {(m[7] - m[5]) / s, 0.25 * s, (m[1] + m[3]) / s, (m[2] + m[6]) / s};
  } else if (m[4] >= m[8]) {
    const double s = 2.0 * std::sqrt(1.0 - m[0] + m[4] - m[8]);
    q = {(m[2] - m[6]) / s, (m[1] + m[3]) / s, 0.25 * s, (m[5] + m[7]) / s};
  } else {
    const double s = 2.0 * std::sqrt(1.0 - m[0] - m[4] + m[8]);
    q = {(m[3] - m[1]) / s, (m[2] + m[6]) / s, (m[5] + m[7]) / s, 0.25 * s};
  }
  return normalized(q);
}

/// Either representation of a rotation as a quaternion (used by templated kernels).
constexpr const Quat& as_quat(const Quat& q) {
  return q;
}
inline Quat as_quat(const Mat3& r) {
  return quat_from_matrix(r);
}

/// Columns of the rotation matrix of q (the body axes in the world frame), without the
/// full matrix.
constexpr Vec3 body_x_axis(const Quat& q) {
  return {1 - 2 * (q.y * q.y + q.z * q.z), 2 * (q.x * q.y + q.w * q.z),
          2 * (q.x * q.z - q.w * q.y)};
}
constexpr Vec3 body_y_axis(const Quat& q) {
  return {2 * (q.x * q.y - q.w * q.z), 1 - 2 * (q.x * q.x + q.z * q.z),
          2 * (q.y * q.z + q.w * q.x)};
}
constexpr Vec3 body_z_axis(const Quat& q) {
  return {2 * (q.x * q.z + q.w * q.y), 2 * (q.y * q.z - q.w * q.x),
          1 - 2 * (q.x * q.x + q.y * q.y)};
}

/// The same operation for either representation of a rotation (used by templated kernels).
constexpr Vec3 apply_rotation(const Mat3& r, const Vec3& v) {
  return r * v;
}
constexpr Vec3 apply_rotation(const Quat& q, const Vec3& v) {
  return rotate(q, v);
}

/// Shortest rotation taking unit vector a onto unit vector b.
inline Quat quat_between(const Vec3& a, const Vec3& b) {
  const double c = dot(a, b);
  if (c < -1.0 + 1e-12) return quat_from_axis_angle(any_perpendicular(a), M_PI);
  const Vec3 v = cross(a, b);
  return normalized(Quat{1.0 + c, v.x, v.y, v.z});
}

}  // namespace ringdem

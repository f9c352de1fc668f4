#pragma once

#include <cmath>

namespace ringdem {

/// Plain 3-vector of doubles. Kept trivially copyable so that particle fields stored as
/// std::vector<Vec3> are contiguous and can be sent over MPI or written to HDF5 as bytes.
struct Vec3 {
  double x = 0.0, y = 0.0, z = 0.0;

  constexpr Vec3() = default;
  constexpr Vec3(double x_, double y_, double z_) : x(x_), y(y_), z(z_) {}

  constexpr double operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr Vec3& operator+=(const Vec3& o) {
    x += o.x;
    y += o.y;
    z += o.z;
    return *this;
  }
  constexpr Vec3& operator-=(const Vec3& o) {
    x -= o.x;
    y -= o.y;
    z -= o.z;
    return *this;
  }
  constexpr Vec3& operator*=(double s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr bool operator==(const Vec3&) const = default;
};

constexpr Vec3 operator+(Vec3 a, const Vec3& b) {
  return a += b;
}
constexpr Vec3 operator-(Vec3 a, const Vec3& b) {
  return a -= b;
}
constexpr Vec3 operator-(const Vec3& a) {
  return {-a.x, -a.y, -a.z};
}
constexpr Vec3 operator*(Vec3 a, double s) {
  return a *= s;
}
constexpr Vec3 operator*(double s, Vec3 a) {
  return a *= s;
}
constexpr Vec3 operator/(const Vec3& a, double s) {
  const double inv = 1.0 / s;  // one division, three products
  return {a.x * inv, a.y * inv, a.z * inv};
}

constexpr double dot(const Vec3& a, const Vec3& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
constexpr Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
constexpr double norm2(const Vec3& a) {
  return dot(a, a);
}
inline double norm(const Vec3& a) {
  return std::sqrt(norm2(a));
}
/// Component-wise c ? a : b. Written as three selects so that a loop over contacts
/// vectorises (GCC turns them into blends; a ternary on the struct stays a branch).
constexpr Vec3 select(bool c, const Vec3& a, const Vec3& b) {
  return {c ? a.x : b.x, c ? a.y : b.y, c ? a.z : b.z};
}
inline Vec3 normalized(const Vec3& a) {
  const double n = norm(a);
  return select(n > 0.0, a / n, Vec3{});
}

/// Any unit vector perpendicular to the unit vector n.
inline Vec3 any_perpendicular(const Vec3& n) {
  const Vec3 t = std::abs(n.x) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  return normalized(cross(n, t));
}

}  // namespace ringdem

#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// A column of 3-vectors stored as three arrays, x, y and z (structure of arrays). The
/// integrator's particle loops stream each component on its own: with interleaved Vec3 rows
/// the vectoriser spends its time permuting (AVX-512 on the project's machine, where the two
/// integrator passes over the loads and velocities took 19 ns a particle against 11 ns with
/// separate components; docs/performance.md, seventh round). Element access keeps the Vec3
/// interface: a const column hands out values, a mutable one a reference to the three
/// components (Ref), so `c[k] = v`, `c[k] += v`, `c[k].x = a` and `Vec3 v = c[k]` read as they
/// would on a std::vector<Vec3>.
class Vec3Column {
 public:
  using value_type = Vec3;

  /// The three components of one row, by reference. Assigning to it writes the row; it
  /// converts to the row's value. Never keep one past a resize.
  struct Ref {
    double& x;
    double& y;
    double& z;

    operator Vec3() const { return {x, y, z}; }  // NOLINT: converts like a Vec3& would
    Ref& operator=(const Vec3& v) {
      x = v.x;
      y = v.y;
      z = v.z;
      return *this;
    }
    /// Assigns the other row's value (a Ref is a reference, not a rebindable handle).
    Ref& operator=(const Ref& o) { return *this = Vec3(o); }
    Ref& operator+=(const Vec3& v) {
      x += v.x;
      y += v.y;
      z += v.z;
      return *this;
    }
    Ref& operator-=(const Vec3& v) {
      x -= v.x;
      y -= v.y;
      z -= v.z;
      return *this;
    }
  };

  Vec3Column() = default;
  explicit Vec3Column(std::size_t n, const Vec3& value = {}) { assign(n, value); }

  std::size_t size() const { return x_.size(); }
  bool empty() const { return x_.empty(); }
  void resize(std::size_t n) {
    x_.resize(n);
    y_.resize(n);
    z_.resize(n);
  }
  void reserve(std::size_t n) {
    x_.reserve(n);
    y_.reserve(n);
    z_.reserve(n);
  }
  void clear() { resize(0); }
  void assign(std::size_t n, const Vec3& value) {
    x_.assign(n, value.x);
    y_.assign(n, value.y);
    z_.assign(n, value.z);
  }
  void push_back(const Vec3& v) {
    x_.push_back(v.x);
    y_.push_back(v.y);
    z_.push_back(v.z);
  }
  /// Releases the memory that size() does not use.
  void shrink_to_fit() {
    x_.shrink_to_fit();
    y_.shrink_to_fit();
    z_.shrink_to_fit();
  }

  Vec3 operator[](std::size_t k) const { return {x_[k], y_[k], z_[k]}; }
  Ref operator[](std::size_t k) { return {x_[k], y_[k], z_[k]}; }

  double* x() { return x_.data(); }
  double* y() { return y_.data(); }
  double* z() { return z_.data(); }
  const double* x() const { return x_.data(); }
  const double* y() const { return y_.data(); }
  const double* z() const { return z_.data(); }

  /// The rows as interleaved Vec3s, for what reads a column as one block (HDF5, tests).
  std::vector<Vec3> rows() const {
    std::vector<Vec3> out(size());
    for (std::size_t k = 0; k < out.size(); ++k)
      out[k] = (*this)[k];
    return out;
  }
  bool operator==(const Vec3Column&) const = default;

 private:
  std::vector<double> x_, y_, z_;
};

/// A registry column's rows as one contiguous block, for what writes a field as a whole
/// (HDF5): a std::vector as it is, a Vec3Column interleaved into a copy. Bind the result to
/// `const auto&`.
template <class T>
const std::vector<T>& as_rows(const std::vector<T>& column) {
  return column;
}
inline std::vector<Vec3> as_rows(const Vec3Column& column) {
  return column.rows();
}

/// Copies `rows` into the first rows.size() rows of a registry column (the inverse of as_rows).
template <class T>
void assign_rows(std::vector<T>& column, const std::vector<T>& rows) {
  std::copy(rows.begin(), rows.end(), column.begin());
}
inline void assign_rows(Vec3Column& column, const std::vector<Vec3>& rows) {
  for (std::size_t k = 0; k < rows.size(); ++k)
    column[k] = rows[k];
}

}  // namespace ringdem

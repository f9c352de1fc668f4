#include "engine/MoveBounds.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace ringdem {

namespace {
/// A fixed plane's candidates change only by moves along its normal.
bool is_fixed_plane(const RigidBody& b) {
  return b.shape == RigidShape::kPlane && b.motion == Motion::kFixed;
}
}  // namespace

void MoveBounds::reset(const std::vector<RigidBody>& bodies) {
  absolute_ = relative_ = 0.0;
  toward_.assign(bodies.size(), 0.0);
}

double MoveBounds::half_diagonal(const Integrator::VelocityBox& box) {
  if (box.empty()) return 0.0;
  return 0.5 * norm(box.high - box.low);
}

double MoveBounds::largest_speed_along(const Integrator::VelocityBox& box, const Vec3& n) {
  if (box.empty()) return 0.0;
  // n . v is linear in v: its extremes over the box are at the corners, each component at
  // the end its sign of n picks.
  const auto along = [&](double low, double high, double n_k, bool largest) {
    const double a = n_k * low, b = n_k * high;
    return largest ? std::max(a, b) : std::min(a, b);
  };
  const double most = along(box.low.x, box.high.x, n.x, true) +
                      along(box.low.y, box.high.y, n.y, true) +
                      along(box.low.z, box.high.z, n.z, true);
  const double least = along(box.low.x, box.high.x, n.x, false) +
                       along(box.low.y, box.high.y, n.y, false) +
                       along(box.low.z, box.high.z, n.z, false);
  return std::max(most, -least);
}

void MoveBounds::advance(double max_speed, const Integrator::VelocityBox& velocities,
                         const std::vector<RigidBody>& bodies, double dt) {
  if (toward_.size() != bodies.size())
    throw std::logic_error("MoveBounds: a bound toward each rigid body is needed (reset())");
  absolute_ += max_speed * dt;
  // Each bound is a valid one on its own, so the smaller of two is too: |v - c| <= |v| with
  // c = 0. (A non-finite velocity is the divergence guard's to report, at this same step.)
  relative_ += std::min(max_speed, half_diagonal(velocities)) * dt;
  for (std::size_t b = 0; b < bodies.size(); ++b)
    toward_[b] +=
        (is_fixed_plane(bodies[b])
             ? std::min(max_speed, largest_speed_along(velocities, bodies[b].plane_normal()))
             : max_speed) *
        dt;
}

void MoveBounds::restore(double absolute, double relative, std::vector<double> toward) {
  if (toward.size() != toward_.size())
    throw std::runtime_error("restart state has " + std::to_string(toward.size()) +
                             " move bounds toward rigid bodies for " +
                             std::to_string(toward_.size()) + " bodies");
  absolute_ = absolute;
  relative_ = relative;
  toward_ = std::move(toward);
}

}  // namespace ringdem

#pragma once

#include <cstddef>
#include <vector>

#include "domain/RigidBody.hpp"
#include "physics/Integrator.hpp"

namespace ringdem {

/// What the neighbour-list rebuild test reads of the particles' moves since the last rebuild
/// (Simulation::needs_rebuild, docs/physics.md "Neighbour search"). Each bound is a sum over
/// the drifts of a speed that no particle exceeded, in the sense of that bound, times the
/// drift's step: no column of reference positions, and the same on any rank count (the
/// speeds are maxima over the ranks).
/// - absolute(): no particle moved farther (the outflow's test reads it);
/// - relative(): no particle moved farther from one translation common to all, the drifts'
///   sum of c = the centre of each drift's box of velocities times its step. Two particles
///   then moved at most twice this relative to each other, which is all a pair list needs:
///   a flow moving as one does not wear out its skin. At each drift the smaller of the box's
///   half diagonal and the largest speed (a translation of zero) is added;
/// - toward(b): no particle moved farther toward rigid body b's surface: for a fixed plane,
///   only along its normal (the largest normal speed in the box of velocities); for any other
///   body, absolute().
class MoveBounds {
 public:
  /// Zero bounds, one toward each of `bodies`.
  void reset(const std::vector<RigidBody>& bodies);
  /// Adds a drift of step `dt`: `max_speed` and `velocities` are the largest speed and the
  /// box of the velocities over every rank (the same on every rank).
  void advance(double max_speed, const Integrator::VelocityBox& velocities,
               const std::vector<RigidBody>& bodies, double dt);
  double absolute() const { return absolute_; }
  double relative() const { return relative_; }
  double toward(std::size_t body) const { return toward_[body]; }
  const std::vector<double>& toward() const { return toward_; }
  /// The bounds a checkpoint carried (RestartState), `toward` one a body.
  void restore(double absolute, double relative, std::vector<double> toward);

  /// The largest |n . v| of the velocities in `box` (0 for an empty box), n a unit vector.
  static double largest_speed_along(const Integrator::VelocityBox& box, const Vec3& n);
  /// The half diagonal of `box`: no velocity in it is farther from its centre (0 for an
  /// empty box).
  static double half_diagonal(const Integrator::VelocityBox& box);

 private:
  double absolute_ = 0.0, relative_ = 0.0;
  std::vector<double> toward_;
};

}  // namespace ringdem

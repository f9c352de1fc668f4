#pragma once

#include <limits>

#include "core/Vec3.hpp"

namespace ringdem {

class Simulation;

/// Extent of a particle group over all ranks (owned particles), and the top of the group
/// within a horizontal distance of an axis (the rockfall's measures of the net). Collective.
struct GroupExtent {
  Vec3 lo, hi;
  double top_near_axis = -std::numeric_limits<double>::infinity();
  double lowest_near_axis = std::numeric_limits<double>::infinity();
};

GroupExtent group_extent(const Simulation& sim, int group, double axis_x, double axis_y,
                         double axis_radius);

/// Contact load on the particles of a group (their total force less gravity), summed exactly
/// (comm/ExactSum) so that it does not depend on the rank count. Collective.
Vec3 group_contact_load(const Simulation& sim, int group, const Vec3& gravity);

/// What the frame receives from what it holds: the contact load on the held particles of a
/// group (group_contact_load) plus the loads of the brake elements and the support ropes on
/// their anchors (docs/physics.md "Brake elements", "Support ropes"). Collective.
Vec3 frame_load(const Simulation& sim, int group, const Vec3& gravity);

}  // namespace ringdem

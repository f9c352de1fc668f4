#include "app/GroupExtent.hpp"

#include <algorithm>
#include <array>
#include <vector>

#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

GroupExtent group_extent(const Simulation& sim, int group, double axis_x, double axis_y,
                         double axis_radius) {
  const ParticleStore& p = sim.model().particles;
  const double inf = std::numeric_limits<double>::infinity();
  Vec3 lo{inf, inf, inf}, hi{-inf, -inf, -inf};
  double top = -inf, low = inf;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.group[k] != group) continue;
    const Vec3& x = p.position[k];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z - p.radius[k])};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z + p.radius[k])};
    const double dx = x.x - axis_x, dy = x.y - axis_y;
    if (dx * dx + dy * dy <= axis_radius * axis_radius) {
      top = std::max(top, x.z + p.radius[k]);
      low = std::min(low, x.z - p.radius[k]);
    }
  }
  const Communicator& c = sim.comm();
  const auto maxima = c.max(std::array<double, 6>{-lo.x, -lo.y, -lo.z, hi.x, hi.y, hi.z});
  const auto near = c.max(std::array<double, 2>{top, -low});
  GroupExtent e;
  e.lo = {-maxima[0], -maxima[1], -maxima[2]};
  e.hi = {maxima[3], maxima[4], maxima[5]};
  e.top_near_axis = near[0];
  e.lowest_near_axis = -near[1];
  return e;
}

Vec3 group_contact_load(const Simulation& sim, int group, const Vec3& gravity) {
  const ParticleStore& p = sim.model().particles;
  std::vector<ExactSum> partial(3);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.group[k] != group) continue;
    const Vec3 f = p.force[k] - p.mass[k] * gravity;
    partial[0].add(f.x);
    partial[1].add(f.y);
    partial[2].add(f.z);
  }
  const std::vector<double> s = sim.comm().sum_exact(partial);
  return {s[0], s[1], s[2]};
}

Vec3 frame_load(const Simulation& sim, int group, const Vec3& gravity) {
  return group_contact_load(sim, group, gravity) + restraint_totals(sim.model()).frame_load;
}

}  // namespace ringdem

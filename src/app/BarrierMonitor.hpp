#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "core/Vec3.hpp"
#include "engine/MomentumLedger.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

class Simulation;

/// What a free run measures of a barrier in a debris flow (scenario.barrier, docs/debris.md
/// "Barrier measures"). Distances s = (x - position) . d are along the flow direction d from
/// the barrier plane: upstream is s < 0. Every figure is summed exactly or is a maximum over the
/// ranks, so none depends on the rank count.
struct BarrierSample {
  double net_force = 0.0;    ///< along d: contact load on the frame holding the net [N]
  double posts_force = 0.0;  ///< along d: contact force on the posts [N]
  /// Gauge section, s in [-(gauge_distance + gauge_length), -gauge_distance]: flow grains there.
  double gauge_mass = 0.0;  ///< [kg]
  double flow_depth = 0.0;  ///< highest grain top above the bed [m] (0: no grain)
  /// Twice the mass-weighted mean height of the grain centres above the bed [m] (0: no grain):
  /// the depth of a layer of uniform bulk density with the same centroid. A grain saltating
  /// above the flow moves it by its share of the mass, not to its own height.
  double flow_depth_centroid = 0.0;
  double flow_velocity = 0.0;  ///< mass-weighted mean velocity along d [m/s] (0: no grain)
  /// The largest radius of a grain in the gauge [m] (0: no grain): the flow's coarsest grain,
  /// whose passage time sets the shortest window over which its load is a flow's
  /// (scripts/check_debris_bounds.py).
  double largest_gauge_radius = 0.0;
  double bulk_density = 0.0;  ///< gauge mass / (gauge length x width x depth) [kg/m^3]
  double front = -std::numeric_limits<double>::infinity();  ///< largest s + r of a grain [m]
  double retained_mass = 0.0;  ///< grains with s in [-retention_length, 0] [kg]
  double overflow_mass = 0.0;  ///< grains with s > 0 (past the barrier plane) [kg]
  double net_reach = -std::numeric_limits<double>::infinity();  ///< largest s of the net [m]
  double max_utilisation = 0.0;  ///< largest bond utilisation of the net (Eq. 3-5 or strain)
  Vec3 utilisation_at;           ///< midpoint of that bond (lowest gid pair of equals)
};

class BarrierMonitor {
 public:
  /// Resolves the groups and bodies by name; throws std::invalid_argument for one the model
  /// lacks (the loader reports them first).
  BarrierMonitor(const BarrierConfig& config, const Simulation& sim);

  /// One sample. Collective.
  BarrierSample sample(const Simulation& sim) const;

  /// The barrier's loads along d integrated over the run so far [N s], from the momentum
  /// ledger: what the posts and the held particles (the net's frame and shackles) received
  /// from the particles, every step counted. Their change over an interval, divided by its
  /// length, is the interval's mean force, free of the single strikes that an instantaneous
  /// sample may catch or miss.
  struct Impulse {
    double net = 0.0, posts = 0.0;
  };
  Impulse impulse(const MomentumBalance& balance) const;

 private:
  bool is_grain(const Simulation& sim, std::size_t k) const;

  BarrierConfig config_;
  std::vector<int> grain_groups_;  ///< empty: every free particle in no ring
  int net_group_ = -1, frame_group_ = -1;
  std::vector<std::size_t> posts_;
  /// Bodies held by brakes or ropes (a net's shackles as rigid tori): the net's load goes
  /// through them to the frame.
  std::vector<std::int32_t> shackle_bodies_;
  std::size_t bed_ = 0;
};

}  // namespace ringdem

#pragma once

#include <cstddef>
#include <limits>
#include <utility>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/RingGenerator.hpp"

namespace ringdem {

/// Chain-mail ring net, as in the paper's rockfall test (180 rings of 300 mm, 3.9 m x 3.9 m,
/// each ring linked with four others, the outer rings held by rigid shackles that let them
/// rotate and slide). Described below in the net's own frame (x, y in its plane, z its normal);
/// `x_axis` and `normal` place that frame in the world (by default the world's: a horizontal
/// net, as the rockfall's; a debris-flow barrier stands across its channel).
///
/// Layout (our choice; the paper gives no coordinates): the rings sit on a square lattice of
/// pitch s = link_distance / sqrt(2), at the sites (column m, row n) with m + n odd, so that
/// each ring's four diagonal neighbours (m +- 1, n +- 1) are link_distance away and rings in
/// the same row are 2 s apart. Every ring lies in a plane tilted by `tilt` about x, the sign
/// alternating row by row (normal (0, +-sin tilt, cos tilt), + on odd rows): two diagonal
/// neighbours then cross each other's plane once above and once below, so they are linked
/// but start clear of each other (the paper rotates its rings "to an appropriate degree to
/// avoid contact"). scripts/bench/make_ring_grid.py --linked writes the same kind of layout
/// (0.25 m, 12 degrees).
///
/// The defaults are the paper's net: a 19 x 19 lattice holds 180 rings (the corner sites are
/// empty), 3.88 m along x and 3.87 m along y with link_distance 0.28 m; tilt 0.28 rad (16
/// degrees) is close to the tilt of largest clearance between linked rings (19.9 mm between
/// particle centres of different rings, 20.0 mm at 18 degrees), more than twice the 8 mm
/// contact radius. Link distances near 0.29 m, which would fill 3.9 m x 3.9 m with 180 rings
/// more exactly, leave no tilt with linked rings 16 mm apart.
///
/// Shackles: one small ring per boundary ring and side it is on (two on a corner ring),
/// centred on the ring's outermost wire point on that side and perpendicular to the wire
/// there, so the wire passes through the middle of the shackle (a Hopf link). Shackles are
/// meant to be fixed in space.
struct RingNetParameters {
  int rows = 19;                ///< lattice rows, along y (>= 2)
  int columns = 19;             ///< lattice columns, along x (>= 2)
  double link_distance = 0.28;  ///< centre distance of linked rings [m]
  double tilt = 0.28;           ///< tilt of the ring planes about x [rad]
  Vec3 centre;                  ///< centre of the lattice; the ring centres are at its height
  Vec3 normal{0, 0, 1};         ///< the net's z axis in the world (unit)
  Vec3 x_axis{1, 0, 0};         ///< the net's x axis in the world (unit, normal to `normal`)
  double internal_diameter = 0.3;
  double particle_radius = 0.0045;
  int n_particles = 100;
  bool shackles = true;
  double shackle_internal_diameter = 0.06;
  double shackle_particle_radius = 0.008;
  int shackle_n_particles = 14;

  double lattice_pitch() const;
  double centreline_radius() const { return 0.5 * internal_diameter + particle_radius; }
  double shackle_centreline_radius() const {
    return 0.5 * shackle_internal_diameter + shackle_particle_radius;
  }
  /// Extent of the net rings' outer surface along x: (columns - 1) s + 2 (R + r).
  double width() const;
  /// Extent along y; a tilted ring spans R cos(tilt) either side: (rows - 1) s + 2 (R cos + r).
  double length() const;
};

struct LatticeSize {
  int rows = 0;
  int columns = 0;
};

/// The lattice whose width() and length() come closest to `width` x `length` (each at least
/// 2), for the link distance, tilt and ring size of `shape`.
LatticeSize lattice_size_for(double width, double length, const RingNetParameters& shape);

/// Frame of one net ring and its lattice site.
struct RingPlacement {
  Vec3 centre;
  Vec3 normal;     ///< unit ring axis
  Vec3 reference;  ///< unit, in the ring plane: direction of particle 0
  int row = 0;
  int column = 0;
};

enum class NetSide { kMinusX, kPlusX, kMinusY, kPlusY };

/// Frame of one shackle and the net ring it holds.
struct ShacklePlacement {
  Vec3 centre;
  Vec3 normal;     ///< unit: the held ring's wire direction at the shackle
  Vec3 reference;  ///< unit: outwards from the net (particle 0 is the outermost)
  std::size_t net_ring = 0;
  NetSide side = NetSide::kMinusX;
};

struct RingNetLayout {
  RingNetParameters parameters;
  std::vector<RingPlacement> rings;  ///< row by row (y), then by column (x)
  /// Linked neighbours (index pairs into `rings`, first < second), by first then second.
  std::vector<std::pair<std::size_t, std::size_t>> links;
  std::vector<ShacklePlacement> shackles;  ///< by net ring, then side

  RingGeometry ring_geometry(std::size_t ring) const;
  RingGeometry shackle_geometry(std::size_t shackle) const;
  /// Particles of the net rings and shackles together.
  std::size_t n_particles() const;
};

/// The net of `p`. Throws std::invalid_argument for a lattice smaller than 2 x 2, a tilt
/// outside (0, pi/2), non-positive sizes, fewer than 3 particles per ring, a link distance
/// of at least the centreline diameter 2 R (such rings cannot interlink), or axes that are not
/// unit and perpendicular (to 1e-9).
RingNetLayout generate_ring_net(const RingNetParameters& p);

/// Smallest gap between particles of different rings: centre distance minus the two radii
/// (`net_radius` for net particles, `shackle_radius` for shackle particles), found on a cell
/// grid. Rings are numbered net rings first, then shackles. Gaps larger than `search_gap`
/// are not looked for: with none at or below it, gap is +infinity.
struct RingNetClearance {
  double gap = std::numeric_limits<double>::infinity();
  std::size_t ring_a = 0;
  std::size_t ring_b = 0;
};
RingNetClearance smallest_clearance(const RingNetLayout& layout, double net_radius,
                                    double shackle_radius, double search_gap);

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <utility>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// The spatial bins of a re-sort (docs/architecture.md, "Order of the particles"). A grain's
/// bin is the cube of edge `width` that holds its centre, numbered along the order's slowest
/// axis last, the other two x before y before z (z slowest: x fastest, as LAMMPS sorts its
/// atoms); stored in a particle's sort_bin it orders the owned particles and the contact pairs
/// by space, so that a flow whose grains have mixed is walked with its neighbours near in
/// memory. The slowest axis is the one along which the grains reach farthest
/// (slowest_axis()): a channel's grains are then stored in slabs across the flow, and the pile
/// against a net, which multi-rate stepping moves at every sub-step, is one stretch of the store
/// instead of a piece of every row along the channel (docs/performance.md, forty-fourth round).
/// The bin is a function of the position and the order alone, so every rank gives a particle
/// the same one.
///
/// The cube's indices are kept modulo 2048 along the fastest axis and 1024 along the other two
/// (31 bits, with the top bit marking a binned particle): two regions 2048 widths apart along
/// the fastest axis (1024 along the others) share bin numbers and are interleaved in the order,
/// which costs locality, never correctness.
class SpatialBins {
 public:
  /// Set on every binned particle's bin: binned particles come after the unbinned ones (bin 0).
  static constexpr std::uint32_t kBinned = 1u << 31;

  /// The axes, as slowest_axis() numbers them.
  enum Axis : int { kX = 0, kY = 1, kZ = 2 };

  /// The bins of one re-sort: the cubes' edge (> 0) and the axis numbered slowest.
  struct Order {
    double width = 0.0;
    Axis slowest = kZ;
  };

  /// The bin of a centre at x.
  static std::uint32_t bin_of(const Vec3& x, const Order& order);

  /// The axis along which `extent` (the grains' bounding box, over the ranks) is longest; a tie
  /// goes to z, then y, so that a cube of grains keeps z slowest.
  static Axis slowest_axis(const Vec3& extent);

  /// Gives each owned particle that belongs to no ring or clump (body < 0) the bin of its
  /// position; the others keep bin 0, their gid order (a net's particles are made in ring order,
  /// the order its bonds walk).
  static void assign(ParticleStore& p, const Order& order);

  /// The corners of the box that holds the centres of the owned particles that assign() bins:
  /// {+inf...} and {-inf...} for none. Their extremes over the ranks give slowest_axis() its
  /// extent.
  static std::pair<Vec3, Vec3> binned_box(const ParticleStore& p);

  /// The smallest radius of the owned particles that assign() bins (infinity for none); the
  /// minimum over the ranks, doubled, is the width of a re-sort.
  static double smallest_binned_radius(const ParticleStore& p);
};

}  // namespace ringdem

#pragma once

#include <cstdint>

#include "core/Vec3.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// The spatial bins of a re-sort (docs/architecture.md, "Order of the particles"). A grain's
/// bin is the cube of edge `width` that holds its centre, numbered x fastest and z slowest (as
/// LAMMPS sorts its atoms: a bed's bottom layer, which the floor's contacts read, stays one run);
/// stored in a particle's sort_bin it orders the owned particles and the contact pairs by
/// space, so that a flow whose grains have mixed is walked with its neighbours near in memory.
/// The bin is a function of the position and the width alone, so every rank gives a particle
/// the same one.
///
/// The cube's indices are kept modulo 2048 along x and 1024 along y and z (31 bits, with the
/// top bit marking a binned particle): two regions 2048 widths apart along x (1024 along y or
/// z) share bin numbers and are interleaved in the order, which costs locality, never
/// correctness.
class SpatialBins {
 public:
  /// Set on every binned particle's bin: binned particles come after the unbinned ones (bin 0).
  static constexpr std::uint32_t kBinned = 1u << 31;

  /// The bin of a centre at x (a cube of edge width > 0).
  static std::uint32_t bin_of(const Vec3& x, double width);

  /// Gives each owned particle that belongs to no ring or clump (body < 0) the bin of its
  /// position; the others keep bin 0, their gid order (a net's particles are made in ring order,
  /// the order its bonds walk).
  static void assign(ParticleStore& p, double width);

  /// The smallest radius of the owned particles that assign() bins (infinity for none); the
  /// minimum over the ranks, doubled, is the width of a re-sort.
  static double smallest_binned_radius(const ParticleStore& p);
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/GrainSizeDistribution.hpp"

namespace ringdem {

/// A grain of a packing: its centre and radius.
struct PackedGrain {
  Vec3 centre;
  double radius = 0.0;
};

/// Grains filling a box at a solid fraction (engine/GrainSource builds them; an inlet of
/// engine/InflowSource builds one such fill per batch).
struct GrainFill {
  std::string name = "grains";  ///< case-file path, for errors
  Vec3 box_min, box_max;
  GrainSizeDistribution sizes = GrainSizeDistribution::uniform(0.005, 0.005);
  double solid_fraction = 0.3;
  std::uint64_t seed = 1;
  Vec3 velocity;
  double density = 0.0;
  double damping = 0.0;
  std::int32_t material = 0;
  std::int32_t group = 0;
};

/// A packing that random sequential addition could not complete.
class GrainPackingError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The radii of one packing cell (docs/physics.md "Debris grains"): drawn from `sizes` until
/// the next draw would take the solid volume past `target_volume`, then sorted largest first.
/// Only `rng` decides them, so the count of a cell is known without placing its grains.
std::vector<double> draw_cell_radii(const GrainSizeDistribution& sizes, double target_volume,
                                    std::mt19937_64& rng);

/// Random sequential addition: places `radii` (largest first) one after the other at uniform
/// random centres inside the box [lo, hi] (each sphere wholly inside), rejecting any position
/// where it would overlap a sphere already placed, with up to `max_attempts` positions per
/// grain; throws GrainPackingError when a grain finds no room. Grains of neighbouring boxes
/// cannot overlap, since each stays inside its own box.
std::vector<PackedGrain> place_grains(const std::vector<double>& radii, const Vec3& lo,
                                      const Vec3& hi, std::mt19937_64& rng,
                                      int max_attempts = 20000);

/// Reorders a packing cell's grains (place_grains() leaves them in random places, largest
/// first) by the bin of width `bin` from `lo` that holds each centre: z fastest, then y, then
/// x, as the cells themselves are numbered; grains of one bin keep their order. The order
/// becomes the grains' gids, and so the order particles are stored and their contacts walked
/// in: touching grains then lie close together in memory. In random order the contact loop of
/// a packing in contact ran 2 times as long with random runs of 4500 grains and 4 times with
/// a fully random order (docs/performance.md, twenty-second round).
void order_by_space(std::vector<PackedGrain>& grains, const Vec3& lo, double bin);

}  // namespace ringdem

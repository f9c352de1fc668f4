#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <random>
#include <string>

#include "core/Vec3.hpp"
#include "domain/GrainPacking.hpp"
#include "domain/GrainSizeDistribution.hpp"
#include "engine/ParticleSource.hpp"

namespace ringdem {

/// Polydisperse grains filling a box at a solid fraction, without overlaps (docs/physics.md
/// "Debris grains"). The box is cut into packing cells about eight largest diameters wide;
/// each cell draws its radii and places them by random sequential addition from its own
/// stream, seeded by the case seed and the cell's index, so a cell is the same whichever rank
/// builds it. Item cell * per_cell + k is the cell's k-th grain in the order of space
/// (order_by_space(): bins of one largest diameter, z fastest, as the cells): gids are sparse,
/// since a cell holds fewer than per_cell grains, but they depend on the case alone.
/// A rank builds only the cells of its slice of items: no rank ever holds every grain.
class GrainSource final : public ParticleSource {
 public:
  using Spec = GrainFill;
  /// Packing cells are at least this many largest diameters wide (where the box allows).
  static constexpr double kCellDiameters = 8.0;

  explicit GrainSource(const Spec& spec);

  std::string describe() const override { return "grains"; }
  /// The grains it creates: every cell's radii are drawn (not placed) once to count them.
  std::int64_t count() const override;
  std::int64_t gid_range() const override { return cells() * per_cell_; }
  void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
            Model& model) const override;

  std::int64_t cells() const { return std::int64_t{cells_[0]} * cells_[1] * cells_[2]; }
  std::int64_t per_cell() const { return per_cell_; }

 private:
  std::mt19937_64 cell_stream(std::int64_t cell) const;
  Vec3 cell_lower(std::int64_t cell) const;

  Spec spec_;
  std::array<int, 3> cells_{1, 1, 1};
  Vec3 cell_size_;
  double target_volume_ = 0.0;  ///< solid volume per cell
  std::int64_t per_cell_ = 1;   ///< items reserved per cell: more than it can hold
  mutable std::optional<std::int64_t> count_;
};

}  // namespace ringdem

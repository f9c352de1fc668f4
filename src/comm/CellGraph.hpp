#pragma once

#include <cstdint>
#include <vector>

namespace ringdem {

/// What the decomposition weighs in one occupied partition cell.
struct CellLoad {
  std::uint64_t key;
  std::int64_t particles;
  std::int64_t rows;  ///< the weight of the pair-store rows (bonds) counted in the cell
  int rank;           ///< a rank with particles in the cell (the smallest, after merging)
};

/// The graph METIS partitions (DESIGN §4): a vertex per occupied cell, weighing its particles
/// and weighted rows plus one; an edge between cells that share a face, an edge or a corner,
/// weighing the particles that can interact across it.
class CellGraph {
 public:
  /// A cell's vertex weight: its particles and weighted rows, plus one, so that an emptied
  /// cell still counts (the same weight the repartition test at a rebuild sums per rank).
  static std::int64_t vertex_weight(const CellLoad& c) { return c.particles + c.rows + 1; }

  /// The part of each of `cells` (sorted by key, each key once: DomainDecomposition's merged
  /// list), in their order: METIS k-way on their graph with a fixed seed (the same parts for
  /// the same cells), or one part a cell when there are no more cells than parts. The graph
  /// lives only inside the call.
  static std::vector<std::int32_t> partition(const std::vector<CellLoad>& cells, int n_parts);
};

}  // namespace ringdem

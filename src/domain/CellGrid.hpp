#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "core/CellKeys.hpp"
#include "core/Vec3.hpp"

namespace ringdem {

/// Particles binned by cubic cells of one size: a dense grid (counting sort, array lookups)
/// when they fill their bounding box or the box has few cells, hashed cells when they are
/// sparse in a large box (a net far from its boulder, a few grains far apart), so a sparse or
/// very large domain costs nothing extra.
class CellGrid {
 public:
  /// Boxes of up to this many cells take the dense grid however sparse their members, within
  /// kDenseCellsPerMember: 4 MB of cell ranges while the grid lives, against a binary search in
  /// every row a query meets in the hashed cells (a debris channel's finest grains, 54 000 in
  /// 690 000 cells of a box that the net makes tall: the search took 1.6 times as long hashed).
  static constexpr std::size_t kDenseCellFloor = std::size_t{1} << 20;
  /// ... but no more cells than this per member: each build clears, sums and maps every cell,
  /// and a few members far apart (the beads of a net whose bonds broke, flying off) filled a
  /// box of 2^20 cells at each rebuild, three quarters of such a run's time.
  static constexpr std::size_t kDenseCellsPerMember = 32;
  /// Bins `members` (particle indices into `position`) by cells of edge `h`: dense when the
  /// members' box has at most max(2 n + 64, min(`dense_cell_floor`, 32 n)) cells.
  void build(const std::vector<Vec3>& position, const std::vector<std::uint32_t>& members, double h,
             std::size_t dense_cell_floor = kDenseCellFloor);
  /// Calls f(index) for every member in a cell that meets the cube [x - reach, x + reach].
  template <class F>
  void for_each_near(const Vec3& x, double reach, F&& f) const;
  bool dense() const { return dense_; }
  /// Gives the bins' memory back (until the next build; dense() still tells the last one).
  void release_memory() {
    for (auto* v : {&cell_start_, &cell_of_member_, &in_cells_, &cell_x_, &cell_begin_})
      std::vector<std::uint32_t>().swap(*v);
    std::vector<Row>().swap(table_);
    n_cells_ = 0;
  }

 private:
  std::int64_t cell(double coordinate, double origin) const {
    return static_cast<std::int64_t>(std::floor((coordinate - origin) * inv_h_));
  }
  static constexpr std::int64_t kBias = cell_keys::kBias;
  /// z slowest and x fastest, as the dense grid numbers its cells and as a re-sort stores the
  /// grains: sorted, the keys put each row of cells along x together, in x order.
  static std::uint64_t key(std::int64_t cx, std::int64_t cy, std::int64_t cz) {
    return cell_keys::pack(cz, cy, cx);
  }
  static std::uint64_t row_key(std::int64_t cy, std::int64_t cz) { return key(0, cy, cz) >> 21; }

  Vec3 lo_;
  double inv_h_ = 1.0;
  bool dense_ = false;
  std::int64_t dims_[3] = {0, 0, 0};  ///< cells of the members' bounding box, on each axis
  // Dense: members by cell (cells numbered x fastest, z slowest; in_cells_), and where each
  // cell's members start (one entry more than cells: the last is the member count).
  std::vector<std::uint32_t> cell_start_, cell_of_member_, in_cells_;
  // Hashed: the members sorted by cell key (in_cells_); the occupied cells in key order, each
  // with its x index and its range of the members; and each occupied row of cells along x (a y and
  // a z) with its range of the cells, in a table with open addressing (linear probing, a power of
  // two slots, at most half of them used; an empty slot has end 0). A query looks up its rows, not
  // each of its cells: a search along the grains' order (x fastest) meets the same few rows again
  // and again, where a lookup per cell missed the cache at nearly every cell (a polydisperse bed's
  // list build at 10^6 grains took eight times the monodisperse one's).
  struct Row {
    std::uint64_t key = 0;
    std::uint32_t first = 0, end = 0;  ///< its cells
  };
  /// Fibonacci hashing: the key's bits mixed by one multiplication, the top ones kept.
  std::uint64_t home_slot(std::uint64_t k) const {
    return (k * 0x9E3779B97F4A7C15ull) >> table_shift_;
  }
  const Row* find_row(std::uint64_t k) const {
    for (std::uint64_t i = home_slot(k);; i = (i + 1) & table_mask_) {
      const Row& r = table_[i];
      if (r.end == 0) return nullptr;
      if (r.key == k) return &r;
    }
  }
  std::vector<std::uint32_t> cell_x_;      ///< per occupied cell: its x index + kBias
  std::vector<std::uint32_t> cell_begin_;  ///< per occupied cell, and one more: into in_cells_
  std::vector<Row> table_;
  std::uint64_t table_mask_ = 0;
  int table_shift_ = 64;
  std::size_t n_cells_ = 0;  ///< occupied cells
};

template <class F>
void CellGrid::for_each_near(const Vec3& x, double reach, F&& f) const {
  std::int64_t lo[3] = {cell(x.x - reach, lo_.x), cell(x.y - reach, lo_.y),
                        cell(x.z - reach, lo_.z)};
  std::int64_t hi[3] = {cell(x.x + reach, lo_.x), cell(x.y + reach, lo_.y),
                        cell(x.z + reach, lo_.z)};
  // Only the cells of the members' bounding box (cells 0 .. dims - 1 on each axis): a grain
  // far from a level's members (a debris grain and the net's beads) looks up no cell of it.
  for (int d = 0; d < 3; ++d) {
    lo[d] = std::max<std::int64_t>(lo[d], 0);
    hi[d] = std::min<std::int64_t>(hi[d], dims_[d] - 1);
    if (lo[d] > hi[d]) return;
  }
  if (dense_) {
    // Rows of cells along x, as the grains are stored after a re-sort (SpatialBins: x
    // fastest): a row's members are a run in storage, so the search reads nine runs, not
    // one particle a layer apart at each step along z (a quarter of the rebuilds' time at 10^6
    // grains, docs/performance.md, twenty-fourth round).
    for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz)
      for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy) {
        const std::int64_t row = (cz * dims_[1] + cy) * dims_[0];
        for (std::uint32_t s = cell_start_[static_cast<std::size_t>(row + lo[0])];
             s < cell_start_[static_cast<std::size_t>(row + hi[0] + 1)]; ++s)
          f(in_cells_[s]);
      }
    return;
  }
  // Hashed: a box of more cells than are occupied (a large particle searching small ones)
  // visits the members instead.
  const double box = static_cast<double>(hi[0] - lo[0] + 1) *
                     static_cast<double>(hi[1] - lo[1] + 1) *
                     static_cast<double>(hi[2] - lo[2] + 1);
  if (box > static_cast<double>(n_cells_)) {
    for (const std::uint32_t member : in_cells_)
      f(member);
    return;
  }
  const auto x_first = static_cast<std::uint32_t>(lo[0] + kBias),
             x_last = static_cast<std::uint32_t>(hi[0] + kBias);
  for (std::int64_t cz = lo[2]; cz <= hi[2]; ++cz)
    for (std::int64_t cy = lo[1]; cy <= hi[1]; ++cy) {
      const Row* const row = find_row(row_key(cy, cz));
      if (row == nullptr) continue;
      const std::uint32_t* const row_x = cell_x_.data();
      for (std::uint32_t c = static_cast<std::uint32_t>(
               std::lower_bound(row_x + row->first, row_x + row->end, x_first) - row_x);
           c < row->end && row_x[c] <= x_last; ++c)
        for (std::uint32_t s = cell_begin_[c]; s < cell_begin_[c + 1]; ++s)
          f(in_cells_[s]);
    }
}

}  // namespace ringdem

#include "domain/CellGrid.hpp"

#include <algorithm>
#include <limits>

namespace ringdem {

void CellGrid::build(const std::vector<Vec3>& position, const std::vector<std::uint32_t>& members,
                     double h, std::size_t dense_cell_floor) {
  inv_h_ = 1.0 / h;
  constexpr double kBig = std::numeric_limits<double>::max();
  Vec3 lo{kBig, kBig, kBig}, hi{-kBig, -kBig, -kBig};
  for (const std::uint32_t k : members) {
    const Vec3& x = position[k];
    lo = {std::min(lo.x, x.x), std::min(lo.y, x.y), std::min(lo.z, x.z)};
    hi = {std::max(hi.x, x.x), std::max(hi.y, x.y), std::max(hi.z, x.z)};
  }
  lo_ = lo;
  const std::size_t n = members.size();
  const double extent[3] = {std::floor((hi.x - lo.x) * inv_h_) + 1.0,
                            std::floor((hi.y - lo.y) * inv_h_) + 1.0,
                            std::floor((hi.z - lo.z) * inv_h_) + 1.0};
  const double box_cells = extent[0] * extent[1] * extent[2];
  const double members_cells = static_cast<double>(kDenseCellsPerMember) * static_cast<double>(n);
  dense_ = n > 0 && (box_cells <= 2.0 * static_cast<double>(n) + 64.0 ||
                     box_cells <= std::min(static_cast<double>(dense_cell_floor), members_cells));
  n_cells_ = 0;
  for (int d = 0; d < 3; ++d)  // no cells without members
    dims_[d] = n > 0 ? static_cast<std::int64_t>(extent[d]) : 0;
  if (dense_) {
    const auto n_cells = static_cast<std::size_t>(dims_[0] * dims_[1] * dims_[2]);
    // A counting sort in place: each cell's count, summed into where the cell ends, then the
    // members placed from the last, each cell's end moving back to its start. Members keep
    // their order within a cell.
    cell_start_.assign(n_cells + 1, 0);
    cell_of_member_.resize(n);
    for (std::size_t m = 0; m < n; ++m) {
      const Vec3& x = position[members[m]];
      const std::int64_t c =
          (cell(x.z, lo_.z) * dims_[1] + cell(x.y, lo_.y)) * dims_[0] + cell(x.x, lo_.x);
      cell_of_member_[m] = static_cast<std::uint32_t>(c);
      ++cell_start_[static_cast<std::size_t>(c)];
    }
    for (std::size_t c = 1; c < n_cells; ++c)
      cell_start_[c] += cell_start_[c - 1];
    cell_start_[n_cells] = static_cast<std::uint32_t>(n);
    in_cells_.resize(n);
    for (std::size_t m = n; m-- > 0;)
      in_cells_[--cell_start_[cell_of_member_[m]]] = members[m];
    return;
  }
  // (cell key, member) pairs, sorted: scratch of the build. The queries read the members in
  // that order (in_cells_, 4 bytes each, not the 16 of a pair).
  std::vector<std::pair<std::uint64_t, std::uint32_t>> keyed(n);
  for (std::size_t m = 0; m < n; ++m) {
    const Vec3& x = position[members[m]];
    keyed[m] = {key(cell(x.x, lo_.x), cell(x.y, lo_.y), cell(x.z, lo_.z)), members[m]};
  }
  std::sort(keyed.begin(), keyed.end());
  in_cells_.resize(n);
  cell_x_.clear();
  cell_begin_.clear();
  std::vector<std::uint64_t> row_of_cell;
  for (std::uint32_t s = 0; s < n; ++s) {
    in_cells_[s] = keyed[s].second;
    if (s == 0 || keyed[s].first != keyed[s - 1].first) {
      cell_x_.push_back(static_cast<std::uint32_t>(keyed[s].first & ((1u << 21) - 1)));
      cell_begin_.push_back(s);
      row_of_cell.push_back(keyed[s].first >> 21);
    }
  }
  cell_begin_.push_back(static_cast<std::uint32_t>(n));
  std::vector<std::pair<std::uint64_t, std::uint32_t>>().swap(keyed);
  n_cells_ = cell_x_.size();
  std::size_t n_rows = 0;
  for (std::size_t c = 0; c < n_cells_; ++c)
    n_rows += c == 0 || row_of_cell[c] != row_of_cell[c - 1];
  // At least twice as many slots as rows, so that a probe ends soon at an empty one.
  int bits = 4;
  while ((std::size_t{1} << bits) < 2 * n_rows)
    ++bits;
  table_.assign(std::size_t{1} << bits, Row{});
  table_mask_ = (std::uint64_t{1} << bits) - 1;
  table_shift_ = 64 - bits;
  for (std::size_t c = 0; c < n_cells_;) {
    std::size_t e = c + 1;
    while (e < n_cells_ && row_of_cell[e] == row_of_cell[c])
      ++e;
    std::uint64_t i = home_slot(row_of_cell[c]);
    while (table_[i].end != 0)
      i = (i + 1) & table_mask_;
    table_[i] = {row_of_cell[c], static_cast<std::uint32_t>(c), static_cast<std::uint32_t>(e)};
    c = e;
  }
}

}  // namespace ringdem

#pragma once

#include <cstdint>

namespace ringdem::cell_keys {

/// Keys of cubic cells by their integer indices (i, j, k), i in the top bits and k in the
/// bottom ones: 21 bits per axis, biased so that negative indices pack too. The decomposition
/// keys its blocks and partition cells (x, y, z); a neighbour grid its cells (z, y, x), so that
/// sorted keys run along x.
inline constexpr std::int64_t kBias = std::int64_t{1} << 20;

inline std::uint64_t pack(std::int64_t i, std::int64_t j, std::int64_t k) {
  return (static_cast<std::uint64_t>(i + kBias) << 42) |
         (static_cast<std::uint64_t>(j + kBias) << 21) | static_cast<std::uint64_t>(k + kBias);
}

inline void unpack(std::uint64_t key, std::int64_t& i, std::int64_t& j, std::int64_t& k) {
  const std::uint64_t mask = (std::uint64_t{1} << 21) - 1;
  i = static_cast<std::int64_t>((key >> 42) & mask) - kBias;
  j = static_cast<std::int64_t>((key >> 21) & mask) - kBias;
  k = static_cast<std::int64_t>(key & mask) - kBias;
}

/// The 27 keys around `key`, itself included.
template <class F>
void for_each_neighbour(std::uint64_t key, F&& f) {
  std::int64_t i, j, k;
  unpack(key, i, j, k);
  for (std::int64_t di = -1; di <= 1; ++di)
    for (std::int64_t dj = -1; dj <= 1; ++dj)
      for (std::int64_t dk = -1; dk <= 1; ++dk)
        f(pack(i + di, j + dj, k + dk));
}

/// floor(v / n) for n > 0, also for negative v.
inline std::int64_t floor_div(std::int64_t v, std::int64_t n) {
  return v >= 0 ? v / n : -((-v + n - 1) / n);
}

/// The cells of `cell_blocks` blocks a side that hold the 27 blocks around block `key`, each
/// once: per axis the distinct cells of i - 1, i and i + 1 (one, or two at a cell's face, for
/// cells of two blocks or more; three for one-block cells), and their product. The same set as
/// mapping each of for_each_neighbour's blocks to its cell, without the 27 divisions and the
/// search for repeats (most particles sit inside a cell: one cell, their own).
template <class F>
void for_each_cell_around_block(std::uint64_t key, std::int64_t cell_blocks, F&& f) {
  std::int64_t b[3];
  unpack(key, b[0], b[1], b[2]);
  std::int64_t cells[3][3];
  int count[3];
  for (int a = 0; a < 3; ++a) {
    count[a] = 0;
    for (std::int64_t d = -1; d <= 1; ++d) {
      const std::int64_t c = floor_div(b[a] + d, cell_blocks);  // rises with d: repeats adjoin
      if (count[a] == 0 || cells[a][count[a] - 1] != c) cells[a][count[a]++] = c;
    }
  }
  for (int x = 0; x < count[0]; ++x)
    for (int y = 0; y < count[1]; ++y)
      for (int z = 0; z < count[2]; ++z)
        f(pack(cells[0][x], cells[1][y], cells[2][z]));
}

}  // namespace ringdem::cell_keys

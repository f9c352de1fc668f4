#pragma once

#include <algorithm>
#include <bit>
#include <cstdint>
#include <vector>

namespace ringdem {

/// gid -> particle index: an open-addressing hash table (linear probing, power-of-two
/// capacity, at most three quarters full) of particle indices only; a slot's gid is read from
/// the store's gid column, so the table costs 5.3 to 10.7 bytes a particle (a node-based
/// std::unordered_map took about 60 and a heap allocation per insert; at most half full it
/// was 8 to 16, and 16 at 10^6 grains, 4 % of issue 12's bound: docs/performance.md,
/// forty-fifth round). It is rebuilt whole at every neighbour-list rebuild and ghost
/// exchange, so it needs no deletion.
class GidIndex {
 public:
  /// Empties the table and sizes it for `n` entries.
  void reset(std::size_t n) {
    resize_table(std::bit_ceil(capacity_for(n)));
    size_ = 0;
  }
  /// Makes `index` the entry of gids[index] (a later index of the same gid replaces an earlier
  /// one). `gids`, `n`: the store's gid column and its length (entries at n or beyond, left by
  /// a store that shrank since the last reset, match no gid).
  void set(std::uint32_t index, const std::int64_t* gids, std::size_t n) {
    if (capacity_for(size_ + 1) > slots_.size()) grow(gids, n);
    const std::int64_t gid = gids[index];
    for (std::size_t i = home(gid);; i = (i + 1) & mask_) {
      if (slots_[i] == kEmpty) {
        slots_[i] = index;
        ++size_;
        return;
      }
      if (slots_[i] < n && gids[slots_[i]] == gid) {
        slots_[i] = index;
        return;
      }
    }
  }
  /// Index of gid, or -1 when absent.
  std::int64_t find(std::int64_t gid, const std::int64_t* gids, std::size_t n) const {
    if (slots_.empty()) return -1;
    for (std::size_t i = home(gid);; i = (i + 1) & mask_) {
      if (slots_[i] == kEmpty) return -1;
      if (slots_[i] < n && gids[slots_[i]] == gid) return slots_[i];
    }
  }
  std::size_t size() const { return size_; }
  /// Slots of the table (a power of two): size() / capacity() is at most kMaxLoad.
  std::size_t capacity() const { return slots_.size(); }
  /// The most a table is filled before it grows (kMaxLoad). Linear probing's successful
  /// search visits about (1 + 1 / (1 - load)) / 2 slots (Knuth): 2.5 at 3/4 against 1.5 at
  /// 1/2. The table is read at rebuilds and ghost exchanges only, and the neighbour phase of a
  /// 10^6-grain bed did not change (docs/performance.md, forty-fifth round).
  static constexpr std::size_t kMaxLoadNumerator = 3, kMaxLoadDenominator = 4;

 private:
  static constexpr std::uint32_t kEmpty = UINT32_MAX;
  /// Slots of one 64-byte cache line.
  static constexpr std::uint64_t kLine = 64 / sizeof(std::uint32_t);

  /// Gids in runs of kLine share a cache line of the table: the run (gid / kLine) picks the
  /// line by Fibonacci hashing (the top bits of run * 2^64/phi, so that the runs of a source's
  /// consecutive gids, and those of sources at far-apart bases, spread over the table), and
  /// gid % kLine the slot in it. A store holds its owned particles in gid order, or after a
  /// re-sort by space in runs of it as long as the grains of neighbouring bins were made
  /// together, so filling the table touches one line for every kLine particles instead of one
  /// for each (a hash of the whole gid made every insert a cache miss: 5 % of a 10^6-grain
  /// flow's step, at its neighbour-list rebuilds).
  std::size_t home(std::int64_t gid) const {
    const auto g = static_cast<std::uint64_t>(gid);
    const std::uint64_t line = ((g / kLine) * 0x9e3779b97f4a7c15ull) >> line_shift_;
    return static_cast<std::size_t>(line * kLine + g % kLine);
  }
  /// The fewest slots that hold `entries` at most kMaxLoad full.
  static std::size_t capacity_for(std::size_t entries) {
    return (kMaxLoadDenominator * entries + kMaxLoadNumerator - 1) / kMaxLoadNumerator;
  }
  void resize_table(std::size_t capacity) {
    capacity = std::max<std::size_t>(capacity, 2 * kLine);  // a shift by 64 bits is undefined
    slots_.assign(capacity, kEmpty);
    mask_ = capacity - 1;
    line_shift_ = 64 - (std::countr_zero(capacity) - std::countr_zero(kLine));
  }
  void grow(const std::int64_t* gids, std::size_t n) {
    std::vector<std::uint32_t> old;
    old.swap(slots_);
    resize_table(2 * old.size() + (old.empty() ? 16 : 0));
    size_ = 0;
    for (const std::uint32_t index : old)
      if (index != kEmpty && index < n) set(index, gids, n);
  }

  std::vector<std::uint32_t> slots_;
  std::size_t mask_ = 0;
  int line_shift_ = 64;
  std::size_t size_ = 0;
};

}  // namespace ringdem

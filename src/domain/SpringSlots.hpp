#pragma once

#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// The tangential springs of a contact term's candidates, stored only for the candidates that
/// touch. Most candidates of a granular packing do not (a resting lattice bed: about 3 a
/// grain, hardly any touching), so a spring column beside the candidates spent 24 bytes on
/// each for a zero. Here a candidate holds a 4-byte slot number into a pool of the touching
/// springs; a contact that opens takes a slot (a freed one first), one that closes gives it
/// back. The values a kernel reads and writes are the same as a column's, in the same order,
/// so the results are the same bits.
///
/// After reset() the slots are taken in candidate order, so the pool starts in the order the
/// kernel walks it.
class SpringSlots {
 public:
  /// Every candidate of n without a spring; the pool empty, its memory kept.
  void reset(std::size_t n_candidates) {
    slot_.assign(n_candidates, kNoSpring);
    pool_.clear();
    free_.clear();
  }
  /// Gives the memory back (between a pack and the next reset).
  void release_memory() {
    std::vector<std::uint32_t>().swap(slot_);
    std::vector<Vec3>().swap(pool_);
    std::vector<std::uint32_t>().swap(free_);
  }
  std::size_t n_candidates() const { return slot_.size(); }
  /// Whether candidate m has a spring (it touched at its last evaluation).
  bool holds(std::size_t m) const { return slot_[m] != kNoSpring; }
  /// Candidate m's spring; only where holds(m).
  const Vec3& value(std::size_t m) const { return pool_[slot_[m]]; }
  /// Candidate m's spring, made (zero) when it has none: the contact touches.
  Vec3& take(std::size_t m) {
    std::uint32_t& s = slot_[m];
    if (s == kNoSpring) {
      if (free_.empty()) {
        s = static_cast<std::uint32_t>(pool_.size());
        pool_.push_back(Vec3{});
      } else {
        s = free_.back();
        free_.pop_back();
        pool_[s] = Vec3{};
      }
    }
    return pool_[s];
  }
  /// Candidate m's contact is open: its spring, if any, goes back to the pool.
  void release(std::size_t m) {
    std::uint32_t& s = slot_[m];
    if (s == kNoSpring) return;
    free_.push_back(s);
    s = kNoSpring;
  }
  /// Springs held (touching candidates).
  std::size_t n_held() const { return pool_.size() - free_.size(); }

 private:
  /// A candidate's slot when it holds no spring.
  static constexpr std::uint32_t kNoSpring = UINT32_MAX;

  std::vector<std::uint32_t> slot_;  ///< candidate -> its spring in pool_, or kNoSpring
  std::vector<Vec3> pool_;           ///< the springs (physics.md §3), some of them free
  std::vector<std::uint32_t> free_;  ///< slots of pool_ given back, reused first
};

}  // namespace ringdem

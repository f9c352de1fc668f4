#pragma once

#include <cstdint>
#include <utility>
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
  /// Every candidate of n without a spring; the pool empty, with room for a spring on every
  /// candidate. Reserved memory that is never written is never resident, so a pool that grows
  /// to its touching contacts costs what they hold, and no doubling of a full pool (the old
  /// and the new copy at once) makes a peak.
  void reset(std::size_t n_candidates) {
    slot_.assign(n_candidates, kNoSpring);
    pool_.clear();
    free_.clear();
    pool_.reserve(n_candidates);
  }
  /// reset(), with the pool made of `carried`, the springs a rebuild reads back (one column of
  /// keyed rows): carry() then gives candidate m the spring of row `row`, in any order and each
  /// row at most once, and end_carry() puts the carried springs in candidate order in the same
  /// memory and cuts off the rest, so that the springs are never held twice and the kernel
  /// walks the pool in order.
  void reset_carrying(std::size_t n_candidates, std::vector<Vec3>&& carried) {
    slot_.assign(n_candidates, kNoSpring);
    pool_ = std::move(carried);
    free_.clear();
  }
  void carry(std::size_t m, std::size_t row) { slot_[m] = static_cast<std::uint32_t>(row); }
  void end_carry() {
    compact_in_candidate_order([](std::size_t) { return true; });
  }
  /// The springs of the candidates m with holds(m) and keep(m), in candidate order, made in the
  /// pool's own memory, which the slots give up (release_memory() follows): what a rebuild keys
  /// and carries.
  template <class Keep>
  std::vector<Vec3> take_in_candidate_order(Keep&& keep) {
    compact_in_candidate_order(keep);
    std::vector<Vec3> kept = std::move(pool_);
    release_memory();
    return kept;
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
  /// Bit c set where candidate begin + c holds a spring, for the n <= 64 candidates from
  /// `begin`: a kernel that visits only the candidates of a chunk that touch, or that held a
  /// spring to give back (release()), asks for the chunk's at once.
  std::uint64_t held_mask(std::size_t begin, std::size_t n) const {
    std::uint64_t mask = 0;
    for (std::size_t c = 0; c < n; ++c)
      mask |= std::uint64_t{slot_[begin + c] != kNoSpring} << c;
    return mask;
  }
  /// Candidate m's spring; only where holds(m).
  const Vec3& value(std::size_t m) const { return pool_[slot_[m]]; }
  Vec3& value(std::size_t m) { return pool_[slot_[m]]; }
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

  /// Keeps only the springs of the candidates m with holds(m) and keep(m), in candidate order
  /// at the front of the pool, which is cut to them: permuted in place (each swap puts one
  /// spring where it goes), a slot number per spring the scratch, so that a packing's springs
  /// are never held twice.
  template <class Keep>
  void compact_in_candidate_order(Keep&& keep) {
    std::vector<std::uint32_t> target(pool_.size(), kNoSpring);
    std::uint32_t n_kept = 0;
    for (std::size_t m = 0; m < slot_.size(); ++m) {
      if (!holds(m)) continue;
      if (keep(m)) {
        target[slot_[m]] = n_kept;
        slot_[m] = n_kept++;
      } else {
        slot_[m] = kNoSpring;
      }
    }
    for (std::size_t s = 0; s < target.size(); ++s)
      while (target[s] != kNoSpring && target[s] != s) {
        const std::uint32_t d = target[s];
        std::swap(pool_[s], pool_[d]);
        std::swap(target[s], target[d]);
      }
    pool_.resize(n_kept);
    free_.clear();
  }

  std::vector<std::uint32_t> slot_;  ///< candidate -> its spring in pool_, or kNoSpring
  std::vector<Vec3> pool_;           ///< the springs (physics.md §3), some of them free
  std::vector<std::uint32_t> free_;  ///< slots of pool_ given back, reused first
};

}  // namespace ringdem

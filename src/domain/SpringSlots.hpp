#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ContactLedgerState.hpp"

namespace ringdem {

/// The tangential springs of a contact term's candidates, stored only for the candidates that
/// touch. Most candidates of a granular packing do not (a resting lattice bed: about 3 a
/// grain, hardly any touching), so a spring column beside the candidates spent 24 bytes on
/// each for a zero. Here a candidate holds a 4-byte slot number into a pool of the touching
/// springs; a contact that opens takes a slot (a freed one first), one that closes gives it
/// back. The values a kernel reads and writes are the same as a column's, in the same order,
/// so the results are the same bits. Beside each spring the pool keeps what the contact carries
/// to the energy ledger's next step where that books each pair's work in the pair loop
/// (ContactLedgerState), once keep_ledger() asked for it: 16 bytes a contact that a run
/// without that booking does not pay.
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
    ledger_.clear();
    free_.clear();
    pool_.reserve(n_candidates);
    if (ledger_kept_) ledger_.reserve(n_candidates);
  }
  /// reset(), with the pool made of `carried`, the springs a rebuild reads back (one column of
  /// keyed rows), and `ledger` their ledger states (as many, kept; or none, not kept until
  /// keep_ledger()): carry() then gives candidate m the spring of row `row`, in any order and
  /// each row at most once, and end_carry() puts the carried springs in candidate order in the
  /// same memory and cuts off the rest, so that the springs are never held twice and the
  /// kernel walks the pool in order.
  void reset_carrying(std::size_t n_candidates, std::vector<Vec3>&& carried,
                      std::vector<ContactLedgerState>&& ledger) {
    slot_.assign(n_candidates, kNoSpring);
    pool_ = std::move(carried);
    ledger_ = std::move(ledger);
    ledger_kept_ = !ledger_.empty();
    if (ledger_kept_) ledger_.resize(pool_.size());
    free_.clear();
  }
  void carry(std::size_t m, std::size_t row) { slot_[m] = static_cast<std::uint32_t>(row); }
  void end_carry() {
    compact_in_candidate_order([](std::size_t) { return true; });
  }
  /// The springs of the candidates m with holds(m) and keep(m), in candidate order, made in the
  /// pool's own memory, which the slots give up (release_memory() follows), and their ledger
  /// states into `ledger` (none where they are not kept): what a rebuild keys and carries.
  template <class Keep>
  std::vector<Vec3> take_in_candidate_order(Keep&& keep, std::vector<ContactLedgerState>& ledger) {
    compact_in_candidate_order(keep);
    std::vector<Vec3> kept = std::move(pool_);
    ledger = std::move(ledger_);
    release_memory();
    return kept;
  }
  /// Gives the memory back (between a pack and the next reset).
  void release_memory() {
    std::vector<std::uint32_t>().swap(slot_);
    std::vector<Vec3>().swap(pool_);
    std::vector<ContactLedgerState>().swap(ledger_);
    std::vector<std::uint32_t>().swap(free_);
    ledger_kept_ = false;
  }
  /// Keeps a ledger state beside every spring from now on, zero for the springs held now. A
  /// rebuild at the middle of a step carries none (PairContactTerm::book_carried_work()), and
  /// they are made here, at the next evaluation, not in the rebuild: there they came on top of
  /// the rebuild's own scratch, 15 % over the run's peak at 10^6 grains in contact.
  void keep_ledger() {
    if (ledger_kept_) return;
    ledger_.reserve(pool_.capacity());
    ledger_.assign(pool_.size(), ContactLedgerState{});
    ledger_kept_ = true;
  }
  bool keeps_ledger() const { return ledger_kept_; }
  /// Gives the ledger states' memory back (a rebuild that booked what they carried does so
  /// before it keys the springs, which would otherwise come on top of them).
  void drop_ledger() {
    std::vector<ContactLedgerState>().swap(ledger_);
    ledger_kept_ = false;
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
  /// What candidate m carries to the ledger's next step; only where holds(m) and
  /// keeps_ledger().
  const ContactLedgerState& ledger(std::size_t m) const { return ledger_[slot_[m]]; }
  ContactLedgerState& ledger(std::size_t m) { return ledger_[slot_[m]]; }
  /// Candidate m's spring, made (zero, with a zero ledger state) when it has none: the contact
  /// touches.
  Vec3& take(std::size_t m) {
    std::uint32_t& s = slot_[m];
    if (s == kNoSpring) {
      if (free_.empty()) {
        s = static_cast<std::uint32_t>(pool_.size());
        pool_.push_back(Vec3{});
        if (ledger_kept_) ledger_.push_back(ContactLedgerState{});
      } else {
        s = free_.back();
        free_.pop_back();
        pool_[s] = Vec3{};
        if (ledger_kept_) ledger_[s] = ContactLedgerState{};
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
        if (ledger_kept_) std::swap(ledger_[s], ledger_[d]);
        std::swap(target[s], target[d]);
      }
    pool_.resize(n_kept);
    if (ledger_kept_) ledger_.resize(n_kept);
    free_.clear();
  }

  std::vector<std::uint32_t> slot_;         ///< candidate -> its spring in pool_, or kNoSpring
  std::vector<Vec3> pool_;                  ///< the springs (physics.md §3), some of them free
  std::vector<ContactLedgerState> ledger_;  ///< beside each spring, what its contact carries
  bool ledger_kept_ = false;                ///< ledger_ has an entry per pool_ entry
  std::vector<std::uint32_t> free_;         ///< slots of pool_ given back, reused first
};

}  // namespace ringdem

#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <optional>
#include <vector>

#include "comm/ExactSum.hpp"
#include "comm/QuantumSum.hpp"
#include "core/Vec3.hpp"
#include "core/Vec3f.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/GatherMap.hpp"

namespace ringdem {

/// What the energy ledger needs of one dissipative slot's load (docs/physics.md "Energy
/// ledger"): the force terms that dissipate write one record per slot through record().
struct DissipationRecord {
  Vec3 damping;                    ///< viscous force on this particle (Eq. 7 + Eq. 9)
  Vec3 friction;                   ///< tangential spring force on this particle (Coulomb-capped)
  Vec3 arm;                        ///< from this particle's centre to the contact point; 0: idle
  Vec3 rolling;                    ///< rolling-friction torque on this particle
  double tangential_energy = 0.0;  ///< this particle's share of |F_t|^2 / 2 S_t
  double elastic_energy = 0.0;     ///< this particle's share of the contact's elastic energy
  std::int32_t body = -1;          ///< rigid body on the other side, -1 for a particle
};

/// What the ledger needs of the contact loads on one particle from a term that sums per
/// particle (ParticleLoads): the work of a load F at arm r is F . (v + w x r) = F . v +
/// (r x F) . w, so the sums of F and of r x F over the contacts give the power at the
/// end-of-step velocities v, w without a record per contact (physics.md §3 for the loads).
struct alignas(64) ContactMoments {
  /// Provided, so that a new entry (moments_.emplace_back()) is made by the members' zero
  /// initialisers, not value-initialised: that became a rep stos, 8 % of a dense packing's
  /// pair loop.
  ContactMoments() {}
  // The four sums in float, each added in double and rounded once (Vec3f): a power from them
  // is off by about 1e-7 of each load's, far below the ledger's O(dt^2) closure, and an entry
  // is one cache line (64 bytes, 112 in double: 48 bytes a grain in contact at 10^6 grains).
  Vec3f damping;                   ///< sum of the viscous forces (Eq. 7 + Eq. 9)
  Vec3f damping_moment;            ///< sum of arm x viscous force
  Vec3f friction;                  ///< sum of the tangential spring forces (Coulomb-capped)
  Vec3f friction_moment;           ///< sum of arm x spring force, plus the rolling-friction torques
  double tangential_energy = 0.0;  ///< this particle's shares of |F_t|^2 / 2 S_t
  double elastic_energy = 0.0;     ///< this particle's shares of the contacts' elastic energy

  /// Adds one contact's loads on this particle, each component as Vec3f::operator+= adds it
  /// (in double, rounded once to float): the same bits. The twelve floats lie next to each
  /// other and are added four at a time, converted to double and back in vector registers: one
  /// at a time, the conversions and the read-modify-writes of a dense packing's two ends a
  /// contact were about a fifth of its pair loop (docs/performance.md, nineteenth round).
  [[gnu::always_inline]] void add(const Vec3& damping_load, const Vec3& damping_load_moment,
                                  const Vec3& friction_load, const Vec3& friction_load_moment,
                                  double tangential, double elastic) {
    using Doubles = double __attribute__((vector_size(32)));
    using Floats = float __attribute__((vector_size(16)));
    const Doubles add0{damping_load.x, damping_load.y, damping_load.z, damping_load_moment.x};
    const Doubles add1{damping_load_moment.y, damping_load_moment.z, friction_load.x,
                       friction_load.y};
    const Doubles add2{friction_load.z, friction_load_moment.x, friction_load_moment.y,
                       friction_load_moment.z};
    // damping, damping_moment, friction, friction_moment: twelve floats from offset 0
    unsigned char* const sums = reinterpret_cast<unsigned char*>(this);
    Floats s0, s1, s2;
    std::memcpy(&s0, sums, sizeof s0);
    std::memcpy(&s1, sums + sizeof s0, sizeof s1);
    std::memcpy(&s2, sums + 2 * sizeof s0, sizeof s2);
    s0 = __builtin_convertvector(__builtin_convertvector(s0, Doubles) + add0, Floats);
    s1 = __builtin_convertvector(__builtin_convertvector(s1, Doubles) + add1, Floats);
    s2 = __builtin_convertvector(__builtin_convertvector(s2, Doubles) + add2, Floats);
    std::memcpy(sums, &s0, sizeof s0);
    std::memcpy(sums + sizeof s0, &s1, sizeof s1);
    std::memcpy(sums + 2 * sizeof s0, &s2, sizeof s2);
    tangential_energy += tangential;
    elastic_energy += elastic;
  }
};
static_assert(sizeof(ContactMoments) == 64, "a ledger entry is one cache line");
static_assert(offsetof(ContactMoments, damping) == 0 &&
                  offsetof(ContactMoments, damping_moment) == 12 &&
                  offsetof(ContactMoments, friction) == 24 &&
                  offsetof(ContactMoments, friction_moment) == 36,
              "ContactMoments::add() reads the four sums as twelve floats in a row");

/// The energy ledger, written once for every force term: the work of the dissipative contact
/// loads and of driven bodies and particles, from the records the terms write and the gather
/// order, kept per rank and per tally in exact sums (docs/physics.md "Energy ledger"). Each
/// particle's power is computed as before, in a fixed order of its contacts; the exact sums
/// make the totals over the ranks independent of which rank held which particle, without a
/// column per particle. The energy the contacts hold (tangential springs, elastic) is summed
/// the same way each step. (Global damping, booked by the integrator, keeps its columns.)
class EnergyLedger {
 public:
  /// The tallies kept here.
  enum Tally { kDamping, kFriction, kBoundary, kTallies };
  /// The energies the contacts hold after a step, summed per rank (held(), held_by_leaving()).
  enum Held { kTangentialHeld, kContactHeld, kHeldSums };
  /// A tally over the ranks, from the exact totals of intervals() and direct():
  /// dt/2 * intervals + direct (for friction, less the tangential energy the springs hold now,
  /// which the caller sums over the particles' tangential_energy).
  static double tally(double intervals_total, double direct_total, double dt) {
    return 0.5 * dt * intervals_total + direct_total;
  }
  /// This rank's part of the trapezoidal sums since the time step was last set: per step,
  /// the powers at the step's start plus those at its end (unscaled).
  const std::array<ExactSum, kTallies>& intervals() const { return intervals_; }
  /// This rank's part of what is booked as it is: a friction tally's tangential energy at the
  /// ledger's start, the exact work of external forces, and the intervals of earlier time steps.
  const std::array<ExactSum, kTallies>& direct() const { return direct_; }
  /// This rank's sums of its particles' shares of the tangential spring energy and of the
  /// contacts' elastic energy after the last accumulate(), each particle's summed in a fixed
  /// order of its contacts: friction counts the first as not yet dissipated, the energy
  /// balance the second as contact energy. Only a step that ends a batch books them (see
  /// start_accumulation()); asked for after one that did not, this throws std::logic_error.
  const std::array<ExactSum, kHeldSums>& held() const;
  /// The part of held() of particles that an outflow box takes out before the next step: it
  /// leaves the model with them (OutflowSink::remove_leaving()).
  const std::array<ExactSum, kHeldSums>& held_by_leaving() const { return held_leaving_; }
  /// Before the time step changes from `dt_old`: the intervals so far, totalled over the ranks
  /// (`intervals_totals`, the same on every rank), move into direct() (on the root rank only,
  /// so they count once), so that the next intervals take the new step.
  void close_intervals(const std::array<double, kTallies>& intervals_totals, double dt_old,
                       bool root);
  /// The tallies as exact sums to reduce over the ranks and write to a checkpoint: intervals,
  /// the last step's powers, direct (kTallies sums each), then held() and held_by_leaving()
  /// (kHeldSums each), in that order.
  std::vector<ExactSum> state() const;
  /// How many sums state() holds.
  static constexpr std::size_t kStateSums = 3 * kTallies + 2 * kHeldSums;
  /// From a checkpoint's totals (root rank; the others start from zero), or all zero (empty).
  void restore(const std::vector<ExactSum>& totals, bool root);

  /// Off (SimulationSettings::energy_ledger), the terms add no ContactMoments (they ask
  /// enabled() once per evaluation) and begin_step() and the accumulation do nothing: the
  /// tallies stay as they are.
  void set_enabled(bool on) { enabled_ = on; }
  bool enabled() const { return enabled_; }
  /// The interactions this ledger books (ForceRate): multi-rate stepping keeps a ledger per
  /// rate, each with its own slots (GatherMap::ledger_slots of its rate) and step. Only a fast
  /// or single-rate ledger books the drivers' power on driven particles and the work of point
  /// loads (GatherMap::driven_powers, external_powers): the loads of held particles are fast.
  /// Set before the first rebuild().
  void set_rate(ForceRate rate) { rate_ = rate; }

  /// After GatherMap::finish(): one record per ledger slot, stored in the order accumulate()
  /// reads them (one contiguous stream), plus a scratch record for the other slots.
  void rebuild(const GatherMap& gather, std::size_t n_slots);
  /// Records kept since the last rebuild(): the ledger slots' and the scratch one; none while
  /// off.
  std::size_t n_records() const { return records_.size(); }

  /// The record of a slot for the term to fill (the scratch record when no owned particle
  /// books it, e.g. the ghost end of a pair). Off, every slot writes one scratch record (the
  /// ledger keeps no records then). A record that holds a load in an evaluation is written
  /// through this in it: the pass after the kick visits only particles with such records (or
  /// moments, or a driver), since most of a net's records are its mesh's candidates apart,
  /// which a term clears once and then leaves (docs/performance.md, fiftieth round).
  DissipationRecord& record(std::uint32_t slot) {
    if (!enabled_) return unbooked_;
    const std::uint32_t e = record_of_slot_[slot];
    written_[e / 64] |= std::uint64_t{1} << (e % 64);
    return records_[e];
  }
  /// The record of a slot with no load in this evaluation (a candidate apart): idle, as a
  /// DissipationRecord{} is, and not marked written. Member by member: a zero record built on
  /// the stack and copied went through a store-forwarding stall, a third of the samples of a
  /// debris channel's body contacts (docs/performance.md, thirty-eighth round).
  void clear_record(std::uint32_t slot) {
    DissipationRecord& r = enabled_ ? records_[record_of_slot_[slot]] : unbooked_;
    // Each member from constants: a chained assignment read back the member it had just
    // written, the same stall.
    r.damping = Vec3{};
    r.friction = Vec3{};
    r.arm = Vec3{};
    r.rolling = Vec3{};
    r.tangential_energy = 0.0;
    r.elastic_energy = 0.0;
    r.body = -1;
  }

  /// The entry of owned particle k's moments, for a per-particle term to add to through
  /// moments_at(): a zeroed entry taken at the first call of a force evaluation, so that
  /// particles without contacts cost nothing here, neither time nor memory. An entry is an
  /// index (moments_at() of it holds until the next entry is taken), so that a kernel can take
  /// the entries of a chunk of contacts first and add to them after. Where
  /// nearly every owned particle had contacts in the last evaluation (a packing), entry k is
  /// particle k's own (direct): no index to look up, no list, and the pass after the step
  /// reads the entries in particle order.
  std::uint32_t moments_entry(std::uint32_t k) {
    if (own_entries_) return k;
    std::uint32_t& entry = entry_of_[k];
    if (entry == kNoEntry) {
      entry = static_cast<std::uint32_t>(moments_.size());
      touched_list_.push_back(k);
      moments_.emplace_back();
    }
    return entry;
  }
  ContactMoments& moments_at(std::uint32_t entry) { return moments_[entry]; }
  /// How begin_step() keeps the entries: per particle (true), per touched particle (false), or
  /// chosen at each evaluation from how many were touched (nullopt, the default). The ledger
  /// is the same bits either way (tests/unit/test_ledger_entries.cpp); only memory and speed
  /// differ.
  void set_entry_choice(std::optional<bool> per_particle) { entry_choice_ = per_particle; }
  /// Whether this evaluation keeps an entry for every owned particle at its own index.
  bool entries_per_particle() const { return own_entries_; }
  /// Before a neighbour-list rebuild: the last evaluation's moments are booked (after the
  /// kick), so their memory goes back while the rebuild holds the keyed springs (112 bytes a
  /// touched particle at 10^6 grains in contact, the run's peak otherwise); the next
  /// evaluation takes it again.
  void release_moments();
  /// Owned particle k is taken out by an outflow sink before the next step: its powers end the
  /// trapezoid here instead of entering the next step's interval.
  using LeavingTest = std::function<bool(std::size_t k)>;

  /// How the pair term books its contacts (docs/physics.md "Energy ledger"). Per contact: each
  /// contact's work over the step in the pair loop, in the midpoint form, with the damping
  /// force it carried from the last step; no per-particle sums and no pass for them after the
  /// kick. Per particle: the sums of ContactMoments, booked at the end-of-step velocities after
  /// the kick. Per contact needs one rate (a slow contact's velocities are not mid-step ones)
  /// and no rolling friction (its torque is not carried); Simulation chooses.
  enum class PairBooking { kPerParticle, kPerContact };
  void set_pair_booking(PairBooking booking) { pair_booking_ = booking; }
  PairBooking pair_booking() const { return pair_booking_; }
  bool books_pairs_per_contact() const {
    return enabled_ && pair_booking_ == PairBooking::kPerContact;
  }

  /// What the next force evaluation books besides the contacts' work (begin_step()).
  struct EvaluationBooking {
    /// The initial state's evaluation: no interval ends with it (a contact's work is booked
    /// from the first step), and the tangential energy it holds starts the friction tally.
    bool initial = false;
    /// The held energies: the accumulate() after it has book_held. Inside a batch of steps
    /// nothing reads them, and summing them per contact is not free.
    bool held = true;
    /// Grains that leave after this step (the held energies of their contacts leave too).
    LeavingTest leaving;
  };
  /// Before a force evaluation over `n_local` owned particles: no particle has moments yet.
  void begin_step(std::size_t n_local, EvaluationBooking booking);

  /// Per-contact booking (books_pairs_per_contact()), in the pair loop. Each owned end of a
  /// contact books half of the contact's work, so that a pair across two ranks is booked once
  /// in all and the totals are the same on any rank count. The halves are added as integers of
  /// kWorkQuantum (an integer sum is the same in any order) in a ContactWork per chunk of
  /// contacts, which flush_contact_work() adds to the tallies; a half of kFixedLimit quanta or
  /// more (a boulder's contact) goes to an exact sum as it is. Both paths depend on the value
  /// alone, so which one a half takes is the same on every rank.
  struct ContactWork {
    std::int64_t quanta[2] = {0, 0};  ///< kDamping, kFriction
    /// Halves added: at most kMaxHalves before a flush, so that the sum stays in 63 bits.
    int halves = 0;
  };
  static constexpr double kWorkQuantum = 0x1p-50;  ///< W: the unscaled interval sums' unit
  static constexpr double kFixedLimit = 0x1p55;    ///< quanta
  static constexpr int kMaxHalves = 255;           ///< 255 * 2^55 < 2^63
  bool books_powers() const { return !booking_.initial; }
  /// `half_damping`, `half_friction`: half of (F^n + F^{n+1}) . v_rel^{n+1/2} for the viscous
  /// and the tangential spring force (W, unscaled like intervals()), booked once for each of
  /// the contact's `owned_ends` (0, 1 or 2). Two ends book twice the half's quanta (or twice the
  /// half, exact), the same integers as two bookings of one, at one rounding instead of two.
  [[gnu::always_inline]] void add_half_work(ContactWork& work, double half_damping,
                                            double half_friction, int owned_ends) {
    // One contact is a chunk of one: the rounding rule is written once, in add_half_works().
    add_half_works(work, &half_damping, &half_friction, 1,
                   [owned_ends](std::size_t) { return owned_ends; });
  }
  /// add_half_work() for the `n` contacts of a chunk (at most kMaxChunkContacts), lane c's
  /// halves at half_damping[c] and half_friction[c], owned_ends(c) its owned ends: the same
  /// integers added in another order (the same sum), as one loop that vectorises. Booked one
  /// contact at a time in the scatter, the roundings and the adds to `work` in memory were
  /// about 5 % of a packing's pair loop (docs/performance.md, fifty-fourth round).
  static constexpr std::size_t kMaxChunkContacts = kMaxHalves / 2;
  template <class OwnedEnds>
  [[gnu::always_inline]] void add_half_works(ContactWork& work, const double* half_damping,
                                             const double* half_friction, std::size_t n,
                                             OwnedEnds&& owned_ends) {
    std::int64_t sum_damping = 0, sum_friction = 0;
    int halves = 0;
    std::int64_t large = 0;  // (an integer, not a bool: GCC 12 vectorises its reduction)
    for (std::size_t c = 0; c < n; ++c) {
      const int times = owned_ends(c);
      const double q_damping = half_damping[c] * (1.0 / kWorkQuantum);
      const double q_friction = half_friction[c] * (1.0 / kWorkQuantum);
      const bool small_damping = std::fabs(q_damping) < kFixedLimit;
      const bool small_friction = std::fabs(q_friction) < kFixedLimit;
      large |= std::int64_t{!(small_damping & small_friction)};
      // times * round(q), in doubles: exact (times is 0, 1 or 2, |round(q)| <= 2^55).
      sum_damping += static_cast<std::int64_t>(static_cast<double>(times) *
                                               std::nearbyint(small_damping ? q_damping : 0.0));
      sum_friction += static_cast<std::int64_t>(static_cast<double>(times) *
                                                std::nearbyint(small_friction ? q_friction : 0.0));
      halves += times;
    }
    if (large != 0) {  // a boulder's contact: its large halves go to the exact sums
      for (std::size_t c = 0; c < n; ++c) {
        const int times = owned_ends(c);
        if (times == 0) continue;
        if (std::fabs(half_damping[c] * (1.0 / kWorkQuantum)) >= kFixedLimit)
          add_large_half(kDamping, half_damping[c] * times);
        if (std::fabs(half_friction[c] * (1.0 / kWorkQuantum)) >= kFixedLimit)
          add_large_half(kFriction, half_friction[c] * times);
      }
    }
    // At most kMaxHalves halves in `work`, so that its sums stay in 63 bits; and, as after
    // add_half_work(), room for one more contact's two.
    if (work.halves + halves > kMaxHalves) flush_contact_work(work);
    work.quanta[kDamping] += sum_damping;
    work.quanta[kFriction] += sum_friction;
    work.halves += halves;
    if (work.halves >= kMaxHalves - 1) flush_contact_work(work);
  }
  void flush_contact_work(ContactWork& work);
  /// Whether this evaluation's contacts book what they hold (add_contact_energies()).
  bool books_energies() const {
    return booking_.initial || booking_.held || static_cast<bool>(booking_.leaving);
  }
  /// Half of a contact's tangential and elastic energy, for its owned end k.
  void add_contact_energies(std::uint32_t k, double half_tangential, double half_elastic);

  /// After the second half kick of particles and rigid bodies, with the velocities of the end
  /// of the step: adds the work of the last force evaluation to the tallies.
  /// `initial`: the loads of the initial state, which begin the first interval. `book_held`:
  /// as for start_accumulation() below.
  void accumulate(const ParticleStore& p, const std::vector<RigidBody>& bodies,
                  const ForceSlots& slots, const GatherMap& gather, double dt, bool initial = false,
                  const LeavingTest& leaving = {}, bool book_held = true);

  /// accumulate() in three parts, so that the integrator can book each particle between its
  /// two half kicks while the particle is in cache (Integrator::second_then_first_half): the
  /// same operations on each particle, so the same bits. start_accumulation() lists the
  /// particles to visit; accumulate_below(end) books the listed ones with index below `end`
  /// (called with growing ends); finish_accumulation() books the external loads and closes
  /// the step's interval. With `book_held` false the held energies (held()) are not summed:
  /// inside a batch of steps nothing reads them before the next step replaces them, and their
  /// two exact additions a particle in contact were a fifth of a packing's booking pass
  /// (docs/performance.md, nineteenth round). The tallies do not depend on them.
  void start_accumulation(const ParticleStore& p, const GatherMap& gather, bool book_held = true);
  void accumulate_below(std::size_t end, const ParticleStore& p,
                        const std::vector<RigidBody>& bodies, const ForceSlots& slots,
                        const GatherMap& gather, bool initial = false,
                        const LeavingTest& leaving = {});
  void finish_accumulation(const GatherMap& gather, double dt, bool initial = false);

 private:
  /// No particle has moments (every entry taken is given back; direct entries stay, zeroed
  /// by the pass that booked them or by the next begin_step()).
  void clear_moments();
  /// Whether begin_step() ran on a store of `n_local` owned particles since the moments were
  /// last released.
  bool have_moments(std::size_t n_local) const {
    return own_entries_ ? moments_.size() == n_local : entry_of_.size() == n_local;
  }

  void add_large_half(int tally, double half) {
    contact_intervals_[tally].add(half);
    contact_booked_ = true;
  }

  bool enabled_ = true;
  ForceRate rate_ = ForceRate::kAll;
  PairBooking pair_booking_ = PairBooking::kPerParticle;
  EvaluationBooking booking_;  ///< of the last begin_step()
  /// What the pair loop booked per contact in the last evaluation: the intervals' contact work
  /// (added to intervals_ by finish_accumulation()), the held energies and those of leaving
  /// grains (start_accumulation() begins held() and held_by_leaving() with them) and the
  /// tangential energy of the initial state (the friction tally's start).
  std::array<ExactSum, kTallies> contact_intervals_;
  std::array<ExactSum, kHeldSums> contact_held_, contact_held_leaving_;
  ExactSum contact_initial_tangential_;
  bool contact_booked_ = false;           ///< contact_intervals_ is not zero
  bool contact_energies_booked_ = false;  ///< contact_held_* or the initial tangential is not
  bool contact_held_booked_ = false;      ///< the last evaluation booked the held energies
  bool books_drivers() const { return rate_ != ForceRate::kSlow; }
  /// This rank's exact tallies (see intervals(), direct()): the powers of the step being booked,
  /// those of particles that leave after it, and those of the last step.
  std::array<ExactSum, kTallies> intervals_, direct_, now_, closing_, last_;
  /// The per-particle pass's powers of now_ and closing_ as integers, flushed into them by
  /// finish_accumulation(): an exact addition is a read-modify-write of three limbs, and the
  /// pass made three to five a particle, after every sub-step of a net (docs/performance.md,
  /// fiftieth round).
  std::array<QuantumSum, kTallies> now_quanta_, closing_quanta_;
  std::array<QuantumSum, kHeldSums> held_quanta_, held_leaving_quanta_;  ///< the same for held_*
  std::array<ExactSum, kHeldSums> held_, held_leaving_;
  /// held_ is summed by the pass in progress, or was by the last one (start_accumulation()).
  bool held_current_ = true;
  std::vector<DissipationRecord> records_;
  DissipationRecord unbooked_;  ///< what record() gives while the ledger is off
  std::vector<std::uint32_t> record_of_slot_;
  /// A bit per record: written through record() since the last begin_step() (or rebuild()).
  std::vector<std::uint64_t> written_;
  bool written(std::size_t e) const { return (written_[e / 64] >> (e % 64)) & 1u; }
  /// Whether any of records [first, last) was written.
  bool any_written(std::size_t first, std::size_t last) const;
  static constexpr std::uint32_t kNoEntry = 0xffffffffu;
  std::vector<ContactMoments> moments_;      ///< one per particle touched in this evaluation
  std::vector<std::uint32_t> entry_of_;      ///< owned particle -> its moments_, or kNoEntry
  std::vector<std::uint32_t> touched_list_;  ///< the k with an entry, to clear them
  /// Entry k is particle k's (moments_entry()): chosen at begin_step() when more than 7/8 of
  /// the owned particles had contacts in the last evaluation (touched_last_), where n_local
  /// entries take less memory than the touched ones with their index and list.
  bool own_entries_ = false;
  bool own_entries_zeroed_ = false;  ///< every direct entry is zero (the booking pass cleared it)
  std::size_t touched_last_ = 0;
  std::size_t touched_now_ = 0;       ///< direct entries with contacts, counted by the booking pass
  std::optional<bool> entry_choice_;  ///< set_entry_choice()
  std::vector<std::uint32_t> visit_;  ///< scratch: the particles accumulate() visits
  std::vector<std::uint64_t> visit_marks_;  ///< scratch: a bit per owned particle to visit
  std::vector<std::uint32_t> loaded_;       ///< scratch: the particles with a record written
  /// Where accumulate_below() stands: every owned particle or visit_, the next of them, the
  /// next particle with records (GatherMap::ledger_particles) and the next driven one.
  bool scan_all_ = false;
  std::size_t n_visit_ = 0, next_visit_ = 0, next_records_ = 0, next_driven_ = 0;
};

}  // namespace ringdem

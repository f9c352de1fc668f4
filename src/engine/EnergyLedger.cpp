#include "engine/EnergyLedger.hpp"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace ringdem {

void EnergyLedger::release_moments() {
  clear_moments();
  std::vector<ContactMoments>().swap(moments_);
  own_entries_zeroed_ = false;
}

void EnergyLedger::rebuild(const GatherMap& gather, std::size_t n_slots) {
  if (!enabled_) {  // no records to fill: a term's record() is never asked for
    std::vector<DissipationRecord>().swap(records_);
    std::vector<std::uint32_t>().swap(record_of_slot_);
    std::vector<std::uint64_t>().swap(written_);
    return;
  }
  const auto& ledger_slots = gather.ledger_slots(rate_);
  records_.assign(ledger_slots.size() + 1, DissipationRecord{});
  written_.assign((records_.size() + 63) / 64, 0);
  record_of_slot_.assign(n_slots, static_cast<std::uint32_t>(ledger_slots.size()));
  for (std::size_t e = 0; e < ledger_slots.size(); ++e)
    record_of_slot_[ledger_slots[e]] = static_cast<std::uint32_t>(e);
}

void EnergyLedger::begin_step(std::size_t n_local, EvaluationBooking booking) {
  if (!enabled_) return;
  booking_ = std::move(booking);
  std::fill(written_.begin(), written_.end(), std::uint64_t{0});
  if (books_pairs_per_contact()) {
    // No per-particle sums: the pair loop books each contact (add_half_work()).
    contact_held_booked_ = booking_.held;
    if (own_entries_ || !moments_.empty() || !entry_of_.empty()) {
      release_moments();
      std::vector<std::uint32_t>().swap(entry_of_);
      std::vector<std::uint32_t>().swap(touched_list_);
      own_entries_ = false;
    }
    return;
  }
  clear_moments();
  const bool direct = entry_choice_.value_or(8 * touched_last_ > 7 * n_local);
  if (direct) {
    std::vector<std::uint32_t>().swap(entry_of_);
    std::vector<std::uint32_t>().swap(touched_list_);
    if (!own_entries_ || !own_entries_zeroed_ || moments_.size() != n_local) {
      moments_.clear();
      moments_.resize(n_local);
    }
  } else {
    if (own_entries_) moments_.clear();
    // Room for every owned particle: pages never written are never resident, and entries
    // taken one by one would otherwise double the vector (both copies at once) in the pair
    // loop.
    moments_.reserve(n_local);
    touched_list_.reserve(n_local);
    entry_of_.resize(n_local, kNoEntry);
  }
  own_entries_ = direct;
  own_entries_zeroed_ = false;  // the evaluation adds to them
}

void EnergyLedger::flush_contact_work(ContactWork& work) {
  for (int t : {kDamping, kFriction}) {
    const std::int64_t quanta = work.quanta[t];
    if (quanta == 0) continue;
    // Two parts that doubles hold exactly (31 and 32 bits), scaled by powers of two: exact.
    const std::int64_t high = quanta >> 32;  // rounds towards -inf: low is in [0, 2^32)
    const std::int64_t low = quanta - high * (std::int64_t{1} << 32);
    contact_intervals_[t].add(std::ldexp(static_cast<double>(high), 32) * kWorkQuantum);
    contact_intervals_[t].add(static_cast<double>(low) * kWorkQuantum);
    contact_booked_ = true;
  }
  work = ContactWork{};
}

void EnergyLedger::add_contact_energies(std::uint32_t k, double half_tangential,
                                        double half_elastic) {
  contact_energies_booked_ = true;
  // As the per-particle pass books them (accumulate_below()), each contact's halves apart.
  if (booking_.initial) contact_initial_tangential_.add(half_tangential);
  if (booking_.held) {
    contact_held_[kTangentialHeld].add(half_tangential);
    contact_held_[kContactHeld].add(half_elastic);
  }
  if (booking_.leaving && booking_.leaving(k)) {
    contact_held_leaving_[kTangentialHeld].add(half_tangential);
    contact_held_leaving_[kContactHeld].add(half_elastic);
  }
}

bool EnergyLedger::any_written(std::size_t first, std::size_t last) const {
  // A particle's records are a few: tested one by one.
  for (std::size_t e = first; e < last; ++e)
    if (written(e)) return true;
  return false;
}

void EnergyLedger::clear_moments() {
  if (own_entries_) return;
  for (const std::uint32_t k : touched_list_)
    if (k < entry_of_.size()) entry_of_[k] = kNoEntry;
  touched_list_.clear();
  moments_.clear();
}

void EnergyLedger::accumulate(const ParticleStore& p, const std::vector<RigidBody>& bodies,
                              const ForceSlots& slots, const GatherMap& gather, double dt,
                              bool initial, const LeavingTest& leaving, bool book_held) {
  start_accumulation(p, gather, book_held);
  accumulate_below(p.n_local(), p, bodies, slots, gather, initial, leaving);
  finish_accumulation(gather, dt, initial);
}

void EnergyLedger::close_intervals(const std::array<double, kTallies>& intervals_totals,
                                   double dt_old, bool root) {
  for (int t = 0; t < kTallies; ++t) {
    if (root) direct_[t].add(tally(intervals_totals[t], 0.0, dt_old));
    intervals_[t] = ExactSum{};
  }
}

std::vector<ExactSum> EnergyLedger::state() const {
  std::vector<ExactSum> s(intervals_.begin(), intervals_.end());
  s.insert(s.end(), last_.begin(), last_.end());
  s.insert(s.end(), direct_.begin(), direct_.end());
  const auto& held_now = held();  // a checkpoint's: the last step must have booked them
  s.insert(s.end(), held_now.begin(), held_now.end());
  s.insert(s.end(), held_leaving_.begin(), held_leaving_.end());
  return s;
}

void EnergyLedger::restore(const std::vector<ExactSum>& totals, bool root) {
  intervals_ = direct_ = now_ = closing_ = last_ = contact_intervals_ = {};
  held_ = held_leaving_ = contact_held_ = contact_held_leaving_ = {};
  contact_initial_tangential_ = ExactSum{};
  contact_booked_ = contact_energies_booked_ = false;
  held_current_ = true;
  if (totals.empty() || !root) return;
  if (totals.size() != kStateSums)
    throw std::runtime_error("checkpoint: energy ledger state of the wrong size");
  for (int t = 0; t < kTallies; ++t) {
    intervals_[t] = totals[t];
    last_[t] = totals[kTallies + t];
    direct_[t] = totals[2 * kTallies + t];
  }
  for (int h = 0; h < kHeldSums; ++h) {
    held_[h] = totals[3 * kTallies + h];
    held_leaving_[h] = totals[3 * kTallies + kHeldSums + h];
  }
}

const std::array<ExactSum, EnergyLedger::kHeldSums>& EnergyLedger::held() const {
  if (!held_current_)
    throw std::logic_error(
        "EnergyLedger::held(): the last step did not book the held energies (only the last "
        "step of a batch does)");
  return held_;
}

void EnergyLedger::start_accumulation(const ParticleStore& p, const GatherMap& gather,
                                      bool book_held) {
  if (!enabled_) return;
  if (book_held && books_pairs_per_contact() && !contact_held_booked_)
    throw std::logic_error(
        "EnergyLedger: a step that books the held energies followed an evaluation whose "
        "contacts did not book them (EvaluationBooking::held)");
  held_current_ = book_held;
  const std::size_t n_local = p.n_local();
  const bool moments = have_moments(n_local);
  // Only the particles with a load to book now: contacts summed per particle, records, or a
  // driver's power. Where they are not few, every owned particle is visited in index order
  // and accumulate_below() skips the others.
  const auto& particles = gather.ledger_particles(rate_);
  const auto& offsets = gather.ledger_offsets(rate_);
  static const std::vector<GatherMap::ParticlePower> kNone;
  const auto& driven = books_drivers() ? gather.driven_powers() : kNone;
  visit_.clear();
  // Direct entries are all visited (each is cleared after it is read). Of the particles with
  // records, those with a record written in the evaluation: the others' are idle.
  const std::size_t touched = !moments ? 0 : own_entries_ ? n_local : touched_list_.size();
  loaded_.clear();
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (any_written(offsets[i], offsets[i + 1])) loaded_.push_back(particles[i]);
  const std::size_t listed = touched + loaded_.size() + driven.size();
  scan_all_ = 4 * listed > n_local;
  if (!own_entries_) touched_last_ = touched;
  touched_now_ = 0;
  if (!scan_all_) {
    // The three lists' union in ascending order, through a bit per owned particle: the
    // touched entries come in pair order, and sorting them each step was a tenth of a net's
    // integrate phase late in an impact (docs/performance.md, twenty-sixth round).
    visit_marks_.assign((n_local + 63) / 64, 0);
    const auto mark = [this](std::uint32_t k) {
      visit_marks_[k / 64] |= std::uint64_t{1} << (k % 64);
    };
    if (moments)
      for (const std::uint32_t k : touched_list_)
        mark(k);
    for (const std::uint32_t k : loaded_)
      mark(k);
    for (const auto& x : driven)
      mark(x.particle);
    for (std::size_t w = 0; w < visit_marks_.size(); ++w)
      for (std::uint64_t bits = visit_marks_[w]; bits != 0; bits &= bits - 1)
        visit_.push_back(static_cast<std::uint32_t>(64 * w + std::countr_zero(bits)));
  }
  // The pair loop's contacts (per-contact booking) first; the pass adds the particles' own.
  if (contact_energies_booked_) {
    held_ = contact_held_;
    held_leaving_ = contact_held_leaving_;
    direct_[kFriction] += contact_initial_tangential_;
    contact_held_ = contact_held_leaving_ = {};
    contact_initial_tangential_ = ExactSum{};
    contact_energies_booked_ = false;
  } else {
    held_ = held_leaving_ = {};
  }
  n_visit_ = scan_all_ ? n_local : visit_.size();
  next_visit_ = next_records_ = next_driven_ = 0;
}

namespace {
constexpr std::size_t kEntriesAhead = 32;
}  // namespace

void EnergyLedger::accumulate_below(std::size_t end, const ParticleStore& p,
                                    const std::vector<RigidBody>& bodies, const ForceSlots& slots,
                                    const GatherMap& gather, bool initial,
                                    const LeavingTest& leaving) {
  if (!enabled_) return;
  // The tallies (docs/physics.md "Energy ledger"; physics.md §3 for the contact loads, §4
  // for the integrator). Velocity Verlet applies a load F^n, computed at t_n, in two half
  // kicks v^{n-1/2} -> v^n -> v^{n+1/2}; the kinetic energy they change is exactly
  // dt F^n . v^n with v^n the synchronised velocity (the mean of the two half-step
  // velocities), i.e. the load's power at the end of this step's second half kick, which is
  // where this runs. Summing dt P^n is the trapezoidal rule in time for the work: the same
  // as the mid-step form dt (F^n + F^{n+1})/2 . v^{n+1/2} summed over steps. The current
  // step's second kick is only half done, so the tally up to step n is dt/2 P^0 + dt (P^1 +
  // ... + P^{n-1}) + dt/2 P^n = dt/2 sum of (P^{m-1} + P^m) over the steps m <= n: the rank
  // sums P^n in now_ and adds last_ + now_ to intervals_ at each step (finish_accumulation),
  // and the ledger closes to O(dt^2) at every step, the order of velocity Verlet's own energy
  // error. (The work of F^n with the half-step velocity the contact law saw, F^n . v^{n-1/2}
  // dt, would be only first order.)
  const auto& particles = gather.ledger_particles(rate_);
  const auto& offsets = gather.ledger_offsets(rate_);
  const auto& ledger_slots = gather.ledger_slots(rate_);
  static const std::vector<GatherMap::ParticlePower> kNone;
  const auto& driven = books_drivers() ? gather.driven_powers() : kNone;
  const bool moments = have_moments(p.n_local());
  std::size_t i = next_records_, d = next_driven_, v_index = next_visit_;
  for (; v_index < n_visit_; ++v_index) {
    const std::size_t k = scan_all_ ? v_index : visit_[v_index];
    if (k >= end) break;
    // Shared entries (entry_of_) lie in the order the pair loop first touched them, not in
    // this pass's: without a request ahead, reading them was about 40 % of this pass in the
    // pile of a sub-stepped debris channel (docs/performance.md, forty-eighth round).
    if (moments && !own_entries_ && v_index + kEntriesAhead < n_visit_) {
      const std::size_t ahead =
          scan_all_ ? v_index + kEntriesAhead : visit_[v_index + kEntriesAhead];
      const std::uint32_t entry = entry_of_[ahead];
      if (entry != kNoEntry) __builtin_prefetch(&moments_[entry], 1);
    }
    const bool has_moments = moments && (own_entries_ || entry_of_[k] != kNoEntry);
    // The visits skip particles whose records were all idle: so does the index of records.
    while (i < particles.size() && particles[i] < k)
      ++i;
    const bool has_records =
        i < particles.size() && particles[i] == k && any_written(offsets[i], offsets[i + 1]);
    const bool is_driven = d < driven.size() && driven[d].particle == k;
    if (!has_moments && !has_records && !is_driven) continue;
    const Vec3 v = p.velocity[k];
    const Vec3 w = p.omega[k];
    double damping = 0.0, friction = 0.0, boundary = 0.0, tangential = 0.0, elastic = 0.0;
    // Contacts summed per particle by their term, in partner order (ContactMoments): the power
    // of the loads at the end-of-step velocities.
    if (has_moments) {
      // The entries are read in order, among a dozen streams of the integrator's pass over
      // the same particles: the hardware prefetcher does not keep up with them all.
      if (own_entries_ && k + kEntriesAhead < moments_.size())
        __builtin_prefetch(&moments_[k + kEntriesAhead], 1);
      ContactMoments& m = moments_[own_entries_ ? k : entry_of_[k]];
      damping -= dot(m.damping, v) + dot(m.damping_moment, w);
      friction -= dot(m.friction, v) + dot(m.friction_moment, w);
      tangential = m.tangential_energy;
      elastic = m.elastic_energy;
      if (own_entries_) {
        // A touching contact holds elastic energy: counted for the next begin_step()'s choice.
        touched_now_ += elastic != 0.0;
        m = ContactMoments{};  // in cache now; the next evaluation adds to zeros
      }
    }
    // Contacts with a record per slot, in gather order (the same sum on any rank count). Each
    // particle books the work its own contact loads do; over both ends of a pair this is the
    // pair's dissipation. A rigid body's end is booked to the particle: against a driven body
    // its surface velocity enters the relative velocity and the total contact load's power on
    // the body is boundary work; a free body's own kinetic energy is in the ledger.
    if (has_records) {
      for (std::uint32_t e = offsets[i]; e < offsets[i + 1]; ++e) {
        const DissipationRecord& c = records_[e];
        if (c.arm.x == 0.0 && c.arm.y == 0.0 && c.arm.z == 0.0) continue;  // not touching
        Vec3 rel = v + cross(w, c.arm);  // velocity of the particle's contact point
        if (c.body >= 0) {
          const RigidBody& body = bodies[static_cast<std::size_t>(c.body)];
          if (body.motion != Motion::kFixed) {
            const Vec3 vb = body.velocity_at(p.position[k] + c.arm);
            rel -= vb;
            if (body.motion == Motion::kPrescribed)
              boundary += dot(slots.force(ledger_slots[e]), vb);
          }
        }
        damping -= dot(c.damping, rel);
        friction -= dot(c.friction, rel) + dot(c.rolling, w);
        tangential += c.tangential_energy;
        elastic += c.elastic_energy;
      }
    }
    // A driven particle: whatever its interactions push against, the driver supplies.
    if (is_driven) boundary -= driven[d++].power;
    // A particle that leaves before the next step ends its trapezoid with this step, and
    // what its contacts hold leaves with it.
    const bool leaves = leaving && leaving(k);
    std::array<QuantumSum, kTallies>& powers = leaves ? closing_quanta_ : now_quanta_;
    std::array<ExactSum, kTallies>& large = leaves ? closing_ : now_;
    powers[kDamping].add(damping, large[kDamping]);
    powers[kFriction].add(friction, large[kFriction]);
    powers[kBoundary].add(boundary, large[kBoundary]);
    // Friction is what the tangential springs took in and do not hold any more: the tally is
    // the friction work less the tangential energy held now (held()), plus that held when the
    // ledger started.
    if (initial) direct_[kFriction].add(tangential);
    if (held_current_) {  // integer sums: the same bits on any rank count
      held_quanta_[kTangentialHeld].add(tangential, held_[kTangentialHeld]);
      held_quanta_[kContactHeld].add(elastic, held_[kContactHeld]);
    }
    if (leaves) {
      held_leaving_quanta_[kTangentialHeld].add(tangential, held_leaving_[kTangentialHeld]);
      held_leaving_quanta_[kContactHeld].add(elastic, held_leaving_[kContactHeld]);
    }
  }
  next_visit_ = v_index;
  next_records_ = i;
  next_driven_ = d;
}

void EnergyLedger::finish_accumulation(const GatherMap& gather, double dt, bool initial) {
  if (!enabled_) return;
  if (own_entries_ && scan_all_) {  // every entry was read and cleared
    touched_last_ = touched_now_;
    own_entries_zeroed_ = true;
  }
  for (int t = 0; t < kTallies; ++t) {
    now_quanta_[t].flush_into(now_[t]);
    closing_quanta_[t].flush_into(closing_[t]);
  }
  for (int h = 0; h < kHeldSums; ++h) {
    held_quanta_[h].flush_into(held_[h]);
    held_leaving_quanta_[h].flush_into(held_leaving_[h]);
  }
  // External forces: F_ext . (x^{n+1} - x^n), exact for a constant force.
  if (!initial && books_drivers())
    for (const auto& x : gather.external_powers())
      direct_[kBoundary].add(dt * x.power);
  for (int t = 0; t < kTallies; ++t) {
    if (!initial) {  // the interval of this step: its start's powers and its end's
      intervals_[t] += last_[t];
      intervals_[t] += now_[t];
      intervals_[t] += closing_[t];
      // The contacts booked per contact: the whole interval's work already.
      if (contact_booked_) intervals_[t] += contact_intervals_[t];
    }
    last_[t] = now_[t];
    now_[t] = ExactSum{};
    closing_[t] = ExactSum{};
  }
  if (contact_booked_) {
    contact_intervals_ = {};
    contact_booked_ = false;
  }
}

}  // namespace ringdem

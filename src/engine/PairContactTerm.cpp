#include "engine/PairContactTerm.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

#include "engine/ContactKeys.hpp"
#include "engine/Loop.hpp"

namespace ringdem {

namespace {
/// Bit c set where candidate range.begin + c touches (range.size() <= 64): the distance test
/// of the pair loop below, the same operations in the same order, in a loop of its own without
/// branches. Most candidates of a loose or flowing packing do not touch. Tested one at a time in
/// the pair loop, between its spring slots and its pointers reloaded after every store, they
/// cost about 5 ns each, and a flowing block spent half its contact phase there
/// (docs/performance.md, thirtieth round). (Vectorised with gathers it ran slower still.)
[[gnu::optimize("no-tree-vectorize")]] std::uint64_t touching_mask(IndexRange range,
                                                                   const std::uint32_t* pair_a,
                                                                   const std::uint32_t* pair_b,
                                                                   const Vec3* position,
                                                                   const double* radius) {
  const std::size_t n = range.size();
  const std::uint32_t* const a = pair_a + range.begin;
  const std::uint32_t* const b = pair_b + range.begin;
  std::uint64_t mask = 0;
#pragma GCC unroll 4
  for (std::size_t c = 0; c < n; ++c) {
    const Vec3 d = position[b[c]] - position[a[c]];
    const double reach = radius[a[c]] + radius[b[c]];
    mask |= std::uint64_t{!(norm2(d) >= reach * reach)} << c;
  }
  return mask;
}

/// touching_mask() for the candidates of `selected` alone (bit c for range.begin + c): the
/// same test. A sub-step's chunks hold a few fast candidates among grain pairs (5.6 of 64 in
/// the 10^5-grain channel's pile), and testing all 64 was a tenth of the net rank's time
/// (docs/performance.md, forty-third round).
std::uint64_t touching_mask_of(IndexRange range, std::uint64_t selected,
                               const std::uint32_t* pair_a, const std::uint32_t* pair_b,
                               const Vec3* position, const double* radius) {
  std::uint64_t mask = 0;
  for (std::uint64_t bits = selected; bits != 0; bits &= bits - 1) {
    const int c = std::countr_zero(bits);
    const std::uint32_t a = pair_a[range.begin + static_cast<std::size_t>(c)];
    const std::uint32_t b = pair_b[range.begin + static_cast<std::size_t>(c)];
    const Vec3 d = position[b] - position[a];
    const double reach = radius[a] + radius[b];
    mask |= std::uint64_t{!(norm2(d) >= reach * reach)} << c;
  }
  return mask;
}
}  // namespace

double PairContactTerm::ghost_width(const ParticleStore& p) const {
  double r_max = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    r_max = std::max(r_max, p.radius[k]);
  return 2.0 * r_max;
}

void PairContactTerm::find_overlaps(const ParticleStore& p, const std::vector<RigidBody>&,
                                    double fraction, std::vector<ContactOverlap>& out) const {
  for (std::size_t m = 0; m < pairs_.size(); ++m) {
    const std::uint32_t a = pairs_.i[m];
    const std::uint32_t b = pairs_.j[m];
    const double depth = p.radius[a] + p.radius[b] - norm(p.position[b] - p.position[a]);
    if (depth > fraction * std::min(p.radius[a], p.radius[b])) out.push_back({a, b, false, depth});
  }
}

void PairContactTerm::rebuild(RebuildContext& ctx) {
  const ParticleStore& p = ctx.particles;
  const std::size_t n_total = p.n_total();
  // Exclusion lists by particle (the bonded terms' entries), as offsets into one array; none
  // (an empty offset array) where nothing is bonded.
  exclusions_.offset.clear();
  exclusions_.partner_gid.clear();
  if (!ctx.excluded.empty()) {
    exclusions_.offset.assign(n_total + 1, 0);
    for (const auto& e : ctx.excluded)
      ++exclusions_.offset[e.particle + 1];
    for (std::size_t k = 0; k < n_total; ++k)
      exclusions_.offset[k + 1] += exclusions_.offset[k];
    exclusions_.partner_gid.assign(exclusions_.offset[n_total], 0);
    std::vector<std::uint32_t> fill(exclusions_.offset.begin(), exclusions_.offset.end() - 1);
    for (const auto& e : ctx.excluded)
      exclusions_.partner_gid[fill[e.particle]++] = e.partner_gid;
  }

  search_.build(p, ctx.skin, exclusions_, pairs_);
  carry_springs(p);
  rates_current_ = false;
}

void PairContactTerm::classify_rates(const ParticleStore& p) {
  constexpr std::size_t kChunk = PairContactChunk::kSize;
  const std::size_t n = pairs_.size();
  fast_mask_.assign((n + kChunk - 1) / kChunk, 0);
  fast_chunks_.clear();
  for (std::size_t m = 0; m < n; ++m)
    if (is_fast_particle(p, pairs_.i[m]) || is_fast_particle(p, pairs_.j[m]))
      fast_mask_[m / kChunk] |= std::uint64_t{1} << (m % kChunk);
  for (std::size_t c = 0; c < fast_mask_.size(); ++c)
    if (fast_mask_[c] != 0) fast_chunks_.push_back(static_cast<std::uint32_t>(c));
  rates_current_ = true;
}

void PairContactTerm::mark_fast_particles(const ParticleStore& p, std::vector<std::uint8_t>& fast) {
  if (!rates_current_) classify_rates(p);
  constexpr std::size_t kChunk = PairContactChunk::kSize;
  const std::size_t n = fast.size();
  for (const std::uint32_t c : fast_chunks_)
    for (std::uint64_t bits = fast_mask_[c]; bits != 0; bits &= bits - 1) {
      const std::size_t m = c * kChunk + static_cast<std::size_t>(std::countr_zero(bits));
      if (pairs_.i[m] < n) fast[pairs_.i[m]] = 1;
      if (pairs_.j[m] < n) fast[pairs_.j[m]] = 1;
    }
}

void PairContactTerm::mark_net_contacts(const ParticleStore& p,
                                        std::vector<std::uint8_t>& touching) const {
  const std::size_t n = touching.size();
  const auto visit = [&](std::size_t m) {
    const std::uint32_t a = pairs_.i[m];
    const std::uint32_t b = pairs_.j[m];
    const bool net_a = is_net_particle(p, a);
    if (net_a == is_net_particle(p, b)) return;  // two grains, or two net particles
    const double reach = p.radius[a] + p.radius[b];
    if (norm2(p.position[b] - p.position[a]) >= reach * reach) return;  // (the law's test)
    const std::uint32_t grain = net_a ? b : a;
    if (grain < n) touching[grain] = 1;
  };
  if (!rates_current_) {
    for (std::size_t m = 0; m < pairs_.size(); ++m)
      visit(m);
    return;
  }
  // A pair with a net particle is fast: among the fast candidates.
  constexpr std::size_t kChunk = PairContactChunk::kSize;
  for (const std::uint32_t c : fast_chunks_)
    for (std::uint64_t bits = fast_mask_[c]; bits != 0; bits &= bits - 1)
      visit(c * kChunk + static_cast<std::size_t>(std::countr_zero(bits)));
}

void PairContactTerm::carry_springs(const ParticleStore& p) {
  // The keyed rows (the touching springs packed before the migration, or a checkpoint's)
  // become the new candidates' springs, in the rows' own memory: at the rebuild of a packing
  // in contact the keyed rows, a second copy of their springs and an order of them had made
  // the run's peak memory (docs/performance.md, fifteenth round). Of two rows with one key
  // (both ends' ranks held the pair) the first in storage order is taken.
  const std::size_t np = pairs_.size();
  const std::size_t n_carried = springs_.size();
  if (n_carried == 0) {
    // Nothing to carry (a fresh start): a pool with room for every candidate, which grows to
    // what touches without a reallocation (a pool doubled from empty as a packing's contacts
    // closed had held its springs twice for a moment: 28 bytes a grain at 10^6 grains).
    spring_.reset(np);
    springs_ = ContactSpringStore{ContactSpringStore::Partner::kParticle};
    return;
  }
  spring_.reset_carrying(np, std::move(springs_.spring), std::move(springs_.ledger));
  // Rows in candidate order (the usual case: packed from the last candidates, with no re-sort
  // and nothing arrived from another rank since): one pass pairs them by their gids. It stops
  // matching at the first row out of that order; the rows before it have their candidates.
  std::size_t c = 0;
  for (std::size_t m = 0; m < np && c < n_carried; ++m)
    if (p.gid[pairs_.i[m]] == springs_.gid[c] && p.gid[pairs_.j[m]] == springs_.partner[c])
      spring_.carry(m, c++);
  if (c < n_carried) {
    // The rest (after a re-sort, or rows that migration appended) in no order of the
    // candidates': the candidates of one first end (the end first in key order) are
    // consecutive (NeighbourSearch), so each row looks among those of its own first end.
    const auto first_end = [&](std::size_t m) {
      const std::uint32_t i = pairs_.i[m], j = pairs_.j[m];
      return p.sorts_before(j, i) ? j : i;
    };
    constexpr std::uint32_t kNone = UINT32_MAX;
    std::vector<std::uint32_t> first_pair(p.n_total(), kNone);
    for (std::size_t m = np; m-- > 0;)
      first_pair[first_end(m)] = static_cast<std::uint32_t>(m);
    for (std::size_t r = c; r < n_carried; ++r) {
      const std::int64_t x = p.index_of(springs_.gid[r]), y = p.index_of(springs_.partner[r]);
      if (x < 0 || y < 0) continue;  // an end not held here: no candidate
      const auto [a, b] =
          p.sorts_before(static_cast<std::size_t>(y), static_cast<std::size_t>(x))
              ? std::pair{static_cast<std::uint32_t>(y), static_cast<std::uint32_t>(x)}
              : std::pair{static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y)};
      for (std::size_t m = first_pair[a]; m != kNone && m < np && first_end(m) == a; ++m)
        if (pairs_.i[m] == b || pairs_.j[m] == b) {
          if (!spring_.holds(m)) spring_.carry(m, r);  // a row gives its spring once
          break;
        }
    }
  }
  // Read back: the keyed rows' memory goes until the next pack.
  springs_ = ContactSpringStore{ContactSpringStore::Partner::kParticle};
  spring_.end_carry();
}

void PairContactTerm::book_carried_work(const ParticleStore& p, EnergyLedger& ledger, bool mid_step,
                                        double dt) {
  rows_carry_ledger_ = ledger.books_pairs_per_contact() && !mid_step;
  if (!ledger.books_pairs_per_contact() || !mid_step || !spring_.keeps_ledger()) return;
  // The loads each contact carries (those of the last evaluation) do the second half of their
  // work in this step, at their own contact point and the relative velocity of the step's
  // middle: what the next evaluation would book, booked before the rebuild forgets them
  // (docs/physics.md "Energy ledger"). Each owned end books half, as in the pair loop.
  EnergyLedger::ContactWork work;
  const std::size_t n_local = p.n_local();
  for (std::size_t m = 0; m < spring_.n_candidates(); ++m) {
    if (!spring_.holds(m)) continue;
    ContactLedgerState& carried = spring_.ledger(m);
    if (!carried.carries_work()) continue;
    const std::uint32_t a = pairs_.i[m], b = pairs_.j[m];
    const double depth = static_cast<double>(carried.overlap);
    const Vec3 normal =
        step_start_normal(p.position[b] - p.position[a], p.velocity[b] - p.velocity[a], dt);
    const Vec3 v_rel =
        relative_contact_velocity(normal, p.radius[a] - 0.5 * depth, p.radius[b] - 0.5 * depth,
                                  p.velocity[a], p.velocity[b], p.omega[a], p.omega[b]);
    const double half_damping = 0.5 * dot(to_vec3(carried.damping), v_rel);
    const double half_friction = 0.5 * dot(spring_.value(m), v_rel);
    ledger.add_half_work(work, half_damping, half_friction, int{a < n_local} + int{b < n_local});
    carried = ContactLedgerState{};
  }
  ledger.flush_contact_work(work);
}

void PairContactTerm::pack_springs(const ParticleStore& p) {
  // Rows already in the store (a checkpoint's, before the first rebuild) stay.
  springs_.drop_released();
  springs_.set_carries_ledger(rows_carry_ledger_);
  // Booked (book_carried_work()) or never kept: their memory goes before the keys come.
  if (!rows_carry_ledger_) spring_.drop_ledger();
  const auto touching = [this](std::size_t m) { return carries_state(m); };
  if (springs_.size() == 0) {
    // The keys in candidate order, and the springs in that order made in the pool's own
    // memory: at 10^6 grains in contact a second copy of the springs beside the keyed rows was
    // the run's peak (docs/performance.md, fifteenth round).
    springs_.gid.reserve(spring_.n_held());
    springs_.partner.reserve(spring_.n_held());
    for (std::size_t m = 0; m < spring_.n_candidates(); ++m)
      if (spring_.holds(m) && touching(m)) {
        springs_.gid.push_back(p.gid[pairs_.i[m]]);
        springs_.partner.push_back(p.gid[pairs_.j[m]]);
      }
    springs_.spring = spring_.take_in_candidate_order(touching, springs_.ledger);
    if (!rows_carry_ledger_)
      std::vector<ContactLedgerState>().swap(springs_.ledger);
    else
      springs_.ledger.resize(springs_.spring.size());  // zero where the slots kept none
    return;
  }
  springs_.reserve(springs_.size() + spring_.n_held());
  for (std::size_t m = 0; m < spring_.n_candidates(); ++m)
    if (spring_.holds(m) && touching(m))
      springs_.append(p.gid[pairs_.i[m]], p.gid[pairs_.j[m]], spring_.value(m),
                      carried_ledger(m));  // (the ledger state only where the rows carry it)
  // The candidates are rebuilt next: their springs' memory goes before the search's comes.
  spring_.release_memory();
}

ContactSpringStore PairContactTerm::touching_springs_part(const ParticleStore& p, SpringRows rows,
                                                          std::size_t part,
                                                          std::size_t parts) const {
  // The sources in order: the keyed rows, then the candidates.
  const std::size_t keyed = springs_.size(), n = spring_sources();
  const std::size_t first = slice_begin(n, part, parts), last = slice_begin(n, part + 1, parts);
  ContactSpringStore out =
      keyed_touching_springs(p, rows, std::min(first, keyed), std::min(last, keyed));
  // A candidate's first end is an owned particle or a ghost: counted where it is owned.
  const auto counted = [&](std::size_t m) {
    if (!spring_.holds(m) || !carries_state(m)) return false;
    if (rows == SpringRows::kAll) return true;
    const std::int64_t a = p.index_of(p.gid[pairs_.i[m]]);
    return a >= 0 && static_cast<std::size_t>(a) < p.n_local();
  };
  const std::size_t begin = std::max(first, keyed) - keyed, end = std::max(last, keyed) - keyed;
  std::size_t count = out.size();
  for (std::size_t m = begin; m < end; ++m)
    count += counted(m) ? 1 : 0;
  out.reserve(count);
  for (std::size_t m = begin; m < end; ++m)
    if (counted(m))
      out.append(p.gid[pairs_.i[m]], p.gid[pairs_.j[m]], spring_.value(m), carried_ledger(m));
  return out;
}

ContactLedgerState PairContactTerm::carried_ledger(std::size_t m) const {
  return spring_.keeps_ledger() ? spring_.ledger(m) : ContactLedgerState{};
}

bool PairContactTerm::carries_state(std::size_t m) const {
  return norm2(spring_.value(m)) > 0.0 || (spring_.keeps_ledger() && !spring_.ledger(m).is_empty());
}

void PairContactTerm::compute(ComputeContext& ctx) {
  // Compiled for each thing the ledger books (a branch on it in the loop cost the loop with
  // the ledger 6 %).
  using Ledger = PairContactChunk::Ledger;
  const EnergyLedger& ledger = ctx.ledger;
  if (!ledger.enabled())
    compute_pairs<Ledger::kOff>(ctx);
  else if (!ledger.books_pairs_per_contact())
    compute_pairs<Ledger::kPerParticle>(ctx);
  else if (ledger.books_energies())
    compute_pairs<Ledger::kPerContactWithEnergies>(ctx);
  else
    compute_pairs<Ledger::kPerContact>(ctx);
}

template <PairContactChunk::Ledger kLedger>
void PairContactTerm::compute_pairs(ComputeContext& ctx) {
  using Ledger = PairContactChunk::Ledger;
  constexpr bool kBook = kLedger == Ledger::kPerParticle;  // ContactMoments
  constexpr bool kPerContact =
      kLedger == Ledger::kPerContact || kLedger == Ledger::kPerContactWithEnergies;
  constexpr bool kEnergies = kLedger == Ledger::kPerContactWithEnergies;
  const ParticleStore& p = ctx.particles;
  const ParticleLoads loads = ctx.loads;
  EnergyLedger& ledger = ctx.ledger;
  // Raw pointers, read once (nothing in the loop can move them).
  const std::uint32_t* const pair_a = pairs_.i.data();
  const std::uint32_t* const pair_b = pairs_.j.data();
  const Vec3* const position = p.position.data();
  const double* const radius = p.radius.data();
  const Vec3* const velocity = p.velocity.data();
  const Vec3* const omega = p.omega.data();
  const double* const mass = p.mass.data();
  const auto* const motion = p.motion.data();
  const auto* const material = p.material.data();
  Vec3* const force_sum = loads.force;
  Vec3* const torque_sum = loads.torque;
  SpringSlots& springs = spring_;
  PairContactChunk& chunk = chunk_;
  // Per-contact booking: the work of this step (not in the initial state's evaluation).
  const bool book_work = kPerContact && ledger.books_powers();
  if constexpr (kPerContact) springs.keep_ledger();
  EnergyLedger::ContactWork work;
  // The far ends are read in jumps: the pairs come by their end first in key order, which is
  // the storage order of the owned particles, and a grain's partners later in that order lie
  // in a few far-apart runs, each a stream through every array the kernel reads (nine,
  // and the ledger's entries), more streams than the hardware prefetcher follows. The kernel
  // asks for the far end (the one stored later) of the pair kPrefetchAhead ahead itself: on a dense
  // bed it had waited on those loads for half of the pair loop's time (docs/performance.md,
  // fourteenth round). Only while most candidates touch (the last chunk's): a candidate that does
  // not touch reads only the positions and radii, and the requests cost the net's sparse contacts
  // 50 %.
  const std::size_t n_pairs = pairs_.size();
  constexpr std::size_t kPrefetchAhead = 16;
  bool most_touch = true;
  // Multi-rate stepping: only the candidates of the evaluation's rate (ForceRate).
  if (ctx.rate != ForceRate::kAll && !rates_current_) classify_rates(p);
  constexpr std::size_t kChunk = PairContactChunk::kSize;
  const auto rate_mask = [&](IndexRange range) -> std::uint64_t {
    if (ctx.rate == ForceRate::kAll) return ~std::uint64_t{0};
    const std::uint64_t fast = fast_mask_[range.begin / kChunk];
    return ctx.rate == ForceRate::kFast ? fast : ~fast;
  };
  // Particle contacts (physics.md §3), a chunk of candidates at a time: the touching ones are
  // copied into the chunk's columns, the contact law runs over them vectorised, and their
  // loads are added in pair order. The pairs come in ascending order of their ends' sort keys
  // (NeighbourSearch), and each adds its loads to both ends at once: every particle then gets
  // its contacts in ascending partner key, the gather order (DESIGN §4), without a slot per
  // pair. Most candidates of a loose packing do not touch: they cost a distance test in
  // touching_mask() and a bit of held_mask(), and hold no spring.
  // One material pair for every contact (a bed of one rock): its parameters in every lane
  // once, not looked up and stored for each contact.
  const HertzMindlin::Params* const uniform_params = ctx.materials.uniform_pair();
  if (uniform_params != nullptr) chunk.fill_params(*uniform_params);
  // The far ends' arrays by value: captured by reference, each prefetch and load went through
  // the closure to the local and then to the array.
  const auto run_chunk = [&, velocity, omega, mass, motion, material, force_sum,
                          torque_sum](IndexRange range) {
    chunk.n = 0;
    chunk.any_rolling = uniform_params != nullptr && uniform_params->rolling_friction > 0.0;
    // The candidates to visit: those that touch, and those whose contact opened since the
    // last step (their springs go back). Where most of the last chunk's candidates touched (a
    // packing in contact), all of them: the filter would only repeat the test below.
    static_assert(PairContactChunk::kSize <= 64, "a chunk's candidates are one 64-bit mask");
    const std::uint64_t rate = rate_mask(range);
    const std::uint64_t visit =
        most_touch ? (~std::uint64_t{0} >> (64 - range.size())) & rate
        : 4 * static_cast<std::size_t>(std::popcount(rate)) < range.size()
            ? touching_mask_of(range, rate, pair_a, pair_b, position, radius) |
                  (springs.held_mask(range.begin, range.size()) & rate)
            : (touching_mask(range, pair_a, pair_b, position, radius) |
               springs.held_mask(range.begin, range.size())) &
                  rate;
    for_each_selected_in_order(
        range, visit, [&](std::size_t m) __attribute__((always_inline)) {
          const std::uint32_t a = pair_a[m];
          const std::uint32_t b = pair_b[m];
          if (most_touch && m + kPrefetchAhead < n_pairs) {
            const std::uint32_t ahead =
                std::max(pair_a[m + kPrefetchAhead], pair_b[m + kPrefetchAhead]);
            __builtin_prefetch(&position[ahead]);
            __builtin_prefetch(&velocity[ahead]);
            __builtin_prefetch(&omega[ahead]);
            __builtin_prefetch(&radius[ahead]);
            __builtin_prefetch(&mass[ahead]);
            __builtin_prefetch(&motion[ahead]);
            if (uniform_params == nullptr) __builtin_prefetch(&material[ahead]);
            __builtin_prefetch(&force_sum[ahead], 1);
            __builtin_prefetch(&torque_sum[ahead], 1);
            // Written here, not in a helper: GCC 12 takes a function whose only effect is a
            // prefetch for a pure one and deletes its calls (the ledger's entries had such
            // helpers, which never issued a request; issued, they changed nothing measurable:
            // docs/performance.md, thirty-third round).
          }
          const Vec3 d = position[b] - position[a];
          const double reach = radius[a] + radius[b];
          const double dist2 = norm2(d);
          if (dist2 >= reach * reach) {
            if (kPerContact && book_work && springs.holds(m) && springs.ledger(m).carries_work()) {
              // The contact opened in this step: the loads of its start did their work at
              // their contact point and the relative velocity of its middle (those of its end
              // are zero).
              const ContactLedgerState& carried = springs.ledger(m);
              const double depth = static_cast<double>(carried.overlap);
              const Vec3 v_rel = relative_contact_velocity(
                  step_start_normal(d, velocity[b] - velocity[a], ctx.dt), radius[a] - 0.5 * depth,
                  radius[b] - 0.5 * depth, velocity[a], velocity[b], omega[a], omega[b]);
              const double half_damping = 0.5 * dot(to_vec3(carried.damping), v_rel);
              const double half_friction = 0.5 * dot(springs.value(m), v_rel);
              ledger.add_half_work(work, half_damping, half_friction,
                                   int{loads.owned(a)} + int{loads.owned(b)});
            }
            springs.release(m);  // an open contact's spring is zero (physics.md §3)
            return;
          }
          chunk.add_geometry(static_cast<std::uint32_t>(m), a, b, d, dist2, radius[a], radius[b],
                             effective_mass(mass[a], motion[a], mass[b], motion[b]), velocity[a],
                             velocity[b], omega[a], omega[b], springs.take(m));
          if (uniform_params == nullptr)
            chunk.set_params(chunk.n - 1, ctx.materials.pair(material[a], material[b]));
          if constexpr (kPerContact) chunk.carried_ledger.set(chunk.n - 1, springs.ledger(m));
          if constexpr (kBook) {
            // The ledger's entries now, in pair order (the order the scatter adds in).
            const std::size_t c = chunk.n - 1;
            if (loads.owned(a)) chunk.moments_a[c] = ledger.moments_entry(a);
            if (loads.owned(b)) chunk.moments_b[c] = ledger.moments_entry(b);
          }
        });
    most_touch = 2 * chunk.n > range.size();
    chunk.compute<kLedger>(ctx.dt);
    // Each end's loads, and for the ledger its viscous and spring loads and moments
    // (ContactMoments) with half of the pair's tangential and elastic energy.
    for_each_in_order(
        IndexRange{0, chunk.n}, [&](std::size_t c) __attribute__((always_inline)) {
          const std::uint32_t a = chunk.end_a[c];
          const std::uint32_t b = chunk.end_b[c];
          // The pair took its spring when it joined the chunk. Component by component: copied
          // as a Vec3, the spring went through the stack in three stores and a 16-byte load
          // across two of them, which the store buffer cannot forward (a fifth of this loop's
          // time on a packing in contact).
          chunk.spring.copy_to(c, springs.value(chunk.pair[c]));
          if constexpr (kPerContact)
            chunk.ledger_to_carry.copy_to(c, springs.ledger(chunk.pair[c]));
          const Vec3 spring = chunk.spring.get(c);
          const Vec3 force = chunk.force_a.get(c);
          // Per-contact booking: each owned end books half the contact's energies (and its
          // work, below).
          const auto book_contact = [&](std::uint32_t end) __attribute__((always_inline)) {
            if constexpr (kEnergies)
              ledger.add_contact_energies(end, chunk.half_tangential_energy[c],
                                          chunk.half_elastic_energy[c]);
          };
          if (loads.owned(a)) {
            force_sum[a] += force;
            torque_sum[a] += chunk.torque_a.get(c);
            book_contact(a);
            if constexpr (kBook) {
              ledger.moments_at(chunk.moments_a[c])
                  .add(chunk.damping_a.get(c), chunk.damping_moment_a.get(c), spring,
                       chunk.friction_moment_a.get(c), chunk.half_tangential_energy[c],
                       chunk.half_elastic_energy[c]);
            }
          }
          if (loads.owned(b)) {
            force_sum[b] += -force;
            torque_sum[b] += chunk.torque_b.get(c);
            book_contact(b);
            if constexpr (kBook) {
              ledger.moments_at(chunk.moments_b[c])
                  .add(-chunk.damping_a.get(c), chunk.damping_moment_b.get(c), -spring,
                       chunk.friction_moment_b.get(c), chunk.half_tangential_energy[c],
                       chunk.half_elastic_energy[c]);
            }
          }
        });
    if constexpr (kPerContact) {
      static_assert(PairContactChunk::kSize <= EnergyLedger::kMaxChunkContacts);
      if (book_work) {
        // The start's loads and the end's apart, each half rounded on its own
        // (PairContactChunk::start_half_work).
        const auto owned_ends = [&](std::size_t c) __attribute__((always_inline)) {
          return int{loads.owned(chunk.end_a[c])} + int{loads.owned(chunk.end_b[c])};
        };
        ledger.add_half_works(work, chunk.start_half_work.damping, chunk.start_half_work.friction,
                              chunk.n, owned_ends);
        ledger.add_half_works(work, chunk.end_half_work.damping, chunk.end_half_work.friction,
                              chunk.n, owned_ends);
      }
    }
  };
  if (ctx.rate == ForceRate::kFast) {
    for (const std::uint32_t c : fast_chunks_)
      run_chunk(IndexRange{c * kChunk, std::min((c + 1) * kChunk, n_pairs)});
  } else {
    for_each_chunk(IndexRange{0, n_pairs}, kChunk, run_chunk);
  }
  if constexpr (kPerContact) ledger.flush_contact_work(work);
}

}  // namespace ringdem

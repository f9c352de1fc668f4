#pragma once

#include <array>
#include <cstdint>
#include <variant>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/ContactSpringStore.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// A term's store whose rows each join two particles: the bonds of a bond term, the springs
/// of a contact term. The decomposition moves such rows to the owners of their ends, and
/// checkpoints write and read them, through this one handle and the store's field registry,
/// never through a named store. A new kind of term store (a rope's sliding contacts, say) is
/// one more alternative here; it offers what both stores below offer:
///   size(), for_each_field(f), ends(row) (the particle gids it joins; the second is -1 when
///   the partner is no particle), keep_rows(keep), resize(n), settle_arrivals(first) (after
///   migration appended rows [first, size()): drop duplicates, restore the store's order),
///   and kBlockWeight (what a row adds to its cell's weight in the decomposition, a particle
///   counting 1; 0: rows do not count).
using PairStore = std::variant<BondStore*, ContactSpringStore*>;

/// Calls f(store&) with the store behind the handle.
template <class F>
decltype(auto) visit_store(const PairStore& s, F&& f) {
  return std::visit([&](auto* store) -> decltype(auto) { return f(*store); }, s);
}

/// Whether this rank counts row k of a pair store: a row whose ends live on two ranks is held
/// by both, and counts (in block weights, sums, frames, checkpoints) on the rank that owns its
/// first end. The one place of this rule.
template <class Store>
bool counted_here(const ParticleStore& p, const Store& s, std::size_t k) {
  const std::int64_t a = p.index_of(s.ends(k)[0]);
  return a >= 0 && static_cast<std::size_t>(a) < p.n_local();
}

}  // namespace ringdem

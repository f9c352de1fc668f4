#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>

namespace ringdem {

/// The one place where the force terms' kernels are looped. Iterations must be independent
/// (each writes only its own slots and items): a threaded or GPU backend replaces these two
/// functions and every term follows.
struct IndexRange {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

/// Calls f(i) for every i of r. `ivdep`: the kernels gather by index but write only slot i,
/// which the compiler cannot prove; the promise lets the loop vectorise.
template <class F>
[[gnu::always_inline]] inline void for_each(IndexRange r, F&& f) {
#pragma GCC ivdep
  for (std::size_t i = r.begin; i < r.end; ++i)
    f(i);
}

/// Calls f(i) for every i of r in ascending order, one after the other: for a kernel whose
/// iterations add to shared per-particle sums in a fixed order (PairContactTerm), which a
/// threaded backend must keep (colouring, or one range per owner of the sums).
template <class F>
[[gnu::always_inline]] inline void for_each_in_order(IndexRange r, F&& f) {
  for (std::size_t i = r.begin; i < r.end; ++i)
    f(i);
}

/// Calls f(i) in ascending order for the i of r (at most 64 items) whose bit i - r.begin is set
/// in `selected`: for_each_in_order over the items a kernel's first pass picked (the candidates
/// of a chunk that touch), without a test of each of the others.
template <class F>
[[gnu::always_inline]] inline void for_each_selected_in_order(IndexRange r, std::uint64_t selected,
                                                              F&& f) {
  for (; selected != 0; selected &= selected - 1)
    f(r.begin + static_cast<std::size_t>(__builtin_ctzll(selected)));
}

/// Calls f(chunk) for consecutive chunks of at most `chunk` items covering r (kernels that
/// first copy a chunk's scattered inputs into contiguous scratch, then run for_each on it).
template <class F>
inline void for_each_chunk(IndexRange r, std::size_t chunk, F&& f) {
  for (std::size_t start = r.begin; start < r.end; start += chunk)
    f(IndexRange{start, std::min(start + chunk, r.end)});
}

}  // namespace ringdem

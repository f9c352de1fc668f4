#pragma once

#include <mpi.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "comm/ExactSum.hpp"

namespace ringdem {

/// The comm layer's handle: wraps an injected MPI communicator (never MPI_COMM_WORLD inside
/// the library) and owns the reductions. Physics code never sees it.
class Communicator {
 public:
  explicit Communicator(MPI_Comm comm);

  /// A communicator of this rank alone (MPI_COMM_SELF), for work that one rank does by
  /// itself, such as one case of a parameter sweep.
  static Communicator self() { return Communicator(MPI_COMM_SELF); }

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool is_root() const { return rank_ == 0; }
  MPI_Comm raw() const { return comm_; }

  double min(double v) const;
  double max(double v) const;
  std::int64_t sum(std::int64_t v) const;
  /// Element-wise maximum of a small fixed array over the ranks.
  template <std::size_t N>
  std::array<double, N> max(const std::array<double, N>& v) const {
    std::array<double, N> r{};
    max_in_place(v.data(), r.data(), static_cast<int>(N));
    return r;
  }
  std::int64_t min(std::int64_t v) const;
  std::int64_t max(std::int64_t v) const;
  /// Element-wise sums over the ranks of n integers, in place (exact: integer sums).
  void sum_in_place(std::int64_t* values, std::size_t n) const;
  /// Sums that do not depend on the rank count or the order of the terms: each rank passes
  /// its partial ExactSum of some columns, and every rank gets each column's total rounded once
  /// (to nearest), the same bits however the terms are spread. One all-reduce of
  /// ExactSum::kWords integers per column; no rank holds more than its own terms.
  std::vector<double> sum_exact(const std::vector<ExactSum>& partial) const;
  /// The same reduction, keeping each column's total exact (a checkpoint stores it as words).
  std::vector<ExactSum> reduce_exact(const std::vector<ExactSum>& partial) const;
  /// The exact sums (sum_exact) over the ranks of each column's local values.
  std::vector<double> sum_columns(const std::vector<const std::vector<double>*>& columns) const;

  /// Every rank's items, concatenated in rank order, on every rank (trivially copyable T).
  template <class T>
  std::vector<T> allgather(const std::vector<T>& local) const {
    static_assert(std::is_trivially_copyable_v<T>);
    const std::vector<char> bytes =
        allgather_bytes(reinterpret_cast<const char*>(local.data()), local.size() * sizeof(T));
    std::vector<T> out(bytes.size() / sizeof(T));
    // memcpy with a null pointer is undefined even for zero bytes, and an empty vector's
    // data() may be null (every rank gathering nothing, e.g. no rigid-body contacts).
    if (!bytes.empty()) std::memcpy(out.data(), bytes.data(), bytes.size());
    return out;
  }
  /// Rank `root`'s `items` on every rank: the other ranks' `items` are replaced (resized to
  /// the root's count first), trivially copyable T.
  template <class T>
  void broadcast(std::vector<T>& items, int root) const {
    static_assert(std::is_trivially_copyable_v<T>);
    std::int64_t n = static_cast<std::int64_t>(items.size());
    broadcast_bytes(&n, sizeof(n), root);
    items.resize(static_cast<std::size_t>(n));
    broadcast_bytes(items.data(), items.size() * sizeof(T), root);
  }
  /// Point-to-point exchange with a fixed set of partners: send[r] goes to rank r when not
  /// empty, and recv_counts[r] bytes (known in advance) arrive from rank r. No collective:
  /// only the partners synchronise. The arrivals are written to `out`, concatenated in
  /// source-rank order; `out` is resized (its capacity kept), so a caller that reuses it does
  /// not allocate every step.
  void exchange_bytes(const std::vector<std::vector<char>>& send,
                      const std::vector<int>& recv_counts, std::vector<char>& out) const;
  /// Personalised all-to-all of byte buffers: send[r] goes to rank r. Returns what arrived,
  /// concatenated in source-rank order, and the byte count from each source in recv_counts.
  std::vector<char> alltoall_bytes(const std::vector<std::vector<char>>& send,
                                   std::vector<int>& recv_counts) const;
  /// The same, freeing each send buffer once it is packed: a migration's buffers then take
  /// one copy of what leaves, not two, at the peak of a run's memory.
  std::vector<char> alltoall_bytes(std::vector<std::vector<char>>&& send,
                                   std::vector<int>& recv_counts) const;
  /// The same from one buffer that holds what goes to each rank one after the other,
  /// send_counts[r] bytes for rank r: packed where it is built, with no copy (a migration's
  /// peak then holds what leaves once). `packed` is freed before the result is returned.
  std::vector<char> alltoall_bytes(std::vector<char>&& packed, const std::vector<int>& send_counts,
                                   std::vector<int>& recv_counts) const;

  /// True on every rank when any rank passes true.
  bool any(bool v) const;
  /// How many ranks of this communicator share this rank's node (its memory).
  int ranks_on_this_node() const;
  void barrier() const;

 private:
  std::vector<char> allgather_bytes(const char* data, std::size_t n) const;
  void max_in_place(const double* in, double* out, int n) const;
  void broadcast_bytes(void* data, std::size_t n, int root) const;

  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
};

/// The ranks of a communicator that share a colour, as a communicator of their own (in the
/// parent's rank order), freed with this handle: e.g. the groups of ranks that run one case of a
/// parameter study together. Collective over the parent.
class SplitCommunicator {
 public:
  SplitCommunicator(const Communicator& parent, int colour);
  ~SplitCommunicator();
  SplitCommunicator(const SplitCommunicator&) = delete;
  SplitCommunicator& operator=(const SplitCommunicator&) = delete;

  const Communicator& get() const { return comm_; }

 private:
  static MPI_Comm split(const Communicator& parent, int colour);

  MPI_Comm raw_;
  Communicator comm_;
};

}  // namespace ringdem

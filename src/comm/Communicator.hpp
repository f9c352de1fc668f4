#pragma once

#include <mpi.h>

#include <cstdint>
#include <vector>

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
  std::int64_t min(std::int64_t v) const;
  std::int64_t max(std::int64_t v) const;
  /// Sum of doubles that does not depend on the number of ranks or their order: every
  /// rank's values are gathered and added in one fixed order on every rank. Each rank passes
  /// its terms keyed by a global id; terms are summed in key order.
  double sum_by_key(const std::vector<std::int64_t>& keys, const std::vector<double>& values) const;
  /// True on every rank when any rank passes true.
  bool any(bool v) const;
  void barrier() const;

 private:
  MPI_Comm comm_;
  int rank_ = 0;
  int size_ = 1;
};

}  // namespace ringdem

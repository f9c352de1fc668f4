#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "comm/Communicator.hpp"

namespace ringdem {

/// Moves items keyed by a dense global row (0..n_rows-1: a particle gid, a bond id) to the
/// rank whose contiguous block of rows holds them, so that each rank writes one hyperslab and
/// a file's row order does not depend on the rank count. Rank r holds rows
/// [r n / P, (r + 1) n / P). The plan (who sends which row where) is built once; to_blocks()
/// then moves one field per call in that order.
class RowBlocks {
 public:
  /// `local_rows`: the rows this rank contributes (each row contributed by exactly one rank).
  /// Throws std::runtime_error when the rows are not a permutation of 0..n_rows-1.
  RowBlocks(const Communicator& comm, std::int64_t n_rows,
            const std::vector<std::int64_t>& local_rows);

  std::int64_t n_rows() const { return n_rows_; }
  std::int64_t first_row() const { return first_; }
  std::int64_t block_size() const { return count_; }
  static std::int64_t block_begin(std::int64_t n_rows, int rank, int ranks) {
    return n_rows * rank / ranks;
  }

  /// values[i] belongs to local_rows[i]; returns this rank's block in row order.
  template <class T>
  std::vector<T> to_blocks(const std::vector<T>& values) const {
    static_assert(std::is_trivially_copyable_v<T>);
    if (values.size() < send_order_.size())
      throw std::invalid_argument("RowBlocks::to_blocks: fewer values than rows");
    std::vector<std::vector<char>> send(static_cast<std::size_t>(comm_.size()));
    for (std::size_t r = 0; r < send.size(); ++r)
      send[r].resize(send_counts_[r] * sizeof(T));
    std::vector<std::size_t> fill(send.size(), 0);
    for (std::size_t k = 0; k < send_order_.size(); ++k) {
      const std::size_t i = send_order_[k];
      const std::size_t r = dest_[i];
      std::memcpy(send[r].data() + fill[r]++ * sizeof(T), &values[i], sizeof(T));
    }
    std::vector<int> recv_counts;
    const std::vector<char> arrived = comm_.alltoall_bytes(send, recv_counts);
    std::vector<T> block(static_cast<std::size_t>(count_));
    for (std::size_t k = 0; k < recv_slot_.size(); ++k)
      std::memcpy(&block[recv_slot_[k]], arrived.data() + k * sizeof(T), sizeof(T));
    return block;
  }

 private:
  const Communicator& comm_;
  std::int64_t n_rows_ = 0, first_ = 0, count_ = 0;
  std::vector<std::size_t> dest_;        ///< destination rank of local item i
  std::vector<std::size_t> send_order_;  ///< local items sorted by destination rank
  std::vector<std::size_t> send_counts_;
  std::vector<std::size_t> recv_slot_;  ///< block slot of the k-th arriving item
};

}  // namespace ringdem

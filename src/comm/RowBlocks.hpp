#pragma once

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <type_traits>
#include <vector>

#include "comm/Communicator.hpp"

namespace ringdem {

/// Moves items keyed by a unique global key (a particle gid, a bond id; sparse, held by any
/// ranks) to the rank whose contiguous block of rows holds them, so that each rank writes one
/// hyperslab and a file's row order does not depend on the rank count. A key's row is its
/// position among all keys in increasing order; rank r holds rows [r n / P, (r + 1) n / P) of
/// the n keys. Dense keys 0..n-1 are their own rows.
///
/// The rows are found by a sample sort: each rank sends its sorted keys to the rank of their
/// key range (splitters from P weighted samples per rank), which ranks them and answers with
/// their rows. No rank holds more than its own keys, its key range and its block (plus P^2
/// samples). The plan (who sends which item where) is built once; to_blocks() then moves one
/// field per call in that order.
class RowBlocks {
 public:
  /// `local_keys`: the keys of this rank's items. Throws std::runtime_error (on every rank)
  /// when a key is held twice, on one rank or on two.
  RowBlocks(const Communicator& comm, const std::vector<std::int64_t>& local_keys);

  std::int64_t n_rows() const { return n_rows_; }
  std::int64_t first_row() const { return first_; }
  std::int64_t block_size() const { return count_; }
  /// The keys of this rank's block, increasing (the key of row first_row() + i).
  const std::vector<std::int64_t>& block_keys() const { return block_keys_; }
  /// The row of each local key (local_rows()[i] belongs to local_keys[i]).
  const std::vector<std::int64_t>& local_rows() const { return local_rows_; }
  static std::int64_t block_begin(std::int64_t n_rows, int rank, int ranks) {
    return n_rows * rank / ranks;
  }

  /// Collective: the rows of any keys (a bond's far end, say), -1 for a key that is not one
  /// of the keys. Asks the rank whose block holds each key.
  std::vector<std::int64_t> rows_of(const std::vector<std::int64_t>& keys) const;

  /// values[i] belongs to local_keys[i]; returns this rank's block in row (key) order.
  template <class T>
  std::vector<T> to_blocks(const std::vector<T>& values) const {
    static_assert(std::is_trivially_copyable_v<T>);
    if (values.size() < send_order_.size())
      throw std::invalid_argument("RowBlocks::to_blocks: fewer values than keys");
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
  void rank_keys(const std::vector<std::int64_t>& local_keys);
  void plan(const std::vector<std::int64_t>& local_keys);

  const Communicator& comm_;
  std::int64_t n_rows_ = 0, first_ = 0, count_ = 0;
  std::vector<std::int64_t> local_rows_;
  std::vector<std::int64_t> block_keys_;
  std::vector<std::int64_t> block_first_key_;  ///< smallest key of each non-empty block
  std::vector<int> block_rank_;                ///< the rank of that block
  std::vector<std::size_t> dest_;              ///< destination rank of local item i
  std::vector<std::size_t> send_order_;        ///< local items sorted by destination rank
  std::vector<std::size_t> send_counts_;
  std::vector<std::size_t> recv_slot_;  ///< block slot of the k-th arriving item
};

}  // namespace ringdem

#include "comm/RowBlocks.hpp"

#include <algorithm>
#include <string>

namespace ringdem {

RowBlocks::RowBlocks(const Communicator& comm, std::int64_t n_rows,
                     const std::vector<std::int64_t>& local_rows)
    : comm_(comm), n_rows_(n_rows) {
  const int ranks = comm.size();
  first_ = block_begin(n_rows, comm.rank(), ranks);
  count_ = block_begin(n_rows, comm.rank() + 1, ranks) - first_;
  dest_.resize(local_rows.size());
  send_counts_.assign(static_cast<std::size_t>(ranks), 0);
  bool out_of_range = false;
  for (std::size_t i = 0; i < local_rows.size(); ++i) {
    const std::int64_t row = local_rows[i];
    if (row < 0 || row >= n_rows) {
      out_of_range = true;
      continue;
    }
    // The block owner: the largest r with block_begin(r) <= row.
    auto r = static_cast<int>((row * ranks) / std::max<std::int64_t>(n_rows, 1));
    while (r + 1 < ranks && block_begin(n_rows, r + 1, ranks) <= row)
      ++r;
    while (r > 0 && block_begin(n_rows, r, ranks) > row)
      --r;
    dest_[i] = static_cast<std::size_t>(r);
    ++send_counts_[dest_[i]];
  }
  if (comm.any(out_of_range))
    throw std::runtime_error("RowBlocks: a row lies outside 0.." + std::to_string(n_rows - 1) +
                             " (gids or bond ids are not dense)");
  send_order_.resize(local_rows.size());
  for (std::size_t i = 0; i < send_order_.size(); ++i)
    send_order_[i] = i;
  std::stable_sort(send_order_.begin(), send_order_.end(),
                   [this](std::size_t a, std::size_t b) { return dest_[a] < dest_[b]; });
  // Send the rows themselves once: the arrival order is the order of every later field.
  std::vector<std::int64_t> rows_sorted(local_rows.size());
  for (std::size_t k = 0; k < send_order_.size(); ++k)
    rows_sorted[k] = local_rows[send_order_[k]];
  std::vector<std::vector<char>> send(static_cast<std::size_t>(ranks));
  std::size_t offset = 0;
  for (std::size_t r = 0; r < send.size(); ++r) {
    const std::size_t bytes = send_counts_[r] * sizeof(std::int64_t);
    send[r].resize(bytes);
    if (bytes > 0)
      std::memcpy(send[r].data(), reinterpret_cast<const char*>(rows_sorted.data()) + offset,
                  bytes);
    offset += bytes;
  }
  std::vector<int> recv_counts;
  const std::vector<char> arrived = comm_.alltoall_bytes(send, recv_counts);
  const std::size_t n_arrived = arrived.size() / sizeof(std::int64_t);
  std::vector<char> seen(static_cast<std::size_t>(count_), 0);
  bool bad = n_arrived != static_cast<std::size_t>(count_);
  recv_slot_.resize(n_arrived);
  for (std::size_t k = 0; k < n_arrived && !bad; ++k) {
    std::int64_t row = 0;
    std::memcpy(&row, arrived.data() + k * sizeof(row), sizeof(row));
    const auto slot = static_cast<std::size_t>(row - first_);
    if (seen[slot]) bad = true;
    seen[slot] = 1;
    recv_slot_[k] = slot;
  }
  if (comm.any(bad))
    throw std::runtime_error("RowBlocks: rows are not a permutation of 0.." +
                             std::to_string(n_rows - 1) +
                             " over the ranks (a row is missing or "
                             "contributed twice)");
}

}  // namespace ringdem

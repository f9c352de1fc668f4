#include "comm/RowBlocks.hpp"

#include <algorithm>
#include <limits>
#include <numeric>

namespace ringdem {

namespace {

/// Splits `items` (grouped by destination rank, counts[r] for rank r) into one byte buffer
/// per rank.
template <class T>
std::vector<std::vector<char>> to_buffers(const std::vector<T>& items,
                                          const std::vector<std::size_t>& counts) {
  std::vector<std::vector<char>> send(counts.size());
  std::size_t at = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    send[r].resize(counts[r] * sizeof(T));
    if (counts[r] > 0) std::memcpy(send[r].data(), items.data() + at, counts[r] * sizeof(T));
    at += counts[r];
  }
  return send;
}

template <class T>
std::vector<T> from_bytes(const std::vector<char>& bytes) {
  std::vector<T> out(bytes.size() / sizeof(T));
  if (!out.empty()) std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

/// The rank of the block that holds `row` (the largest r with block_begin(r) <= row).
int block_owner(std::int64_t row, std::int64_t n_rows, int ranks) {
  auto r = static_cast<int>((row * ranks) / std::max<std::int64_t>(n_rows, 1));
  while (r + 1 < ranks && RowBlocks::block_begin(n_rows, r + 1, ranks) <= row)
    ++r;
  while (r > 0 && RowBlocks::block_begin(n_rows, r, ranks) > row)
    --r;
  return r;
}

struct Sample {
  std::int64_t key, weight;
};

/// P - 1 splitters that cut the keys into P ranges of about n / P keys each: every rank
/// contributes up to P samples of its sorted keys, each weighted by the keys it stands for.
/// (Only the balance of the sort depends on them, never the rows.)
std::vector<std::int64_t> splitters(const Communicator& comm,
                                    const std::vector<std::int64_t>& sorted, std::int64_t n) {
  const int ranks = comm.size();
  const std::size_t m = sorted.size();
  const std::size_t s = std::min(m, static_cast<std::size_t>(ranks));
  std::vector<Sample> mine;
  for (std::size_t j = 0; j < s; ++j) {
    const std::size_t from = j * m / s, to = (j + 1) * m / s;
    mine.push_back({sorted[from], static_cast<std::int64_t>(to - from)});
  }
  std::vector<Sample> all = comm.allgather(mine);
  std::sort(all.begin(), all.end(), [](const Sample& a, const Sample& b) { return a.key < b.key; });
  std::vector<std::int64_t> cut;
  std::int64_t before = 0;
  std::size_t k = 0;
  for (int r = 1; r < ranks; ++r) {
    const std::int64_t target = n * r / ranks;
    while (k < all.size() && before + all[k].weight <= target)
      before += all[k++].weight;
    // Keys from the first sample past the target on go to range r or later.
    cut.push_back(k < all.size() ? all[k].key : std::numeric_limits<std::int64_t>::max());
  }
  return cut;
}

}  // namespace

RowBlocks::RowBlocks(const Communicator& comm, const std::vector<std::int64_t>& local_keys)
    : comm_(comm) {
  rank_keys(local_keys);
  plan(local_keys);
}

void RowBlocks::rank_keys(const std::vector<std::int64_t>& local_keys) {
  const int ranks = comm_.size();
  const std::size_t n_local = local_keys.size();
  n_rows_ = comm_.sum(static_cast<std::int64_t>(n_local));
  std::vector<std::size_t> order(n_local);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return local_keys[a] < local_keys[b]; });
  std::vector<std::int64_t> sorted(n_local);
  for (std::size_t j = 0; j < n_local; ++j)
    sorted[j] = local_keys[order[j]];
  // Each key range r goes to rank r: a contiguous run of the sorted keys.
  const std::vector<std::int64_t> cut = splitters(comm_, sorted, n_rows_);
  std::vector<std::size_t> counts(static_cast<std::size_t>(ranks), 0);
  for (const std::int64_t key : sorted)
    ++counts[static_cast<std::size_t>(std::upper_bound(cut.begin(), cut.end(), key) - cut.begin())];
  std::vector<int> recv_bytes;
  const std::vector<std::int64_t> arrived =
      from_bytes<std::int64_t>(comm_.alltoall_bytes(to_buffers(sorted, counts), recv_bytes));
  // Rank the range's keys; the ranges before it (in rank order) hold all smaller keys.
  std::vector<std::size_t> by_key(arrived.size());
  std::iota(by_key.begin(), by_key.end(), 0);
  std::sort(by_key.begin(), by_key.end(),
            [&](std::size_t a, std::size_t b) { return arrived[a] < arrived[b]; });
  bool duplicate = false;
  for (std::size_t j = 1; j < by_key.size(); ++j)
    duplicate |= arrived[by_key[j]] == arrived[by_key[j - 1]];
  if (comm_.any(duplicate))
    throw std::runtime_error("RowBlocks: a key (gid or bond id) is held twice");
  const std::vector<std::int64_t> range_sizes =
      comm_.allgather(std::vector<std::int64_t>{static_cast<std::int64_t>(arrived.size())});
  const std::int64_t offset =
      std::accumulate(range_sizes.begin(), range_sizes.begin() + comm_.rank(), std::int64_t{0});
  std::vector<std::int64_t> rows(arrived.size());
  for (std::size_t j = 0; j < by_key.size(); ++j)
    rows[by_key[j]] = offset + static_cast<std::int64_t>(j);
  // Answer each source in the order its keys came: its sorted order.
  std::vector<std::size_t> reply_counts(static_cast<std::size_t>(ranks));
  for (std::size_t r = 0; r < reply_counts.size(); ++r)
    reply_counts[r] = static_cast<std::size_t>(recv_bytes[r]) / sizeof(std::int64_t);
  const std::vector<std::int64_t> answer =
      from_bytes<std::int64_t>(comm_.alltoall_bytes(to_buffers(rows, reply_counts), recv_bytes));
  local_rows_.assign(n_local, -1);
  for (std::size_t j = 0; j < n_local; ++j)
    local_rows_[order[j]] = answer[j];
}

void RowBlocks::plan(const std::vector<std::int64_t>& local_keys) {
  const int ranks = comm_.size();
  first_ = block_begin(n_rows_, comm_.rank(), ranks);
  count_ = block_begin(n_rows_, comm_.rank() + 1, ranks) - first_;
  const std::size_t n_local = local_rows_.size();
  dest_.resize(n_local);
  send_counts_.assign(static_cast<std::size_t>(ranks), 0);
  for (std::size_t i = 0; i < n_local; ++i) {
    dest_[i] = static_cast<std::size_t>(block_owner(local_rows_[i], n_rows_, ranks));
    ++send_counts_[dest_[i]];
  }
  send_order_.resize(n_local);
  std::iota(send_order_.begin(), send_order_.end(), 0);
  std::stable_sort(send_order_.begin(), send_order_.end(),
                   [this](std::size_t a, std::size_t b) { return dest_[a] < dest_[b]; });
  // Send each item's row and key once: the arrival order is the order of every later field.
  struct RowKey {
    std::int64_t row, key;
  };
  std::vector<RowKey> sent(n_local);
  for (std::size_t k = 0; k < n_local; ++k)
    sent[k] = {local_rows_[send_order_[k]], local_keys[send_order_[k]]};
  std::vector<int> recv_bytes;
  const std::vector<RowKey> arrived =
      from_bytes<RowKey>(comm_.alltoall_bytes(to_buffers(sent, send_counts_), recv_bytes));
  if (static_cast<std::int64_t>(arrived.size()) != count_)
    throw std::logic_error("RowBlocks: a block received the wrong number of rows");
  recv_slot_.resize(arrived.size());
  block_keys_.resize(arrived.size());
  for (std::size_t k = 0; k < arrived.size(); ++k) {
    recv_slot_[k] = static_cast<std::size_t>(arrived[k].row - first_);
    block_keys_[recv_slot_[k]] = arrived[k].key;
  }
  // Where each block starts in key order, for rows_of().
  const std::vector<std::int64_t> firsts =
      comm_.allgather(std::vector<std::int64_t>{block_keys_.empty() ? 0 : block_keys_.front()});
  for (int r = 0; r < ranks; ++r)
    if (block_begin(n_rows_, r + 1, ranks) > block_begin(n_rows_, r, ranks)) {
      block_first_key_.push_back(firsts[static_cast<std::size_t>(r)]);
      block_rank_.push_back(r);
    }
}

std::vector<std::int64_t> RowBlocks::rows_of(const std::vector<std::int64_t>& keys) const {
  const auto ranks = static_cast<std::size_t>(comm_.size());
  // The block holding a key: the last non-empty block whose first key is not above it.
  std::vector<std::size_t> dest(keys.size(), ranks);
  std::vector<std::size_t> counts(ranks, 0);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const auto it = std::upper_bound(block_first_key_.begin(), block_first_key_.end(), keys[i]);
    if (it == block_first_key_.begin()) continue;  // below every key: not one of them
    dest[i] = static_cast<std::size_t>(
        block_rank_[static_cast<std::size_t>(it - block_first_key_.begin() - 1)]);
    ++counts[dest[i]];
  }
  std::vector<std::size_t> order;
  for (std::size_t i = 0; i < keys.size(); ++i)
    if (dest[i] < ranks) order.push_back(i);
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return dest[a] < dest[b]; });
  std::vector<std::int64_t> asked(order.size());
  for (std::size_t k = 0; k < order.size(); ++k)
    asked[k] = keys[order[k]];
  std::vector<int> recv_bytes;
  std::vector<std::int64_t> questions =
      from_bytes<std::int64_t>(comm_.alltoall_bytes(to_buffers(asked, counts), recv_bytes));
  for (auto& q : questions) {
    const auto it = std::lower_bound(block_keys_.begin(), block_keys_.end(), q);
    q = it != block_keys_.end() && *it == q ? first_ + (it - block_keys_.begin()) : -1;
  }
  std::vector<std::size_t> reply_counts(ranks);
  for (std::size_t r = 0; r < ranks; ++r)
    reply_counts[r] = static_cast<std::size_t>(recv_bytes[r]) / sizeof(std::int64_t);
  const std::vector<std::int64_t> answers = from_bytes<std::int64_t>(
      comm_.alltoall_bytes(to_buffers(questions, reply_counts), recv_bytes));
  std::vector<std::int64_t> rows(keys.size(), -1);
  for (std::size_t k = 0; k < order.size(); ++k)
    rows[order[k]] = answers[k];
  return rows;
}

}  // namespace ringdem

#include "comm/Communicator.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace ringdem {

Communicator::Communicator(MPI_Comm comm) : comm_(comm) {
  MPI_Comm_rank(comm_, &rank_);
  MPI_Comm_size(comm_, &size_);
}

double Communicator::min(double v) const {
  double r = v;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MIN, comm_);
  return r;
}

double Communicator::max(double v) const {
  double r = v;
  MPI_Allreduce(&v, &r, 1, MPI_DOUBLE, MPI_MAX, comm_);
  return r;
}

std::int64_t Communicator::sum(std::int64_t v) const {
  std::int64_t r = v;
  MPI_Allreduce(&v, &r, 1, MPI_INT64_T, MPI_SUM, comm_);
  return r;
}

std::int64_t Communicator::min(std::int64_t v) const {
  std::int64_t r = v;
  MPI_Allreduce(&v, &r, 1, MPI_INT64_T, MPI_MIN, comm_);
  return r;
}

std::int64_t Communicator::max(std::int64_t v) const {
  std::int64_t r = v;
  MPI_Allreduce(&v, &r, 1, MPI_INT64_T, MPI_MAX, comm_);
  return r;
}

std::vector<ExactSum> Communicator::reduce_exact(const std::vector<ExactSum>& partial) const {
  // On one rank the partial sums are the totals (the step loop asks for a body's loads every
  // step).
  if (size_ == 1) return partial;
  // Integer sums of canonical words are exact and associative, so MPI's reduction order does
  // not matter.
  std::vector<std::int64_t> words(partial.size() * ExactSum::kWords);
  for (std::size_t c = 0; c < partial.size(); ++c) {
    const auto w = partial[c].export_words();
    std::copy(w.begin(), w.end(), words.begin() + static_cast<std::ptrdiff_t>(c * w.size()));
  }
  if (!words.empty())
    MPI_Allreduce(MPI_IN_PLACE, words.data(), static_cast<int>(words.size()), MPI_INT64_T, MPI_SUM,
                  comm_);
  std::vector<ExactSum> totals;
  totals.reserve(partial.size());
  for (std::size_t c = 0; c < partial.size(); ++c)
    totals.push_back(ExactSum::from_words(words.data() + c * ExactSum::kWords));
  return totals;
}

std::vector<double> Communicator::sum_exact(const std::vector<ExactSum>& partial) const {
  const std::vector<ExactSum> totals = reduce_exact(partial);
  std::vector<double> sums(totals.size());
  for (std::size_t c = 0; c < totals.size(); ++c)
    sums[c] = totals[c].value();
  return sums;
}

std::vector<double> Communicator::sum_columns(
    const std::vector<const std::vector<double>*>& columns) const {
  std::vector<ExactSum> partial(columns.size());
  for (std::size_t c = 0; c < columns.size(); ++c)
    for (const double v : *columns[c])
      partial[c].add(v);
  return sum_exact(partial);
}

std::vector<char> Communicator::allgather_bytes(const char* data, std::size_t n) const {
  const int count = static_cast<int>(n);
  std::vector<int> counts(static_cast<std::size_t>(size_));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm_);
  std::vector<int> displs(counts.size(), 0);
  std::partial_sum(counts.begin(), counts.end() - 1, displs.begin() + 1);
  std::vector<char> out(static_cast<std::size_t>(displs.back() + counts.back()));
  MPI_Allgatherv(data, count, MPI_BYTE, out.data(), counts.data(), displs.data(), MPI_BYTE, comm_);
  return out;
}

void Communicator::broadcast_bytes(void* data, std::size_t n, int root) const {
  MPI_Bcast(data, static_cast<int>(n), MPI_BYTE, root, comm_);
}

std::vector<char> Communicator::alltoall_bytes(const std::vector<std::vector<char>>& send,
                                               std::vector<int>& recv_counts) const {
  std::vector<std::vector<char>> copy = send;
  return alltoall_bytes(std::move(copy), recv_counts);
}

std::vector<char> Communicator::alltoall_bytes(std::vector<std::vector<char>>&& send,
                                               std::vector<int>& recv_counts) const {
  if (static_cast<int>(send.size()) != size_)
    throw std::invalid_argument("alltoall_bytes: one buffer per rank expected");
  std::vector<int> send_counts(send.size());
  std::size_t total = 0;
  for (const auto& b : send)
    total += b.size();
  std::vector<char> packed;
  packed.reserve(total);
  for (std::size_t r = 0; r < send.size(); ++r) {
    send_counts[r] = static_cast<int>(send[r].size());
    packed.insert(packed.end(), send[r].begin(), send[r].end());
    std::vector<char>().swap(send[r]);
  }
  return alltoall_bytes(std::move(packed), send_counts, recv_counts);
}

std::vector<char> Communicator::alltoall_bytes(std::vector<char>&& packed,
                                               const std::vector<int>& send_counts,
                                               std::vector<int>& recv_counts) const {
  if (static_cast<int>(send_counts.size()) != size_)
    throw std::invalid_argument("alltoall_bytes: one count per rank expected");
  std::vector<int> send_displs(send_counts.size(), 0);
  std::partial_sum(send_counts.begin(), send_counts.end() - 1, send_displs.begin() + 1);
  if (static_cast<std::size_t>(send_displs.back()) + static_cast<std::size_t>(send_counts.back()) !=
      packed.size())
    throw std::invalid_argument("alltoall_bytes: the counts do not add up to the buffer");
  recv_counts.assign(send_counts.size(), 0);
  MPI_Alltoall(send_counts.data(), 1, MPI_INT, recv_counts.data(), 1, MPI_INT, comm_);
  // MPI's displacements are ints: refuse plainly what would overflow them.
  const std::int64_t recv_total =
      std::accumulate(recv_counts.begin(), recv_counts.end(), std::int64_t{0});
  // Every rank throws, not only the one that would receive too much (the others would wait).
  if (any(recv_total > std::numeric_limits<int>::max()))
    throw std::runtime_error(
        "alltoall_bytes: more than 2 GiB would arrive at one rank in one exchange");
  std::vector<int> recv_displs(send_counts.size(), 0);
  std::partial_sum(recv_counts.begin(), recv_counts.end() - 1, recv_displs.begin() + 1);
  std::vector<char> out(static_cast<std::size_t>(recv_total));
  MPI_Alltoallv(packed.data(), send_counts.data(), send_displs.data(), MPI_BYTE, out.data(),
                recv_counts.data(), recv_displs.data(), MPI_BYTE, comm_);
  std::vector<char>().swap(packed);
  return out;
}

void Communicator::sum_in_place(std::int64_t* values, std::size_t n) const {
  if (size_ == 1 || n == 0) return;
  MPI_Allreduce(MPI_IN_PLACE, values, static_cast<int>(n), MPI_INT64_T, MPI_SUM, comm_);
}

void Communicator::max_in_place(const double* in, double* out, int n) const {
  MPI_Allreduce(in, out, n, MPI_DOUBLE, MPI_MAX, comm_);
}

void Communicator::exchange_bytes(const std::vector<std::vector<char>>& send,
                                  const std::vector<int>& recv_counts,
                                  std::vector<char>& out) const {
  std::vector<int> displs(recv_counts.size(), 0);
  std::partial_sum(recv_counts.begin(), recv_counts.end() - 1, displs.begin() + 1);
  out.resize(static_cast<std::size_t>(displs.back() + recv_counts.back()));
  std::vector<MPI_Request> requests;
  constexpr int kTag = 7301;
  for (int r = 0; r < size_; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    if (recv_counts[ru] == 0) continue;
    requests.emplace_back();
    MPI_Irecv(out.data() + displs[ru], recv_counts[ru], MPI_BYTE, r, kTag, comm_, &requests.back());
  }
  for (int r = 0; r < size_; ++r) {
    const auto ru = static_cast<std::size_t>(r);
    if (send[ru].empty()) continue;
    requests.emplace_back();
    MPI_Isend(send[ru].data(), static_cast<int>(send[ru].size()), MPI_BYTE, r, kTag, comm_,
              &requests.back());
  }
  MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE);
}

bool Communicator::any(bool v) const {
  int x = v ? 1 : 0;
  int r = 0;
  MPI_Allreduce(&x, &r, 1, MPI_INT, MPI_LOR, comm_);
  return r != 0;
}

void Communicator::barrier() const {
  MPI_Barrier(comm_);
}

int Communicator::ranks_on_this_node() const {
  MPI_Comm node;
  MPI_Comm_split_type(comm_, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node);
  int n = 1;
  MPI_Comm_size(node, &n);
  MPI_Comm_free(&node);
  return n;
}

MPI_Comm SplitCommunicator::split(const Communicator& parent, int colour) {
  MPI_Comm part = MPI_COMM_NULL;
  MPI_Comm_split(parent.raw(), colour, parent.rank(), &part);
  return part;
}

SplitCommunicator::SplitCommunicator(const Communicator& parent, int colour)
    : raw_(split(parent, colour)), comm_(raw_) {}

SplitCommunicator::~SplitCommunicator() {
  MPI_Comm_free(&raw_);
}

}  // namespace ringdem

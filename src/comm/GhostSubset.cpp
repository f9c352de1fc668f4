#include "comm/GhostSubset.hpp"

#include <cstring>
#include <stdexcept>

namespace ringdem {

void GhostSubset::select(const Communicator& comm, const ParticleStore& p,
                         const std::vector<std::vector<std::uint32_t>>& layer_send,
                         const std::vector<int>& layer_recv_count,
                         const std::vector<std::uint8_t>& selected, bool reads_any) {
  const auto n_ranks = static_cast<std::size_t>(comm.size());
  send_.assign(n_ranks, {});
  recv_.assign(n_ranks, {});
  current_ = true;
  n_local_ = p.n_local();
  n_ghost_ = p.n_ghost();
  if (n_ranks == 1) return;
  const std::vector<std::uint8_t> reads =
      comm.allgather(std::vector<std::uint8_t>{static_cast<std::uint8_t>(reads_any ? 1 : 0)});
  // A byte per ghost sent: each receiver learns which of the ghosts it holds are selected
  // (their sizes are the layer's, known at both ends).
  std::vector<std::vector<char>> flags(n_ranks);
  for (std::size_t r = 0; r < n_ranks; ++r) {
    flags[r].reserve(layer_send[r].size());
    for (const std::uint32_t k : layer_send[r]) {
      const bool chosen = reads[r] != 0 && (k >= selected.size() || selected[k] != 0);
      flags[r].push_back(chosen ? 1 : 0);
      if (chosen) send_[r].push_back(k);
    }
  }
  std::vector<char> received;
  comm.exchange_bytes(flags, layer_recv_count, received);
  std::size_t ghost = p.n_local(), at = 0;
  for (std::size_t r = 0; r < n_ranks; ++r)
    for (int i = 0; i < layer_recv_count[r]; ++i, ++ghost, ++at)
      if (received[at] != 0) recv_[r].push_back(static_cast<std::uint32_t>(ghost));
}

void GhostSubset::update(const Communicator& comm, ParticleStore& p) {
  if (!current_) throw std::logic_error("GhostSubset::update(): no ghosts selected for this layer");
  if (p.n_local() != n_local_ || p.n_ghost() != n_ghost_)
    throw std::logic_error("GhostSubset::update(): the particles changed since select()");
  const auto n_ranks = static_cast<std::size_t>(comm.size());
  if (n_ranks == 1) return;
  const unsigned flags = field_flag::kGhostStep;
  std::size_t size = 0;
  p.for_each_field([&](const FieldInfo& f, auto& v) {
    if (f.flags & flags) size += sizeof(v[0]);
  });
  // Column by column, as DomainDecomposition::update_ghosts() sends the whole layer.
  send_buffers_.resize(n_ranks);
  recv_bytes_.resize(n_ranks);
  for (std::size_t r = 0; r < n_ranks; ++r) {
    std::vector<char>& buffer = send_buffers_[r];
    buffer.resize(send_[r].size() * size);
    char* out = buffer.data();
    p.for_each_field([&](const FieldInfo& f, auto& v) {
      if (!(f.flags & flags)) return;
      constexpr std::size_t kBytes = sizeof(v[0]);
      for (const std::uint32_t k : send_[r]) {
        std::memcpy(out, static_cast<const void*>(&v[k]), kBytes);
        out += kBytes;
      }
    });
    recv_bytes_[r] = static_cast<int>(recv_[r].size() * size);
  }
  comm.exchange_bytes(send_buffers_, recv_bytes_, recv_buffer_);
  const char* data = recv_buffer_.data();
  for (std::size_t r = 0; r < n_ranks; ++r)
    p.for_each_field([&](const FieldInfo& f, auto& v) {
      if (!(f.flags & flags)) return;
      constexpr std::size_t kBytes = sizeof(v[0]);
      for (const std::uint32_t g : recv_[r]) {
        std::memcpy(static_cast<void*>(&v[g]), data, kBytes);
        data += kBytes;
      }
    });
}

std::size_t GhostSubset::n_sent() const {
  std::size_t n = 0;
  for (const auto& s : send_)
    n += s.size();
  return n;
}

std::size_t GhostSubset::n_received() const {
  std::size_t n = 0;
  for (const auto& r : recv_)
    n += r.size();
  return n;
}

}  // namespace ringdem

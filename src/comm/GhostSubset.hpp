#pragma once

#include <cstdint>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Some of the ghost layer, refreshed on its own: multi-rate stepping's sub-steps move only
/// some particles (engine/SubstepParticles), and only their ghosts need the per-step fields
/// between two refreshes of the whole layer. Each owner says which of the ghosts it sends are
/// selected, so both ends of every message know its size; a rank pair with none selected
/// either way exchanges no message at all. Part of DomainDecomposition, which holds the layer.
class GhostSubset {
 public:
  /// From the layer's send lists (per rank, owned indices in the order sent) and receive counts
  /// (per rank; the ghosts from a rank lie together after the owned particles, ranks in order,
  /// each in the order sent): selects the ghosts of the owned particles k with
  /// `selected[k] != 0` (an index beyond `selected` counts as selected), for the ranks that
  /// say `reads_any`. A rank that reads none of its ghosts between two refreshes of the whole
  /// layer (multi-rate stepping: one without movers) is sent none: a net's beads held as far
  /// ghosts by the rank of the grains alone had gone to it at every sub-step. Collective.
  void select(const Communicator& comm, const ParticleStore& p,
              const std::vector<std::vector<std::uint32_t>>& layer_send,
              const std::vector<int>& layer_recv_count, const std::vector<std::uint8_t>& selected,
              bool reads_any);
  /// The layer changed (a new ghost layer): nothing is selected until the next select().
  void clear() { current_ = false; }
  /// Refreshes the per-step ghost fields (field_flag::kGhostStep) of the selected ghosts from
  /// their owners; the other ghosts keep theirs. Collective; throws std::logic_error when
  /// nothing was selected since the layer last changed.
  void update(const Communicator& comm, ParticleStore& p);
  /// Selected ghosts this rank sends and receives, over all ranks.
  std::size_t n_sent() const;
  std::size_t n_received() const;

 private:
  bool current_ = false;
  std::size_t n_local_ = 0, n_ghost_ = 0;         ///< the store's at select(): its ghosts' indices
  std::vector<std::vector<std::uint32_t>> send_;  ///< per rank: owned indices to send
  std::vector<std::vector<std::uint32_t>> recv_;  ///< per rank: ghost indices to fill, in order
  std::vector<std::vector<char>> send_buffers_;   ///< scratch of update()
  std::vector<int> recv_bytes_;
  std::vector<char> recv_buffer_;
};

}  // namespace ringdem

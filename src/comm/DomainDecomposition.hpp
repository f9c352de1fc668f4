#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/BondStore.hpp"
#include "domain/ContactHistory.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Spatial domain decomposition (DESIGN §4). Space is cut into cubic blocks at least one
/// interaction range wide (contact reach + skin, longest bond); only occupied blocks exist.
/// METIS k-way partitions the block graph (vertex weight: particles and bonds in the block;
/// edge weight: the particles that can interact across the shared face), a particle belongs
/// to the rank owning its block, and every rank receives as ghosts the particles of all blocks
/// adjacent to its own. Bonds live on every rank that owns one of their ends (owner computes),
/// contact history travels with the particles. All MPI traffic of the particle data is here.
class DomainDecomposition {
 public:
  DomainDecomposition(const Communicator& comm, double block_size, double imbalance_threshold);

  /// First distribution: every rank holds the whole model; each keeps its own particles,
  /// the bonds of its particles, and receives its ghosts.
  void distribute_initial(ParticleStore& p, BondStore& bonds);

  /// Migration at a neighbour-list rebuild: owned particles move to the owner of their
  /// block (repartitioning first when the imbalance exceeds the threshold), bonds to every
  /// rank owning an end, history entries to the owners of their particles; then the ghost
  /// layer is rebuilt. `history` holds this rank's entries on entry, the new ones on exit.
  void redistribute(ParticleStore& p, BondStore& bonds, ContactHistory& history);

  /// Refreshes the per-step ghost fields (field_flag::kGhostStep) from their owners.
  void update_ghosts(ParticleStore& p);

  double block_size() const { return block_size_; }
  std::int64_t repartitions() const { return repartitions_; }

  /// Per-rank numbers for the pre-flight report (gathered on every rank).
  struct RankReport {
    std::int64_t particles = 0, ghosts = 0, bonds = 0, cut_bonds = 0, blocks = 0;
  };
  std::vector<RankReport> report(const ParticleStore& p, const BondStore& bonds) const;
  /// max(local particles) / mean - 1 over the ranks.
  double imbalance(const ParticleStore& p) const;

  /// Block key of a position (exposed for tests).
  std::uint64_t block_of(const Vec3& x) const;

 private:
  struct BlockLoad {
    std::uint64_t key;
    std::int64_t particles;
    std::int64_t bonds;
    int rank;  ///< a rank with particles in the block (the smallest, after merging)
  };
  /// Occupied blocks of all ranks, merged and sorted by key (identical on every rank).
  std::vector<BlockLoad> global_blocks(const ParticleStore& p, const BondStore& bonds,
                                       bool all_ranks_hold_everything) const;
  void partition(const std::vector<BlockLoad>& blocks);
  void assign_new_blocks(const std::vector<BlockLoad>& blocks);
  int owner_of(const Vec3& x) const;
  void build_ghosts(ParticleStore& p);

  const Communicator& comm_;
  double block_size_;
  double imbalance_threshold_;
  std::unordered_map<std::uint64_t, int> owner_;
  std::vector<std::vector<std::uint32_t>> ghost_send_;  ///< per rank: local indices to send
  std::vector<int> ghost_recv_count_;                   ///< per rank: ghosts received
  std::vector<std::vector<char>> ghost_send_buffers_;   ///< per-step scratch of update_ghosts
  std::vector<int> ghost_recv_bytes_;
  std::vector<char> ghost_recv_buffer_;
  std::int64_t repartitions_ = 0;
};

}  // namespace ringdem

#pragma once

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/BondStore.hpp"
#include "domain/PairStore.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Spatial domain decomposition (DESIGN §4). Space is cut into cubic blocks at least one
/// interaction range wide (contact reach + skin, longest bond); only occupied blocks exist.
/// METIS k-way partitions the block graph (vertex weight: particles and bonds in the block;
/// edge weight: the particles that can interact across the shared face), a particle belongs
/// to the rank owning its block, and every rank receives as ghosts the particles of all blocks
/// adjacent to its own. Bonds live on every rank that owns one of their ends (owner computes),
/// the contact terms' spring stores travel with the particles. All MPI traffic of the particle
/// data is here; it reaches every store through its field registry.
class DomainDecomposition {
 public:
  DomainDecomposition(const Communicator& comm, double block_size, double imbalance_threshold);

  /// First distribution, from any spread of the particles over the ranks (each held by one
  /// rank, none a ghost) and of the bonds and springs (each held by at least one rank, not
  /// necessarily with its particles): partitions the blocks, then sends every particle to
  /// the owner of its block, every bond and spring row to the owners of its particles
  /// (found through a gid directory spread over the ranks), and builds the ghost layer.
  /// No rank ever holds more than its own items and what it receives.
  void distribute_initial(ParticleStore& p, const std::vector<PairStore>& stores);

  /// Migration at a neighbour-list rebuild: owned particles move to the owner of their
  /// block (repartitioning first when the imbalance exceeds the threshold), bonds to every
  /// rank owning an end, spring rows to the owners of their particles; then the ghost layer is
  /// rebuilt. Each pair store holds this rank's rows on entry, the new ones on exit.
  void redistribute(ParticleStore& p, const std::vector<PairStore>& stores);

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
    std::int64_t rows;  ///< rows of the weighing pair stores (bonds) counted in the block
    int rank;           ///< a rank with particles in the block (the smallest, after merging)
  };
  /// Occupied blocks of all ranks, merged and sorted by key (identical on every rank).
  std::vector<BlockLoad> global_blocks(const ParticleStore& p,
                                       const std::vector<PairStore>& stores) const;
  void partition(const std::vector<BlockLoad>& blocks);
  void assign_new_blocks(const std::vector<BlockLoad>& blocks);
  int owner_of(const Vec3& x) const;
  void build_ghosts(ParticleStore& p);
  /// The owner of each of `gids`, given the owner of each owned particle of p (owner[k]), from
  /// the rank that holds it. Throws if a gid exists on no rank.
  std::vector<int> owners_of_gids(const ParticleStore& p, const std::vector<int>& owner,
                                  const std::vector<std::int64_t>& gids) const;
  /// Where each held item goes: owned particle k to rank particle[k], row h of pair store s
  /// to the (up to two, -1 for none) ranks in rows[s][h].
  struct Destinations {
    std::vector<int> particle;
    std::vector<std::vector<std::array<int, 2>>> rows;
  };
  /// Moves the items to their destinations, lets each pair store settle its arrivals, keeps
  /// owned particles in gid order, and rebuilds the ghost layer.
  void migrate(ParticleStore& p, const std::vector<PairStore>& stores, const Destinations& to);

  const Communicator& comm_;
  double block_size_;
  double imbalance_threshold_;
  std::unordered_map<std::uint64_t, int> owner_;  ///< block -> rank; empty on one rank
  std::int64_t blocks_held_ = 0;  ///< occupied blocks at the last partition or migration
  std::vector<std::vector<std::uint32_t>> ghost_send_;  ///< per rank: local indices to send
  std::vector<int> ghost_recv_count_;                   ///< per rank: ghosts received
  std::vector<std::vector<char>> ghost_send_buffers_;   ///< per-step scratch of update_ghosts
  std::vector<int> ghost_recv_bytes_;
  std::vector<char> ghost_recv_buffer_;
  std::int64_t repartitions_ = 0;
};

}  // namespace ringdem

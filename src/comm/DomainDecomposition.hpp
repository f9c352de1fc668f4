#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "comm/CellGraph.hpp"
#include "comm/Communicator.hpp"
#include "comm/FarGhosts.hpp"
#include "comm/GhostSubset.hpp"
#include "domain/BondStore.hpp"
#include "domain/PairStore.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Spatial domain decomposition (DESIGN §4). Space is cut into cubic blocks at least one
/// interaction range wide (contact reach + skin, longest bond), and blocks are grouped into
/// cubic partition cells of k x k x k blocks; only occupied cells exist. METIS k-way
/// partitions the cell graph (vertex weight: particles and bonds in the cell; edge weight: the
/// particles that can interact across the shared face), a particle belongs to the rank owning
/// its cell, and every rank receives as ghosts the particles of every block adjacent to a block
/// of one of its cells: the ghost layer stays one block thick whatever k is.
///
/// Every rank holds the owner of every occupied cell. With blocks one reach wide (about one
/// grain each) a map of blocks would grow with the whole model on every rank; k is chosen at
/// each partition so that there are about max(4096, 256 x ranks) cells, and the map then
/// stays small at any model size (`cell_blocks` fixes k instead, for tests). Bonds live on every
/// rank that owns one of their ends (owner computes), the contact terms' spring stores travel with
/// the particles. All MPI traffic of the particle data is here; it reaches every store through its
/// field registry.
class DomainDecomposition {
 public:
  /// `cell_blocks`: blocks per partition-cell edge; 0 chooses it from the particle count.
  DomainDecomposition(const Communicator& comm, double block_size, double imbalance_threshold,
                      int cell_blocks = 0);

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

  /// Particles, and then pair-store rows, migrate in rounds of at most max(bytes, an eighth of
  /// the store) each, so that a migration in which most items leave (the first distribution,
  /// a restart's) never holds the store and two copies of what moves at once. Default 8 MiB; tests
  /// set it small to get many rounds.
  void set_migration_round_bytes(std::size_t bytes) { round_min_bytes_ = bytes; }
  /// Rounds the last migration took (the same on every rank): its particles', its rows'.
  std::int64_t last_migration_rounds() const { return last_rounds_; }
  std::int64_t last_row_migration_rounds() const { return last_row_rounds_; }

  /// Particles that a term couples beyond the blocks' width (FarGhosts): from the next ghost
  /// layer on, each rank also holds those within the rule's reach of its own. Every rank adds
  /// the same rules.
  void add_far_ghosts(FarGhostRule rule) { far_.emplace_back(std::move(rule), block_size_); }

  /// Each row of a weighing store (PairStore's kBlockWeight: bonds) weighs `scale` times its
  /// store's weight in the partition (default 1): multi-rate stepping evaluates the bonds at
  /// every one of a grain step's `scale` sub-steps, the grains' contacts once.
  void set_row_weight_scale(int scale) { row_weight_scale_ = scale; }

  /// Refreshes the ghosts' fields that have one of `fields` (field_flag; by default the
  /// per-step ones, kGhostStep) from their owners. Collective.
  void update_ghosts(ParticleStore& p, unsigned fields = field_flag::kGhostStep);
  /// Selects the ghosts of the owned particles k with `selected[k] != 0` for
  /// update_ghost_subset(), until the ghost layer next changes, for the ranks that say
  /// `reads_any` (GhostSubset). Collective.
  void select_ghost_subset(const ParticleStore& p, const std::vector<std::uint8_t>& selected,
                           bool reads_any = true) {
    ghost_subset_.select(comm_, p, ghost_send_, ghost_recv_count_, selected, reads_any);
  }
  /// update_ghosts() of the selected ghosts alone. Collective.
  void update_ghost_subset(ParticleStore& p) { ghost_subset_.update(comm_, p); }
  const GhostSubset& ghost_subset() const { return ghost_subset_; }

  double block_size() const { return block_size_; }
  std::int64_t repartitions() const { return repartitions_; }

  /// Per-rank numbers for the pre-flight report (gathered on every rank).
  struct RankReport {
    std::int64_t particles = 0, ghosts = 0, bonds = 0, cut_bonds = 0, cells = 0;
  };
  std::vector<RankReport> report(const ParticleStore& p, const BondStore& bonds) const;
  /// max(local particles) / mean - 1 over the ranks.
  double imbalance(const ParticleStore& p) const;
  /// max / mean - 1 of the ranks' partition weights: particles and weighted rows (bonds, and
  /// with sub-steps their scale) per cell, as the partition and its repartition test weigh
  /// them. Collective.
  double weighted_imbalance(const ParticleStore& p, const std::vector<PairStore>& stores) const {
    return cell_imbalance(global_cells(p, stores));
  }

  /// Block key of a position (exposed for tests).
  std::uint64_t block_of(const Vec3& x) const;
  /// Blocks per edge of a partition cell (chosen at the last partition).
  int cell_blocks() const { return cell_blocks_; }
  /// Occupied partition cells at the last partition or migration (over all ranks); on one
  /// rank, at the last partition (a migration there assigns nothing and does not count them).
  std::int64_t cells() const { return cells_held_; }

 private:
  /// max / mean - 1 of the ranks' summed cell weights, each cell counted for its owner (the
  /// repartition test at a rebuild, after the new cells are assigned).
  double cell_imbalance(const std::vector<CellLoad>& cells) const;
  /// Occupied cells of all ranks, merged and sorted by key (identical on every rank).
  std::vector<CellLoad> global_cells(const ParticleStore& p,
                                     const std::vector<PairStore>& stores) const;
  /// Chooses k from the global particle count (or keeps the fixed one), then partitions.
  void partition(const ParticleStore& p, const std::vector<PairStore>& stores);
  void assign_new_cells(const std::vector<CellLoad>& cells);
  std::uint64_t cell_of_block(std::uint64_t block) const;
  std::uint64_t cell_of(const Vec3& x) const { return cell_of_block(block_of(x)); }
  int owner_of(const Vec3& x) const;
  void build_ghosts(ParticleStore& p);
  /// The owner of each of `gids`, given the owner of each owned particle of p (owner[k]), from
  /// the rank that holds it. Throws if a gid exists on no rank.
  std::vector<int> owners_of_gids(const ParticleStore& p, const std::vector<int>& owner,
                                  const std::vector<std::int64_t>& gids) const;
  /// Where each held item goes: owned particle k to rank particle[k], row h of pair store s
  /// to the (up to two, -1 for none) ranks row(s, h), asked once per row (a column of them
  /// was 8 bytes a contact at the peak of a rebuild of 10^6 grains in contact).
  struct Destinations {
    std::vector<int> particle;
    std::function<std::array<int, 2>(std::size_t store, std::size_t row)> row;
  };
  /// Moves the items to their destinations, lets each pair store settle its arrivals, keeps
  /// owned particles in the order of their sort keys (ParticleStore::sorts_before), and rebuilds
  /// the ghost layer.
  void migrate(ParticleStore& p, const std::vector<PairStore>& stores, const Destinations& to);
  /// The particle part of migrate(): owned particle k goes to rank owner[k]; the ghosts go.
  void migrate_particles(ParticleStore& p, const std::vector<int>& owner);
  /// The rows part of migrate(), in rounds: each store keeps its rows with an end here, then
  /// holds every arrival after them. Returns each store's first arrival.
  std::vector<std::size_t> migrate_rows(const std::vector<PairStore>& stores,
                                        const Destinations& to);

  const Communicator& comm_;
  std::size_t round_min_bytes_ = std::size_t{8} << 20;
  std::int64_t last_rounds_ = 0;
  std::int64_t last_row_rounds_ = 0;
  double block_size_;
  double imbalance_threshold_;
  int row_weight_scale_ = 1;                      ///< set_row_weight_scale()
  int fixed_cell_blocks_ = 0;                     ///< 0: k is chosen at each partition
  int cell_blocks_ = 1;                           ///< k: blocks per cell edge
  std::unordered_map<std::uint64_t, int> owner_;  ///< cell -> rank; empty on one rank
  /// Appends to `ranks` the ranks other than this one that need a particle of `block` as a
  /// ghost: the owners of the cells of the 27 blocks around it, sorted, each once.
  void collect_halo_ranks(std::uint64_t block, std::vector<int>& ranks) const;
  /// With cells of one block, a particle's block has 27 distinct neighbour cells to look up, so
  /// the result is cached per block (offset and count into halo_rank_pool_) while owner_ stays
  /// as it is. Such partitions hold few blocks (few particles a rank, docs/parallel.md), so the
  /// cache stays small; with larger cells a block has at most 8 cells to look up, uncached.
  std::unordered_map<std::uint64_t, std::pair<std::uint32_t, std::uint32_t>> halo_ranks_;
  std::vector<int> halo_rank_pool_;
  std::pair<const int*, const int*> cached_halo_ranks(std::uint64_t block);
  void forget_halo_ranks() {
    halo_ranks_.clear();
    halo_rank_pool_.clear();
  }
  std::vector<FarGhosts> far_;
  std::int64_t cells_held_ = 0;  ///< occupied cells at the last partition or migration
  std::vector<std::vector<std::uint32_t>> ghost_send_;  ///< per rank: local indices to send
  std::vector<int> ghost_recv_count_;                   ///< per rank: ghosts received
  std::vector<std::vector<char>> ghost_send_buffers_;   ///< per-step scratch of update_ghosts
  std::vector<int> ghost_recv_bytes_;
  std::vector<char> ghost_recv_buffer_;
  GhostSubset ghost_subset_;  ///< select_ghost_subset()
  std::int64_t repartitions_ = 0;
};

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <functional>
#include <unordered_map>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Particles that one force term couples farther apart than the decomposition's blocks are
/// wide, where only a few particles reach that far: a secondary mesh couples each bead of a
/// ring with every other bead of it and with every grain on the ring's disc, half a ring's
/// perimeter apart (docs/physics.md "Secondary mesh"), while the grains' contacts reach one
/// grain diameter. Blocks as wide as the mesh would make every grain's ghost layer that thick.
struct FarGhostRule {
  double reach = 0.0;  ///< largest centre distance coupled, the skin included (m)
  /// The few particles that couple far (a meshed ring's beads).
  std::function<bool(const ParticleStore&, std::size_t)> anchor;
  /// The particles that couple with anchors (the grains a mesh can hold). Anchors couple with
  /// each other whether or not they are partners too.
  std::function<bool(const ParticleStore&, std::size_t)> partner;
};

/// Where a particle goes as a ghost beyond the one-block layer, so that every rank that owns
/// an anchor or a partner holds every anchor and partner within the rule's reach of it:
/// - an anchor goes to every rank that owns an anchor or a partner in one of the 27 zones
///   around its own (zones of D blocks a side, D = ceil(reach / block size): two particles
///   within the reach lie in the same or neighbouring zones);
/// - a partner to every rank whose anchors in one of those zones span a box of blocks within D
///   blocks of its own along each axis (a box per rank and zone: a partner then tests a few
///   boxes, not every anchor's block, and a rank whose box is near but whose anchors are not
///   only gets a few ghosts too many).
/// Both lists are gathered from every rank at each ghost-layer build (index()): the boxes, and
/// the zones next to an anchor's in which each rank owns anchors or partners (a zone is about
/// the reach wide: a net's few). No rank holds more than these small lists.
class FarGhosts {
 public:
  FarGhosts(FarGhostRule rule, double block_size);

  /// Collective: gathers every rank's anchor blocks and occupied zones. `block_of` gives a
  /// position's block key (cell_keys::pack of its block indices).
  void index(const Communicator& comm, const ParticleStore& p,
             const std::function<std::uint64_t(const Vec3&)>& block_of);
  /// Appends the ranks other than this one that owned particle k, in block `block`, must reach
  /// beyond the one-block layer (unsorted, possibly repeated).
  void append_targets(const ParticleStore& p, std::size_t k, std::uint64_t block,
                      std::vector<int>& ranks) const;
  /// Blocks per zone edge (D).
  std::int64_t zone_blocks() const { return zone_blocks_; }

 private:
  /// The blocks (i, j, k) from `low` to `high` hold every anchor that `rank` owns in `zone`.
  struct AnchorBox {
    std::uint64_t zone;
    std::int64_t low[3], high[3];
    std::int32_t rank;
  };
  std::uint64_t zone_of_block(std::uint64_t block) const;

  FarGhostRule rule_;
  std::int64_t zone_blocks_;
  int rank_ = 0;
  /// Zone -> the other ranks' anchor boxes in it and in the 26 zones around it.
  std::unordered_map<std::uint64_t, std::vector<AnchorBox>> anchors_near_;
  /// Zone -> the ranks that own an anchor or a partner in it or in the 26 zones around it.
  std::unordered_map<std::uint64_t, std::vector<int>> owners_near_;
};

}  // namespace ringdem

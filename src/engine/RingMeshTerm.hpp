#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "engine/ForceTerm.hpp"
#include "engine/Model.hpp"
#include "physics/RingMesh.hpp"

namespace ringdem {

/// The secondary meshes of the nets (RingMesh, docs/physics.md "Secondary mesh"): contacts
/// between a meshed ring and a grain coarse enough to be held, each with a slot for the grain;
/// each ring in contact has one slot per bead, the sum of its contacts' loads on that bead in
/// the order of the grains' gids. A rank evaluates the contacts whose grain or any of whose
/// ring's beads it owns, from the ring's beads in gid order: its far ghosts (far_ghosts())
/// bring the whole ring and every grain that touches it to every rank that owns one of them,
/// so each rank sums the same loads in the same order.
class RingMeshTerm final : public ForceTerm {
 public:
  explicit RingMeshTerm(std::vector<RingMeshSpec> meshes) : meshes_(std::move(meshes)) {}

  std::string_view name() const override { return "ring_mesh"; }
  /// Nothing beyond the other terms' layer: the mesh's reach is far_ghosts()'.
  double ghost_width(const ParticleStore&) const override { return 0.0; }
  /// The beads of meshed rings (anchors) and the grains a mesh can hold (partners), as far
  /// apart as half a ring's perimeter (pi R, with 10 % for stretched bonds), which bounds a
  /// bead's distance from any other and from a point of the ring's disc, plus a grain's radius.
  /// As a ghost width it made every block that wide, and every grain's ghost layer that thick.
  std::optional<FarGhostRule> far_ghosts(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  void compute(ComputeContext& ctx) override;
  void mark_net_contacts(const ParticleStore& p,
                         std::vector<std::uint8_t>& touching) const override;

  /// The smallest stability limit of the case's meshes (RingMesh::time_step_limit), for the
  /// lightest grain a mesh can hold: a sphere of the opening's diameter of the least dense
  /// material. Infinite without meshes.
  static double time_step_limit(const Model& model);

 private:
  struct MeshRing {
    std::uint32_t mesh;        ///< index into meshes_
    std::uint32_t first_bead;  ///< into bead_: the ring's beads in gid order
    std::int64_t key;          ///< gid of its first bead: the gather key of the ring's slots
    std::uint32_t first_contact = 0, n_contacts = 0;  ///< its contacts, by grain gid
    std::uint32_t first_slot = 0;  ///< its beads' slots, one each (after its grains')
    bool loaded = false;           ///< a contact touched in the last compute()
  };
  std::vector<RingMeshSpec> meshes_;
  std::vector<MeshRing> rings_;       ///< meshed rings with every bead present here
  std::vector<std::uint32_t> bead_;   ///< particle indices, beads_per_ring per ring
  std::vector<std::uint32_t> grain_;  ///< contact c: the grain's particle index (ring by ring)
  std::vector<char> touching_;        ///< contact c touched in the last compute()
  SlotRange slots_;                   ///< each ring's contacts' grain slots, then its beads'
  // compute scratch: a ring's bead positions and velocities
  std::vector<Vec3> position_, velocity_;
};

}  // namespace ringdem

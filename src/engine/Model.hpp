#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/BrakeStore.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "domain/RopeStore.hpp"
#include "engine/InflowSpec.hpp"
#include "engine/OutflowSink.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"
#include "physics/MaterialTable.hpp"
#include "physics/RingMesh.hpp"

namespace ringdem {

/// A constant force on one particle, by gid (applied loads of tests and drivers). Loads are
/// few, so every rank holds the list and applies those on particles it owns: no per-particle
/// column that every grain would carry and every step would read.
struct PointLoad {
  std::int64_t gid = -1;
  Vec3 force;
};

/// A net's secondary mesh (`particles.nets[].mesh`, docs/physics.md "Secondary mesh"): the
/// rings with body ids first_body .. first_body + n_rings - 1, each of beads_per_ring particles
/// in gid order round the ring, hold the grains that RingMesh catches.
struct RingMeshSpec {
  std::int32_t first_body = 0;
  std::int32_t n_rings = 0;
  int beads_per_ring = 0;
  double centreline_radius = 0.0;  ///< of the rings as built (m)
  double ring_mass = 0.0;          ///< of one ring (kg): the stability limit's m_ring
  RingMesh::Params params;
};

/// Everything a simulation holds, built from a validated case.
struct Model {
  ParticleStore particles;
  BondStore bonds;
  std::vector<RigidBody> bodies;
  BrakeStore brakes;  ///< brake elements holding rigid bodies to the frame (braked shackles)
  RopeStore ropes;    ///< support ropes that rigid bodies (a net's shackles) slide on
  std::vector<OutflowBox> outflow;  ///< boxes that grains may not leave (`outflow[]`)
  std::vector<InflowSpec> inflow;   ///< inlets that add grains during the run (`inflow[]`)
  std::vector<PointLoad> point_loads;
  std::vector<RingMeshSpec> ring_meshes;  ///< nets with a secondary mesh
  MaterialTable materials;
  std::vector<std::string> bond_type_names;
  std::vector<BondTimoshenko::Params> bond_types;
  /// Plastic limits per bond type (bonds[].plastic), for a plastic bond model; empty otherwise.
  std::vector<BondTimoshenkoPlastic::Params> plastic_bond_types;
  std::string bond_model = "timoshenko";        ///< name in the bond model table
  std::string contact_model = "hertz_mindlin";  ///< name in the contact model table
  std::vector<std::string> group_names;
  /// Particles and bonds the case's sources create at start-up, over all ranks (the pre-flight
  /// report and start-up checks; a restart restores the checkpoint's own counts instead).
  std::int64_t initial_particles = 0;
  std::int64_t initial_bonds = 0;

  int group_id(const std::string& name) const;
};

}  // namespace ringdem

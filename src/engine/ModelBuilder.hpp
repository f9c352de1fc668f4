#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/RingNet.hpp"
#include "engine/BondTerm.hpp"
#include "engine/Model.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

/// The generator's parameters of a validated `particles.nets` entry (the loader checks a net
/// with the same ones).
RingNetParameters net_parameters(const RingNetConfig& net);

/// Builds rank `rank`'s share of a case's model: materials, bond types, groups and rigid
/// bodies in full (they are small), and an equal slice of every particle source's items
/// (engine/ParticleSource.hpp) with the bonds that touch them. Gids run over the sources in
/// case order (rings, nets, lattices, grains, spheres) and do not depend on the rank count; the
/// Simulation's first distribution moves every particle to the owner of its block.
/// build_model(config) is the whole model, for one rank. The store is reserved once, before
/// the first particle, for the slice (ParticleStore::reserve_share).
Model build_model(const CaseConfig& config, int rank = 0, int ranks = 1);
/// This rank's share for a simulation over `comm`.
Model build_model(const CaseConfig& config, const Communicator& comm);
/// Everything but the particles and bonds, for a restart, which reads those from the
/// checkpoint. initial_particles and initial_bonds still count what the sources create.
Model build_model_without_particles(const CaseConfig& config);

/// The Cundall coefficient the case gives particle group `group` (damping.groups, else
/// damping.global).
double group_damping(const CaseConfig& config, const std::string& group);
/// Whether the case's damping section gives some particle group a nonzero coefficient.
bool case_damps_particles(const CaseConfig& config);

/// Adds bond `id` between two particles of the model's bond law, strengths drawn by
/// (seed, gid pair).
void add_bond(Model& model, std::int64_t id, const BondEnd& a, const BondEnd& b, int bond_type,
              std::uint64_t seed);
/// The same between two particles of this rank's store (by index), with the next free id. A
/// model built without bonds starts keeping orientations here (ParticleStore::
/// tracks_orientation), its particles at the identity.
void add_bond(Model& model, std::size_t index_a, std::size_t index_b, int bond_type,
              std::uint64_t seed);

}  // namespace ringdem

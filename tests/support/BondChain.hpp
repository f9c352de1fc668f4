#pragma once

// The set-up shared by the bond terms' unit tests (test_bond_may_fail.cpp,
// test_plastic_bond_term.cpp): a straight chain of particles bonded end to end, and the
// rebuild and evaluation context a term runs in, without a Simulation around it.

#include <cstddef>
#include <cstdint>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "engine/EnergyLedger.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/ForceTerm.hpp"
#include "engine/GatherMap.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "physics/MaterialTable.hpp"

namespace ringdem::testing {

/// n + 1 steel particles (7800 kg/m^3) of `radius` on the x axis, `spacing` apart, gids 0..n.
inline ParticleStore straight_chain(std::size_t n, double spacing, double radius) {
  ParticleStore p;
  for (std::size_t k = 0; k <= n; ++k) {
    ParticleStore::NewParticle np;
    np.gid = static_cast<std::int64_t>(k);
    np.position = {spacing * static_cast<double>(k), 0.0, 0.0};
    np.radius = radius;
    np.density = 7800.0;
    p.add(np);
  }
  p.rebuild_index();
  return p;
}

/// Bond k between particles k and k + 1 of `p` in their current state, for k < n (bond type
/// 0, strength seed 1), appended to `bonds`.
inline void bond_chain(BondStore& bonds, const ParticleStore& p, std::size_t n,
                       const BondTimoshenko::Params& params) {
  for (std::size_t k = 0; k < n; ++k) {
    const BondEnd a{static_cast<std::int64_t>(k), p.position[k], p.orientation[k], p.radius[k]};
    const BondEnd b{static_cast<std::int64_t>(k + 1), p.position[k + 1], p.orientation[k + 1],
                    p.radius[k + 1]};
    TimoshenkoBondTerm::create(bonds, params, 0, static_cast<std::int64_t>(k), a, b, 1);
  }
}

/// What a term needs to rebuild and evaluate on one rank: slots, gather map, ledger (off
/// unless a test turns it on), no rigid bodies, steel.
struct TermBench {
  std::vector<ExcludedPair> excluded;
  SlotAllocator allocator;
  GatherMap gather;
  std::vector<RigidBody> bodies;
  ForceSlots slots;
  EnergyLedger ledger;
  MaterialTable materials{{Material{"steel", 7800.0, 200e9, 0.3, 0.5, 0.3, 0.0}}, {}};

  /// The term's rebuild over `p`; the slots are zeroed.
  void rebuild(ForceTerm& term, ParticleStore& p) {
    gather.begin(p.n_local());
    RebuildContext ctx{p, bodies, 0.001, excluded, allocator, gather, 0};
    term.rebuild(ctx);
    slots.assign(allocator.size());
  }
  /// One evaluation at time 0 with step `dt`.
  void compute(ForceTerm& term, ParticleStore& p, double dt) {
    ComputeContext ctx{
        p,      bodies, materials, slots,
        ledger, 0.0,    dt,        ParticleLoads{p.force.data(), p.torque.data(), p.n_local()}};
    term.compute(ctx);
  }
};

}  // namespace ringdem::testing

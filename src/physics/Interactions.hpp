#pragma once

#include <cstdint>
#include <vector>

#include "domain/BondStore.hpp"
#include "domain/ContactHistory.hpp"
#include "domain/NeighbourSearch.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "physics/MaterialTable.hpp"

namespace ringdem {

/// Every force between particles and between particles and rigid bodies: bonds, particle
/// contacts, particle–rigid-body contacts. Each interaction writes its contribution to its
/// own slots; gather() then sums, for every owned particle, the slots in partner-gid order,
/// so the sum is the same whatever the storage order or the rank count.
class Interactions {
 public:
  /// Neighbour lists, rigid-body candidates, bond ends and the gather map; the tangential
  /// springs in `history` are given to the pairs they belong to. Needs the particle index
  /// to be current.
  void rebuild(const ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies,
               double skin, const ContactHistory& history);
  /// The springs of all touching pairs, for the next rebuild (and for migration).
  ContactHistory export_history() const;

  /// Evaluates every bond for the current positions and orientations (rotation matrices
  /// must be up to date). Bonds that fail are marked broken with their time and the elastic
  /// energy they held (BondStore::break_energy: the mean of the energy at the end of the step
  /// and at its start, x - v dt with the mid-step velocities; dt = 0 takes the end only).
  void compute_bonds(const ParticleStore& p, BondStore& bonds, double time, double dt = 0.0);
  /// Recomputes the output state of every bond (axial force, largest bending moment,
  /// utilisation, elastic energy) for the current configuration; returns the summed energy.
  double update_bond_diagnostics(const ParticleStore& p, BondStore& bonds) const;
  /// Evaluates particle–particle and particle–rigid-body contacts; sets the rigid bodies'
  /// contact force and torque of this step.
  void compute_contacts(const ParticleStore& p, std::vector<RigidBody>& bodies,
                        const MaterialTable& materials, double dt);

  /// force = gravity * mass + external force + sum of the slots, torque = sum of the slots (owned
  /// particles). Also notes the power F_ext . v of the external forces on free particles at
  /// the mid-step velocities, for accumulate_ledger().
  void gather(ParticleStore& p, const Vec3& gravity);

  /// Energy ledger (docs/physics.md "Energy ledger"), after the second half kick of the
  /// particles and the rigid bodies, with the velocities of the end of the step: adds to each
  /// owned particle's dissipated_damping, dissipated_friction and boundary_work the work of
  /// the last force evaluation (its power at the synchronised velocities times dt; power_*
  /// keep that power for the trapezoid end correction), the change of its tangential spring
  /// energy, and the work of its external force over the step. `initial`: the loads of the
  /// initial state, entered with weight dt/2 and no work over a step.
  void accumulate_ledger(ParticleStore& p, const std::vector<RigidBody>& bodies, double dt,
                         bool initial = false);

  /// One particle's contact load on a rigid body in the last compute_contacts(), for the
  /// rank-independent reduction of the body loads (summed in (body, gid) order).
  struct BodyLoad {
    std::int64_t gid;
    std::int32_t body;
    Vec3 force;   ///< on the body
    Vec3 torque;  ///< on the body, about its reference point
  };
  const std::vector<BodyLoad>& body_loads() const { return body_loads_; }

  /// Set when a bond broke during the last compute(): its pair may now touch.
  bool bonds_broke() const { return bonds_broke_; }
  std::size_t n_contact_candidates() const { return pairs_.size(); }
  /// Elastic energy stored in the contacts of the last compute_contacts() (this rank's sum;
  /// ParticleStore::contact_energy holds each owned particle's share, for sums by gid).
  double contact_energy() const { return contact_energy_; }

 private:
  NeighbourSearch search_;
  PairExclusions exclusions_;
  PairCandidates pairs_;
  std::vector<Vec3> pair_spring_;
  std::vector<std::int64_t> pair_gid_a_, pair_gid_b_;  ///< gids of pairs_ (history keys)
  std::vector<std::uint32_t> wall_particle_, wall_body_;
  std::vector<std::int64_t> wall_gid_;
  std::vector<Vec3> wall_spring_;

  /// Per-interaction contributions, structure of arrays so the kernels store contiguously.
  /// Layout: bond a-ends [0, nb), bond b-ends [nb, 2nb), contact i-sides, contact j-sides,
  /// then particle–rigid-body contacts.
  struct Slots {
    std::vector<double> fx, fy, fz, tx, ty, tz;
    void assign(std::size_t n) {
      for (auto* v : {&fx, &fy, &fz, &tx, &ty, &tz})
        v->assign(n, 0.0);
    }
    std::size_t size() const { return fx.size(); }
    void set(std::size_t i, const Vec3& f, const Vec3& t) {
      fx[i] = f.x;
      fy[i] = f.y;
      fz[i] = f.z;
      tx[i] = t.x;
      ty[i] = t.y;
      tz[i] = t.z;
    }
  };
  Slots slots_;
  std::vector<std::uint8_t> bond_failed_;  ///< scratch: bonds that failed in this step

  /// Energy ledger: the parts of one contact slot's load that the ledger needs, written by
  /// compute_contacts() in the order accumulate_ledger() reads them (ledger_slot_ order).
  struct ContactWork {
    Vec3 damping;                    ///< viscous force on this particle (Eq. 7 + Eq. 9)
    Vec3 friction;                   ///< tangential spring force on this particle (Coulomb-capped)
    Vec3 arm;                        ///< from this particle's centre to the contact point
    Vec3 rolling;                    ///< rolling-friction torque on this particle
    double tangential_energy = 0.0;  ///< this particle's share of |F_t|^2 / 2 S_t
    double elastic_energy = 0.0;     ///< this particle's share of the contact's elastic energy
  };
  std::vector<ContactWork> work_;  ///< one per ledger_slot_ entry, then a scratch record
  /// Record in work_ of each contact slot (index = slot - first contact slot); the scratch
  /// record for the end of a pair that a ghost holds.
  std::vector<std::uint32_t> work_index_;
  /// Owned particles the ledger visits every step (those with contact candidates, and driven
  /// ones), with their contact slots in gather order.
  std::vector<std::uint32_t> ledger_particle_, ledger_offset_, ledger_slot_;
  bool ledger_list_changed_ = false;  ///< particles off the list get zero power once
  struct ExternalPower {
    std::uint32_t particle;
    double power;  ///< F_ext . v at the mid-step velocity
  };
  std::vector<ExternalPower> external_;
  /// Scratch of the bond loop: end positions and orientations of one chunk, by component.
  struct BondScratch {
    double xa[3][256], xb[3][256], qa[4][256], qb[4][256];
  };
  BondScratch bond_scratch_;
  std::vector<std::uint32_t> gather_offset_, gather_slot_;

  bool bonds_broke_ = false;
  double contact_energy_ = 0.0;
  std::vector<BodyLoad> body_loads_;
};

}  // namespace ringdem

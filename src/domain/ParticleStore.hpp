#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "core/Motion.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "domain/GidIndex.hpp"

namespace ringdem {

/// What the comm layer, output and checkpoints do with a particle field. Every loop over
/// fields (resize, permutation, migration, ghost exchange, HDF5, checkpoints) reads these.
namespace field_flag {
inline constexpr unsigned kMigrate = 1u << 0;     ///< travels with an owned particle to a new rank
inline constexpr unsigned kGhostOnce = 1u << 1;   ///< sent when a ghost is created
inline constexpr unsigned kGhostStep = 1u << 2;   ///< refreshed on ghosts every step
inline constexpr unsigned kOutput = 1u << 3;      ///< written to frame files
inline constexpr unsigned kCheckpoint = 1u << 4;  ///< part of the restart state
/// A checkpoint written without the field (an energy ledger switched off) restores zeros.
inline constexpr unsigned kZeroIfAbsent = 1u << 5;
/// Sent again to the ghosts when multi-rate stepping's rates change without a rebuild
/// (Simulation::change_rates()): a ghost created before the change holds the old value.
inline constexpr unsigned kGhostRates = 1u << 6;
}  // namespace field_flag

struct FieldInfo {
  std::string_view name;
  unsigned flags;
  bool has(unsigned f) const { return (flags & f) != 0; }
};

/// Moves the rows k of a store with keep[k] != 0 to the front, in order, field by field through
/// its registry, and returns how many there are; the caller resizes the store to that.
template <class Store>
std::size_t compact_rows(Store& s, const std::vector<char>& keep) {
  // Rows before the first dropped one stay where they are: a rebuild that moves nothing (the
  // usual case) copies nothing.
  std::size_t first_gap = 0;
  while (first_gap < keep.size() && keep[first_gap])
    ++first_gap;
  if (first_gap == keep.size()) return keep.size();
  std::vector<std::size_t> order;
  for (std::size_t k = first_gap; k < keep.size(); ++k)
    if (keep[k]) order.push_back(k);
  s.for_each_field([&](const FieldInfo&, auto& v) {
    for (std::size_t m = 0; m < order.size(); ++m)
      v[first_gap + m] = v[order[m]];
  });
  return first_gap + order.size();
}

/// Structure-of-arrays particle store: owned particles at [0, n_local), ghosts at
/// [n_local, n_local + n_ghost). for_each_field() is the single field registry.
class ParticleStore {
 public:
  // --- fields (declared here, registered in for_each_field) ---
  std::vector<std::int64_t> gid;
  std::vector<Vec3> position;
  std::vector<Vec3> velocity;
  std::vector<Vec3> omega;  ///< angular velocity, world frame
  /// Only while tracks_orientation(): bonds are all that read it; a model without bonds keeps
  /// this column empty.
  std::vector<Quat> orientation;
  std::vector<Vec3> force;
  std::vector<Vec3> torque;
  std::vector<double> radius;
  std::vector<double> mass;
  /// Cundall global damping coefficient of this particle; only while tracks_damping().
  std::vector<double> damping;
  std::vector<std::int32_t> material;
  std::vector<std::int32_t> body;   ///< ring / clump id, -1 for none
  std::vector<std::int32_t> group;  ///< particle group (case-file name table)
  std::vector<Motion> motion;
  /// The spatial bin the particle was given at the last re-sort (SpatialBins; 0 for a particle
  /// of a ring or clump, and until a particle's first re-sort). With the gid it is the key of
  /// the order in which the owned particles are stored and every particle's contacts are
  /// summed (sorts_before()): a property of the particle, so the sums are the same bits on any
  /// rank count (DESIGN §4), and, after a re-sort, an order of space.
  std::vector<std::uint32_t> sort_bin;
  // --- energy ledger (docs/physics.md "Energy ledger"); only while books_global_damping().
  // The contact terms' tallies and the energy the contacts hold are kept per rank in exact
  // sums (engine/EnergyLedger); what a particle carries is its global damping, which the
  // integrator books in its vector pass. Owned state (migrated and checkpointed, never sent to
  // ghosts), summed exactly over the ranks (comm/ExactSum) so the totals do not depend on the
  // rank count.
  /// Cundall global damping (the integrator books it per particle): dissipated_global holds
  /// dt/2 P^0 + sum_{n>=1} dt P^n of its power P, power_global the last P^n, so the tally up to
  /// the current step is dissipated_global - dt/2 power_global (global_damping_tally()).
  std::vector<double> dissipated_global;
  std::vector<double> power_global;
  /// Multi-rate stepping (simulation.substeps > 1, docs/physics.md "Two time scales"): the
  /// loads of the slow interactions (gravity, grain–grain and grain–body contacts) of the last
  /// grain step, which kick the particles at the grain step's ends; only while
  /// tracks_slow_loads().
  std::vector<Vec3> slow_force;
  std::vector<Vec3> slow_torque;
  /// Multi-rate stepping: 1 where a grain touched the net (a ring's bead, a held particle or a
  /// net's mesh) at the last check (Simulation::note_net_contacts()). Every interaction of such
  /// a grain is fast (is_fast_particle()): a grain pinched between a ring and the bed, its
  /// bed contact at the grains' step, had the ring's sub-steps pump energy into it (r-RESPA
  /// resonance; docs/physics.md "Two time scales"). Only while tracks_slow_loads().
  std::vector<std::uint8_t> net_contact;

  /// The trapezoidal tally of an accumulator and its last power (see dissipated_global).
  static double ledger_value(double accumulated, double last_power, double dt) {
    return accumulated - 0.5 * dt * last_power;
  }
  /// Particle k's Cundall coefficient (0 where the store keeps none).
  double damping_of(std::size_t k) const { return tracks_damping_ ? damping[k] : 0.0; }
  /// Particle k's global-damping tally up to the current step.
  double global_damping_tally(std::size_t k, double dt) const {
    return ledger_value(dissipated_global[k], power_global[k], dt);
  }
  /// Moment of inertia of a solid sphere, 2/5 m r^2 (isotropic), from its mass and radius: no
  /// column of its own (8 B a particle less in memory and in every ghost exchange).
  static double sphere_inertia(double m, double r) { return 0.4 * m * r * r; }
  double inertia(std::size_t k) const { return sphere_inertia(mass[k], radius[k]); }
  /// Kinetic energy (translation and rotation) and potential energy -m g.x of particle k.
  double kinetic_energy(std::size_t k) const {
    return 0.5 * mass[k] * norm2(velocity[k]) + 0.5 * inertia(k) * norm2(omega[k]);
  }
  double potential_energy(std::size_t k, const Vec3& gravity) const {
    return -mass[k] * dot(gravity, position[k]);
  }

  /// The field registry: calls f(FieldInfo, std::vector<T>&) for every field.
  template <class F>
  void for_each_field(F&& f) {
    using namespace field_flag;
    constexpr unsigned kState = kMigrate | kCheckpoint;
    f(FieldInfo{"gid", kState | kGhostOnce | kOutput}, gid);
    f(FieldInfo{"position", kState | kGhostStep | kOutput}, position);
    f(FieldInfo{"velocity", kState | kGhostStep | kOutput}, velocity);
    f(FieldInfo{"omega", kState | kGhostStep | kOutput}, omega);
    if (tracks_orientation_) f(FieldInfo{"orientation", kState | kGhostStep}, orientation);
    f(FieldInfo{"force", kState}, force);
    f(FieldInfo{"torque", kState}, torque);
    f(FieldInfo{"radius", kState | kGhostOnce | kOutput}, radius);
    f(FieldInfo{"mass", kState | kGhostOnce}, mass);
    if (tracks_damping_) f(FieldInfo{"damping", kState | kZeroIfAbsent}, damping);
    f(FieldInfo{"material", kState | kGhostOnce}, material);
    f(FieldInfo{"body", kState | kGhostOnce | kOutput}, body);
    f(FieldInfo{"group", kState | kGhostOnce | kOutput}, group);
    f(FieldInfo{"motion", kState | kGhostOnce}, motion);
    // Ghosts need it too: the neighbour search walks the pairs in key order. A checkpoint of
    // format 11 has none: every particle restarts at bin 0, the order it was in (gid order).
    f(FieldInfo{"sort_bin", kState | kGhostOnce | kZeroIfAbsent}, sort_bin);
    if (books_global_damping()) for_each_ledger_field(f);
    if (tracks_slow_loads_) {
      f(FieldInfo{"slow_force", kState}, slow_force);
      f(FieldInfo{"slow_torque", kState}, slow_torque);
      // Ghosts need it: a pair's rate is decided on every rank that holds it. A checkpoint
      // written before the column existed restarts with none (the next check sets them).
      f(FieldInfo{"net_contact", kState | kGhostOnce | kGhostRates | kZeroIfAbsent}, net_contact);
    }
  }

  /// Whether the store keeps the slow loads of multi-rate stepping (slow_force). Off by
  /// default: single-rate runs carry no such columns.
  bool tracks_slow_loads() const { return tracks_slow_loads_; }
  /// Turns the columns on (zeros) or off (emptied).
  void set_tracks_slow_loads(bool on);

  /// Whether the energy ledger is kept (simulation.energy_ledger). Off, the store keeps none of
  /// its columns: in memory, migration and checkpoints a particle carries only what moves it.
  /// On by default.
  bool tracks_ledger() const { return tracks_ledger_; }
  /// Turns the ledger on (every particle's tallies at zero) or off (its columns emptied).
  void set_tracks_ledger(bool on);
  /// Whether the store keeps a Cundall damping coefficient per particle. Off where nothing in
  /// the model is damped (ModelBuilder: no damping in the case, as in a debris flow's grains):
  /// the column and the ledger's two global-damping columns are empty (24 B a particle), the
  /// integrator takes its undamped path, and migration and checkpoints carry none of them.
  /// Simulation::set_group_damping() turns it on where a coefficient is set later (on every
  /// rank alike), and a checkpoint with the column does on restore. On by default.
  bool tracks_damping() const { return tracks_damping_; }
  /// Turns the coefficients on (every particle at 0, undamped) or off (emptied).
  void set_tracks_damping(bool on);
  /// Whether the particles carry global-damping tallies: the ledger is kept and some
  /// particle can be damped.
  bool books_global_damping() const { return tracks_ledger_ && tracks_damping_; }

 private:
  /// The ledger's part of the registry (for_each_field() while books_global_damping()).
  template <class F>
  void for_each_ledger_field(F&& f) {
    using namespace field_flag;
    constexpr unsigned kLedger = kMigrate | kCheckpoint | kZeroIfAbsent;
    f(FieldInfo{"dissipated_global", kLedger}, dissipated_global);
    f(FieldInfo{"power_global", kLedger}, power_global);
  }

 public:
  /// Whether the store keeps the particles' orientations. Only bonds read them (the beam ends'
  /// frames): a model without bonds turns the column off, which takes 32 B a particle out of
  /// memory, of every migration and ghost refresh and of checkpoints. On by default.
  bool tracks_orientation() const { return tracks_orientation_; }
  /// Turns the column on (every particle at the identity) or off (emptied).
  void set_tracks_orientation(bool on);

  std::size_t n_local() const { return n_local_; }
  std::size_t n_ghost() const { return n_ghost_; }
  std::size_t n_total() const { return n_local_ + n_ghost_; }

  /// Everything needed to create one particle; derived quantities are filled in by add().
  struct NewParticle {
    std::int64_t gid = -1;
    Vec3 position;
    Vec3 velocity;
    Vec3 omega;
    Quat orientation;
    double radius = 0.0;
    double density = 0.0;
    double damping = 0.0;
    std::int32_t material = 0;
    std::int32_t body = -1;
    std::int32_t group = 0;
    Motion motion = Motion::kFree;
  };

  /// Appends an owned particle (only while there are no ghosts). Returns its index.
  std::size_t add(const NewParticle& p);

  /// Makes room for n particles in every column, so that adding up to n allocates nothing.
  void reserve(std::size_t n);
  /// Makes room, before the first particle, for a rank's share of n particles of a model
  /// spread over `ranks`: n on one rank, kDistributedHeadroom times n on several, for what the
  /// first distribution leaves there (the partition's share, give or take its imbalance, and
  /// the ghost layer). A column that outgrows its reservation is copied into a larger one, and
  /// the heap keeps the outgrown copy (docs/performance.md, fifty-sixth round); room not used
  /// is address space only, its pages never touched.
  void reserve_share(std::size_t n, int ranks);
  static constexpr double kDistributedHeadroom = 1.25;
  /// Resizes the owned range; drops all ghosts.
  void resize_local(std::size_t n);
  /// Takes out the owned particles k with keep_owned[k] == 0 (one entry per owned particle);
  /// the ghosts stay, after the owned ones, so a migration can still route what names them.
  /// Returns how many were taken out.
  std::size_t remove_owned(const std::vector<char>& keep_owned);
  /// Sets the ghost count, resizing every field to n_local + n_ghost.
  void resize_ghosts(std::size_t n);
  /// Reorders the owned particles: new index i takes old index order[i].
  void permute_local(const std::vector<std::size_t>& order);

  /// Rebuilds the gid -> index map over owned and ghost particles.
  void rebuild_index();
  /// Whether particle a comes before particle b in the sort key (sort_bin, gid): the order of
  /// the owned particles in the store and of the contact pairs' sums.
  bool sorts_before(std::size_t a, std::size_t b) const {
    return sort_bin[a] != sort_bin[b] ? sort_bin[a] < sort_bin[b] : gid[a] < gid[b];
  }

  /// Index of gid, or -1 when this rank holds no such particle.
  std::int64_t index_of(std::int64_t gid_value) const {
    return index_.find(gid_value, gid.data(), gid.size());
  }

 private:
  void resize_all(std::size_t n);
  /// Sizes the ledger's columns to the particles (zeros) while books_global_damping(), frees
  /// them otherwise.
  void resize_ledger_columns();

  bool tracks_orientation_ = true;
  bool tracks_ledger_ = true;
  bool tracks_damping_ = true;
  bool tracks_slow_loads_ = false;
  std::size_t n_local_ = 0;
  std::size_t n_ghost_ = 0;
  GidIndex index_;
};

}  // namespace ringdem

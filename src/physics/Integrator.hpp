#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"

namespace ringdem {

/// Velocity Verlet for translation and rotation (physics.md §4). Spheres have isotropic
/// inertia, so the world-frame angular velocity is integrated directly and the orientation
/// follows by a Cayley update q <- cay(omega dt) q, not the exact exponential map: a unit
/// quaternion turning by 2 atan(|omega dt|/2) = |omega dt| (1 - |omega dt|^2/12 + ...) about
/// omega, inverted exactly by cay(-omega dt), so the update stays time-reversible.
struct Integrator {
  /// Which owned particles turn their orientations in the drift. Only bonds read orientations
  /// (spheres are isotropic): none where the store keeps none, else every particle, or only
  /// those flagged in `only` (one byte per owned particle, 1 to turn), whose others keep their
  /// orientation unchanged.
  struct Turning {
    bool orientations = false;
    const std::uint8_t* only = nullptr;
    /// Implicit: `true` turns every particle, `false` none (the store keeps no orientations).
    Turning(bool turn_all) : orientations(turn_all) {}
    Turning(bool turn, const std::uint8_t* flagged) : orientations(turn), only(flagged) {}
  };
  /// The smallest box, component by component, that holds some particles' velocities (empty:
  /// low above high). The neighbour-list test bounds how far particles moved relative to one
  /// another by its half diagonal (Simulation::needs_rebuild): a flow that moves as one does
  /// not wear out the skin. NaN components are left out (the runaway guard reports them).
  struct VelocityBox {
    Vec3 low{kEmptyLow, kEmptyLow, kEmptyLow}, high{-kEmptyLow, -kEmptyLow, -kEmptyLow};
    static constexpr double kEmptyLow = std::numeric_limits<double>::infinity();
    void add(const Vec3& v) {
      low = {v.x < low.x ? v.x : low.x, v.y < low.y ? v.y : low.y, v.z < low.z ? v.z : low.z};
      high = {v.x > high.x ? v.x : high.x, v.y > high.y ? v.y : high.y,
              v.z > high.z ? v.z : high.z};
    }
    void add(const VelocityBox& b) {
      low = {b.low.x < low.x ? b.low.x : low.x, b.low.y < low.y ? b.low.y : low.y,
             b.low.z < low.z ? b.low.z : low.z};
      high = {b.high.x > high.x ? b.high.x : high.x, b.high.y > high.y ? b.high.y : high.y,
              b.high.z > high.z ? b.high.z : high.z};
    }
    bool empty() const { return !(low.x <= high.x && low.y <= high.y && low.z <= high.z); }
  };
  /// What the drift pass saw, folded into its one pass over the particles.
  struct Drift {
    /// Largest speed |v| dt of this drift: the neighbour-list test adds it up over the steps
    /// since the last rebuild, a bound on every particle's move (Simulation::needs_rebuild).
    double max_speed = 0.0;
    /// Largest (|v| dt / max_step)^2 or (|omega| dt / max_turn)^2 of this step, and
    /// kRunaway for a non-finite velocity: above 1, a particle moved farther in one step than
    /// a contact can be tracked (the divergence guard).
    double worst_runaway = 0.0;
    std::size_t worst_index = 0;  ///< the particle of worst_runaway
    /// The box of this drift's velocities (every particle it saw, fixed ones at rest too).
    VelocityBox velocities;
  };
  static constexpr double kRunaway = 1e300;
  /// v += F/m dt/2, x += v dt (and the same for rotation), owned particles, turning the
  /// orientations as `turning` says. Once a
  /// particle's load has kicked it, the same pass starts the next step's load: F = m g, T = 0
  /// (GatherMap::initialise_loads without a second pass over the particles).
  static Drift first_half(ParticleStore& p, double dt, const Vec3& gravity, double max_step,
                          double max_turn, Turning turning);
  /// Applies the global damping to the new loads (physics.md §4), then v += F/m dt/2,
  /// omega += T/I dt/2 for owned free particles; the damped loads stay for the next step.
  /// Adds the energy the damping took out (its power at the new velocities, times dt) to the
  /// particles' dissipated_global ledger.
  static void second_half(ParticleStore& p, double dt);
  /// second_half() of this step, then `between(end)`, then first_half() of the next step,
  /// block by block of kBlock particles: between(end) is called once the particles below `end`
  /// have their end-of-step velocities and before any of them drifts, with growing ends up to
  /// the number of owned particles. The same bits as the three in turn, in one pass from
  /// memory over the particles instead of three (a million grains' columns do not stay in cache).
  static Drift second_then_first_half(ParticleStore& p, double dt, const Vec3& gravity,
                                      double max_step, double max_turn, Turning turning,
                                      const std::function<void(std::size_t end)>& between);
  /// Particles a chunk of the second half kick: each chunk takes the damped or the undamped
  /// way as a whole (a multiple of the passes' four lanes).
  static constexpr std::size_t kChunk = 64;
  /// Particles a block of second_then_first_half(): each of its three parts runs over a block
  /// before the next starts, so a block's columns (about 4 MB) come back from the last-level
  /// cache. Measured on 10^6 grains (BM_IntegrateGrains): 11.5-11.8 ns a particle-step against
  /// 12.5-13 ns for blocks of 4 096 or 65 536 particles and 15 ns for chunks of 64 alone, which
  /// break the memory streams too often.
  static constexpr std::size_t kBlock = 256 * kChunk;

  /// A run of owned particles [begin, end): multi-rate stepping drifts and kicks only the runs
  /// of particles that its fast loads can move (SubstepParticles).
  struct Run {
    std::size_t begin, end;
  };
  /// The largest squared speeds |v|^2 and |omega|^2 of some particles (infinite for a
  /// non-finite one), as a drift pass raises them.
  struct SquaredSpeeds {
    double v2 = 0.0, w2 = 0.0;
    VelocityBox velocities;  ///< and the box of their velocities
  };
  /// first_half() of the particles in `runs` alone. The others are particles that no load
  /// kicks (drift_unloaded() moves them later): their velocities do not change, so `others`,
  /// their squared speeds, enter the Drift as this pass over them would have seen them.
  static Drift first_half(ParticleStore& p, double dt, const Vec3& gravity, double max_step,
                          double max_turn, Turning turning, const std::vector<Run>& runs,
                          const SquaredSpeeds& others);
  /// second_half() of the particles in `runs` alone.
  static void second_half(ParticleStore& p, double dt, const std::vector<Run>& runs);
  /// `drifts` steps of first_half() and second_half() of the free particles in `runs`, whose
  /// loads are all zero and stay so (no gravity: multi-rate stepping's fast loads): each
  /// velocity plus the zero kick, then x += v dt `drifts` times. The same operations on them as
  /// those passes, so the same bits, in one pass instead of 2 x `drifts`.
  static void drift_unloaded(ParticleStore& p, double dt, const std::vector<Run>& runs, int drifts);
  /// The largest squared speeds of the particles in `runs`.
  static SquaredSpeeds squared_speeds(const ParticleStore& p, const std::vector<Run>& runs);

  /// v += F/m half_dt, omega += T/I half_dt for owned free particles, from the loads given
  /// (multi-rate stepping's slow kicks: ParticleStore::slow_force). Four particles at a time;
  /// the loads are read only (the last partial four goes through a copy that is written back
  /// unchanged, hence not const).
  static void kick(ParticleStore& p, std::vector<Vec3>& force, std::vector<Vec3>& torque,
                   double half_dt);

  /// Rigid bodies: prescribed ones move with their velocity; free ones are integrated from
  /// their contact load plus gravity.
  static void first_half(std::vector<RigidBody>& bodies, double dt, const Vec3& gravity);
  static void second_half(std::vector<RigidBody>& bodies, double dt, const Vec3& gravity);
};

/// Cundall's non-viscous global damping, per particle and component (physics.md §4):
/// F_i <- F_i - alpha |F_i| sign(v_i), T_i <- T_i - alpha |T_i| sign(omega_i). The step
/// applies it inside second_half(); this is for the loads of the initial state, and it starts
/// the dissipated_global ledger (first trapezoid weight dt/2 of the initial damping power).
void apply_global_damping(ParticleStore& p, double dt);

}  // namespace ringdem

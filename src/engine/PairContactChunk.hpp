#pragma once

#include <cstddef>
#include <cstdint>

#include "core/Vec3.hpp"
#include "domain/ContactLedgerState.hpp"
#include "engine/ChunkColumn.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {

/// The velocity of b's contact point relative to a's, for the contact along `normal` (from a to
/// b) with arms arm_a and arm_b from the centres (physics.md §3).
[[gnu::always_inline]] inline Vec3 relative_contact_velocity(const Vec3& normal, double arm_a,
                                                             double arm_b, const Vec3& va,
                                                             const Vec3& vb, const Vec3& wa,
                                                             const Vec3& wb) {
  return (vb + cross(wb, normal * (-arm_b))) - (va + cross(wa, normal * arm_a));
}

/// Scratch for PairContactTerm's kernel: up to kSize touching pairs of one chunk of
/// candidates, their inputs copied into columns (structure of arrays) in pair order, the
/// contact law run over them as one vectorised loop, and its results in columns for the
/// in-order scatter. The contact law of a pair is a long chain of square roots and divisions;
/// one pair at a time it waited on them (40 ns a contact), across the lanes of a vector it
/// does not. Every lane does the operations the scalar loop did, in the same order, and the
/// build rounds vector and scalar code alike (no FMA contraction): the same bits.
struct PairContactChunk {
  static constexpr std::size_t kSize = 64;

  /// What the kernel computes for the energy ledger (EnergyLedger::PairBooking): nothing (off),
  /// the per-particle loads and moments, or each contact's work (with or without its energies,
  /// which only some evaluations book: EnergyLedger::books_energies()).
  enum class Ledger { kOff, kPerParticle, kPerContact, kPerContactWithEnergies };

  using Column = ChunkColumn<kSize>;

  std::size_t n = 0;  ///< touching pairs in the chunk
  bool any_rolling = false;
  std::uint32_t pair[kSize], end_a[kSize], end_b[kSize];
  /// The ends' entries in the energy ledger's moments (EnergyLedger::moments_entry), where the
  /// ledger is booked and the end is owned.
  std::uint32_t moments_a[kSize], moments_b[kSize];

  // Inputs: the separation b - a and its square, the radii, the effective mass, velocities,
  // the pair's material parameters, and the tangential spring carried from the last step.
  Column separation;
  alignas(64) double dist2[kSize], radius_a[kSize], radius_b[kSize], m_star[kSize];
  Column velocity_a, velocity_b, omega_a, omega_b;
  alignas(64) double e_star[kSize], g_star[kSize], beta[kSize], friction[kSize],
      rolling_friction[kSize];
  Column spring;  ///< in: carried; out: updated (physics.md §3)
  /// Per-contact booking: the ledger states of the pairs (ContactLedgerState), as they are
  /// stored: the gather and the scatter copy four floats a contact, and compute_lanes() rebuilds
  /// the start's normal (step_start_normal()), a vector of lanes at a time (one contact at a
  /// time, the normal's square root and division were a fifth of the pair loop:
  /// docs/performance.md, forty-seventh round).
  struct LedgerStateColumn {
    alignas(64) float damping_x[kSize], damping_y[kSize], damping_z[kSize];
    alignas(64) float overlap[kSize];
    [[gnu::always_inline]] void set(std::size_t c, const ContactLedgerState& s) {
      damping_x[c] = s.damping.x;
      damping_y[c] = s.damping.y;
      damping_z[c] = s.damping.z;
      overlap[c] = s.overlap;
    }
    /// Lane c, the state of ContactLedgerState::of() (in compute_lanes(), inlined there).
    [[gnu::always_inline]] void store(std::size_t c, const Vec3& damping, double depth) {
      set(c, ContactLedgerState::of(damping, depth));
    }
    [[gnu::always_inline]] Vec3 damping(std::size_t c) const {
      return {damping_x[c], damping_y[c], damping_z[c]};
    }
    /// Lane `to` = lane `from`.
    void copy_lane(std::size_t from, std::size_t to) {
      damping_x[to] = damping_x[from];
      damping_y[to] = damping_y[from];
      damping_z[to] = damping_z[from];
      overlap[to] = overlap[from];
    }
    /// state = lane c, field by field (see PairContactTerm::compute_pairs on spring copies).
    void copy_to(std::size_t c, ContactLedgerState& s) const {
      s.damping.x = damping_x[c];
      s.damping.y = damping_y[c];
      s.damping.z = damping_z[c];
      s.overlap = overlap[c];
    }
  };
  LedgerStateColumn carried_ledger;   ///< in: from the last step
  LedgerStateColumn ledger_to_carry;  ///< out: to the next step

  // Results: the force on a (b gets its opposite), each end's torque, and for the energy
  // ledger each end's viscous load and moments (ContactMoments) and half the pair's energies.
  Column force_a, torque_a, torque_b;
  Column damping_a, damping_moment_a, damping_moment_b, friction_moment_a, friction_moment_b;
  alignas(64) double half_tangential_energy[kSize], half_elastic_energy[kSize];
  /// Per-contact booking: half the work of each of the contact's loads over the step, F . u
  /// with u the relative velocity of the step's middle at the load's own contact point, of the
  /// viscous force and of the tangential spring force (docs/physics.md "Energy ledger"), for
  /// each owned end to book: those of the step's start (the carried loads; zero where the pair
  /// carries none) and those of its end apart. Each is rounded to the ledger's integers on its
  /// own, so that a rebuild in the middle of a step, which books the start's half then
  /// (PairContactTerm::book_carried_work()), books the same integers as a step without one;
  /// their sum rounded once was not (a tally's last bits depended on the rebuilds' steps).
  struct HalfWorkColumns {
    alignas(64) double damping[kSize], friction[kSize];
  };
  HalfWorkColumns start_half_work, end_half_work;

  /// Appends a touching pair (the caller has tested it) with its material parameters.
  void add(std::uint32_t m, std::uint32_t a, std::uint32_t b, const Vec3& d, double d2, double ra,
           double rb, double mass, const Vec3& va, const Vec3& vb, const Vec3& wa, const Vec3& wb,
           const HertzMindlin::Params& params, const Vec3& carried) {
    add_geometry(m, a, b, d, d2, ra, rb, mass, va, vb, wa, wb, carried);
    set_params(n - 1, params);
  }
  /// Appends a touching pair whose material parameters are already in its lane: those of
  /// fill_params(), where every pair of the run has the same (MaterialTable::uniform_pair()).
  /// A pair's own parameters, looked up by its ends' materials and stored in five columns, were
  /// a tenth of a packing's contacts phase (docs/performance.md, fifty-third round).
  [[gnu::always_inline]] void add_geometry(std::uint32_t m, std::uint32_t a, std::uint32_t b,
                                           const Vec3& d, double d2, double ra, double rb,
                                           double mass, const Vec3& va, const Vec3& vb,
                                           const Vec3& wa, const Vec3& wb, const Vec3& carried) {
    const std::size_t c = n++;
    pair[c] = m;
    end_a[c] = a;
    end_b[c] = b;
    separation.set(c, d);
    dist2[c] = d2;
    radius_a[c] = ra;
    radius_b[c] = rb;
    m_star[c] = mass;
    velocity_a.set(c, va);
    velocity_b.set(c, vb);
    omega_a.set(c, wa);
    omega_b.set(c, wb);
    spring.set(c, carried);
  }
  /// The material parameters of lane c.
  [[gnu::always_inline]] void set_params(std::size_t c, const HertzMindlin::Params& params) {
    e_star[c] = params.e_star;
    g_star[c] = params.g_star;
    beta[c] = params.beta;
    friction[c] = params.friction;
    rolling_friction[c] = params.rolling_friction;
    any_rolling = any_rolling || params.rolling_friction > 0.0;
  }
  /// The same parameters in every lane (the lanes a chunk's add_geometry() fills).
  void fill_params(const HertzMindlin::Params& params) {
    for (std::size_t c = 0; c < kSize; ++c)
      set_params(c, params);
  }
  /// The contact law (physics.md §3, HertzMindlin) over lanes 0..n-1, as one loop (in whole
  /// vectors: pad_to_whole_vectors()).
  template <Ledger kLedger>
  void compute(double dt) {
    const std::size_t lanes = pad_to_whole_vectors();
    if (any_rolling)
      compute_lanes<kLedger, true>(dt, lanes);
    else
      compute_lanes<kLedger, false>(dt, lanes);
  }

  /// The lanes the law runs over are a multiple of this (the widest vector: 8 doubles).
  static constexpr std::size_t kLaneMultiple = 8;
  static_assert(kSize % kLaneMultiple == 0, "a full chunk is whole vectors");

 private:
  /// Fills lanes n.. up to the next multiple of kLaneMultiple with lane n-1's inputs and
  /// returns that multiple. A chunk's last n % 8 contacts ran in the vectorised loop's scalar
  /// remainder, each one through the law's chain of square roots and divisions in turn: a third
  /// of the kernel's time on a packing in contact (docs/performance.md, fifty-fourth round).
  /// Each lane's result depends on its own inputs alone, and nothing reads the filled lanes'
  /// results (the scatter stops at n).
  std::size_t pad_to_whole_vectors();
  /// The loop, in PairContactChunk.cpp: compiled there with floating-point operations taken
  /// not to trap (CMakeLists.txt), which it needs to vectorise, and only there, so that every
  /// caller (the term, the tests) runs the same code.
  template <Ledger kLedger, bool kRolling>
  void compute_lanes(double dt, std::size_t lanes);
};

}  // namespace ringdem

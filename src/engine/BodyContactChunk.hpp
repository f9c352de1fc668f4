#pragma once

#include <cstddef>
#include <cstdint>

#include "core/Vec3.hpp"
#include "engine/ChunkColumn.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {

/// Scratch for BodyContactTerm's kernel: up to kSize touching particle–body contacts, their
/// contact-law inputs copied into columns (structure of arrays) in candidate order, the law run
/// over them as one vectorised loop, and its results in columns for the scatter. One contact
/// at a time the law's chain of square roots and divisions was most of the term's time (the
/// 48 400 grains on the floor of the 10^6-grain bed: 75 ns a contact). Every lane does the
/// operations the scalar code did, in the same order, and the build rounds vector and scalar
/// code alike (no FMA contraction): the same bits (tests/unit/test_body_contact_chunk.cpp).
struct BodyContactChunk {
  static constexpr std::size_t kSize = 64;

  using Column = ChunkColumn<kSize>;

  std::size_t n = 0;  ///< touching contacts in the chunk
  bool any_rolling = false;
  std::uint32_t candidate[kSize];  ///< the term's candidate row of each lane

  // Inputs (HertzMindlin::Input with arm_j = 0, and the pair's parameters), and the tangential
  // spring carried from the last step.
  Column normal, v_rel, omega_particle, omega_body;
  alignas(64) double overlap[kSize], r_star[kSize], m_star[kSize], arm[kSize];
  alignas(64) double e_star[kSize], g_star[kSize], beta[kSize], friction[kSize],
      rolling_friction[kSize];
  Column spring;  ///< in: carried; out: updated (physics.md §3)

  // Results for the particle: the force, the torque about its centre, and for the energy
  // ledger's record the viscous force, the rolling torque and the energies.
  Column force, torque, damping, rolling;
  alignas(64) double tangential_energy[kSize], elastic_energy[kSize];

  /// Appends a touching contact (the caller has tested it). `in.dt` is not kept: compute()
  /// takes the step.
  void add(std::uint32_t w, const HertzMindlin::Input& in, const HertzMindlin::Params& params,
           const Vec3& carried) {
    const std::size_t c = n++;
    candidate[c] = w;
    normal.set(c, in.normal);
    v_rel.set(c, in.v_rel);
    omega_particle.set(c, in.omega_i);
    omega_body.set(c, in.omega_j);
    overlap[c] = in.overlap;
    r_star[c] = in.r_star;
    m_star[c] = in.m_star;
    arm[c] = in.arm_i;
    e_star[c] = params.e_star;
    g_star[c] = params.g_star;
    beta[c] = params.beta;
    friction[c] = params.friction;
    rolling_friction[c] = params.rolling_friction;
    any_rolling = any_rolling || params.rolling_friction > 0.0;
    spring.set(c, carried);
  }

  /// The contact law (physics.md §3, HertzMindlin) over lanes 0..n-1, as one loop.
  void compute(double dt) {
    if (any_rolling)
      compute_lanes<true>(dt);
    else
      compute_lanes<false>(dt);
  }

 private:
  /// The loop, in BodyContactChunk.cpp, compiled there with floating-point operations taken
  /// not to trap (CMakeLists.txt), which it needs to vectorise.
  template <bool kRolling>
  void compute_lanes(double dt);
};

}  // namespace ringdem

#include "engine/TimoshenkoBondTerm.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/Loop.hpp"

namespace ringdem {

Quat TimoshenkoBondTerm::rotated_back(const Quat& q, const Vec3& omega, double dt) {
  // dq(-omega dt) undoes the integrator's Cayley update q <- dq(omega dt) q (Integrator.cpp).
  return cayley_turned(q, omega * (-0.5 * dt));
}

TimoshenkoBondTerm::TimoshenkoBondTerm(BondStore& bonds, std::vector<BondTimoshenko::Params> types)
    : BondTerm(bonds), types_(std::move(types)) {}

std::size_t TimoshenkoBondTerm::create(BondStore& bonds, const BondTimoshenko::Params& params,
                                       std::int32_t type, std::int64_t id, const BondEnd& end_a,
                                       const BondEnd& end_b, std::uint64_t seed) {
  const bool in_order = end_a.gid < end_b.gid;
  const BondEnd& a = in_order ? end_a : end_b;
  const BondEnd& b = in_order ? end_b : end_a;
  const double length0 = norm(b.position - a.position);
  const auto section = BondTimoshenko::Section::make(params, a.radius, b.radius, length0);
  const auto ref =
      BondTimoshenko::Reference::make(a.position, a.orientation, b.position, b.orientation);
  const auto strength = BondTimoshenko::draw_strength(params, seed, a.gid, b.gid);
  const std::size_t k = bonds.append(id, a.gid, b.gid, type);
  store(bonds, k, section, ref, strength);
  return k;
}

void TimoshenkoBondTerm::store(BondStore& bonds, std::size_t k, const BondTimoshenko::Section& s,
                               const BondTimoshenko::Reference& ref,
                               const BondTimoshenko::Strength& st) {
  bonds.length0[k] = s.length0;
  bonds.k_axial[k] = s.k_axial;
  bonds.k_torsion[k] = s.k_torsion;
  bonds.k_shear[k] = s.k_shear;
  bonds.k_bend_self[k] = s.k_bend_self;
  bonds.k_bend_cross[k] = s.k_bend_cross;
  bonds.inv_area[k] = s.inv_area;
  bonds.bend_factor[k] = s.bend_factor;
  bonds.frame_a[k] = ref.frame_a;
  bonds.frame_b[k] = ref.frame_b;
  bonds.tensile_strength[k] = st.tensile;
  bonds.compressive_strength[k] = st.compressive;
  bonds.shear_strength[k] = st.shear;
}

BondTimoshenko::Section TimoshenkoBondTerm::section(const BondStore& bonds, std::size_t k) {
  return BeamColumns(bonds).section(k);
}

double TimoshenkoBondTerm::ghost_width(const ParticleStore&) const {
  return bond_reach(bonds_);
}

double TimoshenkoBondTerm::bond_reach(const BondStore& bonds) {
  // Bonds may stretch 25 % before a partner leaves the ghost layer (steel bonds break at a
  // few per cent).
  double bond_max = 0.0;
  for (double l : bonds.length0)
    bond_max = std::max(bond_max, l);
  return 1.25 * bond_max;
}

void TimoshenkoBondTerm::rebuild(RebuildContext& ctx) {
  register_bonds(bonds_, ctx, slots_a_, slots_b_);
}

void TimoshenkoBondTerm::register_bonds(BondStore& bonds, RebuildContext& ctx, SlotRange& slots_a,
                                        SlotRange& slots_b) {
  const ParticleStore& p = ctx.particles;
  const std::size_t nb = bonds.size();
  bonds.index_a.resize(nb);
  bonds.index_b.resize(nb);
  for (std::size_t k = 0; k < nb; ++k) {
    const std::int64_t ia = p.index_of(bonds.gid_a[k]);
    const std::int64_t ib = p.index_of(bonds.gid_b[k]);
    // An intact bond has both ends here (block width >= bond length). The ends of a broken
    // bond drift apart: a missing end borrows the other's index, which the bond loop only
    // reads and then masks.
    if ((ia < 0 || ib < 0) && (!bonds.broken[k] || (ia < 0 && ib < 0)))
      throw std::runtime_error("bond " + std::to_string(bonds.gid_a[k]) + "-" +
                               std::to_string(bonds.gid_b[k]) + " has an end this rank lacks");
    bonds.index_a[k] = static_cast<std::uint32_t>(ia >= 0 ? ia : ib);
    bonds.index_b[k] = static_cast<std::uint32_t>(ib >= 0 ? ib : ia);
    if (!bonds.broken[k]) {  // intact bonds only: a broken pair may touch
      ctx.excluded.push_back({bonds.index_a[k], bonds.gid_b[k]});
      ctx.excluded.push_back({bonds.index_b[k], bonds.gid_a[k]});
    }
  }
  slots_a = ctx.allocator.take(nb);
  slots_b = ctx.allocator.take(nb);
  const auto term = ctx.term_number;
  for (std::size_t k = 0; k < nb; ++k) {
    if (bonds.broken[k]) continue;  // exerts nothing; a bond breaking later forces a rebuild
    ctx.gather.add(bonds.index_a[k], bonds.gid_b[k], term,
                   slots_a.begin + static_cast<std::uint32_t>(k), false);
    ctx.gather.add(bonds.index_b[k], bonds.gid_a[k], term,
                   slots_b.begin + static_cast<std::uint32_t>(k), false);
  }
}

void TimoshenkoBondTerm::compute(ComputeContext& ctx) {
  broke_ = false;
  const ParticleStore& p = ctx.particles;
  BondStore& bonds = bonds_;
  const std::size_t nb = bonds.size();
  failed_.resize(nb);
  // Bonds (physics.md §1): forces and the failure test of Eq. 3–5 every step, written so the
  // loop vectorises: bond data in contiguous arrays, particle data gathered by index, no
  // branches (broken bonds are masked to zero force). The loop only flags the bonds that may
  // fail (BondTimoshenko::may_fail(), without the three square roots of the stresses); the
  // pass after it decides those exactly and zeroes the loads of the ones that fail, which the
  // loop would have masked. Output quantities are recomputed on demand by
  // update_diagnostics().
  std::int64_t* __restrict__ const failed = failed_.data();  // flagged, then failed
  const BeamColumns col(bonds);
  BeamSlots out(ctx.slots, slots_a_, slots_b_);
  BeamChunk& g = scratch_;
  for_each_chunk(IndexRange{0, nb}, BeamChunk::kSize, [&](IndexRange chunk) {
    g.load(p, bonds, chunk);
    for_each(chunk, [&](std::size_t k) {
      const std::size_t c = k - chunk.begin;
      const auto sec = col.section(k);
      const auto r =
          BondTimoshenko::compute(sec, col.reference(k), g.x_a(c), g.q_a(c), g.x_b(c), g.q_b(c));
      const std::int64_t intact = g.broken[c] == 0;
      failed[k] = col.may_fail(k, sec, r) & intact;
      out.write(k, intact, r);
    });
  });
  if (std::find(failed_.begin(), failed_.end(), 1) == failed_.end()) return;
  // Each flagged bond recomputed from the same inputs: the loop's bits (no contraction, so no
  // difference between its vector lanes and this scalar code).
  bool any_failed = false;
  for (std::size_t k = 0; k < nb; ++k) {
    if (!failed_[k]) continue;
    const std::uint32_t a = bonds.index_a[k], b = bonds.index_b[k];
    const auto sec = col.section(k);
    const auto r = BondTimoshenko::compute(sec, col.reference(k), p.position[a], p.orientation[a],
                                           p.position[b], p.orientation[b]);
    failed_[k] = col.fails(k, sec, r);
    if (failed_[k]) out.clear(k);
    any_failed = any_failed || failed_[k];
  }
  if (any_failed) book_failures(p, ctx.time, ctx.dt);
}

void TimoshenkoBondTerm::book_failures(const ParticleStore& p, double time, double dt) {
  BondStore& bonds = bonds_;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!failed_[k]) continue;
    const std::uint32_t a = bonds.index_a[k], b = bonds.index_b[k];
    const auto sec = section(bonds, k);
    const auto ref = reference(bonds, k);
    const auto r = BondTimoshenko::compute(sec, ref, p.position[a], p.orientation[a], p.position[b],
                                           p.orientation[b]);
    bonds.broken[k] = 1;
    bonds.failure[k] =
        BondTimoshenko::check_failure(BondTimoshenko::stresses(sec, r), strength(bonds, k));
    bonds.break_time[k] = time;
    // Energy ledger: the bond's force acted through the first half of this step and is zero
    // from this evaluation on, so the energy it takes out of the books is its mean over the
    // step (trapezoid; second order, docs/physics.md "Energy ledger"). The start of the step
    // is x - v dt, q rotated back by omega dt (the mid-step velocities the drift used).
    const auto r0 = BondTimoshenko::compute(sec, ref, p.position[a] - p.velocity[a] * dt,
                                            rotated_back(p.orientation[a], p.omega[a], dt),
                                            p.position[b] - p.velocity[b] * dt,
                                            rotated_back(p.orientation[b], p.omega[b], dt));
    bonds.break_energy[k] = 0.5 * (r0.energy + r.energy);
    broke_ = true;
  }
}

double TimoshenkoBondTerm::update_diagnostics(const ParticleStore& p) const {
  return write_diagnostics(bonds_, [&](std::size_t k) {
    const std::uint32_t a = bonds_.index_a[k];
    const std::uint32_t b = bonds_.index_b[k];
    const auto sec = section(bonds_, k);
    const auto r = BondTimoshenko::compute(sec, reference(bonds_, k), p.position[a],
                                           p.orientation[a], p.position[b], p.orientation[b]);
    return Diagnostics{
        r.axial_force, std::max(r.bending_a, r.bending_b),
        BondTimoshenko::utilisation(BondTimoshenko::stresses(sec, r), strength(bonds_, k)),
        r.energy};
  });
}

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <vector>

#include "core/Select.hpp"
#include "domain/BondStore.hpp"
#include "engine/BondTerm.hpp"
#include "engine/ForceSlots.hpp"
#include "engine/Loop.hpp"
#include "physics/BondTimoshenko.hpp"

namespace ringdem {

/// The beam terms' vector loops run over bonds in chunks: a scalar pass copies the chunk's end
/// positions and orientations (gathered by particle index) into these contiguous arrays, by
/// component, so that the vector loop after it loads everything contiguously; and the bonds'
/// broken flags as 64-bit integers. The vectoriser sizes its vectors by a loop's narrowest type:
/// one byte column in the loop makes it run 64 bonds at a time, eight registers a double,
/// and the kernel then spends a third of its instructions spilling them.
struct BeamChunk {
  static constexpr std::size_t kSize = 256;
  double xa[3][kSize], xb[3][kSize], qa[4][kSize], qb[4][kSize];
  std::int64_t broken[kSize];

  /// Copies the ends of bonds [chunk.begin, chunk.end) to entries 0, 1, ...
  void load(const ParticleStore& p, const BondStore& bonds, IndexRange chunk) {
    const Vec3* const pos = p.position.data();
    const Quat* const rot = p.orientation.data();
    for (std::size_t c = 0; c < chunk.size(); ++c) {
      broken[c] = bonds.broken[chunk.begin + c];
      const std::uint32_t a = bonds.index_a[chunk.begin + c], b = bonds.index_b[chunk.begin + c];
      xa[0][c] = pos[a].x, xa[1][c] = pos[a].y, xa[2][c] = pos[a].z;
      xb[0][c] = pos[b].x, xb[1][c] = pos[b].y, xb[2][c] = pos[b].z;
      qa[0][c] = rot[a].w, qa[1][c] = rot[a].x, qa[2][c] = rot[a].y, qa[3][c] = rot[a].z;
      qb[0][c] = rot[b].w, qb[1][c] = rot[b].x, qb[2][c] = rot[b].y, qb[3][c] = rot[b].z;
    }
  }
  Vec3 x_a(std::size_t c) const { return {xa[0][c], xa[1][c], xa[2][c]}; }
  Vec3 x_b(std::size_t c) const { return {xb[0][c], xb[1][c], xb[2][c]}; }
  Quat q_a(std::size_t c) const { return {qa[0][c], qa[1][c], qa[2][c], qa[3][c]}; }
  Quat q_b(std::size_t c) const { return {qb[0][c], qb[1][c], qb[2][c], qb[3][c]}; }
};

/// A beam store's per-bond columns as raw pointers, read once (the vectoriser needs
/// loop-invariant bases it can prove), with the kernel's view of bond k.
struct BeamColumns {
  const double* length0;
  const double* k_axial;
  const double* k_torsion;
  const double* k_shear;
  const double* k_bend_self;
  const double* k_bend_cross;
  const double* inv_area;
  const double* bend_factor;
  const Quat* frame_a;
  const Quat* frame_b;
  const double* tensile_strength;
  const double* compressive_strength;
  const double* shear_strength;

  explicit BeamColumns(const BondStore& b)
      : length0(b.length0.data()),
        k_axial(b.k_axial.data()),
        k_torsion(b.k_torsion.data()),
        k_shear(b.k_shear.data()),
        k_bend_self(b.k_bend_self.data()),
        k_bend_cross(b.k_bend_cross.data()),
        inv_area(b.inv_area.data()),
        bend_factor(b.bend_factor.data()),
        frame_a(b.frame_a.data()),
        frame_b(b.frame_b.data()),
        tensile_strength(b.tensile_strength.data()),
        compressive_strength(b.compressive_strength.data()),
        shear_strength(b.shear_strength.data()) {}

  [[gnu::always_inline]] BondTimoshenko::Section section(std::size_t k) const {
    BondTimoshenko::Section s;
    s.length0 = length0[k];
    s.k_axial = k_axial[k];
    s.k_torsion = k_torsion[k];
    s.k_shear = k_shear[k];
    s.k_bend_self = k_bend_self[k];
    s.k_bend_cross = k_bend_cross[k];
    s.inv_area = inv_area[k];
    s.bend_factor = bend_factor[k];
    return s;
  }
  [[gnu::always_inline]] BondTimoshenko::Reference reference(std::size_t k) const {
    return {frame_a[k], frame_b[k]};
  }
  [[gnu::always_inline]] BondTimoshenko::Strength strength(std::size_t k) const {
    return {tensile_strength[k], compressive_strength[k], shear_strength[k]};
  }
  /// Whether Eq. 3–5 break bond k in state r (0 or 1, branch-free).
  [[gnu::always_inline]] std::int64_t fails(std::size_t k, const BondTimoshenko::Section& s,
                                            const BondTimoshenko::Result& r) const {
    const auto st = BondTimoshenko::stresses(s, r);
    return (st.tensile > tensile_strength[k]) | (st.compressive > compressive_strength[k]) |
           (st.shear > shear_strength[k]);
  }
  /// BondTimoshenko::may_fail() of bond k (0 or 1, branch-free): 1 wherever fails() is 1.
  [[gnu::always_inline]] std::int64_t may_fail(std::size_t k, const BondTimoshenko::Section& s,
                                               const BondTimoshenko::Result& r) const {
    return BondTimoshenko::may_fail(s, r, strength(k));
  }
};

/// The slots of a beam term's two ends (one range per end, bond k at begin + k), as raw
/// component pointers read once: the vector loop needs loop-invariant bases it can prove.
struct BeamSlots {
  double* __restrict__ fxa;
  double* __restrict__ fya;
  double* __restrict__ fza;
  double* __restrict__ txa;
  double* __restrict__ tya;
  double* __restrict__ tza;
  double* __restrict__ fxb;
  double* __restrict__ fyb;
  double* __restrict__ fzb;
  double* __restrict__ txb;
  double* __restrict__ tyb;
  double* __restrict__ tzb;

  BeamSlots(ForceSlots& s, SlotRange a, SlotRange b)
      : fxa(s.fx.data() + a.begin),
        fya(s.fy.data() + a.begin),
        fza(s.fz.data() + a.begin),
        txa(s.tx.data() + a.begin),
        tya(s.ty.data() + a.begin),
        tza(s.tz.data() + a.begin),
        fxb(s.fx.data() + b.begin),
        fyb(s.fy.data() + b.begin),
        fzb(s.fz.data() + b.begin),
        txb(s.tx.data() + b.begin),
        tyb(s.ty.data() + b.begin),
        tzb(s.tz.data() + b.begin) {}

  /// Zeros bond k's end loads: the bits write(k, false, r) writes.
  void clear(std::size_t k) {
    fxa[k] = fya[k] = fza[k] = txa[k] = tya[k] = tza[k] = 0.0;
    fxb[k] = fyb[k] = fzb[k] = txb[k] = tyb[k] = tzb[k] = 0.0;
  }
  /// Bond k's end loads, or zeros where !keep: a select (select_bits, which AVX2 vectorises
  /// too), not a product: a broken bond's result may be NaN (ends far apart or borrowed).
  [[gnu::always_inline]] void write(std::size_t k, bool keep, const BondTimoshenko::Result& r) {
    const auto pick = [keep](double x) { return select_bits(keep, x, 0.0); };
    fxa[k] = pick(r.force_a.x);
    fya[k] = pick(r.force_a.y);
    fza[k] = pick(r.force_a.z);
    txa[k] = pick(r.torque_a.x);
    tya[k] = pick(r.torque_a.y);
    tza[k] = pick(r.torque_a.z);
    fxb[k] = pick(r.force_b.x);
    fyb[k] = pick(r.force_b.y);
    fzb[k] = pick(r.force_b.z);
    txb[k] = pick(r.torque_b.x);
    tyb[k] = pick(r.torque_b.y);
    tzb[k] = pick(r.torque_b.z);
  }
};

/// Bonds of the co-rotational Timoshenko beam law (model "timoshenko", physics.md §1,
/// Eq. 1–5): elastic, brittle. The bond store is the model's (frames and checkpoints read it);
/// this term keeps the bond types' parameters, its slot ranges and the kernel's scratch.
class TimoshenkoBondTerm final : public BondTerm {
 public:
  TimoshenkoBondTerm(BondStore& bonds, std::vector<BondTimoshenko::Params> types);

  std::string_view name() const override { return "timoshenko"; }
  double ghost_width(const ParticleStore& p) const override;
  void rebuild(RebuildContext& ctx) override;
  /// Forces and the failure test of Eq. 3–5. Bonds that fail are marked broken with their
  /// time and the elastic energy they held (break_energy: the mean of the energy at the end of
  /// the step and at its start, x - v dt with the mid-step velocities; dt = 0 takes the end).
  void compute(ComputeContext& ctx) override;
  bool topology_changed() const override { return broke_; }

  /// Recomputes the output columns (axial force, largest bending moment, utilisation, energy)
  /// for the current configuration; returns the summed energy.
  double update_diagnostics(const ParticleStore& p) const override;

  /// Creates bond `id` between two ends (either order; the store keeps the lower gid first):
  /// section from the type's parameters and the end radii, reference frames from the ends'
  /// orientations, strengths drawn by (seed, gid pair). Returns the bond's index in the store.
  static std::size_t create(BondStore& bonds, const BondTimoshenko::Params& params,
                            std::int32_t type, std::int64_t id, const BondEnd& a, const BondEnd& b,
                            std::uint64_t seed);
  /// Stores a section, reference and strengths in bond k's columns.
  static void store(BondStore& bonds, std::size_t k, const BondTimoshenko::Section& s,
                    const BondTimoshenko::Reference& ref, const BondTimoshenko::Strength& st);
  /// The kernel's view of bond k's columns.
  static BondTimoshenko::Section section(const BondStore& bonds, std::size_t k);
  static BondTimoshenko::Reference reference(const BondStore& bonds, std::size_t k) {
    return {bonds.frame_a[k], bonds.frame_b[k]};
  }
  static BondTimoshenko::Strength strength(const BondStore& bonds, std::size_t k) {
    return {bonds.tensile_strength[k], bonds.compressive_strength[k], bonds.shear_strength[k]};
  }

  // Shared with the other beam laws over the same store (TimoshenkoPlasticBondTerm).
  /// Ghost width of a store of beam bonds: 1.25 times the longest bond.
  static double bond_reach(const BondStore& bonds);
  /// rebuild() of a store of beam bonds: resolves both ends' indices (throws if an intact
  /// bond lacks one), excludes intact pairs from contact, takes one slot range per end and
  /// registers the intact bonds' slots with the gather map.
  static void register_bonds(BondStore& bonds, RebuildContext& ctx, SlotRange& slots_a,
                             SlotRange& slots_b);
  /// The orientation a particle had one step earlier (for the energy a breaking bond held at
  /// the start of its last step): the inverse of the integrator's Cayley update.
  static Quat rotated_back(const Quat& q, const Vec3& omega, double dt);
  /// What update_diagnostics() writes of one intact bond.
  struct Diagnostics {
    double axial_force, bending_moment, utilisation, energy;
  };
  /// update_diagnostics() of a store of beam bonds: the output columns of each intact bond k
  /// from `of(k)` (a Diagnostics), zeros for the broken ones; returns the intact bonds' summed
  /// energy.
  template <class Of>
  static double write_diagnostics(BondStore& bonds, Of&& of) {
    double total = 0.0;
    for (std::size_t k = 0; k < bonds.size(); ++k) {
      const Diagnostics d = bonds.broken[k] ? Diagnostics{0.0, 0.0, 0.0, 0.0} : of(k);
      bonds.axial_force[k] = d.axial_force;
      bonds.bending_moment[k] = d.bending_moment;
      bonds.utilisation[k] = d.utilisation;
      bonds.energy[k] = d.energy;
      if (!bonds.broken[k]) total += d.energy;
    }
    return total;
  }

 private:
  void book_failures(const ParticleStore& p, double time, double dt);

  std::vector<BondTimoshenko::Params> types_;
  SlotRange slots_a_, slots_b_;
  std::vector<std::int64_t> failed_;  ///< scratch: bonds that failed in this step (BeamChunk)
  bool broke_ = false;
  BeamChunk scratch_;
};

}  // namespace ringdem

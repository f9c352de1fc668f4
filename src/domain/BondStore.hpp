#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/BondFailure.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// The bonds of one bond term (one bond model), structure of arrays (one array per scalar or
/// vector member, so the bond loop loads them contiguously and vectorises), keyed by the
/// ordered gid pair (gid_a < gid_b). Bonds reference particles by gid; local indices are
/// resolved after every rebuild of the particle index. for_each_field() is the bond field
/// registry, with the same flags as the particle one: migration, checkpoints and frames read it.
///
/// The columns are those of the co-rotational beam laws (physics.md §1): the stiffness
/// coefficients the kernel reads, the reference frames and the strengths. A law with more
/// per-bond state (a plastic law's plastic deformations, say) declares it as model columns:
/// named double columns that the registry lists after the common ones, so migration,
/// checkpoints and frames carry them without knowing the law.
class BondStore {
 public:
  /// A per-bond double column declared by the bond model, with its registry flags.
  struct ModelColumn {
    std::string name;
    unsigned flags = 0;
  };
  // --- identity ---
  std::vector<std::int64_t> id;  ///< global bond id in creation order (file row)
  std::vector<std::int64_t> gid_a, gid_b;
  std::vector<std::int32_t> type;  ///< bond type (case-file table)
  // --- stiffness coefficients the kernel reads (BondTimoshenko::Section, physics.md §1) ---
  std::vector<double> length0, k_axial, k_torsion, k_shear, k_bend_self, k_bend_cross;
  std::vector<double> inv_area, bend_factor;
  // --- reference frame in each end's body frame ---
  std::vector<Quat> frame_a, frame_b;
  // --- strengths (Eq. 3–5) ---
  std::vector<double> tensile_strength, compressive_strength, shear_strength;
  // --- state ---
  std::vector<std::uint8_t> broken;  ///< 0 intact, 1 broken
  std::vector<BondFailure> failure;
  std::vector<double> break_time;  ///< simulated time of failure, -1 while intact
  /// Elastic energy the bond held when it broke (energy ledger: mean of its energy at the
  /// start and the end of the step in which it broke), 0 while intact.
  std::vector<double> break_energy;
  // --- output quantities, refreshed by the bond term's diagnostics ---
  std::vector<double> axial_force, bending_moment, utilisation, energy;

  /// The field registry: calls f(FieldInfo, std::vector<T>&) for every field.
  template <class F>
  void for_each_field(F&& f) {
    fields(*this, f);
  }
  template <class F>
  void for_each_field(F&& f) const {
    fields(*this, f);
  }

  /// Declares the bond model's columns (once, while the store is empty).
  void declare_model_columns(const std::vector<ModelColumn>& columns);
  std::size_t n_model_columns() const { return model_columns_.size(); }
  /// Column c of the model's columns, in declaration order: one value per bond.
  std::vector<double>& model_column(std::size_t c) { return model_values_[c]; }
  const std::vector<double>& model_column(std::size_t c) const { return model_values_[c]; }

  /// Local indices of the two ends (not a field: resolved from the gids).
  std::vector<std::uint32_t> index_a, index_b;

  std::size_t size() const { return gid_a.size(); }

  /// Appends intact bond `bond_id` (expects gid_first < gid_second, the canonical order) with
  /// every other column zero; returns its index for the caller to fill.
  std::size_t append(std::int64_t bond_id, std::int64_t gid_first, std::int64_t gid_second,
                     std::int32_t bond_type);

  /// The particle gids bond k joins (the pair-store protocol, domain/PairStore.hpp).
  std::array<std::int64_t, 2> ends(std::size_t k) const { return {gid_a[k], gid_b[k]}; }
  /// What a bond adds to its cell's weight in the decomposition, a particle counting 1. A
  /// bond-step cost 53 ns against 42 ns for a grain's particle-step on the project's 2-core
  /// machine, and 215 against about 104 ns on a 16-core node (the full debris case,
  /// docs/scaling.md): two, so that a net with its bonds is not taken for twice as many grains
  /// and left whole on one rank.
  static constexpr int kBlockWeight = 2;
  /// n bonds; new rows are zero (the end indices too: they are resolved at the next rebuild).
  void resize(std::size_t n);
  /// Keeps the bonds k with keep[k] != 0, in order.
  void keep_rows(const std::vector<char>& keep);
  /// After migration appended bonds [first, size()): drops an arrival this rank already holds
  /// (a bond comes from both owners of its ends) and restores the canonical (gid_a, gid_b)
  /// order, so that storage does not depend on arrival order. The end indices are left zero,
  /// for the next rebuild to resolve.
  void settle_arrivals(std::size_t first);

  std::size_t count_broken() const;

 private:
  template <class Self, class F>
  static void fields(Self& s, F& f) {
    using namespace field_flag;
    constexpr unsigned kState = kMigrate | kCheckpoint;
    f(FieldInfo{"id", kState | kOutput}, s.id);
    f(FieldInfo{"gid_a", kState | kOutput}, s.gid_a);
    f(FieldInfo{"gid_b", kState | kOutput}, s.gid_b);
    f(FieldInfo{"type", kState}, s.type);
    f(FieldInfo{"length0", kState}, s.length0);
    f(FieldInfo{"k_axial", kState}, s.k_axial);
    f(FieldInfo{"k_torsion", kState}, s.k_torsion);
    f(FieldInfo{"k_shear", kState}, s.k_shear);
    f(FieldInfo{"k_bend_self", kState}, s.k_bend_self);
    f(FieldInfo{"k_bend_cross", kState}, s.k_bend_cross);
    f(FieldInfo{"inv_area", kState}, s.inv_area);
    f(FieldInfo{"bend_factor", kState}, s.bend_factor);
    f(FieldInfo{"frame_a", kState}, s.frame_a);
    f(FieldInfo{"frame_b", kState}, s.frame_b);
    f(FieldInfo{"tensile_strength", kState}, s.tensile_strength);
    f(FieldInfo{"compressive_strength", kState}, s.compressive_strength);
    f(FieldInfo{"shear_strength", kState}, s.shear_strength);
    f(FieldInfo{"broken", kState | kOutput}, s.broken);
    f(FieldInfo{"failure", kState | kOutput}, s.failure);
    f(FieldInfo{"break_time", kState | kOutput}, s.break_time);
    f(FieldInfo{"break_energy", kState}, s.break_energy);
    f(FieldInfo{"axial_force", kOutput}, s.axial_force);
    f(FieldInfo{"bending_moment", kOutput}, s.bending_moment);
    f(FieldInfo{"utilisation", kOutput}, s.utilisation);
    f(FieldInfo{"energy", kOutput}, s.energy);
    for (std::size_t c = 0; c < s.model_columns_.size(); ++c)
      f(FieldInfo{s.model_columns_[c].name, s.model_columns_[c].flags}, s.model_values_[c]);
  }

  std::vector<ModelColumn> model_columns_;
  std::vector<std::vector<double>> model_values_;
};

}  // namespace ringdem

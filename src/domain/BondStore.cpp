#include "domain/BondStore.hpp"

#include <stdexcept>

namespace ringdem {

void BondStore::add(std::int64_t gid_first, std::int64_t gid_second, std::int32_t bond_type,
                    const BondTimoshenko::Section& s, const BondTimoshenko::Reference& ref,
                    const BondTimoshenko::Strength& st) {
  if (gid_first >= gid_second)
    throw std::invalid_argument("BondStore::add expects gid_first < gid_second");
  const std::size_t k = size();
  for_each_field([k](const FieldInfo&, auto& v) { v.resize(k + 1); });
  index_a.resize(k + 1);
  index_b.resize(k + 1);
  id[k] = static_cast<std::int64_t>(k);
  gid_a[k] = gid_first;
  gid_b[k] = gid_second;
  type[k] = bond_type;
  r_b[k] = s.r_b;
  area[k] = s.area;
  inertia[k] = s.inertia;
  length0[k] = s.length0;
  k_axial[k] = s.k_axial;
  k_torsion[k] = s.k_torsion;
  k_shear[k] = s.k_shear;
  k_couple[k] = s.k_couple;
  k_bend_self[k] = s.k_bend_self;
  k_bend_cross[k] = s.k_bend_cross;
  inv_area[k] = s.inv_area;
  bend_factor[k] = s.bend_factor;
  frame_a[k] = ref.frame_a;
  frame_b[k] = ref.frame_b;
  tensile_strength[k] = st.tensile;
  compressive_strength[k] = st.compressive;
  shear_strength[k] = st.shear;
  broken[k] = 0;
  failure[k] = BondTimoshenko::Failure::kNone;
  break_time[k] = -1.0;
  break_energy[k] = 0.0;
}

std::size_t BondStore::count_broken() const {
  std::size_t n = 0;
  for (auto b : broken)
    n += b;
  return n;
}

}  // namespace ringdem

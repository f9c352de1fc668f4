#include "domain/BondStore.hpp"

#include <stdexcept>

namespace ringdem {

void BondStore::add(std::int64_t gid_first, std::int64_t gid_second, std::int32_t bond_type,
                    const BondTimoshenko::Section& s, const BondTimoshenko::Reference& ref,
                    const BondTimoshenko::Strength& st) {
  if (gid_first >= gid_second)
    throw std::invalid_argument("BondStore::add expects gid_first < gid_second");
  gid_a.push_back(gid_first);
  gid_b.push_back(gid_second);
  type.push_back(bond_type);
  section.push_back(s);
  reference.push_back(ref);
  strength.push_back(st);
  broken.push_back(0);
  failure.push_back(BondTimoshenko::Failure::kNone);
  break_time.push_back(-1.0);
  axial_force.push_back(0.0);
  bending_moment.push_back(0.0);
  utilisation.push_back(0.0);
  energy.push_back(0.0);
  index_a.push_back(0);
  index_b.push_back(0);
}

std::size_t BondStore::count_broken() const {
  std::size_t n = 0;
  for (auto b : broken)
    n += b;
  return n;
}

}  // namespace ringdem

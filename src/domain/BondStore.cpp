#include "domain/BondStore.hpp"

#include <stdexcept>

namespace ringdem {

std::size_t BondStore::append(std::int64_t bond_id, std::int64_t gid_first,
                              std::int64_t gid_second, std::int32_t bond_type) {
  if (gid_first >= gid_second)
    throw std::invalid_argument("BondStore::append expects gid_first < gid_second");
  const std::size_t k = size();
  for_each_field([k](const FieldInfo&, auto& v) { v.resize(k + 1); });
  index_a.resize(k + 1);
  index_b.resize(k + 1);
  id[k] = bond_id;
  gid_a[k] = gid_first;
  gid_b[k] = gid_second;
  type[k] = bond_type;
  broken[k] = 0;
  failure[k] = BondFailure::kNone;
  break_time[k] = -1.0;
  break_energy[k] = 0.0;
  return k;
}

std::size_t BondStore::count_broken() const {
  std::size_t n = 0;
  for (auto b : broken)
    n += b;
  return n;
}

}  // namespace ringdem

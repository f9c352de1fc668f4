#include "domain/BondStore.hpp"

#include <stdexcept>

namespace ringdem {

std::size_t BondStore::append(std::int64_t bond_id, std::int64_t gid_first, std::int64_t gid_second,
                              std::int32_t bond_type) {
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

void BondStore::declare_model_columns(const std::vector<ModelColumn>& columns) {
  if (size() != 0 || !model_columns_.empty())
    throw std::logic_error("BondStore: model columns are declared once, before the first bond");
  for (const auto& c : columns) {
    for (const auto& other : model_columns_)
      if (other.name == c.name)
        throw std::invalid_argument("BondStore: model column '" + c.name + "' declared twice");
    bool clash = false;
    for_each_field([&](const FieldInfo& f, auto&) { clash = clash || f.name == c.name; });
    if (clash) throw std::invalid_argument("BondStore: '" + c.name + "' is a common bond column");
    model_columns_.push_back(c);
    model_values_.emplace_back();
  }
}

std::size_t BondStore::count_broken() const {
  std::size_t n = 0;
  for (auto b : broken)
    n += b;
  return n;
}

}  // namespace ringdem

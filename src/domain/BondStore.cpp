#include "domain/BondStore.hpp"

#include <algorithm>
#include <numeric>
#include <set>
#include <stdexcept>
#include <tuple>
#include <utility>

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

void BondStore::resize(std::size_t n) {
  for_each_field([n](const FieldInfo&, auto& v) { v.resize(n); });
  index_a.assign(n, 0);
  index_b.assign(n, 0);
}

void BondStore::keep_rows(const std::vector<char>& keep) {
  resize(compact_rows(*this, keep));
}

void BondStore::settle_arrivals(std::size_t first) {
  const auto key = [this](std::size_t k) { return std::make_pair(gid_a[k], gid_b[k]); };
  // The rows held before are usually in canonical order already (the last settle left them so,
  // and dropping rows keeps the order), and a rebuild brings few arrivals (the cut bonds, which
  // each owner of an end sends again): then only the arrivals are sorted and merged in.
  bool held_in_order = true;
  for (std::size_t k = 1; k < first && held_in_order; ++k)
    held_in_order = key(k - 1) < key(k);
  std::vector<std::size_t> order;
  if (held_in_order) {
    std::vector<std::size_t> arrivals(size() - first);
    std::iota(arrivals.begin(), arrivals.end(), first);
    // Stable: of equal arrivals the first is kept, as below.
    std::stable_sort(arrivals.begin(), arrivals.end(),
                     [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
    std::vector<std::size_t> fresh;
    for (const std::size_t k : arrivals) {
      if (!fresh.empty() && key(fresh.back()) == key(k)) continue;
      std::size_t lo = 0, hi = first;  // is it held already? binary search of [0, first)
      while (lo < hi) {
        const std::size_t mid = lo + (hi - lo) / 2;
        if (key(mid) < key(k))
          lo = mid + 1;
        else
          hi = mid;
      }
      if (lo < first && key(lo) == key(k)) continue;
      fresh.push_back(k);
    }
    if (fresh.empty()) {
      resize(first);
      return;
    }
    order.reserve(first + fresh.size());
    std::size_t h = 0;
    for (const std::size_t k : fresh) {
      while (h < first && key(h) < key(k))
        order.push_back(h++);
      order.push_back(k);
    }
    while (h < first)
      order.push_back(h++);
  } else {
    std::set<std::pair<std::int64_t, std::int64_t>> held;
    std::vector<char> keep(size(), 1);
    for (std::size_t k = 0; k < first; ++k)
      held.emplace(gid_a[k], gid_b[k]);
    for (std::size_t k = first; k < size(); ++k)
      keep[k] = held.emplace(gid_a[k], gid_b[k]).second ? 1 : 0;
    keep_rows(keep);
    order.resize(size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](std::size_t x, std::size_t y) { return key(x) < key(y); });
  }
  for_each_field([&](const FieldInfo&, auto& v) {
    auto old = v;
    v.resize(order.size());
    for (std::size_t m = 0; m < order.size(); ++m)
      v[m] = old[order[m]];
  });
  index_a.assign(order.size(), 0);
  index_b.assign(order.size(), 0);
}

std::size_t BondStore::count_broken() const {
  std::size_t n = 0;
  for (auto b : broken)
    n += b;
  return n;
}

}  // namespace ringdem

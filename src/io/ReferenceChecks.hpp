#pragma once

/// The checks of names that one part of a case gives and another refers to, shared by the
/// cross-key checks (CaseValidation, DebrisValidation): names unique within their list, a
/// reference to a defined name, a particle group that some particles use.

#include <fmt/format.h>

#include <map>
#include <set>
#include <string>
#include <vector>

#include "io/Schema.hpp"

namespace ringdem {

/// The names of `items` (each item's `name`), reporting a repeated one at its entry. `reliable`
/// is set false when the list or a name has errors, so that references to it are not judged.
template <class E>
std::vector<std::string> unique_names(const std::vector<E>& items, std::string E::*name,
                                      const std::string& list_path, const std::string& what,
                                      schema::Context& ctx, bool* reliable) {
  std::vector<std::string> names;
  std::map<std::string, std::size_t> first;
  // A missing or malformed list would make every reference to it an error too.
  *reliable = !ctx.failed_here(list_path);
  for (std::size_t i = 0; i < items.size(); ++i) {
    const std::string item_path = schema::index_path(list_path, i);
    const std::string name_path = item_path + ".name";
    if (ctx.failed(name_path) || !ctx.given(name_path)) {
      *reliable = false;
      continue;
    }
    const std::string& n = items[i].*name;
    const auto [it, inserted] = first.emplace(n, i);
    if (!inserted) {
      ctx.error(ctx.where(name_path, item_path), name_path,
                fmt::format("duplicate {} name '{}' (already used by {})", what, n,
                            schema::index_path(list_path, it->second)));
      continue;
    }
    names.push_back(n);
  }
  return names;
}

/// Reports `value` at `key_path` if it is not one of `names` (defined in `defined_in`).
/// `fallback` locates the error when the key itself was not given (a default value).
void check_reference(const std::string& value, const std::vector<std::string>& names,
                     bool names_reliable, const std::string& key_path, const std::string& fallback,
                     const std::string& what, const std::string& defined_in, schema::Context& ctx);

/// Reports `group` at `key_path` if no particle generator uses it.
void check_group(const std::string& group, const std::set<std::string>& groups,
                 const std::string& key_path, const std::string& fallback, schema::Context& ctx);

}  // namespace ringdem

#include "io/ReferenceChecks.hpp"

#include <algorithm>

namespace ringdem {

void check_reference(const std::string& value, const std::vector<std::string>& names,
                     bool names_reliable, const std::string& key_path, const std::string& fallback,
                     const std::string& what, const std::string& defined_in, schema::Context& ctx) {
  if (ctx.failed(key_path) || std::find(names.begin(), names.end(), value) != names.end()) return;
  if (!names_reliable) return;  // the list itself has errors; do not guess
  std::string message =
      fmt::format("{} '{}'{} is not defined in '{}'", what, value,
                  ctx.given(key_path) ? "" : " (the default, key not given)", defined_in);
  const std::string hint = schema::did_you_mean(value, names);
  if (!hint.empty())
    message += hint;
  else if (names.empty())
    message += " (none defined)";
  else
    message += " (defined: " + schema::join_names(names) + ")";
  ctx.error(ctx.where(key_path, fallback), key_path, message);
}

void check_group(const std::string& group, const std::set<std::string>& groups,
                 const std::string& key_path, const std::string& fallback, schema::Context& ctx) {
  if (ctx.failed(key_path) || groups.count(group) != 0) return;
  const std::vector<std::string> names(groups.begin(), groups.end());
  std::string message = fmt::format("particle group '{}'{} is not used by any particles", group,
                                    ctx.given(key_path) ? "" : " (the default, key not given)");
  const std::string hint = schema::did_you_mean(group, names);
  message += hint.empty() ? " (groups: " + schema::join_names(names) + ")" : hint;
  ctx.error(ctx.where(key_path, fallback), key_path, message);
}

}  // namespace ringdem

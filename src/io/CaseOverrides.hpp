#pragma once

/// The --set overrides of the command line ("key.path=value"), applied to the YAML document of
/// a case file before it is parsed, so that overridden values are checked like any other.

#include <yaml-cpp/yaml.h>

#include <string>
#include <vector>

#include "io/Schema.hpp"

namespace ringdem {

/// Applies each "key.path=value" of `overrides` to `root` in order. Key paths are resolved
/// against the case schema (list entries by index: "a.0.b" or "a[0].b"; the value is parsed as
/// YAML). Malformed or unknown paths are reported to `ctx` at "--set:N:column", N being the
/// 1-based number of the override; every set key is recorded so later errors point at it.
void apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides,
                     schema::Context& ctx);

}  // namespace ringdem

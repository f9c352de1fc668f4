#pragma once

#include <string>
#include <vector>

#include "io/CaseConfig.hpp"
#include "io/InputError.hpp"

namespace ringdem {

/// Reads a case file, applies the --set overrides ("key.path=value"; list entries by index,
/// "rigid_bodies.0.radius=0.02" or "rigid_bodies[0].radius=0.02"; the value is parsed as YAML,
/// e.g. "[0,0,-9.81]"), fills in defaults and validates everything. Throws InputError listing
/// every problem found (syntax errors: the parser's one error). A file that cannot be read is an
/// InputError too. docs/case-file.md documents every key. Input that is valid but most likely
/// a mistake goes into `warnings` when given (Severity::kWarning, ordered as errors are).
CaseConfig load_case(const std::string& path, const std::vector<std::string>& overrides = {},
                     std::vector<Diagnostic>* warnings = nullptr);

/// As load_case, from text; `display_name` is the file name used in messages and for the
/// default case name (its stem).
CaseConfig load_case_from_string(const std::string& yaml_text, const std::string& display_name,
                                 const std::vector<std::string>& overrides = {},
                                 std::vector<Diagnostic>* warnings = nullptr);

/// The resolved configuration (defaults and overrides applied) as YAML that load_case accepts.
std::string dump_case(const CaseConfig& config);

/// Markdown tables of every key of a case file (type, default, allowed range, unit, meaning),
/// generated from the same schema the loader uses; docs/case-file.md embeds it.
std::string describe_case_schema();

}  // namespace ringdem

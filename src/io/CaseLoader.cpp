// Loading a case file: reads the YAML, applies the --set overrides (CaseOverrides), parses and
// checks every key with the schema tables (CaseSchema), runs the cross-key checks
// (CaseValidation) and collects all errors into one InputError.

#include "io/CaseLoader.hpp"

#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/CaseOverrides.hpp"
#include "io/CaseSchema.hpp"
#include "io/CaseValidation.hpp"
#include "io/Schema.hpp"

namespace ringdem {

namespace {

using schema::Context;
using schema::Location;

std::string default_name(const std::string& display_name) {
  const std::string stem = std::filesystem::path(display_name).stem().string();
  return stem.empty() ? "case" : stem;
}

}  // namespace

// ---- public API -------------------------------------------------------------------------------

CaseConfig load_case_from_string(const std::string& yaml_text, const std::string& display_name,
                                 const std::vector<std::string>& overrides,
                                 std::vector<Diagnostic>* warnings) {
  Context ctx(display_name);
  CaseConfig config;
  try {
    YAML::Node root;
    try {
      root = YAML::Load(yaml_text);
    } catch (const YAML::ParserException& e) {
      throw InputError({Diagnostic{display_name, e.mark.line + 1, e.mark.column + 1, "",
                                   "invalid YAML: " + e.msg}});
    }
    if (!root.IsDefined() || root.IsNull()) root.reset(YAML::Node(YAML::NodeType::Map));
    apply_overrides(root, overrides, ctx);
    config.source_path = display_name;  // validation finds files named relative to the case
    case_schema().parse(config, root, root, "", ctx);
    cross_validate_case(config, ctx);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    ctx.error(Location{display_name, 0, 0}, "",
              std::string("internal error while reading the case: ") + e.what());
  }
  if (!ctx.diagnostics().empty()) throw InputError(ctx.sorted_diagnostics());
  if (warnings != nullptr) *warnings = ctx.sorted_warnings();
  if (config.name.empty()) config.name = default_name(display_name);
  config.source_path = display_name;
  return config;
}

CaseConfig load_case(const std::string& path, const std::vector<std::string>& overrides,
                     std::vector<Diagnostic>* warnings) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  std::string problem;
  if (!std::filesystem::exists(status))
    problem = "case file not found";
  else if (std::filesystem::is_directory(status))
    problem = "is a directory, not a case file";
  std::string text;
  if (problem.empty()) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (!in && !in.eof())
      problem = "cannot read the case file";
    else
      text = buffer.str();
  }
  if (!problem.empty()) throw InputError({Diagnostic{path, 0, 0, "", problem}});
  return load_case_from_string(text, path, overrides, warnings);
}

std::string dump_case(const CaseConfig& config) {
  YAML::Emitter out;
  out.SetIndent(2);
  case_schema().dump(config, out);
  return std::string(out.c_str()) + "\n";
}

std::string describe_case_schema() {
  return schema::markdown_reference(case_schema().info(), "Top level");
}

}  // namespace ringdem

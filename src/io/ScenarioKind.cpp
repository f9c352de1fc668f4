#include "io/ScenarioKind.hpp"

#include <array>
#include <stdexcept>
#include <string>
#include <utility>

namespace ringdem {

namespace {

/// The only place scenario names are compared.
constexpr std::array<std::pair<const char*, ScenarioKind>, 3> kScenarioNames{{
    {"free_run", ScenarioKind::kFreeRun},
    {"tensile_test", ScenarioKind::kTensileTest},
    {"rockfall", ScenarioKind::kRockfall},
}};

}  // namespace

ScenarioKind scenario_kind(const CaseConfig& config) {
  for (const auto& [name, kind] : kScenarioNames)
    if (config.scenario.type == name) return kind;
  throw std::invalid_argument("unknown scenario.type '" + config.scenario.type + "'");
}

const char* scenario_name(ScenarioKind kind) {
  for (const auto& [name, k] : kScenarioNames)
    if (k == kind) return name;
  throw std::logic_error("scenario kind missing from the table");
}

}  // namespace ringdem

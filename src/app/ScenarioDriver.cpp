#include "app/ScenarioDriver.hpp"

#include <array>
#include <stdexcept>

#include "app/FreeRunDriver.hpp"
#include "app/RockfallDriver.hpp"
#include "app/TensileDriver.hpp"

namespace ringdem {

namespace {

struct ScenarioEntry {
  const char* name;  ///< scenario.type in case files
  ScenarioKind kind;
  std::unique_ptr<ScenarioDriver> (*make)(const CaseConfig&);
};

template <class Driver>
std::unique_ptr<ScenarioDriver> make(const CaseConfig& config) {
  return std::make_unique<Driver>(config);
}

/// The only place scenario names are compared.
constexpr std::array<ScenarioEntry, 3> kScenarios{{
    {"free_run", ScenarioKind::kFreeRun, &make<FreeRunDriver>},
    {"tensile_test", ScenarioKind::kTensileTest, &make<TensileDriver>},
    {"rockfall", ScenarioKind::kRockfall, &make<RockfallDriver>},
}};

const ScenarioEntry& entry_of(const CaseConfig& config) {
  for (const ScenarioEntry& e : kScenarios)
    if (config.scenario.type == e.name) return e;
  throw std::invalid_argument("unknown scenario.type '" + config.scenario.type + "'");
}

}  // namespace

ScenarioKind scenario_kind(const CaseConfig& config) {
  return entry_of(config).kind;
}

const char* scenario_name(ScenarioKind kind) {
  for (const ScenarioEntry& e : kScenarios)
    if (e.kind == kind) return e.name;
  throw std::logic_error("scenario kind missing from the table");
}

std::unique_ptr<ScenarioDriver> make_scenario_driver(const CaseConfig& config) {
  return entry_of(config).make(config);
}

}  // namespace ringdem

#include "app/ScenarioDriver.hpp"

#include <array>
#include <stdexcept>
#include <string>

#include "app/FreeRunDriver.hpp"
#include "app/RockfallDriver.hpp"
#include "app/TensileDriver.hpp"
#include "engine/ModelBuilder.hpp"

namespace ringdem {

namespace {

template <class Driver>
std::unique_ptr<ScenarioDriver> make(const CaseConfig& config) {
  return std::make_unique<Driver>(config);
}

/// The driver of each scenario kind (io/ScenarioKind.hpp reads the names).
struct ScenarioEntry {
  ScenarioKind kind;
  std::unique_ptr<ScenarioDriver> (*make)(const CaseConfig&);
};
constexpr std::array<ScenarioEntry, 3> kDrivers{{
    {ScenarioKind::kFreeRun, &make<FreeRunDriver>},
    {ScenarioKind::kTensileTest, &make<TensileDriver>},
    {ScenarioKind::kRockfall, &make<RockfallDriver>},
}};

}  // namespace

std::unique_ptr<ScenarioDriver> make_scenario_driver(const CaseConfig& config) {
  const ScenarioKind kind = scenario_kind(config);
  for (const ScenarioEntry& e : kDrivers)
    if (e.kind == kind) return e.make(config);
  throw std::logic_error(std::string("no driver for scenario ") + scenario_name(kind));
}

Model build_scenario_model(const CaseConfig& config, const Communicator& comm) {
  Model model = build_model(config, comm);
  make_scenario_driver(config)->prepare_model(model);
  return model;
}

}  // namespace ringdem

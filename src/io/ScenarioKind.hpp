#pragma once

#include "io/CaseConfig.hpp"

namespace ringdem {

/// The scenarios a case file can name in `scenario.type`. The names are read in one place
/// (ScenarioKind.cpp); the drivers are made from the kind by the table in app/ScenarioDriver.cpp.
enum class ScenarioKind { kFreeRun, kTensileTest, kRockfall };

/// The scenario of a case (throws std::invalid_argument for a name the table does not hold).
ScenarioKind scenario_kind(const CaseConfig& config);
/// The name of a scenario in case files and in summary.json.
const char* scenario_name(ScenarioKind kind);

}  // namespace ringdem

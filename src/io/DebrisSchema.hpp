#pragma once

/// The schema tables of the debris entries of a case file: `particles.grains[]` (with their
/// size distributions), `outflow[]`, `inflow[]` and `scenario.barrier`. Declarations of keys only;
/// the checks that relate keys to each other are in io/GrainsInput.cpp.

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

const schema::Table<GrainsConfig>& grains_table();
const schema::Table<OutflowConfig>& outflow_table();
const schema::Table<SphereFileConfig>& sphere_file_table();
const schema::Table<InflowConfig>& inflow_table();
const schema::Table<BarrierConfig>& barrier_table();

}  // namespace ringdem

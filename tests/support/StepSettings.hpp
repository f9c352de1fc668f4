#pragma once

#include "engine/Simulation.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem::testing {

/// A case's settings with the time step and the neighbour skin that a test chooses.
inline SimulationSettings settings_at(const CaseConfig& c, double dt, double skin = 0.001) {
  SimulationSettings s = settings_from_case(c);
  s.dt = dt;
  s.skin = skin;
  return s;
}

}  // namespace ringdem::testing

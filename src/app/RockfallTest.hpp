#pragma once

#include <string>

#include "app/RunCommand.hpp"
#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

/// Radius of a sphere of `mass` and `density`.
double sphere_radius(double mass, double density);

/// Scenario `rockfall` (docs/rockfall.md): the net sags under gravity until its kinetic energy
/// falls below a threshold, then a spherical boulder is released `drop_height` above the sagged
/// net and the run goes on for `duration` after its first contact. Writes series.csv (time from
/// first contact, boulder motion and acceleration, frame force, broken bonds, energies and the
/// energy ledger), sag.csv and summary.json; frames and checkpoints as the output section says.
/// Returns the exit code (kExitCheckpointed after a requested stop).
int run_rockfall(const CaseConfig& config, const RunOptions& options, const std::string& out_dir,
                 const Communicator& comm);

}  // namespace ringdem

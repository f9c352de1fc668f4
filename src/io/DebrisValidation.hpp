#pragma once

/// Cross-key checks of a debris flow's parts: the inlets, the outflow boxes and the barrier
/// (docs/debris.md). The grain boxes and sizes that inlets share with release volumes are
/// GrainsInput's.

#include <set>
#include <string>

#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// Cross-key checks of the inlet at path `p`: its box and sizes as for grains, a velocity, a
/// solid fraction that random sequential addition reaches, an end after the start; a warning
/// when it opens only after the run has ended (`run_duration`, CaseMagnitudes.hpp).
void validate_inflow(const InflowConfig& inflow, const std::string& p, double run_duration,
                     schema::Context& ctx);

/// Cross-key checks of outflow box i (after its groups are known to exist):
/// - its box_max above its box_min;
/// - its groups against what it can take, free particles in no ring: a group of ring particles
///   only (a net's, its shackles') is an error, as the box would do nothing with it;
/// - the grain sources (`particles.grains`, `inflow`) of the groups it takes against its box:
///   a source box wholly outside it is an error (every grain would be taken out at its first
///   step), one that reaches out of it a warning (some would).
void validate_outflow(const CaseConfig& c, std::size_t i, schema::Context& ctx);

/// scenario.barrier: a free run's; its groups and bodies defined (`groups`: those some particles
/// use; `bodies_ok`: the rigid bodies' names are reliable); the bed a plane and no post; the
/// net's and the frame's groups none of the flow's. Normalises its direction.
void validate_barrier(CaseConfig& c, schema::Context& ctx, const std::set<std::string>& groups,
                      bool bodies_ok);

}  // namespace ringdem

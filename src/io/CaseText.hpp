#pragma once

#include <string>
#include <utility>
#include <vector>

#include "io/CaseConfig.hpp"

namespace ringdem {

/// One key of a case in canonical form: its path and its value as text.
struct CaseKey {
  std::string path;  ///< "simulation.dt", "bonds[ring].youngs_modulus", "particles.rings[0].centre"
  std::string value;  ///< as the resolved-configuration dump writes it (round-trip numbers)
};

/// The resolved case (defaults, derived values and --set overrides applied) flattened to one
/// "path = value" line per key, in schema order, from the same dump as `ringdem run` prints
/// (dump_case), so numbers have their full round-trip precision. A list of maps gives a line
/// "path = N entries" and its entries' keys under "path[label]", the label being the entry's
/// `name` when it has one (materials, bonds, rigid bodies) and its index otherwise; a list of
/// scalars (a vector) is one value "[x, y, z]". Newlines and backslashes in values are escaped,
/// so every key is one line. Checkpoints store it (io/Checkpoint) to compare the case they
/// were written by with the case a restart is given (io/RestartChanges).
std::string canonical_case_text(const CaseConfig& config);

/// The keys of a canonical text, in order. Lines without " = " are ignored.
std::vector<CaseKey> case_text_keys(const std::string& text);

}  // namespace ringdem

#pragma once

#include <cstdint>

#include "domain/ContactHistory.hpp"

namespace ringdem {

/// What a checkpoint restores besides the particle, bond and body fields (io/Checkpoint).
struct RestartState {
  double time = 0.0;
  std::int64_t steps = 0;
  double dt = 0.0;
  std::int64_t rebuilds = 0;
  ContactHistory history;  ///< every tangential spring once (any rank may hold any entry)
};

}  // namespace ringdem

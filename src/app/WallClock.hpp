#pragma once

#include <chrono>

namespace ringdem {

/// The clock of the progress lines and the wall times that runs report.
using WallClock = std::chrono::steady_clock;

/// Seconds of wall time since `start`.
inline double seconds_since(WallClock::time_point start) {
  return std::chrono::duration<double>(WallClock::now() - start).count();
}

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace ringdem {

/// The run diverged: a particle or body moved farther in one step than contacts can be
/// tracked, or its state is not finite. Thrown by Simulation::step on every rank at the same
/// step, with the same message (what, where, when and the likely cause).
class DivergenceError : public std::runtime_error {
 public:
  DivergenceError(const std::string& what, std::int64_t step, double time)
      : std::runtime_error(what), step_(step), time_(time) {}
  std::int64_t step() const { return step_; }
  double time() const { return time_; }

 private:
  std::int64_t step_;
  double time_;
};

}  // namespace ringdem

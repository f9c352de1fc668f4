#pragma once

#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

struct RunOptions {
  std::string case_path;
  std::string output_dir;  ///< empty: results/<case name>
  std::vector<std::string> overrides;
  bool quiet = false;
};

/// `ringdem run`: builds the case, prints the banner, configuration and pre-flight numbers,
/// steps to the end time with progress lines, and writes series.csv and summary.json.
/// Returns the process exit code.
int run_case(const CaseConfig& config, const RunOptions& options, const Communicator& comm);

}  // namespace ringdem

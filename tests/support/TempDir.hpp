#pragma once

#include <stdlib.h>

#include <filesystem>
#include <stdexcept>
#include <string>

namespace ringdem::testing {

/// A new, empty directory under the system's temporary directory, named ringdem_<tag>_XXXXXX;
/// the test removes it.
inline std::string temp_dir(const std::string& tag) {
  std::string templ =
      (std::filesystem::temp_directory_path() / ("ringdem_" + tag + "_XXXXXX")).string();
  if (!mkdtemp(templ.data())) throw std::runtime_error("mkdtemp failed for " + templ);
  return templ;
}

}  // namespace ringdem::testing

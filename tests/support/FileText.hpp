#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace ringdem::testing {

/// The whole contents of a file ("" when it cannot be read): results that a test compares byte
/// for byte with another run's.
inline std::string file_text(const std::filesystem::path& file) {
  std::stringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

}  // namespace ringdem::testing

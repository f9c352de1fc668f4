#pragma once

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace ringdem::testing {

/// The whole contents of a file: results that a test compares byte for byte with another
/// run's. A file that cannot be read throws, so that two missing files never compare equal.
inline std::string file_text(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw std::runtime_error("cannot read " + file.string());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace ringdem::testing

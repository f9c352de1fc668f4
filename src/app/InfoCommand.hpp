#pragma once

#include <ostream>
#include <string>

namespace ringdem {

/// `ringdem info FILE`: what a frame or checkpoint file holds (kind, version, case, counts,
/// times, datasets and their shapes; checkpoints are checked against their checksums).
/// Returns the exit code: 0, or 2 for a file that cannot be read.
int print_file_info(const std::string& path, std::ostream& out);

/// Seconds from "3600", "90m", "2h", "1h30m" or "H:MM:SS". Throws std::invalid_argument.
double parse_duration(const std::string& text);

}  // namespace ringdem

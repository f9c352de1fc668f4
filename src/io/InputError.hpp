#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace ringdem {

/// An error stops the loading (InputError); a warning is input that is valid but most likely
/// not what was meant (an inlet that opens after the run ends), reported and run as it is.
enum class Severity { kError, kWarning };

/// One problem found in an input file, located as precisely as the parser allows.
/// line and column are 1-based; 0 means "no position" (e.g. a file that cannot be opened).
/// Values that came from a command-line override are reported with file "--set", line = the
/// 1-based number of the override and column = the column inside "key=value".
struct Diagnostic {
  std::string file;
  int line = 0;
  int column = 0;
  std::string key_path;  ///< e.g. "particles.rings[0].particle_radius"; empty for syntax errors
  std::string message;   ///< includes the offending value and the allowed range or choices
  Severity severity = Severity::kError;
};

/// "file:line:col: error: key.path: message" ("warning:" for a warning; position and key path
/// left out when unknown).
inline std::string format_diagnostic(const Diagnostic& d) {
  std::string out = d.file;
  if (d.line > 0) {
    out += ':' + std::to_string(d.line);
    if (d.column > 0) out += ':' + std::to_string(d.column);
  }
  out += d.severity == Severity::kWarning ? ": warning: " : ": error: ";
  if (!d.key_path.empty()) out += d.key_path + ": ";
  out += d.message;
  return out;
}

inline std::string format_diagnostics(const std::vector<Diagnostic>& diagnostics) {
  std::string out;
  for (const Diagnostic& d : diagnostics)
    out += format_diagnostic(d) + '\n';
  return out;
}

/// Every problem of an input file at once. The command line prints format() to stderr and
/// exits with code 2.
class InputError : public std::runtime_error {
 public:
  explicit InputError(std::vector<Diagnostic> diags)
      : std::runtime_error(format_diagnostics(diags)), diagnostics(std::move(diags)) {}

  std::vector<Diagnostic> diagnostics;

  /// One line per diagnostic, each ending in '\n'.
  std::string format() const { return format_diagnostics(diagnostics); }
};

}  // namespace ringdem

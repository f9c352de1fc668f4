#pragma once

/// What a case folder of a parameter study records about its case, so that `ringdem sweep
/// --restart` can tell the cases that are done from those still to run, and refuse a folder
/// that holds another study's cases:
/// - `sweep_case.txt`, written when the case starts: the overrides that make it, one a line;
/// - `sweep_case_resolved.txt`, written with it: the resolved case (io/CaseText), so that a
///   restart sees a case file or sweep file edited since a case was run;
/// - `sweep_row.csv`, written when it ends (or is not started): its row of sweep.csv, a line of
///   column names and a line of values.

#include <optional>
#include <string>
#include <vector>

namespace ringdem {

/// Exit code recorded for a case that was not started because the study had to stop (SIGUSR1 or
/// the study's wall-time limit), the same as a case that stopped with a checkpoint.
inline constexpr int kExitCaseNotStarted = 3;

struct SweepCaseRecord {
  /// The overrides of sweep_case.txt; empty when the file is missing (a case not yet started,
  /// or a folder written before the file existed).
  std::optional<std::vector<std::string>> overrides;
  /// The resolved case of sweep_case_resolved.txt; empty when the file is missing (written by
  /// an older ringdem).
  std::optional<std::string> case_text;
  std::string header;  ///< sweep_row.csv's column names; empty when there is no row
  std::string values;  ///< sweep_row.csv's values

  bool has_row() const { return !header.empty(); }
  /// The row's exit code: its `exit_code` column, or 0 for a tensile test's row (which is
  /// written only when the test has ended). Needs has_row().
  int exit_code() const;
  /// A row that the study keeps on a restart: any but a stopped or not started case's (exit
  /// code 3). A failed case (exit 1) is kept: running it again fails again; remove its folder to
  /// run it anew.
  bool finished() const { return has_row() && exit_code() != kExitCaseNotStarted; }
};

/// Reads the record of the case folder `dir` (missing files leave their fields empty).
SweepCaseRecord read_case_record(const std::string& dir);
/// Writes sweep_case.txt and sweep_case_resolved.txt (creates the folder).
void write_case_start(const std::string& dir, const std::vector<std::string>& overrides,
                      const std::string& case_text);
/// Writes sweep_row.csv (creates the folder).
void write_case_row(const std::string& dir, const std::string& header, const std::string& values);

}  // namespace ringdem

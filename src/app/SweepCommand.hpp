#pragma once

/// `ringdem sweep SWEEP.yaml`: a parameter study over the keys of one case file. The cases are
/// spread over the MPI ranks (case i on rank i mod size, each run on one rank), each writes
/// its own folder, and rank 0 writes a combined table. docs/tensile.md describes the file.

#include <optional>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"
#include "io/Schema.hpp"

namespace ringdem {

/// Values of one swept key: a list, or a range from..to in `count` steps.
struct SweepParameterConfig {
  std::string key;  ///< a --set key path of the case, e.g. bonds.0.youngs_modulus
  std::vector<std::string> values;
  struct Range {
    double from = 0.0;
    double to = 0.0;
    int count = 2;
    std::string spacing = "linear";  ///< linear | log
  };
  std::optional<Range> range;
  /// Where each value (parameter_values()) stands in the sweep file: its list entry, or the
  /// range it comes from. A case's errors from the value point there (load_sweep_cases()).
  std::vector<schema::Location> value_at;
};

struct SweepConfig {
  int schema_version = 1;
  std::string name;
  std::string case_path;         ///< relative to the sweep file
  std::vector<std::string> set;  ///< overrides applied to every case: the file's, then --set's
  std::vector<schema::Location> set_at;  ///< where each of the file's own `set` entries stands
  std::vector<SweepParameterConfig> parameters;
  std::string combine = "product";  ///< product (every combination) | zip (i-th with i-th)
  std::string source_path;
};

/// One case of the study: the overrides that make it and its folder name.
struct SweepCase {
  std::string folder;                         ///< case_000, case_001, ...
  std::vector<std::string> parameter_values;  ///< one per parameter, as given
  std::vector<std::size_t> value_index;       ///< one per parameter: which of its values
  std::vector<std::string> overrides;         ///< common set + key=value per parameter
};

/// Reads and validates a sweep file (InputError with file:line:col on errors).
SweepConfig load_sweep(const std::string& path, const std::vector<std::string>& overrides = {});
SweepConfig load_sweep_from_string(const std::string& yaml_text, const std::string& display_name,
                                   const std::vector<std::string>& overrides = {});

/// The values of a parameter: the list, or the range expanded.
std::vector<std::string> parameter_values(const SweepParameterConfig& parameter);
/// Every case of the study, in order (product: the last parameter varies fastest).
std::vector<SweepCase> expand_sweep(const SweepConfig& sweep);

/// Each case's configuration, loaded and checked before any runs (cheap), so that a bad value
/// stops the study at once. An error of a case says which case it is in, and an error of one of
/// its overrides points where the sweep gave it: the parameter's value or the `set` entry in the
/// sweep file, or the command line's --set (InputError). The cases' warnings, located alike,
/// go into `warnings` when given: each once, with the cases it comes from ("in every case").
std::vector<CaseConfig> load_sweep_cases(const SweepConfig& sweep,
                                         const std::vector<SweepCase>& cases,
                                         std::vector<Diagnostic>* warnings = nullptr);

/// Whether the file at `path` is a sweep file (a YAML map with `parameters` and `case`), which
/// `ringdem check` validates with every case instead of as a case file. False for anything
/// else, a file that is not YAML included: loading it as a case reports that.
bool is_sweep_file(const std::string& path);

struct SweepOptions {
  std::string sweep_path;
  std::string output_dir;              ///< empty: results/<sweep name>
  std::vector<std::string> overrides;  ///< applied to every case after the sweep's own `set`
  bool quiet = false;
  bool break_lock = false;  ///< take over a lock of the output folder held on another host
  /// Continue a study in its output folder: keep the cases that are done (their sweep_row.csv),
  /// continue a stopped case from its newest checkpoint, start the others (SweepCaseRecord).
  bool restart = false;
  /// Wall seconds for the whole study (0: no limit): a case running when they are spent writes a
  /// checkpoint and stops; the cases after it do not start. Both exit with code 3.
  double max_walltime = 0.0;
  /// Ranks that run each case together (a divisor of the job's rank count): the next case goes
  /// to the first group of them that comes free.
  int ranks_per_case = 1;
};

/// Runs the study; returns the exit code: the largest of the cases' (a case that is no tensile
/// test runs as `ringdem run` runs it: 1 diverged or failed, 3 stopped with a checkpoint; 3 also
/// for a case not started because the study was asked to stop: SIGUSR1, max_walltime). Writes
/// OUT/case_NNN/{summary.json, series.csv} per case and OUT/sweep.csv (one row per case: its
/// parameters and its summary numbers; for a case that is no tensile test its exit code and
/// every number of its summary.json).
int run_sweep(const SweepOptions& options, const Communicator& world);

}  // namespace ringdem

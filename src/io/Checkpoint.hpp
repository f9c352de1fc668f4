#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "engine/Model.hpp"
#include "engine/RestartState.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem {

/// Named numbers a scenario driver needs to continue (next record time, peak values, phase).
struct DriverState {
  std::vector<std::string> names;
  std::vector<double> values;
  void set(const std::string& name, double v);
  /// The value, or `fallback` when the checkpoint did not hold it.
  double get(const std::string& name, double fallback = 0.0) const;
};

/// What a checkpoint says about itself (root attributes).
struct CheckpointInfo {
  std::string path;
  std::int64_t format_version = 0;
  std::string version;  ///< of the ringdem that wrote it
  std::string case_name;
  double time = 0.0;
  double dt = 0.0;
  std::int64_t step = 0;
  std::int64_t rebuilds = 0;
  std::int64_t segment = 0;  ///< frame-file segment that was being written
  std::int64_t ranks = 0;    ///< rank count that wrote it
  std::int64_t particles = 0;
  std::int64_t bonds = 0;
  std::int64_t bodies = 0;
  std::int64_t history_entries = 0;
  /// Sub-steps of dt (simulation.substeps) in a sub-stepped run's checkpoint, whose dt is the
  /// grain step; 1 for one rate.
  std::int64_t substeps = 1;
  std::int64_t dt_origin_step = 0;  ///< RestartState::dt_origin_step
  double dt_origin_time = 0.0;
  /// The case it was written by, as canonical text (io/CaseText), checked against its
  /// checksum, and the model fingerprint of that text (io/RestartChanges).
  std::string case_text;
  std::string model_fingerprint;
};

/// Checkpoints (DESIGN §5): every piece of state the next step reads — particle and bond fields
/// flagged kCheckpoint in the registries (rows by gid and bond id, so the file does not depend
/// on the rank count), each contact term's springs, the rigid bodies, time, step, dt and the
/// driver's state — written collectively to "<name>.tmp" and renamed, with a checksum per dataset.
class CheckpointStore {
 public:
  /// `dir` is created by rank 0 if missing; `keep` newest checkpoints are kept.
  CheckpointStore(std::string dir, int keep = 2);

  /// Collective: writes `model`'s fields and `state` (Simulation::restart_state(), whose
  /// springs are each rank's owned contacts), and `config`, the case the model was built
  /// from, as canonical text with its model fingerprint (a restart compares it with the case
  /// it is given). Returns the final path.
  std::string write(const Communicator& comm, Model& model, const RestartState& state,
                    const DriverState& driver, std::int64_t segment,
                    const CaseConfig& config) const;

  /// Checkpoints in `dir`, oldest first.
  std::vector<std::string> list() const;
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
  int keep_;
};

/// Collective: reads a checkpoint into `model` (built from `config` without particles,
/// build_model_without_particles) and returns the simulation state; fills `driver`. Each rank
/// reads one block of the particle, bond and spring rows (no rank reads them all); the
/// Simulation's first distribution moves them to their owners. Rigid bodies and the driver
/// state are read by every rank. The row counts are the checkpoint's own (particles may have
/// come and gone since the start); it belongs to `config` when its model fingerprint matches
/// its case text and that case's kFixed keys are those of `config` (io/RestartChanges,
/// model_identity). Throws Hdf5Error with a clear message for a missing, truncated, incomplete
/// or corrupted file, or one of another case.
RestartState read_checkpoint(const Communicator& comm, const std::string& path,
                             const CaseConfig& config, Model& model, DriverState& driver,
                             CheckpointInfo* info = nullptr);

/// Root attributes and the case text (ringdem info, --restart auto). Throws Hdf5Error for a file
/// that is no complete checkpoint of a format version this ringdem reads (11 to 13: the list of
/// versions and what each added is at kFormatVersion in io/Checkpoint.cpp).
CheckpointInfo read_checkpoint_info(const std::string& path);

/// Checks every dataset of a checkpoint against its checksum; returns the dataset names checked.
/// Throws Hdf5Error naming the first dataset that fails.
std::vector<std::string> verify_checkpoint(const std::string& path);

/// `--restart auto`: the newest checkpoint in `dir` that validates, or "" when none.
/// Unreadable newer ones are reported in `skipped`.
std::string latest_valid_checkpoint(const std::string& dir, std::vector<std::string>* skipped);

}  // namespace ringdem

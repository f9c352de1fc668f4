#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace ringdem {

/// What a restart does with a key whose value differs between the case a checkpoint was written
/// by and the case it is continued with.
enum class RestartKeyKind {
  kFree,     ///< may change: it does not alter the saved state or the physics (end time, output)
  kApplied,  ///< applied from the restart on, only with `ringdem run --allow-changes`
  kFixed,    ///< defines the model the saved state belongs to: refused, even with --allow-changes
};

/// What applying a kApplied key takes besides reading the case again.
enum class RestartEffect {
  kNone,      ///< the restart reads it from the case (contact coefficients, skin, thresholds)
  kTimeStep,  ///< the time step is chosen again (Simulation::change_time_step)
  kDamping,   ///< the particles' damping coefficients are set again from the damping section
};

/// One row of the table of keys (docs/output.md, "What may change on a restart").
struct RestartKeyRule {
  std::string_view pattern;  ///< key path; '*' matches any text (also dots and brackets)
  RestartKeyKind kind;
  RestartEffect effect;
  std::string_view note;  ///< why, for the messages
};

/// The one table: the first row whose pattern matches a key's path (CaseText paths) decides;
/// the last row ("*") makes every other key kFixed.
const std::vector<RestartKeyRule>& restart_key_rules();
const RestartKeyRule& restart_rule_of(const std::string& path);

/// A key that differs; `before` or `after` is empty when the key is absent on that side.
struct CaseChange {
  std::string path;
  std::string before;  ///< in the checkpoint's case
  std::string after;   ///< in the case given now
  const RestartKeyRule* rule = nullptr;
};

/// Every key of two canonical case texts (io/CaseText) that differs, in the order of `after`
/// (keys only in `before` last).
std::vector<CaseChange> case_changes(const std::string& before, const std::string& after);

/// Fingerprint of the model a case defines: a 64-bit FNV-1a hash, as 16 hex digits, of the
/// canonical lines of every key that is not kFree (what a restart compares).
std::string model_fingerprint(const std::string& canonical_text);

/// The same hash over the kFixed keys alone: the identity of the model a checkpoint's state
/// belongs to, equal on both sides of every restart that may go on (read_checkpoint checks it;
/// kApplied keys may differ with --allow-changes).
std::string model_identity(const std::string& canonical_text);

/// The verdict on a restart's changes. Throws InputError (exit code 2), one line per key, when a
/// kFixed key differs, or a kApplied one without `allow_changes`. `case_file` and `checkpoint`
/// name the two sides in the messages.
void check_restart_changes(const std::vector<CaseChange>& changes, bool allow_changes,
                           const std::string& case_file, const std::string& checkpoint);

/// The table as Markdown (docs/output.md embeds it; a unit test compares).
std::string describe_restart_rules();

/// "simulation.end_time 0.06 -> 0.1" for the log.
std::string describe_change(const CaseChange& change);

}  // namespace ringdem

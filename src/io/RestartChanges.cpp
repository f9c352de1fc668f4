#include "io/RestartChanges.hpp"

#include <fmt/format.h>

#include <map>

#include "io/CaseText.hpp"
#include "io/Hdf5File.hpp"
#include "io/InputError.hpp"

namespace ringdem {

namespace {

using K = RestartKeyKind;
using E = RestartEffect;

/// Glob match: '*' matches any run of characters.
bool matches(std::string_view pattern, std::string_view text) {
  if (pattern.empty()) return text.empty();
  if (pattern.front() == '*') {
    for (std::size_t skip = 0; skip <= text.size(); ++skip)
      if (matches(pattern.substr(1), text.substr(skip))) return true;
    return false;
  }
  return !text.empty() && pattern.front() == text.front() &&
         matches(pattern.substr(1), text.substr(1));
}

std::string shown(const std::string& value) {
  return value.empty() ? std::string("(absent)") : value;
}

}  // namespace

const std::vector<RestartKeyRule>& restart_key_rules() {
  constexpr std::string_view kNextRow = "rows of series.csv from the next one on";
  constexpr std::string_view kContact = "contact coefficients from the restart on";
  constexpr std::string_view kRestTest = "the net's rest test from the restart on";
  static const std::vector<RestartKeyRule> rules{
      // May change on any restart: they neither alter the saved state nor the physics.
      {"name", K::kFree, E::kNone, "a label"},
      {"description", K::kFree, E::kNone, "free text"},
      {"simulation.end_time", K::kFree, E::kNone, "where the run stops"},
      {"simulation.progress_interval", K::kFree, E::kNone, "progress lines"},
      {"simulation.series_interval", K::kFree, E::kNone, kNextRow},
      {"simulation.allow_initial_overlap", K::kFree, E::kNone, "read at a fresh start only"},
      {"simulation.initial_overlap_tolerance", K::kFree, E::kNone, "read at a fresh start only"},
      {"output.*", K::kFree, E::kNone, "frames and checkpoints from the restart on"},
      {"scenario.tensile_test.max_displacement", K::kFree, E::kNone, "where the test stops"},
      {"scenario.tensile_test.record_interval", K::kFree, E::kNone, kNextRow},
      {"scenario.rockfall.duration", K::kFree, E::kNone, "where the run stops"},
      {"scenario.rockfall.record_interval", K::kFree, E::kNone, kNextRow},
      // Applied from the restart on with --allow-changes: the run then differs from one that
      // never stopped, so it must be asked for.
      {"simulation.dt", K::kApplied, E::kTimeStep, "the new time step from the restart on"},
      {"simulation.dt_safety", K::kApplied, E::kTimeStep,
       "with an automatic dt, the time step is chosen again"},
      {"simulation.skin", K::kApplied, E::kNone, "neighbour lists from the restart on"},
      {"simulation.imbalance_threshold", K::kApplied, E::kNone,
       "repartitioning from the restart on"},
      {"simulation.sort_every", K::kApplied, E::kNone,
       "the grains' re-sorts from the restart on (the order of summation, at round-off)"},
      {"simulation.substeps", K::kFixed, E::kNone,
       "the grain step is part of the trajectory, and the checkpoint holds the slow loads of "
       "the last one (docs/physics.md \"Two time scales\")"},
      {"simulation.energy_ledger", K::kApplied, E::kNone,
       "the ledger books from the restart on; a free run's energy balance then counts from the "
       "restart"},
      {"damping.*", K::kApplied, E::kDamping, "damping coefficients from the restart on"},
      {"materials[*].youngs_modulus", K::kApplied, E::kTimeStep,
       "contact stiffness from the restart on (an automatic dt is chosen again)"},
      {"materials[*].poisson_ratio", K::kApplied, E::kTimeStep,
       "contact stiffness from the restart on (an automatic dt is chosen again)"},
      {"materials[*].restitution", K::kApplied, E::kNone, kContact},
      {"materials[*].friction", K::kApplied, E::kNone, kContact},
      {"materials[*].rolling_friction", K::kApplied, E::kNone, kContact},
      {"interactions*", K::kApplied, E::kNone, kContact},
      {"scenario.tensile_test.failure_load_fraction", K::kApplied, E::kNone,
       "the failure criterion from the restart on"},
      {"scenario.rockfall.sag_damping", K::kApplied, E::kNone,
       "the net's damping while it sags, from the restart on"},
      {"scenario.rockfall.impact_damping", K::kApplied, E::kNone,
       "the net's damping after the release, from the restart on"},
      {"scenario.rockfall.sag_max_time", K::kApplied, E::kNone, kRestTest},
      {"scenario.rockfall.sag_dt", K::kApplied, E::kNone,
       "the time step while the net sags or re-settles, from the restart on"},
      {"scenario.rockfall.sag_min_time", K::kApplied, E::kNone, kRestTest},
      {"scenario.rockfall.sag_kinetic_energy", K::kApplied, E::kNone, kRestTest},
      {"scenario.rockfall.sag_check_interval", K::kApplied, E::kNone, kRestTest},
      {"scenario.rockfall.resettle_max_time", K::kApplied, E::kNone, kRestTest},
      // A mesh holds no state of its own between steps beyond what its next rebuild finds.
      {"particles.nets[*].mesh.stiffness", K::kApplied, E::kTimeStep,
       "the nets' secondary mesh from the restart on (an automatic dt is chosen again)"},
      {"particles.nets[*].mesh.damping_ratio", K::kApplied, E::kNone,
       "the nets' secondary mesh from the restart on"},
      {"particles.nets[*].mesh.opening", K::kApplied, E::kNone,
       "which grains the nets' secondary mesh holds, from the restart on"},
      // The model the saved state belongs to: refused even with --allow-changes.
      {"particles*", K::kFixed, E::kNone,
       "the particles and bonds were created from it; the checkpoint holds their state"},
      {"bonds*", K::kFixed, E::kNone,
       "each bond's stiffness and strengths were set when it was created and are saved with it"},
      {"materials*", K::kFixed, E::kNone,
       "particle masses and material numbers are saved with the particles"},
      {"rigid_bodies*", K::kFixed, E::kNone,
       "defines the rigid bodies (shape, size, mass, material, motion) whose state the "
       "checkpoint holds"},
      {"simulation.gravity", K::kFixed, E::kNone, "the loads and energies of the saved state"},
      {"simulation.contact_model", K::kFixed, E::kNone,
       "the contact law whose tangential springs the checkpoint holds"},
      {"scenario*", K::kFixed, E::kNone, "the scenario's state is restored from the checkpoint"},
      {"*", K::kFixed, E::kNone, "defines the model"},
  };
  return rules;
}

const RestartKeyRule& restart_rule_of(const std::string& path) {
  for (const RestartKeyRule& rule : restart_key_rules())
    if (matches(rule.pattern, path)) return rule;
  return restart_key_rules().back();
}

std::vector<CaseChange> case_changes(const std::string& before, const std::string& after) {
  std::map<std::string, std::string> old_values;
  for (CaseKey& k : case_text_keys(before))
    old_values[k.path] = std::move(k.value);
  std::vector<CaseChange> changes;
  for (const CaseKey& k : case_text_keys(after)) {
    const auto it = old_values.find(k.path);
    if (it == old_values.end()) {
      changes.push_back({k.path, "", k.value, &restart_rule_of(k.path)});
      continue;
    }
    if (it->second != k.value)
      changes.push_back({k.path, it->second, k.value, &restart_rule_of(k.path)});
    old_values.erase(it);
  }
  for (const CaseKey& k : case_text_keys(before))
    if (old_values.count(k.path))
      changes.push_back({k.path, k.value, "", &restart_rule_of(k.path)});
  return changes;
}

namespace {

/// FNV-1a over the canonical lines of the keys whose rule is at least `least` (kFree < kApplied
/// < kFixed).
std::string keys_hash(const std::string& canonical_text, RestartKeyKind least) {
  std::uint64_t hash = fnv1a64(nullptr, 0);
  for (const CaseKey& k : case_text_keys(canonical_text)) {
    if (static_cast<int>(restart_rule_of(k.path).kind) < static_cast<int>(least)) continue;
    const std::string line = k.path + " = " + k.value + "\n";
    hash = fnv1a64(line.data(), line.size(), hash);
  }
  return fmt::format("{:016x}", hash);
}

}  // namespace

std::string model_fingerprint(const std::string& canonical_text) {
  return keys_hash(canonical_text, RestartKeyKind::kApplied);
}

std::string model_identity(const std::string& canonical_text) {
  return keys_hash(canonical_text, RestartKeyKind::kFixed);
}

std::string describe_restart_rules() {
  std::string out = "| key | on a restart | why, or what happens |\n|---|---|---|\n";
  for (const RestartKeyRule& r : restart_key_rules()) {
    const char* kind = r.kind == RestartKeyKind::kFree      ? "may change"
                       : r.kind == RestartKeyKind::kApplied ? "applied with `--allow-changes`"
                                                            : "refused";
    const std::string key =
        r.pattern == "*" ? std::string("every other key") : fmt::format("`{}`", r.pattern);
    out += fmt::format("| {} | {} | {} |\n", key, kind, r.note);
  }
  return out;
}

std::string describe_change(const CaseChange& c) {
  return fmt::format("{}: {} -> {}", c.path, shown(c.before), shown(c.after));
}

void check_restart_changes(const std::vector<CaseChange>& changes, bool allow_changes,
                           const std::string& case_file, const std::string& checkpoint) {
  std::vector<const CaseChange*> refused;
  bool fixed = false;
  for (const CaseChange& c : changes) {
    if (c.rule->kind == RestartKeyKind::kFixed ||
        (c.rule->kind == RestartKeyKind::kApplied && !allow_changes))
      refused.push_back(&c);
    fixed = fixed || c.rule->kind == RestartKeyKind::kFixed;
  }
  if (refused.empty()) return;
  std::vector<Diagnostic> d;
  d.push_back({case_file, 0, 0, "",
               fmt::format("refusing to restart: the case differs from the one {} was written by, "
                           "in {} key{} that change the results:",
                           checkpoint, refused.size(), refused.size() == 1 ? "" : "s")});
  constexpr std::size_t kShown = 30;
  for (std::size_t k = 0; k < refused.size() && k < kShown; ++k) {
    const CaseChange& c = *refused[k];
    const bool applicable = c.rule->kind == RestartKeyKind::kApplied;
    d.push_back(
        {case_file, 0, 0, c.path,
         fmt::format(
             "{} in the checkpoint, {} in the case: {}", shown(c.before), shown(c.after),
             applicable ? fmt::format("may be applied with --allow-changes ({})", c.rule->note)
                        : fmt::format("cannot be applied to the saved state ({})", c.rule->note))});
  }
  if (refused.size() > kShown)
    d.push_back({case_file, 0, 0, "", fmt::format("... and {} more", refused.size() - kShown)});
  d.push_back(
      {case_file, 0, 0, "",
       fixed ? std::string("a changed model needs a fresh start: another output folder (-o), or "
                           "no --restart; keys that may change on any restart are listed in "
                           "docs/output.md")
             : std::string("run with --allow-changes to apply them from the restart on, or start "
                           "afresh in another output folder (-o)")});
  throw InputError(std::move(d));
}

}  // namespace ringdem

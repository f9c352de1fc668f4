#include "app/SweepCommand.hpp"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include "app/CaseClaims.hpp"
#include "app/OutputLock.hpp"
#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/StopSignals.hpp"
#include "app/SweepCaseRecord.hpp"
#include "app/TensileTest.hpp"
#include "io/CaseLoader.hpp"
#include "io/CaseText.hpp"
#include "io/RestartChanges.hpp"
#include "io/ResultsWriter.hpp"
#include "io/Schema.hpp"

namespace ringdem {

namespace {

using schema::above;
using schema::at_least;
using schema::Table;
using schema::Type;

const Table<SweepParameterConfig::Range>& range_table() {
  using R = SweepParameterConfig::Range;
  static const Table<R> table{
      "parameters[].range",
      "Evenly spaced values from `from` to `to` (both included).",
      {
          schema::number("from", &R::from, schema::unbounded(), "", "First value").required(),
          schema::number("to", &R::to, schema::unbounded(), "", "Last value").required(),
          schema::integer("count", &R::count, at_least(2), "Number of values").required(),
          schema::choice("spacing", &R::spacing, {"linear", "log"},
                         "linear: equal differences; log: equal ratios (from, to > 0)"),
      }};
  return table;
}

const Table<SweepParameterConfig>& parameter_table() {
  using P = SweepParameterConfig;
  static const Table<P> table{
      "parameters[]",
      "One swept key of the case: give `values` or `range`.",
      {
          schema::text("key", &P::key, Type::kName,
                       "Key path in the case file, as for --set (e.g. bonds.0.youngs_modulus)")
              .required(),
          schema::value_list("values", &P::values,
                             "The values (any YAML scalars; zipped, one may repeat)"),
          schema::optional_section("range", &P::range, range_table(), "A range of numbers"),
      }};
  return table;
}

const Table<SweepConfig>& sweep_table() {
  using S = SweepConfig;
  static const Table<S> table{
      "",
      "Top level of a sweep file.",
      {
          schema::integer("schema_version", &S::schema_version, schema::exactly(1),
                          "Version of this file format")
              .required(),
          schema::text("name", &S::name, Type::kString, "Study name (output folder)")
              .default_text("file name without extension"),
          schema::text("case", &S::case_path, Type::kName,
                       "Case file the study varies (relative to the sweep file)")
              .required(),
          schema::name_list("set", &S::set, "Overrides key=value applied to every case"),
          schema::list("parameters", &S::parameters, parameter_table(), "Swept keys").required(),
          schema::choice("combine", &S::combine, {"product", "zip"},
                         "product: every combination; zip: the i-th values of all parameters "
                         "together (equal counts)"),
      }};
  return table;
}

std::string format_value(double v) {
  return schema::format_number(v);
}

}  // namespace

std::vector<std::string> parameter_values(const SweepParameterConfig& p) {
  if (!p.range) return p.values;
  const auto& r = *p.range;
  std::vector<std::string> out;
  for (int i = 0; i < r.count; ++i) {
    const double t = static_cast<double>(i) / (r.count - 1);
    const double v =
        r.spacing == "log" ? r.from * std::pow(r.to / r.from, t) : r.from + t * (r.to - r.from);
    out.push_back(format_value(v));
  }
  return out;
}

namespace {

/// Where value `i` of parameter `p` was given: its list entry, or the range it comes from.
schema::Location value_location(const schema::Context& ctx, std::size_t p, std::size_t i) {
  const std::string path = schema::index_path("parameters", p);
  return ctx.given(path + ".range") ? ctx.where(path + ".range")
                                    : ctx.where(schema::index_path(path + ".values", i), path);
}

/// A sweep may not run one case twice. In a product a value repeated in one parameter repeats
/// every combination it is in; zipped, a value may repeat as long as another parameter differs
/// in the same case.
void refuse_repeated_cases(const SweepConfig& config, schema::Context& ctx) {
  std::vector<std::vector<std::string>> values;
  for (const auto& p : config.parameters)
    values.push_back(parameter_values(p));
  if (config.combine == "zip") {
    for (std::size_t i = 0; i < values.front().size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        bool same = true;
        for (const auto& v : values)
          same = same && v[i] == v[j];
        if (!same) continue;
        ctx.error(value_location(ctx, 0, i), schema::index_path("parameters", 0),
                  fmt::format("case {} repeats case {}: every parameter has the same value in "
                              "both (combine: zip)",
                              i, j));
        break;
      }
    return;
  }
  for (std::size_t p = 0; p < values.size(); ++p)
    for (std::size_t i = 0; i < values[p].size(); ++i)
      for (std::size_t j = 0; j < i; ++j)
        if (values[p][i] == values[p][j]) {
          ctx.error(value_location(ctx, p, i), schema::index_path("parameters", p),
                    fmt::format("duplicate value '{}': combine: product would run every case "
                                "with it twice",
                                values[p][i]));
          break;
        }
}

}  // namespace

SweepConfig load_sweep_from_string(const std::string& yaml_text, const std::string& display_name,
                                   const std::vector<std::string>& overrides) {
  schema::Context ctx(display_name);
  SweepConfig config;
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::ParserException& e) {
    throw InputError({Diagnostic{display_name, e.mark.line + 1, e.mark.column + 1, "",
                                 "invalid YAML: " + e.msg}});
  }
  if (!root.IsDefined() || root.IsNull()) root.reset(YAML::Node(YAML::NodeType::Map));
  sweep_table().parse(config, root, root, "", ctx);
  std::size_t zip_count = 0;
  for (std::size_t i = 0; i < config.parameters.size(); ++i) {
    const auto& p = config.parameters[i];
    const std::string path = schema::index_path("parameters", i);
    if (ctx.failed(path)) continue;
    const bool has_values = ctx.given(path + ".values"), has_range = ctx.given(path + ".range");
    if (has_values == has_range) {
      ctx.error(ctx.where(path), path, "give either `values` or `range`");
      continue;
    }
    if (has_range && p.range->spacing == "log" && !(p.range->from > 0 && p.range->to > 0))
      ctx.error(ctx.where(path + ".range"), path + ".range",
                "log spacing needs from > 0 and to > 0");
    const std::size_t n = parameter_values(p).size();
    if (config.combine == "zip" && zip_count != 0 && n != zip_count)
      ctx.error(ctx.where(path), path,
                fmt::format("combine: zip needs the same number of values for every parameter "
                            "({} before, {} here)",
                            zip_count, n));
    zip_count = n;
  }
  if (ctx.given("name") && !ctx.failed("name")) {
    const std::string problem = schema::folder_name_problem(config.name);
    if (!problem.empty())
      ctx.error(ctx.where("name"), "name",
                fmt::format("'{}' {}: the name is the output folder results/<name>, so it may "
                            "not contain '/' or '\\' nor be '.' or '..'",
                            config.name, problem));
  }
  if (config.parameters.empty() && ctx.given("parameters") && !ctx.failed("parameters"))
    ctx.error(ctx.where("parameters"), "parameters", "must list at least one parameter");
  if (ctx.diagnostics().empty() && !config.parameters.empty()) refuse_repeated_cases(config, ctx);
  if (!ctx.diagnostics().empty()) throw InputError(ctx.sorted_diagnostics());
  for (std::size_t p = 0; p < config.parameters.size(); ++p)
    for (std::size_t i = 0; i < parameter_values(config.parameters[p]).size(); ++i)
      config.parameters[p].value_at.push_back(value_location(ctx, p, i));
  for (std::size_t i = 0; i < config.set.size(); ++i)
    config.set_at.push_back(ctx.where(schema::index_path("set", i), "set"));
  if (config.name.empty()) {
    const std::string stem = std::filesystem::path(display_name).stem().string();
    config.name = stem.empty() ? "sweep" : stem;
  }
  // The case path is relative to the sweep file.
  const std::filesystem::path case_path(config.case_path);
  if (case_path.is_relative())
    config.case_path =
        (std::filesystem::path(display_name).parent_path() / case_path).lexically_normal().string();
  config.set.insert(config.set.end(), overrides.begin(), overrides.end());
  config.source_path = display_name;
  return config;
}

SweepConfig load_sweep(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({Diagnostic{path, 0, 0, "", "sweep file not found or unreadable"}});
  std::ostringstream buffer;
  buffer << in.rdbuf();
  return load_sweep_from_string(buffer.str(), path, overrides);
}

std::vector<SweepCase> expand_sweep(const SweepConfig& sweep) {
  std::vector<std::vector<std::string>> values;
  for (const auto& p : sweep.parameters)
    values.push_back(parameter_values(p));
  std::vector<std::vector<std::size_t>> choices;  // index into each parameter's values
  if (sweep.combine == "zip") {
    for (std::size_t i = 0; i < values.front().size(); ++i)
      choices.push_back(std::vector<std::size_t>(values.size(), i));
  } else {
    choices.push_back({});
    for (const auto& v : values) {
      std::vector<std::vector<std::size_t>> next;
      for (const auto& c : choices)
        for (std::size_t i = 0; i < v.size(); ++i) {
          auto extended = c;
          extended.push_back(i);
          next.push_back(std::move(extended));
        }
      choices = std::move(next);
    }
  }
  std::vector<SweepCase> cases;
  for (std::size_t k = 0; k < choices.size(); ++k) {
    SweepCase c;
    c.folder = fmt::format("case_{:03}", k);
    c.overrides = sweep.set;
    for (std::size_t p = 0; p < values.size(); ++p) {
      const std::string& v = values[p][choices[k][p]];
      c.parameter_values.push_back(v);
      c.value_index.push_back(choices[k][p]);
      c.overrides.push_back(sweep.parameters[p].key + "=" + v);
    }
    cases.push_back(std::move(c));
  }
  return cases;
}

namespace {

std::string csv_number(double v) {
  return std::isfinite(v) ? fmt::format("{:.10g}", v) : "";
}

std::string csv_text(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s)
    out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

const char* kSummaryColumns =
    "stop_reason,peak_load_N,displacement_at_peak_m,elongation_at_failure_m,"
    "first_bond_break_time_s,broken_bonds,stage_transition_displacement_m,"
    "bending_stage_stiffness_N_per_m,tensile_stage_stiffness_N_per_m,steps,wall_time_s,"
    "particle_steps_per_s";

/// A case's row of sweep.csv, as columns and values (each rank writes its cases' rows into
/// their folders, rank 0 joins them).
using SweepRow = std::vector<std::pair<std::string, std::string>>;

/// The numbers of a summary.json (read as YAML, of which JSON is a part) in the file's order,
/// an object's members as "object.member": lists, text, null and the loop's time per phase (not
/// a result of the case) left out.
void add_summary_numbers(const YAML::Node& node, const std::string& prefix, SweepRow& row) {
  for (const auto& member : node) {
    const std::string key = prefix + member.first.as<std::string>();
    const YAML::Node& value = member.second;
    if (value.IsMap()) {
      if (key != "time_per_phase_s") add_summary_numbers(value, key + ".", row);
      continue;
    }
    double x = 0.0;  // a quoted scalar is JSON text, whatever it reads like
    if (value.IsScalar() && value.Tag() != "!" && YAML::convert<double>::decode(value, x))
      row.emplace_back(key, csv_number(x));
  }
}

/// A case of any scenario but the tensile test, run by `ringdem run`'s loop on the ranks of
/// `group`: its exit code (0 done, 1 diverged or failed, ...) and, on the group's first rank,
/// the numbers of its summary.json.
SweepRow run_scenario_case(const CaseConfig& config, const RunOptions& run,
                           const Communicator& group) {
  const std::string& dir = run.output_dir;
  // A summary left by an earlier study in this folder must not stand for a case that ends
  // before it writes its own (the first rank writes it).
  if (group.is_root()) std::filesystem::remove(dir + "/summary.json");
  int code = 1;
  try {
    code = run_case(config, run, group);
  } catch (const std::exception& e) {
    fmt::print(stderr, "ringdem sweep: {}: {}\n", dir, e.what());
  }
  SweepRow row{{"exit_code", std::to_string(code)}};
  if (group.is_root() && std::filesystem::exists(dir + "/summary.json"))
    add_summary_numbers(YAML::LoadFile(dir + "/summary.json"), "", row);
  return row;
}

std::string summary_row(const TensileResult& r) {
  const auto opt = [](const std::optional<double>& v) {
    return v ? csv_number(*v) : std::string();
  };
  return fmt::format("{},{},{},{},{},{},{},{},{},{},{},{}", stop_reason_name(r.stop_reason),
                     csv_number(r.analysis.peak_load), csv_number(r.analysis.displacement_at_peak),
                     opt(r.elongation_at_failure), opt(r.first_bond_break_time), r.broken_bonds,
                     opt(r.analysis.stage_transition_displacement),
                     csv_number(r.analysis.bending_stage_stiffness),
                     csv_number(r.analysis.tensile_stage_stiffness), r.steps,
                     csv_number(r.wall_time), csv_number(r.particle_steps_per_s));
}

}  // namespace

bool is_sweep_file(const std::string& path) {
  try {
    const YAML::Node root = YAML::LoadFile(path);
    return root.IsMap() && root["parameters"] && root["case"];
  } catch (const YAML::Exception&) {
    return false;
  }
}

namespace {

/// Where a case's diagnostic points: the overrides are c.overrides in order, numbered from 1
/// (apply_overrides): the file's `set`, the command line's, then one per parameter. One that
/// came from the file's `set` or a parameter's value points there in the sweep file; one from
/// the command line keeps its own --set number.
void locate_in_sweep(const SweepConfig& sweep, const SweepCase& c, Diagnostic& d) {
  if (d.file != "--set" || d.line <= 0) return;
  const auto n = static_cast<std::size_t>(d.line - 1);
  const schema::Location* at =
      n < sweep.set_at.size() ? &sweep.set_at[n]
      : n >= sweep.set.size() && n - sweep.set.size() < sweep.parameters.size()
          ? &sweep.parameters[n - sweep.set.size()].value_at[c.value_index[n - sweep.set.size()]]
          : nullptr;
  if (at != nullptr) {
    d.file = at->file;
    d.line = at->line;
    d.column = at->column;
  } else {
    d.line -= static_cast<int>(sweep.set_at.size());  // the command line's own number
  }
}

/// "case_001: key=value, key=value".
std::string describe_case(const SweepConfig& sweep, const SweepCase& c) {
  std::string which = c.folder;
  for (std::size_t p = 0; p < sweep.parameters.size(); ++p)
    which +=
        fmt::format("{} {}={}", p == 0 ? ":" : ",", sweep.parameters[p].key, c.parameter_values[p]);
  return which;
}

}  // namespace

std::vector<CaseConfig> load_sweep_cases(const SweepConfig& sweep,
                                         const std::vector<SweepCase>& cases,
                                         std::vector<Diagnostic>* warnings) {
  std::vector<CaseConfig> configs;
  // Each warning once, with the cases it comes from, in the order they first come.
  std::vector<std::pair<Diagnostic, std::vector<std::string>>> seen;
  for (const SweepCase& c : cases) {
    std::vector<Diagnostic> case_warnings;
    try {
      configs.push_back(load_case(sweep.case_path, c.overrides, &case_warnings));
    } catch (const InputError& e) {
      std::vector<Diagnostic> located = e.diagnostics;
      for (Diagnostic& d : located) {
        locate_in_sweep(sweep, c, d);
        d.message += " (in " + describe_case(sweep, c) + ")";
      }
      throw InputError(located);
    }
    for (Diagnostic& d : case_warnings) {
      locate_in_sweep(sweep, c, d);
      const std::string text = format_diagnostic(d);
      auto it = std::find_if(seen.begin(), seen.end(), [&](const auto& entry) {
        return format_diagnostic(entry.first) == text;
      });
      if (it == seen.end()) it = seen.insert(seen.end(), {d, {}});
      it->second.push_back(describe_case(sweep, c));
    }
  }
  if (warnings != nullptr) {
    warnings->clear();
    for (auto& [d, which] : seen) {
      std::string in;
      for (const std::string& w : which)
        in += (in.empty() ? "" : "; ") + w;
      d.message += which.size() == cases.size() && cases.size() > 1 ? " (in every case)"
                                                                    : " (in " + in + ")";
      warnings->push_back(d);
    }
  }
  return configs;
}

namespace {

/// On a restart, every case folder that is there must hold this study's case: a folder of a
/// case with other overrides (another study, or this one changed) is refused before anything
/// runs, so that the table never mixes two studies. Every rank checks every case (cheap).
void check_restart_folders(const std::string& out_dir, const SweepConfig& sweep,
                           const std::vector<SweepCase>& cases,
                           const std::vector<std::string>& case_texts) {
  std::vector<Diagnostic> problems;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const SweepCase& c = cases[k];
    const std::string dir = out_dir + "/" + c.folder;
    const SweepCaseRecord record = read_case_record(dir);
    if (record.overrides && *record.overrides != c.overrides) {
      std::string was, is;
      for (const std::string& o : *record.overrides)
        was += (was.empty() ? "" : " ") + o;
      for (const std::string& o : c.overrides)
        is += (is.empty() ? "" : " ") + o;
      problems.push_back({sweep.source_path, 0, 0, "",
                          fmt::format("--restart: {} was run with other values ({}) than this "
                                      "study gives it ({}); continue the study it belongs to, or "
                                      "give another output folder",
                                      dir, was.empty() ? "none" : was, is.empty() ? "none" : is)});
    } else if (!record.overrides && record.has_row()) {
      problems.push_back({sweep.source_path, 0, 0, "",
                          fmt::format("--restart: {} does not say which values it was run with "
                                      "(no sweep_case.txt: written by an older ringdem); give "
                                      "another output folder",
                                      dir)});
    } else if (record.finished() && record.case_text && *record.case_text != case_texts[k]) {
      // A case that is kept must be the case this study would run now; one that continues
      // from a checkpoint is checked by the restart itself (io/RestartChanges).
      const std::vector<CaseChange> changes = case_changes(*record.case_text, case_texts[k]);
      std::string listed;
      for (std::size_t i = 0; i < changes.size() && i < 3; ++i)
        listed += (listed.empty() ? "" : "; ") + describe_change(changes[i]);
      if (changes.size() > 3) listed += fmt::format("; and {} more", changes.size() - 3);
      problems.push_back({sweep.source_path, 0, 0, "",
                          fmt::format("--restart: {} was run from another case than this study "
                                      "gives it now ({}); restore the case or sweep file it was "
                                      "run with, remove the folder to run the case again, or give "
                                      "another output folder",
                                      dir, listed)});
    }
  }
  if (!problems.empty()) throw InputError(problems);
}

/// What a group of ranks does next in a study (CaseAction), and with which case.
enum class CaseAction : std::int64_t { kNoCaseLeft, kKept, kNotStarted, kStart };
struct NextCase {
  CaseAction action = CaseAction::kNoCaseLeft;
  std::size_t index = 0;
  double study_seconds = 0.0;  ///< the study's wall time when the case was claimed
};

/// The group's first rank claims the next case and decides what becomes of it; the others get
/// its decision, so that a group never disagrees. Collective over `group`.
NextCase next_case_of_group(CaseClaims& claims, const Communicator& group,
                            const SweepOptions& options, const std::string& out_dir,
                            const std::vector<SweepCase>& cases,
                            std::chrono::steady_clock::time_point study_start) {
  std::vector<std::int64_t> next{static_cast<std::int64_t>(CaseAction::kNoCaseLeft), 0, 0};
  if (group.is_root()) {
    if (const std::optional<std::size_t> claimed = claims.next()) {
      const auto elapsed = std::chrono::steady_clock::now() - study_start;
      const double seconds = std::chrono::duration<double>(elapsed).count();
      CaseAction action = CaseAction::kStart;
      if (options.restart && read_case_record(out_dir + "/" + cases[*claimed].folder).finished())
        action = CaseAction::kKept;
      // The study stops on SIGUSR1 (or the first SIGINT, SIGTERM or SIGHUP during a case that
      // can checkpoint: app/StopSignals) or at its wall-time limit: the case that runs then
      // writes a checkpoint and stops (a tensile test runs to its end); the cases after it do
      // not start.
      else if (stop_signal_received() ||
               (options.max_walltime > 0.0 && seconds >= options.max_walltime))
        action = CaseAction::kNotStarted;
      next = {static_cast<std::int64_t>(action), static_cast<std::int64_t>(*claimed),
              std::chrono::duration_cast<std::chrono::nanoseconds>(elapsed).count()};
    }
  }
  group.broadcast(next, 0);
  return {static_cast<CaseAction>(next[0]), static_cast<std::size_t>(next[1]),
          1e-9 * static_cast<double>(next[2])};
}

}  // namespace

int run_sweep(const SweepOptions& options, const Communicator& world) {
  const auto study_start = std::chrono::steady_clock::now();
  if (options.ranks_per_case < 1 || world.size() % options.ranks_per_case != 0)
    throw InputError(
        {{options.sweep_path, 0, 0, "",
          fmt::format("--ranks-per-case {} does not divide the {} rank{} of this "
                      "job: start a multiple of it (each case runs on that many "
                      "ranks, the next case on the first group that comes free)",
                      options.ranks_per_case, world.size(), world.size() == 1 ? "" : "s")}});
  const SweepConfig sweep = load_sweep(options.sweep_path, options.overrides);
  const std::vector<SweepCase> cases = expand_sweep(sweep);
  // Every case is checked before any runs, on every rank.
  std::vector<Diagnostic> warnings;
  std::vector<CaseConfig> configs = load_sweep_cases(sweep, cases, &warnings);
  if (world.is_root()) fmt::print(stderr, "{}", format_diagnostics(warnings));
  const std::string out_dir =
      options.output_dir.empty() ? "results/" + sweep.name : options.output_dir;
  std::vector<std::string> case_texts(cases.size());
  for (std::size_t k = 0; k < cases.size(); ++k) {
    configs[k].name = sweep.name + "_" + cases[k].folder;
    case_texts[k] = canonical_case_text(configs[k]);
  }
  if (options.restart) check_restart_folders(out_dir, sweep, cases, case_texts);
  const bool root = world.is_root() && !options.quiet;
  // Held to the end of the study: no second sweep into this folder (app/OutputLock.hpp).
  const OutputLock lock = lock_output_folder(out_dir, world, options.break_lock);
  if (root)
    fmt::print("sweep {} ({}): {} cases of {} over {} rank{}{}, output in {}{}\n", sweep.name,
               sweep.source_path, cases.size(), sweep.case_path, world.size(),
               world.size() == 1 ? "" : "s",
               options.ranks_per_case > 1 ? fmt::format(" ({} to a case)", options.ranks_per_case)
                                          : std::string(),
               out_dir, options.restart ? ", continuing the cases not done" : "");
  world.barrier();

  // Each case runs on a group of options.ranks_per_case ranks (one by default), the next case
  // on the first group that comes free (app/CaseClaims). The group's first rank claims it and
  // decides what happens to it; the others follow, so a group never disagrees.
  const int per_case = options.ranks_per_case;
  const SplitCommunicator split(world, world.rank() / per_case);
  const Communicator& group = split.get();
  const bool leader = group.is_root();
  const std::string ranks =
      per_case == 1 ? fmt::format("rank {}", world.rank())
                    : fmt::format("ranks {}-{}", world.rank(), world.rank() + per_case - 1);
  CaseClaims claims(out_dir, cases.size(), world,
                    static_cast<std::size_t>(world.rank() / per_case));
  std::int64_t worst_exit = 0;
  for (;;) {
    const NextCase next = next_case_of_group(claims, group, options, out_dir, cases, study_start);
    if (next.action == CaseAction::kNoCaseLeft) break;
    const std::size_t k = next.index;
    const std::string dir = out_dir + "/" + cases[k].folder;
    std::string parameters;
    for (std::size_t p = 0; p < sweep.parameters.size(); ++p)
      parameters += fmt::format(" {}={}", sweep.parameters[p].key, cases[k].parameter_values[p]);
    const bool say = leader && !options.quiet;
    if (next.action == CaseAction::kKept) {  // its row stays as it is
      if (leader) {
        const int code = read_case_record(dir).exit_code();
        worst_exit = std::max<std::int64_t>(worst_exit, code);
        if (say)
          fmt::print("[{}] {}:{}: done before (exit {}), kept\n", ranks, cases[k].folder,
                     parameters, code);
      }
      continue;
    }
    if (next.action == CaseAction::kNotStarted) {
      worst_exit = std::max<std::int64_t>(worst_exit, kExitCaseNotStarted);
      if (leader) {
        write_case_start(dir, cases[k].overrides, case_texts[k]);  // the folder is this study's
        write_case_row(dir, "exit_code", std::to_string(kExitCaseNotStarted));
      }
      if (say)
        fmt::print("[{}] {}:{}: not started (the study was asked to stop)\n", ranks,
                   cases[k].folder, parameters);
      continue;
    }
    if (leader) write_case_start(dir, cases[k].overrides, case_texts[k]);
    std::string header, values;
    if (scenario_kind(configs[k]) == ScenarioKind::kTensileTest) {
      TensileRunOptions run;
      run.output_dir = dir;
      run.verbose = false;
      const TensileResult r = run_tensile_test(configs[k], run, group);
      header = kSummaryColumns;
      values = summary_row(r);
      if (say)
        fmt::print("[{}] {}:{}: {}, peak {:.2f} kN at {:.1f} mm, {:.0f} s\n", ranks,
                   cases[k].folder, parameters, stop_reason_name(r.stop_reason),
                   1e-3 * r.analysis.peak_load, 1e3 * r.analysis.displacement_at_peak, r.wall_time);
    } else {
      RunOptions run;
      run.output_dir = dir;
      run.quiet = true;
      run.restart = options.restart ? "auto" : "";
      if (options.max_walltime > 0.0) run.max_walltime = options.max_walltime - next.study_seconds;
      const SweepRow row = run_scenario_case(configs[k], run, group);
      worst_exit = std::max<std::int64_t>(worst_exit, std::stoi(row.front().second));
      for (const auto& [column, value] : row) {
        header += (header.empty() ? "" : ",") + column;
        values += (values.empty() ? "" : ",") + value;
      }
      if (say)
        fmt::print("[{}] {}:{}: exit {}\n", ranks, cases[k].folder, parameters, row.front().second);
    }
    std::fflush(stdout);
    if (leader) write_case_row(dir, header, values);
  }
  claims.close(world);
  worst_exit = world.max(worst_exit);  // also the barrier before rank 0 reads the rows

  if (world.is_root()) {
    // The cases' columns in the order they first come (the cases of one study share them, but
    // a case that failed early has fewer); a case without a column leaves its cell empty.
    std::vector<std::string> columns;
    std::vector<std::map<std::string, std::string>> rows(cases.size());
    for (std::size_t k = 0; k < cases.size(); ++k) {
      const SweepCaseRecord record = read_case_record(out_dir + "/" + cases[k].folder);
      const std::vector<std::string> names = split_csv_line(record.header);
      const std::vector<std::string> cells = split_csv_line(record.values);
      for (std::size_t c = 0; c < names.size(); ++c) {
        if (std::find(columns.begin(), columns.end(), names[c]) == columns.end())
          columns.push_back(names[c]);
        rows[k][names[c]] = c < cells.size() ? cells[c] : std::string();
      }
    }
    std::ofstream table(out_dir + "/sweep.csv");
    table << "case,folder";
    for (const auto& p : sweep.parameters)
      table << "," << csv_text(p.key);
    for (const std::string& column : columns)
      table << "," << column;
    table << "\n";
    for (std::size_t k = 0; k < cases.size(); ++k) {
      table << k << "," << cases[k].folder;
      for (const std::string& v : cases[k].parameter_values)
        table << "," << csv_text(v);
      for (const std::string& column : columns)
        table << "," << rows[k][column];
      table << "\n";
    }
    if (root) fmt::print("combined table: {}/sweep.csv\n", out_dir);
    if (root && worst_exit == kExitCaseNotStarted)
      fmt::print(
          "some cases stopped with a checkpoint or did not start (exit_code 3 in sweep.csv): "
          "`ringdem sweep {} -o {} --restart` continues them and keeps the others\n",
          options.sweep_path, out_dir);
  }
  return static_cast<int>(worst_exit);
}

}  // namespace ringdem

#include <mpi.h>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <exception>
#include <iostream>
#include <new>

#include "app/BuildInfo.hpp"
#include "app/Calibration.hpp"
#include "app/InfoCommand.hpp"
#include "app/LaunchedRank.hpp"
#include "app/RunCommand.hpp"
#include "app/RunControl.hpp"
#include "app/StopSignals.hpp"
#include "app/SweepCommand.hpp"
#include "comm/Communicator.hpp"
#include "core/HugePageAdvice.hpp"
#include "core/Version.hpp"
#include "engine/FrameRestraints.hpp"
#include "io/CaseLoader.hpp"
#include "io/InputError.hpp"
#include "io/SizeEstimate.hpp"

namespace {

// Exit codes of DESIGN §6.
constexpr int kExitRuntimeError = 1;
constexpr int kExitInputError = 2;

}  // namespace

int main(int argc, char** argv) {
  // First thing: SIGUSR1 (checkpoint and stop) must never hit the default action, which kills.
  ringdem::install_stop_signal_handler();
#if defined(__GLIBC__)
  // Blocks of 4 MiB and more come straight from the system (with the huge-page advice,
  // core/HugePageAdvice.hpp) and go back to it when freed. By default glibc raises that
  // threshold to the largest block freed so far (up to 32 MiB), after which the scratch of every
  // neighbour-list rebuild (bins, slots, orders, a few to 25 MiB at 10^6 grains) comes from the
  // heap and the holes it leaves stay resident: 27 MiB, 7 % of the peak of 10^6 grains in
  // contact (docs/performance.md, fifteenth round). Below 4 MiB the heap keeps a freed block's
  // pages for the next rebuild: from the system, each rebuild faulted them in afresh, 4 KiB at
  // a time, half of the neighbour phase of 10^5 grains in contact (thirty-third round).
  mallopt(M_MMAP_THRESHOLD, static_cast<int>(ringdem::kAdviseFrom));
#endif
  CLI::App app{"ringdem: MPI-parallel discrete elements for flexible steel ring nets", "ringdem"};
  app.set_version_flag(
      "--version", [] { return ringdem::build_info(); },
      "print the version and the MPI, HDF5 and METIS versions, then exit");
  app.require_subcommand(1);

  ringdem::RunOptions run_opts;
  auto* run = app.add_subcommand("run", "run a case");
  run->add_option("case", run_opts.case_path, "case file (YAML)")->required();
  run->add_option("-o,--output", run_opts.output_dir, "output folder (default results/<name>)");
  run->add_option("--set", run_opts.overrides, "override a case key: key.path=value")
      ->take_all()
      ->allow_extra_args(false);
  run->add_flag("-q,--quiet", run_opts.quiet, "no banner or progress lines");
  run->add_flag("--force-size", run_opts.force_size,
                "run even when the size estimate exceeds the memory available on a node");
  run->add_option("--restart", run_opts.restart,
                  "continue from a checkpoint: its path, or 'auto' for the newest valid one in "
                  "<output>/checkpoints (a fresh start when there is none)");
  const char* const break_lock_help =
      "take over the output folder's lock (ringdem.lock) even though it names a run on another "
      "host: only when you know that run has ended (e.g. its node failed)";
  run->add_flag("--break-lock", run_opts.break_lock, break_lock_help);
  run->add_flag("--allow-changes", run_opts.allow_changes,
                "on a restart, apply changed keys that can be applied to the saved state (time "
                "step, damping, contact coefficients; docs/output.md) instead of refusing them");
  std::string max_walltime;
  run->add_option("--max-walltime", max_walltime,
                  "write a checkpoint and exit with code 3 after this wall time (seconds, or "
                  "H:MM:SS, or 90m / 2h)");

  std::string info_path;
  auto* info = app.add_subcommand("info", "what a frame or checkpoint file holds");
  info->add_option("file", info_path, "frames_*.h5 or checkpoint_*.h5")->required();

  std::string check_path;
  std::vector<std::string> check_overrides;
  auto* check = app.add_subcommand(
      "check", "validate a case file, or a sweep file and each of its cases, without running");
  check->add_option("case", check_path, "case or sweep file (YAML)")->required();
  check->add_option("--set", check_overrides, "override a case key: key.path=value")
      ->allow_extra_args(false);

  ringdem::SweepOptions sweep_opts;
  auto* sweep = app.add_subcommand("sweep", "run a parameter study (cases spread over the ranks)");
  sweep->add_option("sweep", sweep_opts.sweep_path, "sweep file (YAML)")->required();
  sweep->add_option("-o,--output", sweep_opts.output_dir, "output folder (default results/<name>)");
  sweep->add_option("--set", sweep_opts.overrides, "override a key of every case: key.path=value")
      ->take_all()
      ->allow_extra_args(false);
  sweep->add_flag("-q,--quiet", sweep_opts.quiet, "no progress lines");
  sweep->add_flag("--break-lock", sweep_opts.break_lock, break_lock_help);
  sweep->add_flag("--restart", sweep_opts.restart,
                  "continue the study in its output folder: keep the cases that are done, "
                  "continue a stopped case from its newest checkpoint, start the others");
  sweep
      ->add_option("--ranks-per-case", sweep_opts.ranks_per_case,
                   "ranks that run each case together (default 1; the job's rank count must be "
                   "a multiple): the next case goes to the first group that comes free")
      ->check(CLI::PositiveNumber);
  std::string sweep_max_walltime;
  sweep->add_option("--max-walltime", sweep_max_walltime,
                    "wall time for the whole study (as run's): the case running then writes a "
                    "checkpoint and stops, the cases after it do not start; exit code 3");

  ringdem::CalibrationOptions cal_opts;
  std::vector<double> lambda_range, modulus_range;
  auto* calibrate = app.add_subcommand(
      "calibrate",
      "fit the bond radius multiplier (and E_b) to a measured load-displacement curve");
  calibrate->add_option("case", cal_opts.case_path, "tensile-test case file (YAML)")->required();
  calibrate
      ->add_option("--reference", cal_opts.reference_path,
                   "measured curve: CSV with columns displacement_m and load_N")
      ->required();
  calibrate
      ->add_option("--fit", cal_opts.fit,
                   "lambda (E_b from Eq. 17 when the bond has derive_from) or lambda_and_modulus")
      ->check(CLI::IsMember({"lambda", "lambda_and_modulus"}));
  calibrate->add_option("-o,--output", cal_opts.output_dir,
                        "output folder (default results/<case name>_calibration)");
  calibrate->add_option("--set", cal_opts.overrides, "override a case key: key.path=value")
      ->take_all()
      ->allow_extra_args(false);
  calibrate->add_option("--bond", cal_opts.bond, "bond to fit (default: the one the rings use)");
  calibrate->add_option("--lambda-range", lambda_range, "lambda bounds (default 0.2 1.0)")
      ->expected(2);
  calibrate->add_option("--modulus-range", modulus_range, "E_b bounds in Pa (default 40e9 600e9)")
      ->expected(2);
  calibrate->add_option("--scan", cal_opts.scan_points,
                        "lambda fit: evenly spaced first trials (default 5)");
  calibrate->add_option("--tolerance", cal_opts.lambda_tolerance,
                        "tolerance on lambda (default 0.001)");
  calibrate->add_option("--modulus-tolerance", cal_opts.modulus_tolerance,
                        "relative tolerance on E_b (default 0.002)");
  calibrate->add_option("--misfit-tolerance", cal_opts.misfit_tolerance,
                        "two-parameter fit: stop when the simplex's misfits (relative to the "
                        "reference peak) differ by at most this (default 0.002)");
  calibrate->add_option("--max-evaluations", cal_opts.max_evaluations,
                        "most tensile tests to run (default 40)");
  calibrate->add_flag("-q,--quiet", cal_opts.quiet, "no progress lines");
  calibrate->add_flag("--break-lock", cal_opts.break_lock, break_lock_help);

  // Under mpirun every rank parses the same command line: only the first prints the help, the
  // version or a parse error, once for the job.
  std::ostream silent(nullptr);
  const bool speaks = ringdem::launched_rank() == 0;
  std::ostream& parser_out = speaks ? std::cout : silent;
  std::ostream& parser_err = speaks ? std::cerr : silent;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e, parser_out, parser_err);
    return code == 0 ? 0 : kExitInputError;
  }

  if (lambda_range.size() == 2) {
    cal_opts.lambda_lower = lambda_range[0];
    cal_opts.lambda_upper = lambda_range[1];
  }
  if (modulus_range.size() == 2) {
    cal_opts.modulus_lower = modulus_range[0];
    cal_opts.modulus_upper = modulus_range[1];
  }

  // --max-walltime of run or sweep: a duration ("3600", "1:00:00", "60m").
  const auto parse_walltime = [&parser_err](const std::string& text, double& seconds) {
    if (text.empty()) return true;
    try {
      seconds = ringdem::parse_duration(text);
      return true;
    } catch (const std::exception& e) {
      parser_err << "ringdem: --max-walltime: " << e.what() << "\n";
      return false;
    }
  };
  if (*run && !parse_walltime(max_walltime, run_opts.max_walltime)) return kExitInputError;
  if (*sweep && !parse_walltime(sweep_max_walltime, sweep_opts.max_walltime))
    return kExitInputError;

  // `info` and `check` need no MPI: started by mpirun or srun, the first process answers and the
  // others leave at once, so that the answer is printed once.
  if ((*info || *check) && !speaks) return 0;
  if (*info) return ringdem::print_file_info(info_path, std::cout);

  if (*check) {
    try {
      if (ringdem::is_sweep_file(check_path)) {  // the study and each of its cases
        const ringdem::SweepConfig study = ringdem::load_sweep(check_path, check_overrides);
        const std::vector<ringdem::SweepCase> cases = ringdem::expand_sweep(study);
        std::vector<ringdem::Diagnostic> warnings;
        ringdem::load_sweep_cases(study, cases, &warnings);
        std::cerr << ringdem::format_diagnostics(warnings);
        fmt::print("{}: valid sweep ({} cases of {}, {} parameter{}, combine: {})\n", check_path,
                   cases.size(), study.case_path, study.parameters.size(),
                   study.parameters.size() == 1 ? "" : "s", study.combine);
        return 0;
      }
      std::vector<ringdem::Diagnostic> warnings;
      const auto config = ringdem::load_case(check_path, check_overrides, &warnings);
      std::cerr << ringdem::format_diagnostics(warnings);
      fmt::print(
          "{}: valid ({} materials, {} bond types, {} rings, {} nets, {} rigid bodies, "
          "scenario {})\n",
          check_path, config.materials.size(), config.bonds.size(), config.rings.size(),
          config.nets.size(), config.rigid_bodies.size(), config.scenario.type);
      const ringdem::SizeEstimate size = ringdem::estimate_size(config);
      const double have = ringdem::available_memory_bytes();
      fmt::print(
          "size estimate: {}{}\n", ringdem::describe(size, 1),
          have > 0.0 && size.bytes_per_rank(1) > have
              ? fmt::format(" (more than the {:.0f} MiB available here)", have / (1024.0 * 1024.0))
              : std::string());
      // What sizes a job besides memory: the step and how many of them the run may take.
      if (const auto plan = ringdem::plan_time_steps_with_restraints(config)) {
        if (const auto warning = ringdem::restraint_step_warning(config, *plan))
          std::cerr << ringdem::format_diagnostic({check_path, 0, 0, "simulation.dt", *warning,
                                                   ringdem::Severity::kWarning})
                    << '\n';
        fmt::print(
            "time step: {:.4g} s ({}, {:.3f} of the smallest stability limit, {:.4g} s: {}); "
            "at most {:.0f} steps in the {:.4g} s the run may last ({})\n",
            plan->dt, plan->fixed ? "fixed" : "auto", plan->dt / plan->limit, plan->limit,
            plan->limit_what, std::ceil(plan->steps), plan->duration,
            plan->duration_key.rfind("scenario.rockfall.", 0) == 0
                ? std::string("the rockfall's phases at their longest")
                : plan->duration_key);
      }
      return 0;
    } catch (const ringdem::InputError& e) {
      std::cerr << e.format();
      return kExitInputError;
    }
  }

  // The input the run was started with, for errors that do not name it themselves.
  const std::string input_file = *sweep       ? sweep_opts.sweep_path
                                 : *calibrate ? cal_opts.case_path
                                              : run_opts.case_path;
  MPI_Init(&argc, &argv);
  int code = 0;
  {
    MPI_Comm world;
    MPI_Comm_dup(MPI_COMM_WORLD, &world);
    ringdem::Communicator comm(world);
    try {
      if (*sweep) {
        code = ringdem::run_sweep(sweep_opts, comm);
      } else if (*calibrate) {
        ringdem::run_calibration(cal_opts, comm);
      } else {
        std::vector<ringdem::Diagnostic> warnings;
        const auto config = ringdem::load_case(run_opts.case_path, run_opts.overrides, &warnings);
        if (comm.is_root()) std::cerr << ringdem::format_diagnostics(warnings);
        code = ringdem::run_case(config, run_opts, comm);
      }
    } catch (const ringdem::InputError& e) {
      if (comm.is_root()) std::cerr << e.format();
      code = kExitInputError;
    } catch (const std::bad_alloc&) {
      // Out of memory has no message of its own ("std::bad_alloc"): say which input was too big.
      std::cerr << fmt::format(
          "ringdem: error on rank {}: out of memory (std::bad_alloc) while running {}: the model "
          "needs more memory than this process may use; make it smaller (fewer particles) or "
          "spread it over more ranks on more nodes\n",
          comm.rank(), input_file);
      std::cerr.flush();
      if (comm.size() > 1) MPI_Abort(world, kExitRuntimeError);
      code = kExitRuntimeError;
    } catch (const std::exception& e) {
      std::cerr << fmt::format("ringdem: error on rank {} while running {}: {}\n", comm.rank(),
                               input_file, e.what());
      std::cerr.flush();
      // The other ranks may be waiting in a collective: end the whole job.
      if (comm.size() > 1) MPI_Abort(world, kExitRuntimeError);
      code = kExitRuntimeError;
    }
    MPI_Comm_free(&world);
  }
  MPI_Finalize();
  // A checkpointed stop on Ctrl-C, kill or scancel ends as the signal would have (128 + its
  // number, as a shell reports it), so that a job script does not take it for the stop before a
  // time limit (code 3) and resubmit.
  if (code == ringdem::kExitCheckpointed && ringdem::terminating_signal() != 0)
    code = 128 + ringdem::terminating_signal();
  return code;
}

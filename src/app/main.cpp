#include <mpi.h>

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>

#include "app/BuildInfo.hpp"
#include "app/RunCommand.hpp"
#include "app/SweepCommand.hpp"
#include "comm/Communicator.hpp"
#include "core/Version.hpp"
#include "io/CaseLoader.hpp"

namespace {

// Exit codes of DESIGN §6.
constexpr int kExitRuntimeError = 1;
constexpr int kExitInputError = 2;

}  // namespace

int main(int argc, char** argv) {
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

  std::string check_path;
  std::vector<std::string> check_overrides;
  auto* check = app.add_subcommand("check", "validate a case file without running it");
  check->add_option("case", check_path, "case file (YAML)")->required();
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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : kExitInputError;
  }

  if (*check) {
    try {
      const auto config = ringdem::load_case(check_path, check_overrides);
      fmt::print("{}: valid ({} materials, {} bonds types, {} rings, {} rigid bodies)\n",
                 check_path, config.materials.size(), config.bonds.size(), config.rings.size(),
                 config.rigid_bodies.size());
      return 0;
    } catch (const ringdem::InputError& e) {
      std::cerr << e.format();
      return kExitInputError;
    }
  }

  MPI_Init(&argc, &argv);
  int code = 0;
  {
    MPI_Comm world;
    MPI_Comm_dup(MPI_COMM_WORLD, &world);
    ringdem::Communicator comm(world);
    try {
      if (*sweep) {
        code = ringdem::run_sweep(sweep_opts, comm);
      } else {
        const auto config = ringdem::load_case(run_opts.case_path, run_opts.overrides);
        code = ringdem::run_case(config, run_opts, comm);
      }
    } catch (const ringdem::InputError& e) {
      if (comm.is_root()) std::cerr << e.format();
      code = kExitInputError;
    } catch (const std::exception& e) {
      std::cerr << fmt::format("ringdem: error on rank {}: {}\n", comm.rank(), e.what());
      code = kExitRuntimeError;
    }
    MPI_Comm_free(&world);
  }
  MPI_Finalize();
  return code;
}

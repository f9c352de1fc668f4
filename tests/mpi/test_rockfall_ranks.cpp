// A repeated rockfall (issue 14 point 4), with fixed or braked shackles, on this run's ranks
// gives the same bits as on one rank: the sag and re-settle rest checks, the releases above the
// measured net top, the removal of the boulder and every row of the results read quantities reduced
// over the ranks. On one rank the compared run halves the Verlet skin (its neighbour lists are
// rebuilt at other steps) so that it is not a copy of the reference.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "SharedTempDir.hpp"
#include "TestCases.hpp"
#include "app/ScenarioDriver.hpp"
#include "app/ScenarioRunner.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

std::string text_of(const fs::path& file) {
  std::stringstream s;
  s << std::ifstream(file).rdbuf();
  return s.str();
}

/// Runs `c` on this run's ranks (with half the skin on one rank) and, on rank 0, on one rank;
/// expects the same results files and impacts; returns the one-rank summary (rank 0).
nlohmann::json expect_same_on_every_rank_count(const CaseConfig& c, const std::string& tag) {
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  long long pid = rank == 0 ? static_cast<long long>(getpid()) : 0;
  MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir =
      fs::temp_directory_path() / ("ringdem_rockfall_ranks_" + tag + std::to_string(pid));
  CaseConfig compared = c;
  if (size == 1) compared.simulation.skin *= 0.5;

  ScenarioRunOptions run;
  run.verbose = false;
  run.handle_stop_requests = false;
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    run.output_dir = (dir / "ranks").string();
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(compared);
    EXPECT_EQ(run_scenario(*driver, run, comm), 0);
  }
  nlohmann::json one;
  if (rank == 0) {
    run.output_dir = (dir / "one").string();
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(c);
    EXPECT_EQ(run_scenario(*driver, run, Communicator::self()), 0);
    for (const char* file : {"series.csv", "sag.csv", "resettle.csv"}) {
      const std::string text = text_of(dir / "one" / file);
      EXPECT_FALSE(text.empty()) << file;
      EXPECT_TRUE(text_of(dir / "ranks" / file) == text) << file;
    }
    one = nlohmann::json::parse(text_of(dir / "one/summary.json"));
    const auto ranks = nlohmann::json::parse(text_of(dir / "ranks/summary.json"));
    EXPECT_EQ(ranks.at("impacts"), one.at("impacts"));
    EXPECT_EQ(ranks.at("steps"), one.at("steps"));
    EXPECT_EQ(ranks.at("energy_dissipated_J"), one.at("energy_dissipated_J"));
    fs::remove_all(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return one;
}

TEST(RockfallRanks, RepeatedImpactIsTheSameOnEveryRankCount) {
  const nlohmann::json one = expect_same_on_every_rank_count(
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml", {"scenario.rockfall.impacts=2"}),
      "fixed");
  if (!one.is_null()) {
    EXPECT_EQ(one.at("impacts").size(), 2u);
  }
}

// The same with braked shackles that slide once released (1 N, a quarter of their weight): the
// tori held while the net settles and set free at each release, their brakes' state and work,
// alike on every rank count.
TEST(RockfallRanks, BrakedShacklesAreTheSameOnEveryRankCount) {
  const nlohmann::json one = expect_same_on_every_rank_count(
      load_case_from_string(
          testing::kTinyRockfall, "tiny.yaml",
          {"scenario.rockfall.impacts=2", "particles.nets[0].shackles.brake.activation_force=1"}),
      "braked");
  if (one.is_null()) return;
  ASSERT_EQ(one.at("impacts").size(), 2u);
  EXPECT_GT(one.at("brake_largest_travel_m").get<double>(), 0.0);
  EXPECT_GT(one.at("impacts")[0].at("brake_work_share").get<double>(), 0.0);
  EXPECT_LT(one.at("energy_balance_error").get<double>(), 1e-3);
}

}  // namespace
}  // namespace ringdem

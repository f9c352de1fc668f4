// A repeated rockfall (issue 14 point 4) on this run's ranks gives the same bits as on one
// rank: the sag and re-settle rest checks, the releases above the measured net top, the removal
// of the boulder and every row of the results read quantities reduced over the ranks. On one
// rank the compared run halves the Verlet skin (its neighbour lists are rebuilt at other steps)
// so that it is not a copy of the reference.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

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

TEST(RockfallRanks, RepeatedImpactIsTheSameOnEveryRankCount) {
  const CaseConfig c =
      load_case_from_string(testing::kTinyRockfall, "tiny.yaml", {"scenario.rockfall.impacts=2"});
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  long long pid = rank == 0 ? static_cast<long long>(getpid()) : 0;
  MPI_Bcast(&pid, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  const fs::path dir =
      fs::temp_directory_path() / ("ringdem_rockfall_ranks_" + std::to_string(pid));
  CaseConfig compared = c;
  if (size == 1) compared.simulation.skin *= 0.5;

  ScenarioRunOptions run;
  run.verbose = false;
  run.handle_stop_requests = false;
  MPI_Comm world;
  MPI_Comm_dup(MPI_COMM_WORLD, &world);
  {
    const Communicator comm(world);
    run.output_dir = (dir / "ranks").string();
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(compared);
    EXPECT_EQ(run_scenario(*driver, run, comm), 0);
  }
  MPI_Comm_free(&world);
  if (rank == 0) {
    run.output_dir = (dir / "one").string();
    std::unique_ptr<ScenarioDriver> driver = make_scenario_driver(c);
    EXPECT_EQ(run_scenario(*driver, run, Communicator::self()), 0);
    for (const char* file : {"series.csv", "sag.csv", "resettle.csv"}) {
      const std::string one = text_of(dir / "one" / file);
      EXPECT_FALSE(one.empty()) << file;
      EXPECT_TRUE(text_of(dir / "ranks" / file) == one) << file;
    }
    const auto one = nlohmann::json::parse(text_of(dir / "one/summary.json"));
    const auto ranks = nlohmann::json::parse(text_of(dir / "ranks/summary.json"));
    ASSERT_EQ(one.at("impacts").size(), 2u);
    EXPECT_EQ(ranks.at("impacts"), one.at("impacts"));
    EXPECT_EQ(ranks.at("steps"), one.at("steps"));
    EXPECT_EQ(ranks.at("energy_dissipated_J"), one.at("energy_dissipated_J"));
    fs::remove_all(dir);
  }
  MPI_Barrier(MPI_COMM_WORLD);
}

}  // namespace
}  // namespace ringdem

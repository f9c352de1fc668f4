// A parameter study's cases go to the ranks as they come free (app/CaseClaims): every case to
// exactly one rank, however the ranks race for them, and none kept back by a busy rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <algorithm>
#include <filesystem>
#include <numeric>

#include "SharedTempDir.hpp"
#include "app/CaseClaims.hpp"

namespace ringdem {
namespace {

constexpr std::size_t kCases = 7;

/// Every case this rank gets by asking until none is left.
std::vector<std::int64_t> claim_all(CaseClaims& claims) {
  std::vector<std::int64_t> mine;
  while (const auto k = claims.next())
    mine.push_back(static_cast<std::int64_t>(*k));
  return mine;
}

std::vector<std::int64_t> every_case() {
  std::vector<std::int64_t> all(kCases);
  std::iota(all.begin(), all.end(), 0);
  return all;
}

TEST(CaseClaims, EveryCaseGoesToExactlyOneRankAndAKilledStudysClaimsAreCleared) {
  const testing::WorldCopy world;
  const Communicator comm(world.raw());
  const std::string dir = testing::shared_temp_dir(comm, "claims");
  {
    CaseClaims claims(
        dir, kCases, comm,
        static_cast<std::size_t>(comm.rank()));  // all ranks race for all cases at once
    std::vector<std::int64_t> got = comm.allgather(claim_all(claims));
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, every_case()) << comm.size() << " ranks";
    // Not closed: as a study killed at this point leaves its claims.
  }
  {
    CaseClaims claims(
        dir, kCases, comm,
        static_cast<std::size_t>(comm.rank()));  // the next study into the folder starts afresh
    std::vector<std::int64_t> got = comm.allgather(claim_all(claims));
    std::sort(got.begin(), got.end());
    EXPECT_EQ(got, every_case()) << "after a killed study, " << comm.size() << " ranks";
    claims.close(comm);
  }
  if (comm.is_root()) {
    EXPECT_FALSE(std::filesystem::exists(std::filesystem::path(dir) / CaseClaims::kFolderName));
  }
  comm.barrier();
  if (comm.is_root()) std::filesystem::remove_all(dir);
}

TEST(CaseClaims, ABusyRankKeepsNoCaseBack) {
  const testing::WorldCopy world;
  const Communicator comm(world.raw());
  const std::string dir = testing::shared_temp_dir(comm, "claims");
  CaseClaims claims(dir, kCases, comm, static_cast<std::size_t>(comm.rank()));
  std::vector<std::int64_t> mine;
  // Rank 0 takes one case and is busy with it while the others take the rest.
  if (comm.is_root()) {
    const auto first = claims.next();
    ASSERT_TRUE(first.has_value());
    mine.push_back(static_cast<std::int64_t>(*first));
  }
  comm.barrier();
  if (!comm.is_root()) mine = claim_all(claims);
  comm.barrier();
  if (comm.is_root()) {
    const std::vector<std::int64_t> after = claim_all(claims);
    mine.insert(mine.end(), after.begin(), after.end());
  }
  // A fixed deal (case i on rank i mod N) would have left cases 2, 4, 6 to the busy rank 0 at
  // 2 ranks; here it has its first case only, unless it is alone.
  if (comm.size() == 1) {
    EXPECT_EQ(mine, every_case());
  } else if (comm.is_root()) {
    EXPECT_EQ(mine.size(), 1u);
  }
  std::vector<std::int64_t> got = comm.allgather(mine);
  std::sort(got.begin(), got.end());
  EXPECT_EQ(got, every_case());
  claims.close(comm);
  if (comm.is_root()) std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace ringdem

// Runs the MPI test binary on every rank. gtest output is printed by rank 0 only; other
// ranks print their failures with the rank. A fatal failure (ASSERT_*, FAIL) on one rank
// ends the test body there while the other ranks go on to the next collective and would wait
// forever, so it aborts every rank at once (MPI_Abort, non-zero exit) after its message is
// out. Non-fatal failures (EXPECT_*) let every rank reach the same collectives: the run goes
// on and the exit code is reduced over the ranks at the end.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cstdio>
#include <string>

namespace {

/// On ranks other than 0: print only failures, with the rank, so that a failure on one rank
/// is visible even though rank 0 prints the report.
class RankFailurePrinter : public ::testing::EmptyTestEventListener {
 public:
  explicit RankFailurePrinter(int rank) : rank_(rank) {}
  void OnTestPartResult(const ::testing::TestPartResult& r) override {
    if (r.failed()) {
      std::fprintf(stderr, "[rank %d] %s:%d: %s\n", rank_, r.file_name() ? r.file_name() : "?",
                   r.line_number(), r.summary());
      std::fflush(stderr);
    }
  }

 private:
  int rank_;
};

/// On every rank, after the printers: a fatal failure aborts all ranks.
class AbortOnFatalFailure : public ::testing::EmptyTestEventListener {
 public:
  explicit AbortOnFatalFailure(int rank) : rank_(rank) {}
  // The test's name is kept here: UnitTest::current_test_info() would take the lock that
  // gtest holds while it reports a result, and deadlock.
  void OnTestStart(const ::testing::TestInfo& test) override {
    test_ = std::string(test.test_suite_name()) + "." + test.name();
  }
  void OnTestPartResult(const ::testing::TestPartResult& r) override {
    if (!r.fatally_failed()) return;
    std::fflush(stdout);
    std::fprintf(stderr, "[rank %d] fatal failure in %s: aborting all ranks\n", rank_,
                 test_.empty() ? "?" : test_.c_str());
    std::fflush(stderr);
    MPI_Abort(MPI_COMM_WORLD, 1);
  }

 private:
  int rank_;
  std::string test_;
};

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  // An exception on one rank must end the job (mpirun then stops the others), not be caught
  // by gtest while the other ranks wait in a collective.
  GTEST_FLAG_SET(catch_exceptions, false);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
  if (rank != 0) {
    delete listeners.Release(listeners.default_result_printer());
    listeners.Append(new RankFailurePrinter(rank));
  }
  // Appended last, so the failure's own message is printed before the abort.
  listeners.Append(new AbortOnFatalFailure(rank));
  const int local = RUN_ALL_TESTS();
  int global = 0;
  MPI_Allreduce(&local, &global, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  if (local != 0) std::fprintf(stderr, "rank %d: tests FAILED\n", rank);
  MPI_Finalize();
  return global;
}

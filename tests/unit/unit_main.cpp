// The unit tests run on one process. MPI start-up costs most of a second per process, and
// ctest runs every test in its own process, so MPI is initialised only by the tests that use
// a communicator (testing::self_comm) and finalised here.
#include <gtest/gtest.h>
#include <mpi.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  const int result = RUN_ALL_TESTS();
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (initialised) MPI_Finalize();
  return result;
}

#pragma once

#include <mpi.h>

#include <string>
#include <vector>

#include "TempDir.hpp"
#include "comm/Communicator.hpp"

namespace ringdem::testing {

/// temp_dir(tag) made by the root rank of `comm`, its path given to every rank: a directory
/// all ranks share (they run on one machine). The test removes it.
inline std::string shared_temp_dir(const Communicator& comm, const std::string& tag) {
  std::vector<char> path;
  if (comm.is_root()) {
    const std::string made = temp_dir(tag);
    path.assign(made.begin(), made.end());
  }
  comm.broadcast(path, 0);
  return std::string(path.begin(), path.end());
}

/// A copy of MPI_COMM_WORLD for one test, freed at its end, so that no test's messages can
/// meet another's (the library never sees MPI_COMM_WORLD itself).
class WorldCopy {
 public:
  WorldCopy() { MPI_Comm_dup(MPI_COMM_WORLD, &raw_); }
  ~WorldCopy() { MPI_Comm_free(&raw_); }
  WorldCopy(const WorldCopy&) = delete;
  WorldCopy& operator=(const WorldCopy&) = delete;
  MPI_Comm raw() const { return raw_; }

 private:
  MPI_Comm raw_ = MPI_COMM_NULL;
};

}  // namespace ringdem::testing

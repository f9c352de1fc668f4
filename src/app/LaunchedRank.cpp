#include "app/LaunchedRank.hpp"

#include <array>
#include <cerrno>
#include <cstdlib>

namespace ringdem {

int launched_rank() {
  // Open MPI's mpirun, PMIx launchers (Open MPI 5, srun --mpi=pmix), MPICH's Hydra and Intel
  // MPI, SLURM's srun: the first one set names the rank.
  constexpr std::array<const char*, 4> kVariables{"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK",
                                                  "SLURM_PROCID"};
  for (const char* name : kVariables) {
    const char* text = std::getenv(name);
    if (text == nullptr || *text == '\0') continue;
    char* end = nullptr;
    errno = 0;
    const long rank = std::strtol(text, &end, 10);
    if (errno == 0 && *end == '\0' && rank >= 0) return static_cast<int>(rank);
  }
  return 0;
}

}  // namespace ringdem

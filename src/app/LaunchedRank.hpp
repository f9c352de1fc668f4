#pragma once

namespace ringdem {

/// This process's rank as its launcher numbers it, read before MPI_Init from the environment
/// that mpirun (Open MPI, MPICH, Intel MPI, PMIx) and srun set; 0 when none is set (a plain
/// start). The command line is parsed before MPI starts, so that `info`, `check` and `--help`
/// run without it: this lets only the first process print the parser's help and errors instead
/// of every rank of the job printing the same text.
int launched_rank();

}  // namespace ringdem

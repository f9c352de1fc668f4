#pragma once

#include <string>

namespace ringdem {

/// One line per library ringdem runs with (version as reported at run time), for
/// `ringdem --version` and the run banner. Calling into MPI, HDF5 and METIS here also proves
/// that the toolchain links them.
std::string build_info();

}  // namespace ringdem

#include "app/BuildInfo.hpp"

#include <fmt/core.h>
#include <hdf5.h>
#include <metis.h>
#include <mpi.h>

#include "core/Version.hpp"

namespace ringdem {

std::string build_info() {
  char mpi_version[MPI_MAX_LIBRARY_VERSION_STRING] = {};
  int length = 0;
  MPI_Get_library_version(mpi_version, &length);
  std::string mpi(mpi_version, static_cast<std::size_t>(length));
  if (const auto cut = mpi.find_first_of(",\n"); cut != std::string::npos) mpi.resize(cut);

  unsigned h5_major = 0, h5_minor = 0, h5_release = 0;
  H5get_libversion(&h5_major, &h5_minor, &h5_release);
#ifdef H5_HAVE_PARALLEL
  constexpr const char* h5_kind = "parallel";
#else
  constexpr const char* h5_kind = "serial";
#endif

  // METIS reports its version only at compile time; a call proves the library links.
  idx_t options[METIS_NOPTIONS];
  const bool metis_ok = METIS_SetDefaultOptions(options) == METIS_OK;

  return fmt::format("ringdem {}\n  MPI:   {}\n  HDF5:  {}.{}.{} ({})\n  METIS: {}.{}.{}{}\n",
                     kVersion, mpi, h5_major, h5_minor, h5_release, h5_kind, METIS_VER_MAJOR,
                     METIS_VER_MINOR, METIS_VER_SUBMINOR, metis_ok ? "" : " (library call failed)");
}

}  // namespace ringdem

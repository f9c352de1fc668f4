#pragma once

#include <hdf5.h>

#include <cstdint>
#include <string>

namespace ringdem::testing {

/// Relabels a written checkpoint as format `version` (its root attribute `format_version`), to
/// see how a reader treats a file of another format without keeping old files around.
inline void set_checkpoint_format_version(const std::string& path, std::int64_t version) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  const hid_t a = H5Aopen(f, "format_version", H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_INT64, &version);
  H5Aclose(a);
  H5Fclose(f);
}

}  // namespace ringdem::testing

#include "io/Hdf5File.hpp"

#include <algorithm>
#include <filesystem>
#include <system_error>
#include <utility>

namespace ringdem {

namespace {

/// Closes an HDF5 identifier at scope end.
class Handle {
 public:
  Handle(hid_t id, herr_t (*closer)(hid_t)) : id_(id), closer_(closer) {}
  ~Handle() {
    if (id_ >= 0) closer_(id_);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_;
  herr_t (*closer_)(hid_t);
};

void silence_hdf5() {
  // Our messages name the file and object; HDF5's stack dumps would bury them.
  static const bool done = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)done;
}

hid_t transfer_list(bool parallel) {
  const hid_t dxpl = H5Pcreate(H5P_DATASET_XFER);
  if (parallel) H5Pset_dxpl_mpio(dxpl, H5FD_MPIO_COLLECTIVE);
  return dxpl;
}

}  // namespace

std::uint64_t fnv1a64(const void* data, std::size_t bytes, std::uint64_t seed) {
  const auto* p = static_cast<const unsigned char*>(data);
  std::uint64_t h = seed;
  for (std::size_t i = 0; i < bytes; ++i) {
    h ^= p[i];
    h *= 1099511628211ull;
  }
  return h;
}

namespace {

hid_t parallel_access_list(MPI_Comm comm) {
  const hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  // Collective buffering in pieces of 4 MiB a process instead of the MPI-IO layer's 32 MiB
  // (Open MPI's OMPIO) or 16 MiB (ROMIO): the checkpoint of 2.5 x 10^5 grains in contact a rank
  // peaked 24 MiB higher with the default, and wrote no faster (docs/performance.md, fifty-
  // seventh round). H5Pset_fapl_mpio keeps its own copy of the hints.
  MPI_Info hints;
  MPI_Info_create(&hints);
  MPI_Info_set(hints, "cb_buffer_size", "4194304");
  H5Pset_fapl_mpio(fapl, comm, hints);
  MPI_Info_free(&hints);
  // Metadata written collectively too: fewer small independent writes at scale.
  H5Pset_coll_metadata_write(fapl, true);
  // A viewer (ParaView) reading the file between frames must not make the next frame fail.
  H5Pset_file_locking(fapl, false, true);
  return fapl;
}

}  // namespace

Hdf5File Hdf5File::create(const std::string& path, const Communicator& comm) {
  silence_hdf5();
  Handle fapl(parallel_access_list(comm.raw()), H5Pclose);
  const hid_t id = H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get());
  if (id < 0) throw Hdf5Error("cannot create HDF5 file " + path);
  return Hdf5File(id, path, true, comm.rank());
}

Hdf5File Hdf5File::open_parallel(const std::string& path, const Communicator& comm) {
  silence_hdf5();
  Handle fapl(parallel_access_list(comm.raw()), H5Pclose);
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDWR, fapl.get());
  if (id < 0) throw Hdf5Error("cannot reopen HDF5 file " + path);
  return Hdf5File(id, path, true, comm.rank());
}

Hdf5File Hdf5File::open_read(const std::string& path) {
  silence_hdf5();
  // Say what the path is when it is not a file at all; HDF5 would only say "not an HDF5 file".
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) throw Hdf5Error(path + ": no such file");
  if (std::filesystem::is_directory(status))
    throw Hdf5Error(path + ": is a directory, not an HDF5 file");
  if (!std::filesystem::is_regular_file(status))
    throw Hdf5Error(path + ": not a regular file, so not an HDF5 file");
  if (H5Fis_hdf5(path.c_str()) <= 0)
    throw Hdf5Error(path + ": not an HDF5 file, or it is truncated or unreadable");
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw Hdf5Error(path + ": HDF5 cannot open it (truncated or corrupted?)");
  return Hdf5File(id, path, false, 0);
}

Hdf5File Hdf5File::open_parallel_read(const std::string& path, const Communicator& comm) {
  silence_hdf5();
  Handle fapl(parallel_access_list(comm.raw()), H5Pclose);
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get());
  if (id < 0) throw Hdf5Error(path + ": HDF5 cannot open it (truncated or corrupted?)");
  return Hdf5File(id, path, true, comm.rank());
}

Hdf5File::Hdf5File(Hdf5File&& o) noexcept
    : id_(std::exchange(o.id_, -1)),
      path_(std::move(o.path_)),
      parallel_(o.parallel_),
      rank_(o.rank_) {}

Hdf5File& Hdf5File::operator=(Hdf5File&& o) noexcept {
  if (this != &o) {
    close();
    id_ = std::exchange(o.id_, -1);
    path_ = std::move(o.path_);
    parallel_ = o.parallel_;
    rank_ = o.rank_;
  }
  return *this;
}

Hdf5File::~Hdf5File() {
  close();
}

void Hdf5File::close() {
  if (id_ >= 0) H5Fclose(id_);
  id_ = -1;
}

void Hdf5File::fail(const std::string& what) const {
  throw Hdf5Error(path_ + ": " + what);
}

void Hdf5File::create_group(const std::string& name) {
  Handle g(H5Gcreate2(id_, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.ok()) fail("cannot create group " + name);
}

bool Hdf5File::exists(const std::string& name) const {
  // Check each level: H5Lexists fails on a missing intermediate group.
  std::size_t pos = 0;
  while (true) {
    pos = name.find('/', pos + 1);
    const std::string prefix = name.substr(0, pos);
    if (!prefix.empty() && prefix != "/" && H5Lexists(id_, prefix.c_str(), H5P_DEFAULT) <= 0)
      return false;
    if (pos == std::string::npos) return true;
  }
}

namespace {

template <class T>
void write_attribute(hid_t file, const std::string& object, const std::string& name, hid_t type,
                     const T* value, const std::string& path) {
  Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.ok()) throw Hdf5Error(path + ": no object " + object);
  if (H5Aexists(obj.get(), name.c_str()) > 0) H5Adelete(obj.get(), name.c_str());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj.get(), name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  if (!attr.ok() || H5Awrite(attr.get(), type, value) < 0)
    throw Hdf5Error(path + ": cannot write attribute " + object + "@" + name);
}

}  // namespace

void Hdf5File::set_attribute(const std::string& object, const std::string& name, double v) {
  write_attribute(id_, object, name, H5T_NATIVE_DOUBLE, &v, path_);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name, std::int64_t v) {
  write_attribute(id_, object, name, H5T_NATIVE_INT64, &v, path_);
}

void Hdf5File::set_attribute(const std::string& object, const std::string& name,
                             const std::string& v) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), std::max<std::size_t>(v.size(), 1));
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  std::string padded = v.empty() ? std::string(1, '\0') : v;
  write_attribute(id_, object, name, type.get(), padded.data(), path_);
}

bool Hdf5File::has_attribute(const std::string& object, const std::string& name) const {
  if (!exists(object)) return false;
  Handle obj(H5Oopen(id_, object.c_str(), H5P_DEFAULT), H5Oclose);
  return obj.ok() && H5Aexists(obj.get(), name.c_str()) > 0;
}

namespace {

Handle open_attribute(hid_t file, const std::string& object, const std::string& name,
                      const std::string& path) {
  Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (!obj.ok()) throw Hdf5Error(path + ": no object " + object);
  const hid_t a = H5Aopen(obj.get(), name.c_str(), H5P_DEFAULT);
  if (a < 0) throw Hdf5Error(path + ": attribute " + object + "@" + name + " is missing");
  return Handle(a, H5Aclose);
}

}  // namespace

double Hdf5File::attribute_double(const std::string& object, const std::string& name) const {
  Handle a = open_attribute(id_, object, name, path_);
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0) fail("cannot read attribute " + name);
  return v;
}

std::int64_t Hdf5File::attribute_int(const std::string& object, const std::string& name) const {
  Handle a = open_attribute(id_, object, name, path_);
  std::int64_t v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_INT64, &v) < 0) fail("cannot read attribute " + name);
  return v;
}

std::string Hdf5File::attribute_string(const std::string& object, const std::string& name) const {
  Handle a = open_attribute(id_, object, name, path_);
  Handle type(H5Aget_type(a.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING || H5Tis_variable_str(type.get()) > 0)
    fail("attribute " + name + " is not a fixed-length string");
  std::string v(H5Tget_size(type.get()), '\0');
  if (H5Aread(a.get(), type.get(), v.data()) < 0) fail("cannot read attribute " + name);
  v.resize(v.find('\0') == std::string::npos ? v.size() : v.find('\0'));
  return v;
}

namespace {

/// Rows per chunk: one frame's rows up to 64 Ki; a dataset created empty (no bonds yet) gets
/// 4 Ki, as its rows may come later.
hsize_t chunk_rows(std::int64_t rows) {
  return static_cast<hsize_t>(rows > 0 ? std::min<std::int64_t>(rows, 65536) : 4096);
}

}  // namespace

void Hdf5File::create_rows(const std::string& name, hid_t type, int components, std::int64_t rows,
                           bool extendible) {
  const int rank = components > 1 ? 2 : 1;
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(components)};
  const hsize_t maxdims[2] = {H5S_UNLIMITED, static_cast<hsize_t>(components)};
  Handle space(H5Screate_simple(rank, dims, extendible ? maxdims : nullptr), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  if (extendible) {
    const hsize_t chunk[2] = {chunk_rows(rows), static_cast<hsize_t>(components)};
    H5Pset_chunk(dcpl.get(), rank, chunk);
  }
  Handle d(H5Dcreate2(id_, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
           H5Dclose);
  if (!d.ok()) fail("cannot create dataset " + name);
}

void Hdf5File::create_frames(const std::string& name, hid_t type, int components, std::int64_t rows,
                             int compression) {
  const int rank = components > 1 ? 3 : 2;
  const hsize_t dims[3] = {0, static_cast<hsize_t>(rows), static_cast<hsize_t>(components)};
  const hsize_t maxdims[3] = {H5S_UNLIMITED, H5S_UNLIMITED, static_cast<hsize_t>(components)};
  // One chunk per frame (split beyond 64 Ki rows): a frame is written and read as a whole.
  const hsize_t chunk[3] = {1, chunk_rows(rows), static_cast<hsize_t>(components)};
  Handle space(H5Screate_simple(rank, dims, maxdims), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl.get(), rank, chunk);
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  if (compression > 0) {
    H5Pset_shuffle(dcpl.get());
    H5Pset_deflate(dcpl.get(), static_cast<unsigned>(compression));
  }
  Handle d(H5Dcreate2(id_, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
           H5Dclose);
  if (!d.ok()) fail("cannot create dataset " + name);
}

void Hdf5File::extend_rows(const std::string& name, std::int64_t rows) {
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("no dataset " + name);
  Handle space(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  hsize_t dims[3] = {0, 0, 0}, maxdims[3] = {0, 0, 0};
  H5Sget_simple_extent_dims(space.get(), dims, maxdims);
  // A frame dataset's first dimension is unlimited too: its rows are the second.
  const int row_dim = rank >= 2 && maxdims[1] == H5S_UNLIMITED ? 1 : 0;
  if (maxdims[row_dim] != H5S_UNLIMITED) fail("dataset " + name + " cannot grow in rows");
  if (dims[row_dim] >= static_cast<hsize_t>(rows)) return;
  dims[row_dim] = static_cast<hsize_t>(rows);
  if (H5Dset_extent(d.get(), dims) < 0) fail("cannot extend " + name);
}

void Hdf5File::write_rows(const std::string& name, std::int64_t frame, std::int64_t first_row,
                          std::int64_t count, const void* data, hid_t type) {
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("no dataset " + name);
  Handle fspace0(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(fspace0.get());
  hsize_t dims[3] = {0, 0, 0};
  H5Sget_simple_extent_dims(fspace0.get(), dims, nullptr);
  hsize_t start[3] = {0, 0, 0}, size[3] = {1, 1, 1};
  if (frame >= 0 && dims[0] < static_cast<hsize_t>(frame + 1)) {
    // The frame exists even when it has no rows (no bonds yet), so frames stay aligned.
    dims[0] = static_cast<hsize_t>(frame + 1);
    if (H5Dset_extent(d.get(), dims) < 0) fail("cannot extend " + name);
  }
  // An empty dataset (no contact springs, say): nothing to write on any rank.
  if (frame < 0 && dims[0] == 0) return;
  if (frame >= 0 && rank >= 2 && dims[1] == 0) return;
  if (frame >= 0) {
    start[0] = static_cast<hsize_t>(frame);
    start[1] = static_cast<hsize_t>(first_row);
    size[1] = static_cast<hsize_t>(count);
    if (rank == 3) size[2] = dims[2];
  } else {
    start[0] = static_cast<hsize_t>(first_row);
    size[0] = static_cast<hsize_t>(count);
    if (rank == 2) size[1] = dims[1];
  }
  Handle fspace(H5Dget_space(d.get()), H5Sclose);
  Handle mspace(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (count == 0) {
    H5Sselect_none(fspace.get());
    H5Sselect_none(mspace.get());
  } else {
    H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, size, nullptr);
  }
  Handle dxpl(transfer_list(parallel_), H5Pclose);
  // HDF5 refuses a null buffer even when nothing is selected (an empty block on this rank).
  const double dummy = 0.0;
  if (H5Dwrite(d.get(), type, mspace.get(), fspace.get(), dxpl.get(), data ? data : &dummy) < 0)
    fail("cannot write " + name);
}

void Hdf5File::create_series(const std::string& name, hid_t type) {
  const hsize_t dims = 0, maxdims = H5S_UNLIMITED, chunk = 1024;
  Handle space(H5Screate_simple(1, &dims, &maxdims), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl.get(), 1, &chunk);
  H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER);
  Handle d(H5Dcreate2(id_, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
           H5Dclose);
  if (!d.ok()) fail("cannot create dataset " + name);
}

void Hdf5File::write_series(const std::string& name, std::int64_t frame, const void* value,
                            hid_t type) {
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("no dataset " + name);
  const hsize_t size = static_cast<hsize_t>(frame + 1);
  if (H5Dset_extent(d.get(), &size) < 0) fail("cannot extend " + name);
  Handle fspace(H5Dget_space(d.get()), H5Sclose);
  const hsize_t start = static_cast<hsize_t>(frame), one = 1;
  Handle mspace(H5Screate_simple(1, &one, nullptr), H5Sclose);
  if (parallel_ && rank_ != 0) {
    H5Sselect_none(fspace.get());
    H5Sselect_none(mspace.get());
  } else {
    H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, &start, nullptr, &one, nullptr);
  }
  Handle dxpl(transfer_list(parallel_), H5Pclose);
  if (H5Dwrite(d.get(), type, mspace.get(), fspace.get(), dxpl.get(), value) < 0)
    fail("cannot write " + name);
}

std::vector<std::int64_t> Hdf5File::dims(const std::string& name) const {
  if (!exists(name)) fail("dataset " + name + " is missing");
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("cannot open dataset " + name);
  Handle space(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) fail("cannot read the shape of " + name);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return {dims.begin(), dims.end()};
}

void Hdf5File::check_layout(const std::string& name, std::int64_t frame, int components) const {
  const auto d = dims(name);
  const std::size_t expected_rank = (frame >= 0 ? 2u : 1u) + (components > 1 ? 1u : 0u);
  if (d.size() != expected_rank || (components > 1 && d.back() != components))
    fail("dataset " + name + " has an unexpected shape");
  if (frame >= 0 && frame >= d[0])
    fail("dataset " + name + " has no frame " + std::to_string(frame));
}

void Hdf5File::read_raw(const std::string& name, std::int64_t frame, std::int64_t first_row,
                        std::int64_t count, void* out, hid_t type) const {
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("cannot open dataset " + name);
  Handle fspace(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(fspace.get());
  hsize_t dims[3] = {0, 0, 0};
  H5Sget_simple_extent_dims(fspace.get(), dims, nullptr);
  const int row_dim = frame >= 0 ? 1 : 0;
  if (first_row < 0 || count < 0 ||
      static_cast<hsize_t>(first_row + count) > dims[static_cast<std::size_t>(row_dim)])
    fail("dataset " + name + " has no rows " + std::to_string(first_row) + ".." +
         std::to_string(first_row + count - 1));
  hsize_t start[3] = {0, 0, 0};
  hsize_t size[3] = {dims[0], dims[1], dims[2]};
  if (frame >= 0) {
    start[0] = static_cast<hsize_t>(frame);
    size[0] = 1;
  }
  start[row_dim] = static_cast<hsize_t>(first_row);
  size[row_dim] = static_cast<hsize_t>(count);
  H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, size, nullptr);
  Handle mspace(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (H5Dread(d.get(), type, mspace.get(), fspace.get(), H5P_DEFAULT, out) < 0)
    fail("cannot read dataset " + name + " (corrupted?)");
}

void Hdf5File::read_block_raw(const std::string& name, std::int64_t first_row, std::int64_t count,
                              void* out, hid_t type) const {
  Handle d(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!d.ok()) fail("cannot open dataset " + name);
  Handle fspace(H5Dget_space(d.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(fspace.get());
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(fspace.get(), dims, nullptr);
  if (first_row < 0 || count < 0 || static_cast<hsize_t>(first_row + count) > dims[0])
    fail("dataset " + name + " has no rows " + std::to_string(first_row) + ".." +
         std::to_string(first_row + count));
  // An empty dataset (no contact springs, say): nothing to read on any rank.
  if (dims[0] == 0) return;
  hsize_t start[2] = {static_cast<hsize_t>(first_row), 0};
  hsize_t size[2] = {static_cast<hsize_t>(count), rank == 2 ? dims[1] : 1};
  Handle mspace(H5Screate_simple(rank, size, nullptr), H5Sclose);
  if (count == 0) {
    H5Sselect_none(fspace.get());
    H5Sselect_none(mspace.get());
  } else {
    H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start, nullptr, size, nullptr);
  }
  Handle dxpl(transfer_list(parallel_), H5Pclose);
  // HDF5 refuses a null buffer even when nothing is selected (an empty block on this rank).
  double dummy = 0.0;
  if (H5Dread(d.get(), type, mspace.get(), fspace.get(), dxpl.get(), out ? out : &dummy) < 0)
    fail("cannot read dataset " + name + " (corrupted?)");
}

std::vector<char> Hdf5File::read_bytes(const std::string& name, std::size_t& row_bytes) const {
  const auto d = dims(name);
  Handle ds(H5Dopen2(id_, name.c_str(), H5P_DEFAULT), H5Dclose);
  Handle file_type(H5Dget_type(ds.get()), H5Tclose);
  Handle type(H5Tget_native_type(file_type.get(), H5T_DIR_ASCEND), H5Tclose);
  std::size_t elements = 1;
  for (auto n : d)
    elements *= static_cast<std::size_t>(n);
  const std::size_t size = H5Tget_size(type.get());
  std::vector<char> out(elements * size);
  row_bytes = d.empty() || d[0] == 0 ? 0 : out.size() / static_cast<std::size_t>(d[0]);
  if (!out.empty() && H5Dread(ds.get(), type.get(), H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail("cannot read dataset " + name + " (corrupted?)");
  return out;
}

std::vector<std::string> Hdf5File::list(const std::string& group) const {
  std::vector<std::string> names;
  if (!exists(group)) return names;
  Handle g(H5Gopen2(id_, group.c_str(), H5P_DEFAULT), H5Gclose);
  if (!g.ok()) return names;
  H5G_info_t info;
  H5Gget_info(g.get(), &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len =
        H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    if (len < 0) continue;
    std::string name(static_cast<std::size_t>(len) + 1, '\0');
    H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), name.size(),
                       H5P_DEFAULT);
    name.resize(static_cast<std::size_t>(len));
    names.push_back(name);
  }
  return names;
}

}  // namespace ringdem

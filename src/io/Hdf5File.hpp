#pragma once

#include <hdf5.h>

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "comm/Communicator.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "core/Vec3f.hpp"
#include "domain/ContactLedgerState.hpp"

namespace ringdem {

/// An HDF5 call failed, or a file does not hold what it should; the message names the file
/// and the object.
class Hdf5Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// How a field type is stored: HDF5 element type and components per row (Vec3: 3 doubles,
/// Vec3f: 3 floats, ContactLedgerState: 4 floats, Quat: 4 doubles w, x, y, z, enums: their
/// underlying integer).
template <class T, class Enable = void>
struct H5Layout;
template <>
struct H5Layout<double> {
  static hid_t type() { return H5T_NATIVE_DOUBLE; }
  static constexpr int components = 1;
};
template <>
struct H5Layout<Vec3> {
  static hid_t type() { return H5T_NATIVE_DOUBLE; }
  static constexpr int components = 3;
};
template <>
struct H5Layout<Vec3f> {
  static hid_t type() { return H5T_NATIVE_FLOAT; }
  static constexpr int components = 3;
};
template <>
struct H5Layout<ContactLedgerState> {
  static hid_t type() { return H5T_NATIVE_FLOAT; }
  static constexpr int components = 4;
};
template <>
struct H5Layout<Quat> {
  static hid_t type() { return H5T_NATIVE_DOUBLE; }
  static constexpr int components = 4;
};
template <>
struct H5Layout<std::int64_t> {
  static hid_t type() { return H5T_NATIVE_INT64; }
  static constexpr int components = 1;
};
template <>
struct H5Layout<std::int32_t> {
  static hid_t type() { return H5T_NATIVE_INT32; }
  static constexpr int components = 1;
};
template <>
struct H5Layout<std::uint32_t> {
  static hid_t type() { return H5T_NATIVE_UINT32; }
  static constexpr int components = 1;
};
template <>
struct H5Layout<std::uint8_t> {
  static hid_t type() { return H5T_NATIVE_UINT8; }
  static constexpr int components = 1;
};
template <class T>
struct H5Layout<T, std::enable_if_t<std::is_enum_v<T>>> : H5Layout<std::underlying_type_t<T>> {};

/// 64-bit FNV-1a hash, for checkpoint checksums.
std::uint64_t fnv1a64(const void* data, std::size_t bytes,
                      std::uint64_t seed = 1469598103934665603ull);

/// One open HDF5 file. Created collectively over a communicator (MPI-IO, collective writes) or
/// opened read-only by one process. Datasets hold rows (one per particle or bond) of
/// H5Layout<T>::components values, either fixed [rows, comps] or extendible per frame
/// [frames, rows, comps] with one chunk per frame. Errors throw Hdf5Error; HDF5's own error
/// stack printing is switched off.
class Hdf5File {
 public:
  /// Collective: every rank of `comm` calls it. Truncates an existing file.
  static Hdf5File create(const std::string& path, const Communicator& comm);
  /// Collective: reopens a file for writing (frames are appended between closes).
  static Hdf5File open_parallel(const std::string& path, const Communicator& comm);
  /// Read-only, this process alone.
  static Hdf5File open_read(const std::string& path);
  /// Collective, read-only: every rank of `comm` reads its own rows (read_row_block).
  static Hdf5File open_parallel_read(const std::string& path, const Communicator& comm);

  Hdf5File(Hdf5File&& o) noexcept;
  Hdf5File& operator=(Hdf5File&& o) noexcept;
  Hdf5File(const Hdf5File&) = delete;
  Hdf5File& operator=(const Hdf5File&) = delete;
  ~Hdf5File();
  void close();
  const std::string& path() const { return path_; }

  void create_group(const std::string& name);
  bool exists(const std::string& name) const;

  // Attributes on the file root or any group/dataset (collective when parallel: same value on
  // every rank).
  void set_attribute(const std::string& object, const std::string& name, double v);
  void set_attribute(const std::string& object, const std::string& name, std::int64_t v);
  void set_attribute(const std::string& object, const std::string& name, const std::string& v);
  double attribute_double(const std::string& object, const std::string& name) const;
  std::int64_t attribute_int(const std::string& object, const std::string& name) const;
  std::string attribute_string(const std::string& object, const std::string& name) const;
  bool has_attribute(const std::string& object, const std::string& name) const;

  /// [rows, comps] dataset (collective create): contiguous, or chunked and extendible in rows
  /// (extend_rows) when `extendible`.
  void create_rows(const std::string& name, hid_t type, int components, std::int64_t rows,
                   bool extendible = false);
  /// Per-frame [0, rows, comps], extendible in frames and rows, one chunk per frame (of at
  /// most 64 Ki rows), deflate level `compression` (0: none), no fill values written.
  void create_frames(const std::string& name, hid_t type, int components, std::int64_t rows,
                     int compression);
  /// Collective: grows the row dimension of an extendible dataset (a frame dataset's second,
  /// an extendible fixed one's first) to `rows` when it is smaller.
  void extend_rows(const std::string& name, std::int64_t rows);
  /// Collective write of rows [first_row, first_row + count) of frame `frame` (-1: a fixed
  /// dataset). Extends a frame dataset's frames as needed (every rank passes the same frame).
  void write_rows(const std::string& name, std::int64_t frame, std::int64_t first_row,
                  std::int64_t count, const void* data, hid_t type);
  template <class T>
  void write_rows(const std::string& name, std::int64_t frame, std::int64_t first_row,
                  const std::vector<T>& block) {
    write_rows(name, frame, first_row, static_cast<std::int64_t>(block.size()), block.data(),
               H5Layout<T>::type());
  }
  /// 1-D extendible dataset of one value per frame (time, step).
  void create_series(const std::string& name, hid_t type);
  /// Collective: sets element `frame` (every rank passes the same value; rank 0 writes it).
  void write_series(const std::string& name, std::int64_t frame, const void* value, hid_t type);
  /// Dimensions of a dataset.
  std::vector<std::int64_t> dims(const std::string& name) const;
  /// Reads a whole fixed dataset, or frame `frame` of a frame dataset, checking the row layout.
  template <class T>
  std::vector<T> read_rows(const std::string& name, std::int64_t frame = -1) const {
    const auto d = dims(name);
    const std::int64_t rows = frame >= 0 ? (d.size() > 1 ? d[1] : 0) : (d.empty() ? 0 : d[0]);
    return read_rows<T>(name, frame, 0, rows);
  }
  /// Reads rows [first_row, first_row + count) of a fixed dataset, or of frame `frame`.
  template <class T>
  std::vector<T> read_rows(const std::string& name, std::int64_t frame, std::int64_t first_row,
                           std::int64_t count) const {
    check_layout(name, frame, H5Layout<T>::components);
    std::vector<T> out(static_cast<std::size_t>(count));
    if (!out.empty()) read_raw(name, frame, first_row, count, out.data(), H5Layout<T>::type());
    return out;
  }
  /// Rows [first_row, first_row + count) of a fixed dataset, checking the row layout;
  /// collective on a parallel file (every rank calls it, with its own block, maybe empty).
  template <class T>
  std::vector<T> read_row_block(const std::string& name, std::int64_t first_row,
                                std::int64_t count) const {
    check_layout(name, -1, H5Layout<T>::components);
    std::vector<T> out(static_cast<std::size_t>(count));
    read_block_raw(name, first_row, count, out.data(), H5Layout<T>::type());
    return out;
  }
  /// A whole dataset as raw bytes in its native memory type; `row_bytes` is set to the bytes
  /// per first-dimension row.
  std::vector<char> read_bytes(const std::string& name, std::size_t& row_bytes) const;
  /// The names of the datasets directly below a group.
  std::vector<std::string> list(const std::string& group) const;

 private:
  Hdf5File(hid_t id, std::string path, bool parallel, int rank)
      : id_(id), path_(std::move(path)), parallel_(parallel), rank_(rank) {}
  void check_layout(const std::string& name, std::int64_t frame, int components) const;
  void read_raw(const std::string& name, std::int64_t frame, std::int64_t first_row,
                std::int64_t count, void* out, hid_t type) const;
  void read_block_raw(const std::string& name, std::int64_t first_row, std::int64_t count,
                      void* out, hid_t type) const;
  [[noreturn]] void fail(const std::string& what) const;

  hid_t id_ = -1;
  std::string path_;
  bool parallel_ = false;
  int rank_ = 0;  ///< in the communicator of a parallel file
};

}  // namespace ringdem

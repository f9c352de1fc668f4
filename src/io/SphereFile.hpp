#pragma once

#include <cstdint>
#include <functional>
#include <string>

namespace ringdem {

/// A packing of spheres in a CSV file, one sphere a line (docs/case-file.md, "Sphere files"):
///
///     x,y,z,radius
///     0.01,0.02,0.005,0.004
///
/// The header names the four columns, in that order; lines that are empty or start with '#'
/// are skipped. Sphere i is the i-th data line. Reading keeps one line in memory, so a rank can
/// take its slice of a file of millions of spheres without holding the others.
class SphereFile {
 public:
  /// Opens `path` and reads it through once: the header, every row's four numbers (finite, the
  /// radius above 0). Throws std::runtime_error naming the file and line of the first fault.
  explicit SphereFile(std::string path);

  const std::string& path() const { return path_; }
  /// Spheres in the file.
  std::int64_t count() const { return count_; }
  /// Calls `f(x, y, z, radius)` for spheres [first, last), in file order.
  void read(std::int64_t first, std::int64_t last,
            const std::function<void(double, double, double, double)>& f) const;

  /// Where a sphere file named in a case lies: `path` as given when absolute, else beside the
  /// case file `case_path` (or in the working folder when the case came from no file).
  static std::string resolve(const std::string& path, const std::string& case_path);

 private:
  std::string path_;
  std::int64_t count_ = 0;
};

}  // namespace ringdem

#include "io/SphereFile.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace ringdem {

namespace {

/// A line that holds no sphere: empty, blank or a comment.
bool skipped(const std::string& line) {
  const auto first = line.find_first_not_of(" \t\r");
  return first == std::string::npos || line[first] == '#';
}

/// The four numbers of a data line; throws with the file and line number.
void parse_row(const std::string& line, const std::string& path, std::int64_t line_number,
               double out[4]) {
  const char* p = line.c_str();
  for (int c = 0; c < 4; ++c) {
    char* end = nullptr;
    out[c] = std::strtod(p, &end);
    if (end == p || !std::isfinite(out[c]))
      throw std::runtime_error(fmt::format("{}:{}: column {} is not a finite number: '{}'", path,
                                           line_number, c + 1, line));
    p = end;
    while (*p == ' ' || *p == '\t')
      ++p;
    if (c < 3) {
      if (*p != ',')
        throw std::runtime_error(
            fmt::format("{}:{}: expected 4 comma-separated numbers (x,y,z,radius), got '{}'", path,
                        line_number, line));
      ++p;
    }
  }
  while (*p == ' ' || *p == '\t' || *p == '\r')
    ++p;
  if (*p != '\0')
    throw std::runtime_error(
        fmt::format("{}:{}: expected 4 comma-separated numbers (x,y,z,radius), got '{}'", path,
                    line_number, line));
  if (!(out[3] > 0.0))
    throw std::runtime_error(
        fmt::format("{}:{}: the radius must be above 0, got {}", path, line_number, out[3]));
}

/// The header without blanks: "x,y,z,radius" is the only one accepted.
bool header_ok(const std::string& line) {
  std::string compact;
  for (char ch : line)
    if (ch != ' ' && ch != '\t' && ch != '\r') compact += ch;
  return compact == "x,y,z,radius";
}

}  // namespace

SphereFile::SphereFile(std::string path) : path_(std::move(path)) {
  std::ifstream in(path_);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the sphere file", path_));
  std::string line;
  std::int64_t line_number = 0;
  bool header = false;
  double row[4];
  while (std::getline(in, line)) {
    ++line_number;
    if (skipped(line)) continue;
    if (!header) {
      if (!header_ok(line))
        throw std::runtime_error(
            fmt::format("{}:{}: the first line must be the header 'x,y,z,radius', got '{}'", path_,
                        line_number, line));
      header = true;
      continue;
    }
    parse_row(line, path_, line_number, row);
    ++count_;
  }
  if (!header) throw std::runtime_error(fmt::format("{}: no header 'x,y,z,radius'", path_));
}

void SphereFile::read(std::int64_t first, std::int64_t last,
                      const std::function<void(double, double, double, double)>& f) const {
  std::ifstream in(path_);
  if (!in) throw std::runtime_error(fmt::format("{}: cannot open the sphere file", path_));
  std::string line;
  std::int64_t line_number = 0, index = 0;
  bool header = false;
  double row[4];
  while (index < last && std::getline(in, line)) {
    ++line_number;
    if (skipped(line)) continue;
    if (!header) {
      header = true;
      continue;
    }
    if (index >= first) {
      parse_row(line, path_, line_number, row);
      f(row[0], row[1], row[2], row[3]);
    }
    ++index;
  }
  if (index < last)
    throw std::runtime_error(
        fmt::format("{}: has {} spheres, {} expected (changed while read?)", path_, index, last));
}

std::string SphereFile::resolve(const std::string& path, const std::string& case_path) {
  const std::filesystem::path p(path);
  if (p.is_absolute() || case_path.empty()) return path;
  const std::filesystem::path dir = std::filesystem::path(case_path).parent_path();
  if (dir.empty() || !std::filesystem::is_directory(dir)) return path;
  return (dir / p).lexically_normal().string();
}

}  // namespace ringdem

#include "io/ResultsWriter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace ringdem {

namespace {
std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{:.17g}", v);
}
}  // namespace

JsonObject& JsonObject::set(const std::string& key, double v) {
  json_[key] = v;  // NaN and infinities are written as null
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, long long v) {
  json_[key] = v;
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::string& v) {
  json_[key] = v;
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, bool v) {
  json_[key] = v;
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const JsonObject& v) {
  json_[key] = v.json_;
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::vector<double>& v) {
  json_[key] = v;
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::vector<JsonObject>& v) {
  auto array = nlohmann::ordered_json::array();
  for (const JsonObject& o : v)
    array.push_back(o.json_);
  json_[key] = std::move(array);
  return *this;
}

std::string JsonObject::str() const {
  // A case name or path that is not valid UTF-8 is written with U+FFFD, not thrown on.
  return json_.dump(2, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

void JsonObject::write(const std::string& path) const {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + path);
    f << str() << "\n";
  }
  std::filesystem::rename(tmp, path);
}

SeriesWriter::SeriesWriter(const std::string& path, const std::vector<std::string>& columns)
    : out_(path), n_columns_(columns.size()) {
  if (!out_) throw std::runtime_error("cannot write " + path);
  for (std::size_t i = 0; i < columns.size(); ++i)
    out_ << (i ? "," : "") << columns[i];
  out_ << "\n";
}

SeriesWriter SeriesWriter::resume(const std::string& path, const std::vector<std::string>& columns,
                                  double until) {
  std::ifstream in(path);
  if (!in) return SeriesWriter(path, columns);
  std::string header, line;
  std::getline(in, header);
  std::string expected;
  for (std::size_t i = 0; i < columns.size(); ++i)
    expected += (i ? "," : "") + columns[i];
  if (header != expected)
    throw std::runtime_error(path + ": its columns differ from this run's; cannot continue it");
  std::vector<std::string> kept;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    const double t = std::strtod(line.c_str(), nullptr);
    // A relative margin: the row of the checkpoint step itself is kept.
    if (t <= until + 1e-9 * std::max(1.0, std::abs(until))) kept.push_back(line);
  }
  in.close();
  SeriesWriter w(path, columns);
  for (const auto& k : kept)
    w.out_ << k << "\n";
  w.out_.flush();
  return w;
}

void SeriesWriter::row(const std::vector<double>& values) {
  if (values.size() != n_columns_) throw std::logic_error("series row has the wrong width");
  std::string line;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (i) line += ',';
    line += number(values[i]);
  }
  out_ << line << "\n";
  out_.flush();
}

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
        cell += '"';
        ++i;
      } else if (c == '"') {
        quoted = false;
      } else {
        cell += c;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.push_back(cell);
      cell.clear();
    } else {
      cell += c;
    }
  }
  if (!line.empty()) cells.push_back(cell);
  return cells;
}

}  // namespace ringdem

#pragma once

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>
#include <vector>

namespace ringdem {

/// A JSON object written in insertion order (summary.json), held by nlohmann::ordered_json.
/// Values are numbers (non-finite ones written as null), integers, strings, booleans, arrays of
/// numbers or nested objects; numbers are written in the shortest form that reads back exactly.
class JsonObject {
 public:
  JsonObject& set(const std::string& key, double v);
  JsonObject& set(const std::string& key, long long v);
  JsonObject& set(const std::string& key, int v) { return set(key, static_cast<long long>(v)); }
  JsonObject& set(const std::string& key, const std::string& v);
  JsonObject& set(const std::string& key, const char* v) { return set(key, std::string(v)); }
  JsonObject& set(const std::string& key, bool v);
  JsonObject& set(const std::string& key, const JsonObject& v);
  JsonObject& set(const std::string& key, const std::vector<double>& v);
  JsonObject& set(const std::string& key, const std::vector<JsonObject>& v);

  /// The object as text, indented by 2 per level.
  std::string str() const;
  /// Writes str() to a temporary file beside `path`, then renames it.
  void write(const std::string& path) const;

 private:
  nlohmann::ordered_json json_ = nlohmann::ordered_json::object();
};

/// series.csv: a header line then one row per record, numbers in full precision.
class SeriesWriter {
 public:
  SeriesWriter() = default;
  SeriesWriter(const std::string& path, const std::vector<std::string>& columns);
  /// Continues an existing series after a restart: keeps the header (which must match) and the
  /// rows whose first column is at most `until` (rows a stopped run wrote after its checkpoint
  /// are dropped), then appends. Starts a new file when there is none.
  static SeriesWriter resume(const std::string& path, const std::vector<std::string>& columns,
                             double until);
  void row(const std::vector<double>& values);
  bool is_open() const { return out_.is_open(); }
  std::size_t columns() const { return n_columns_; }

 private:
  std::ofstream out_;
  std::size_t n_columns_ = 0;
};

/// The cells of one line of CSV: a cell in double quotes may hold commas, and "" in it is a
/// quote (as sweep.csv writes text); a line that ends in a comma ends in an empty cell.
std::vector<std::string> split_csv_line(const std::string& line);

}  // namespace ringdem

#pragma once

#include <fstream>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace ringdem {

/// A flat JSON object written in insertion order (summary.json). Values are numbers,
/// integers, strings, booleans or nested objects.
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

  std::string str(int indent = 0) const;
  void write(const std::string& path) const;

 private:
  std::vector<std::pair<std::string, std::string>> items_;  // key, serialised value
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

/// Escapes a string for JSON.
std::string json_escape(const std::string& s);

}  // namespace ringdem

#include "io/ResultsWriter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace ringdem {

namespace {
std::string number(double v) {
  if (!std::isfinite(v)) return "null";
  return fmt::format("{:.17g}", v);
}
}  // namespace

std::string json_escape(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += fmt::format("\\u{:04x}", static_cast<int>(c));
        else
          out += c;
    }
  }
  return out;
}

JsonObject& JsonObject::set(const std::string& key, double v) {
  items_.emplace_back(key, number(v));
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, long long v) {
  items_.emplace_back(key, std::to_string(v));
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::string& v) {
  items_.emplace_back(key, fmt::format("\"{}\"", json_escape(v)));
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, bool v) {
  items_.emplace_back(key, v ? "true" : "false");
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const JsonObject& v) {
  items_.emplace_back(
      key, fmt::format("\x01{}", v.str(0)));  // marker: nested object, re-indented in str()
  return *this;
}
JsonObject& JsonObject::set(const std::string& key, const std::vector<double>& v) {
  std::string s = "[";
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (i) s += ", ";
    s += number(v[i]);
  }
  items_.emplace_back(key, s + "]");
  return *this;
}

std::string JsonObject::str(int indent) const {
  const std::string pad(static_cast<std::size_t>(indent + 2), ' ');
  std::string out = "{\n";
  for (std::size_t i = 0; i < items_.size(); ++i) {
    std::string value = items_[i].second;
    if (!value.empty() && value[0] == '\x01') {
      // Nested object: indent its lines by our depth.
      std::string nested;
      for (std::size_t c = 1; c < value.size(); ++c) {
        nested += value[c];
        if (value[c] == '\n') nested += std::string(static_cast<std::size_t>(indent + 2), ' ');
      }
      value = nested;
    }
    out += fmt::format("{}\"{}\": {}", pad, json_escape(items_[i].first), value);
    out += i + 1 < items_.size() ? ",\n" : "\n";
  }
  out += std::string(static_cast<std::size_t>(indent), ' ') + "}";
  return out;
}

void JsonObject::write(const std::string& path) const {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + path);
    f << str(0) << "\n";
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

}  // namespace ringdem

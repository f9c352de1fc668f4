#include "io/Schema.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <system_error>
#include <tuple>

namespace ringdem::schema {

// ---- Range ------------------------------------------------------------------------------------

bool Range::contains(double v) const {
  if (lo && (lo_inclusive ? v < *lo : v <= *lo)) return false;
  if (hi && (hi_inclusive ? v > *hi : v >= *hi)) return false;
  return true;
}

std::string Range::text() const {
  if (lo && hi) {
    if (*lo == *hi) return format_number(*lo);
    return fmt::format("in {}{}, {}{}", lo_inclusive ? '[' : '(', format_number(*lo),
                       format_number(*hi), hi_inclusive ? ']' : ')');
  }
  if (lo) return (lo_inclusive ? ">= " : "> ") + format_number(*lo);
  if (hi) return (hi_inclusive ? "<= " : "< ") + format_number(*hi);
  return "any";
}

// ---- SectionInfo ------------------------------------------------------------------------------

const KeyInfo* SectionInfo::find(std::string_view key) const {
  for (const KeyInfo& k : keys)
    if (k.name == key) return &k;
  return nullptr;
}

std::vector<std::string> SectionInfo::key_names() const {
  std::vector<std::string> names;
  names.reserve(keys.size());
  for (const KeyInfo& k : keys)
    names.push_back(k.name);
  return names;
}

// ---- Context ----------------------------------------------------------------------------------

namespace {

bool path_within(const std::string& path, const std::string& prefix) {
  if (path.size() < prefix.size() || path.compare(0, prefix.size(), prefix) != 0) return false;
  return path.size() == prefix.size() || path[prefix.size()] == '.' || path[prefix.size()] == '[';
}

}  // namespace

Location Context::locate(const YAML::Node& node, const std::string& path) const {
  YAML::Mark mark = YAML::Mark::null_mark();
  if (node.IsDefined()) mark = node.Mark();
  // The last override that covers the path wins, as it does when overrides are applied.
  for (auto it = overrides_.rbegin(); it != overrides_.rend(); ++it) {
    if (!path_within(path, it->path)) continue;
    int column = it->column;
    if (!mark.is_null() && mark.line == 0) column += mark.column;
    return {"--set", it->index, column};
  }
  if (mark.is_null()) return {file_, 1, 1};
  return {file_, mark.line + 1, mark.column + 1};
}

void Context::error(const Location& at, const std::string& path, std::string message) {
  diagnostics_.push_back({at.file, at.line, at.column, path, std::move(message)});
  failed_.insert(path);
}

Location Context::where(const std::string& path, const std::string& fallback) const {
  if (auto it = where_.find(path); it != where_.end()) return it->second;
  if (auto it = where_.find(fallback); it != where_.end()) return it->second;
  return {file_, 1, 1};
}

bool Context::failed(const std::string& path) const {
  for (auto it = failed_.lower_bound(path); it != failed_.end(); ++it) {
    if (it->compare(0, path.size(), path) != 0) break;
    if (path_within(*it, path)) return true;
  }
  return false;
}

void Context::add_override(std::string path, int index, int value_column) {
  overrides_.push_back({std::move(path), index, value_column});
}

void Context::warn(const Location& at, const std::string& path, std::string message) {
  warnings_.push_back({at.file, at.line, at.column, path, std::move(message), Severity::kWarning});
}

std::vector<Diagnostic> Context::sorted(const std::vector<Diagnostic>& diagnostics) const {
  std::vector<Diagnostic> out = diagnostics;
  std::stable_sort(out.begin(), out.end(), [this](const Diagnostic& a, const Diagnostic& b) {
    return std::make_tuple(a.file != file_, a.line, a.column) <
           std::make_tuple(b.file != file_, b.line, b.column);
  });
  return out;
}

// ---- helpers ----------------------------------------------------------------------------------

std::string join_path(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string index_path(const std::string& parent, std::size_t index) {
  return fmt::format("{}[{}]", parent, index);
}

std::string describe_node(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing (empty value)";
  if (node.IsSequence()) return fmt::format("a list of {} entries", node.size());
  if (node.IsMap()) return "a map";
  return "'" + node.Scalar() + "'";
}

std::string format_number(double v) {
  const double magnitude = std::abs(v);
  if (magnitude == 0.0 || (magnitude >= 1e-4 && magnitude < 1e6)) return fmt::format("{}", v);
  // Shortest round-trip digits in scientific notation, exponent without '+' and leading zeros:
  // 2e11, 1.6e10, 1e-5.
  char buffer[64];
  const auto result =
      std::to_chars(buffer, buffer + sizeof buffer, v, std::chars_format::scientific);
  std::string s(buffer, result.ptr);
  const std::size_t e = s.find('e');
  if (e == std::string::npos) return s;
  std::string exponent = s.substr(e + 1);
  const bool negative = !exponent.empty() && exponent.front() == '-';
  if (!exponent.empty() && (exponent.front() == '-' || exponent.front() == '+'))
    exponent.erase(0, 1);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return s.substr(0, e) + "e" + (negative ? "-" : "") + exponent;
}

std::string format_vec3(const Vec3& v) {
  return fmt::format("[{}, {}, {}]", format_number(v.x), format_number(v.y), format_number(v.z));
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names)
    out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string folder_name_problem(const std::string& name) {
  if (name.find('/') != std::string::npos || name.find('\\') != std::string::npos)
    return "contains a path separator";
  if (name == "." || name == "..") return "names the current or the parent folder";
  for (char ch : name)
    if (static_cast<unsigned char>(ch) < 0x20 || ch == 0x7f) return "contains a control character";
  return {};
}

std::string value_text(const Value& v) {
  struct Visitor {
    std::string operator()(std::monostate) const { return "none"; }
    std::string operator()(double d) const { return format_number(d); }
    std::string operator()(std::int64_t i) const { return std::to_string(i); }
    std::string operator()(std::uint64_t u) const { return std::to_string(u); }
    std::string operator()(bool b) const { return b ? "true" : "false"; }
    std::string operator()(const std::string& s) const { return s.empty() ? "\"\"" : s; }
    std::string operator()(const Vec3& x) const { return format_vec3(x); }
    std::string operator()(const std::array<int, 3>& a) const {
      return fmt::format("[{}, {}, {}]", a[0], a[1], a[2]);
    }
    std::string operator()(const std::array<std::string, 2>& a) const {
      return fmt::format("[{}, {}]", a[0], a[1]);
    }
    std::string operator()(const std::vector<std::string>& a) const {
      return "[" + join_names(a) + "]";
    }
  };
  return std::visit(Visitor{}, v);
}

void emit_value(YAML::Emitter& out, const Value& v) {
  struct Visitor {
    YAML::Emitter& out;
    void operator()(std::monostate) const { out << YAML::Null; }
    void operator()(double d) const { out << format_number(d); }
    void operator()(std::int64_t i) const { out << i; }
    void operator()(std::uint64_t u) const { out << u; }
    void operator()(bool b) const { out << b; }
    void operator()(const std::string& s) const { out << s; }
    void operator()(const Vec3& x) const {
      out << YAML::Flow << YAML::BeginSeq << format_number(x.x) << format_number(x.y)
          << format_number(x.z) << YAML::EndSeq;
    }
    void operator()(const std::array<int, 3>& a) const {
      out << YAML::Flow << YAML::BeginSeq << a[0] << a[1] << a[2] << YAML::EndSeq;
    }
    void operator()(const std::array<std::string, 2>& a) const {
      out << YAML::Flow << YAML::BeginSeq << a[0] << a[1] << YAML::EndSeq;
    }
    void operator()(const std::vector<std::string>& a) const {
      out << YAML::Flow << YAML::BeginSeq;
      for (const std::string& s : a)
        out << s;
      out << YAML::EndSeq;
    }
  };
  std::visit(Visitor{out}, v);
}

std::size_t edit_distance(std::string_view a, std::string_view b) {
  const std::size_t n = a.size(), m = b.size();
  std::vector<std::vector<std::size_t>> d(n + 1, std::vector<std::size_t>(m + 1));
  for (std::size_t i = 0; i <= n; ++i)
    d[i][0] = i;
  for (std::size_t j = 0; j <= m; ++j)
    d[0][j] = j;
  auto lower = [](char c) {
    return static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  };
  for (std::size_t i = 1; i <= n; ++i) {
    for (std::size_t j = 1; j <= m; ++j) {
      const std::size_t cost = lower(a[i - 1]) == lower(b[j - 1]) ? 0 : 1;
      d[i][j] = std::min({d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + cost});
      if (i > 1 && j > 1 && lower(a[i - 1]) == lower(b[j - 2]) &&
          lower(a[i - 2]) == lower(b[j - 1]))
        d[i][j] = std::min(d[i][j], d[i - 2][j - 2] + 1);
    }
  }
  return d[n][m];
}

std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& candidates) {
  const std::size_t limit = word.size() <= 4 ? 1 : 2;
  std::optional<std::string> best;
  std::size_t best_distance = limit + 1;
  for (const std::string& c : candidates) {
    const std::size_t dist = edit_distance(word, c);
    if (dist < best_distance) {
      best_distance = dist;
      best = c;
    }
  }
  return best;
}

std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates) {
  if (auto m = closest_match(word, candidates)) return "; did you mean '" + *m + "'?";
  return {};
}

std::string describe_type(const KeyInfo& key) {
  switch (key.type) {
    case Type::kNumber:
      return "number";
    case Type::kNumberOrAuto:
      return "`auto` or number";
    case Type::kInteger:
      return "integer";
    case Type::kUnsigned:
      return "unsigned integer";
    case Type::kBool:
      return "bool";
    case Type::kString:
      return "string";
    case Type::kName:
      return "name";
    case Type::kChoice:
      return "one of " + join_names(key.choices);
    case Type::kVec3:
      return "3-vector";
    case Type::kIntTriple:
      return "3 integers";
    case Type::kNamePair:
      return "2 names";
    case Type::kNameList:
      return "list of names";
    case Type::kValueList:
      return "list of values";
    case Type::kSection:
      return "section";
    case Type::kList:
      return "list of maps";
    case Type::kNumberMap:
      return "map name: number";
  }
  return "?";
}

// ---- reading leaf values ----------------------------------------------------------------------

namespace {

std::string_view trimmed(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
    s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
    s.remove_suffix(1);
  return s;
}

std::optional<double> parse_double(std::string_view s) {
  s = trimmed(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
  return v;
}

template <class I>
std::optional<I> parse_integer(std::string_view s, bool* overflow) {
  s = trimmed(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  I v{};
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range && end == s.data() + s.size()) *overflow = true;
  if (ec != std::errc() || end != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string with_unit(const std::string& text, const KeyInfo& key) {
  return key.unit.empty() ? text : text + " " + key.unit;
}

std::string range_message(const KeyInfo& key, const std::string& value) {
  return fmt::format("must be {}, got {}", with_unit(key.range.text(), key), value);
}

/// A scalar, or a report of what was found instead.
const std::string* scalar_or_error(const YAML::Node& node, const YAML::Node& at,
                                   const std::string& path, const std::string& expected,
                                   Context& ctx) {
  if (node.IsDefined() && node.IsScalar()) return &node.Scalar();
  ctx.error(at, path, "expected " + expected + ", got " + describe_node(node));
  return nullptr;
}

std::optional<double> read_number(const KeyInfo& key, const YAML::Node& node, const YAML::Node& at,
                                  const std::string& path, const std::string& expected,
                                  Context& ctx) {
  const std::string* s = scalar_or_error(node, at, path, expected, ctx);
  if (s == nullptr) return std::nullopt;
  const auto v = parse_double(*s);
  if (!v) {
    ctx.error(at, path, "expected " + expected + ", got '" + *s + "'");
    return std::nullopt;
  }
  if (!key.range.contains(*v)) {
    ctx.error(at, path, range_message(key, *s));
    return std::nullopt;
  }
  return v;
}

std::optional<std::int64_t> read_int(const KeyInfo& key, const YAML::Node& node,
                                     const YAML::Node& at, const std::string& path, Context& ctx) {
  const std::string* s = scalar_or_error(node, at, path, "an integer", ctx);
  if (s == nullptr) return std::nullopt;
  bool overflow = false;
  const auto v = parse_integer<std::int64_t>(*s, &overflow);
  if (!v || *v < INT_MIN || *v > INT_MAX) {
    if (!v && !overflow) {
      ctx.error(at, path, "expected an integer, got '" + *s + "'");
    } else {
      ctx.error(at, path, fmt::format("{} is too large for an integer (at most {})", *s, INT_MAX));
    }
    return std::nullopt;
  }
  if (!key.range.contains(static_cast<double>(*v))) {
    ctx.error(at, path, range_message(key, *s));
    return std::nullopt;
  }
  return v;
}

std::optional<std::string> read_name(const YAML::Node& node, const YAML::Node& at,
                                     const std::string& path, Context& ctx) {
  const std::string* s = scalar_or_error(node, at, path, "a name", ctx);
  if (s == nullptr) return std::nullopt;
  if (trimmed(*s).empty() || trimmed(*s).size() != s->size()) {
    ctx.error(at, path, "expected a non-empty name without surrounding spaces, got '" + *s + "'");
    return std::nullopt;
  }
  return *s;
}

/// A list of exactly n entries, or a report.
bool sequence_of(const YAML::Node& node, const YAML::Node& at, const std::string& path,
                 std::size_t n, const std::string& expected, Context& ctx) {
  if (node.IsDefined() && node.IsSequence() && node.size() == n) return true;
  ctx.error(at, path, "expected " + expected + ", got " + describe_node(node));
  return false;
}

}  // namespace

std::optional<Value> read_value(const KeyInfo& key, const YAML::Node& node, const YAML::Node& at,
                                const std::string& path, Context& ctx) {
  switch (key.type) {
    case Type::kNumber: {
      if (auto v = read_number(key, node, at, path, "a number", ctx)) return Value{*v};
      return std::nullopt;
    }
    case Type::kNumberOrAuto: {
      if (node.IsDefined() && node.IsScalar() && node.Scalar() == "auto")
        return Value{std::string("auto")};
      if (auto v = read_number(key, node, at, path, "'auto' or a number", ctx)) return Value{*v};
      return std::nullopt;
    }
    case Type::kInteger: {
      if (auto v = read_int(key, node, at, path, ctx)) return Value{*v};
      return std::nullopt;
    }
    case Type::kUnsigned: {
      const std::string* s = scalar_or_error(node, at, path, "an unsigned integer", ctx);
      if (s == nullptr) return std::nullopt;
      bool overflow = false;
      const auto v = parse_integer<std::uint64_t>(*s, &overflow);
      if (!v) {
        ctx.error(at, path,
                  overflow ? "'" + *s + "' is too large (at most 18446744073709551615)"
                           : "expected an unsigned integer (>= 0), got '" + *s + "'");
        return std::nullopt;
      }
      return Value{*v};
    }
    case Type::kBool: {
      const std::string* s = scalar_or_error(node, at, path, "true or false", ctx);
      if (s == nullptr) return std::nullopt;
      std::string lower = *s;
      std::transform(lower.begin(), lower.end(), lower.begin(),
                     [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
      if (lower == "true") return Value{true};
      if (lower == "false") return Value{false};
      ctx.error(at, path, "expected true or false, got '" + *s + "'");
      return std::nullopt;
    }
    case Type::kString: {
      const std::string* s = scalar_or_error(node, at, path, "a string", ctx);
      if (s == nullptr) return std::nullopt;
      return Value{*s};
    }
    case Type::kName: {
      if (auto s = read_name(node, at, path, ctx)) return Value{*s};
      return std::nullopt;
    }
    case Type::kChoice: {
      const std::string expected = "one of: " + join_names(key.choices);
      const std::string* s = scalar_or_error(node, at, path, expected, ctx);
      if (s == nullptr) return std::nullopt;
      if (std::find(key.choices.begin(), key.choices.end(), *s) != key.choices.end())
        return Value{*s};
      ctx.error(at, path, "'" + *s + "' is not " + expected + did_you_mean(*s, key.choices));
      return std::nullopt;
    }
    case Type::kVec3: {
      const std::string expected = with_unit("a 3-vector [x, y, z]", key);
      if (!sequence_of(node, at, path, 3, expected, ctx)) return std::nullopt;
      KeyInfo component = key;
      component.range = unbounded();
      Vec3 v;
      double* parts[3] = {&v.x, &v.y, &v.z};
      bool ok = true;
      for (std::size_t i = 0; i < 3; ++i) {
        const YAML::Node c = node[i];
        ctx.remember(index_path(path, i), c);
        const auto x = read_number(component, c, c, index_path(path, i), "a number", ctx);
        if (x) *parts[i] = *x;
        ok = ok && x.has_value();
      }
      if (!ok) return std::nullopt;
      if (key.nonzero && norm2(v) == 0.0) {
        ctx.error(at, path, "must be a non-zero vector, got " + format_vec3(v));
        return std::nullopt;
      }
      return Value{v};
    }
    case Type::kIntTriple: {
      if (!sequence_of(node, at, path, 3, "3 integers [i, j, k]", ctx)) return std::nullopt;
      std::array<int, 3> a{};
      bool ok = true;
      for (std::size_t i = 0; i < 3; ++i) {
        const YAML::Node c = node[i];
        ctx.remember(index_path(path, i), c);
        const auto x = read_int(key, c, c, index_path(path, i), ctx);
        if (x) a[i] = static_cast<int>(*x);
        ok = ok && x.has_value();
      }
      if (!ok) return std::nullopt;
      return Value{a};
    }
    case Type::kNamePair: {
      if (!sequence_of(node, at, path, 2, "2 names [a, b]", ctx)) return std::nullopt;
      std::array<std::string, 2> a;
      bool ok = true;
      for (std::size_t i = 0; i < 2; ++i) {
        const YAML::Node c = node[i];
        ctx.remember(index_path(path, i), c);
        const auto x = read_name(c, c, index_path(path, i), ctx);
        if (x) a[i] = *x;
        ok = ok && x.has_value();
      }
      if (!ok) return std::nullopt;
      return Value{a};
    }
    case Type::kNameList:
    case Type::kValueList: {
      const bool unique = key.type == Type::kNameList;
      if (!node.IsDefined() || !node.IsSequence() || node.size() == 0) {
        ctx.error(at, path,
                  std::string("expected a list of one or more ") + (unique ? "names" : "values") +
                      " [a, b, ...], got " + describe_node(node));
        return std::nullopt;
      }
      std::vector<std::string> names;
      bool ok = true;
      for (std::size_t i = 0; i < node.size(); ++i) {
        const YAML::Node c = node[i];
        ctx.remember(index_path(path, i), c);
        const auto x = read_name(c, c, index_path(path, i), ctx);
        if (!x) {
          ok = false;
          continue;
        }
        if (unique && std::find(names.begin(), names.end(), *x) != names.end()) {
          ctx.error(c, index_path(path, i), "duplicate name '" + *x + "'");
          ok = false;
          continue;
        }
        names.push_back(*x);
      }
      if (!ok) return std::nullopt;
      return Value{names};
    }
    case Type::kSection:
    case Type::kList:
    case Type::kNumberMap:
      break;
  }
  ctx.error(at, path, "internal error: key has no reader");
  return std::nullopt;
}

// ---- Markdown reference -----------------------------------------------------------------------

namespace {

std::string escape_cell(std::string s) {
  std::string out;
  for (char c : s) {
    if (c == '|')
      out += "\\|";
    else if (c == '\n')
      out += ' ';
    else
      out += c;
  }
  return out;
}

void describe_section(const SectionInfo& section, const std::string& title, std::string& out) {
  out += "### " + title + "\n\n";
  if (!section.doc.empty()) out += section.doc + "\n\n";
  out += "| Key | Type | Default | Allowed | Unit | Meaning |\n";
  out += "|---|---|---|---|---|---|\n";
  for (const KeyInfo& k : section.keys) {
    std::string allowed;
    if (!k.range.unbounded()) allowed = k.range.text();
    if (k.nonzero) allowed = "non-zero";
    if (k.type == Type::kIntTriple && !k.range.unbounded()) allowed = "each " + allowed;
    if (k.type == Type::kNumberMap && !k.range.unbounded()) allowed = "values " + allowed;
    const std::string default_text = k.required ? "**required**" : k.default_text;
    out += fmt::format("| `{}` | {} | {} | {} | {} | {} |\n", k.name, escape_cell(describe_type(k)),
                       escape_cell(default_text), escape_cell(allowed), escape_cell(k.unit),
                       escape_cell(k.doc));
  }
  out += "\n";
  const std::string prefix = title.front() == '`' ? title.substr(1, title.size() - 2) + "." : "";
  for (const KeyInfo& k : section.keys) {
    if (k.child == nullptr) continue;
    const std::string child_title =
        "`" + prefix + k.name + (k.type == Type::kList ? "[]" : "") + "`";
    describe_section(*k.child, child_title, out);
  }
}

}  // namespace

std::string markdown_reference(const SectionInfo& root, const std::string& root_title) {
  std::string out;
  describe_section(root, root_title, out);
  return out;
}

}  // namespace ringdem::schema

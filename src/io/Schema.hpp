#pragma once

/// A small schema engine for YAML input files: one table per section describes every key
/// (name, type, required or default, allowed range, unit, documentation) and binds it to a
/// member of the C++ struct it fills. Parsing, type and range checks, unknown-key detection
/// with did-you-mean hints, --set path resolution, the resolved-configuration dump and the
/// Markdown reference all come from these tables.

#include <yaml-cpp/yaml.h>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/Vec3.hpp"
#include "io/InputError.hpp"

namespace ringdem::schema {

enum class Type {
  kNumber,        ///< finite real number
  kNumberOrAuto,  ///< "auto" or a finite real number
  kInteger,       ///< integer that fits an int
  kUnsigned,      ///< unsigned 64-bit integer (seeds)
  kBool,          ///< true / false
  kString,        ///< any scalar
  kName,          ///< non-empty scalar naming something
  kChoice,        ///< one of `choices`
  kVec3,          ///< [x, y, z]
  kIntTriple,     ///< [i, j, k], each in `range`
  kNamePair,      ///< [name, name]
  kNameList,      ///< [name, ...] (at least one, no duplicates)
  kValueList,     ///< [value, ...] (at least one non-empty scalar; repeats allowed)
  kSection,       ///< map described by `child`
  kList,          ///< list of maps described by `child`
  kNumberMap,     ///< map name -> number in `range`
};

/// Interval of allowed values; an empty side is unbounded.
struct Range {
  std::optional<double> lo, hi;
  bool lo_inclusive = true;
  bool hi_inclusive = true;

  bool contains(double v) const;
  bool unbounded() const { return !lo && !hi; }
  std::string text() const;  ///< "> 0", ">= 0", "in (0, 1]", "1" (exactly)
};

inline Range unbounded() {
  return {};
}
inline Range above(double lo) {
  return {lo, std::nullopt, false, true};
}
inline Range at_least(double lo) {
  return {lo, std::nullopt, true, true};
}
inline Range interval(double lo, bool lo_inclusive, double hi, bool hi_inclusive) {
  return {lo, hi, lo_inclusive, hi_inclusive};
}
inline Range exactly(double v) {
  return {v, v, true, true};
}

struct SectionInfo;

/// Description of one key, independent of the struct it fills.
struct KeyInfo {
  std::string name;
  Type type = Type::kNumber;
  bool required = false;
  Range range;
  bool nonzero = false;              ///< kVec3: the zero vector is rejected
  std::vector<std::string> choices;  ///< kChoice
  std::string unit;                  ///< SI unit, empty if dimensionless
  std::string default_text;          ///< shown in docs; derived from the struct when empty
  std::string doc;
  const SectionInfo* child = nullptr;  ///< kSection, kList
};

struct SectionInfo {
  std::string name;
  std::string doc;
  std::vector<KeyInfo> keys;

  const KeyInfo* find(std::string_view key) const;
  std::vector<std::string> key_names() const;
};

using Value =
    std::variant<std::monostate, double, std::int64_t, std::uint64_t, bool, std::string, Vec3,
                 std::array<int, 3>, std::array<std::string, 2>, std::vector<std::string>>;

struct Location {
  std::string file;
  int line = 0;
  int column = 0;
};

/// Collects diagnostics and remembers where every key was found, so that checks made after
/// parsing (references between sections, cross-field constraints) can point at the right line.
class Context {
 public:
  explicit Context(std::string file) : file_(std::move(file)) {}

  const std::string& file() const { return file_; }

  /// Location of `node`; values that came from a --set override are located in the override.
  Location locate(const YAML::Node& node, const std::string& path) const;
  void error(const Location& at, const std::string& path, std::string message);
  void error(const YAML::Node& at, const std::string& path, std::string message) {
    error(locate(at, path), path, std::move(message));
  }

  /// Records that the key `path` was given in the input, with its value at `node`.
  void remember(const std::string& path, const YAML::Node& node) {
    where_[path] = locate(node, path);
  }
  bool given(const std::string& path) const { return where_.count(path) != 0; }
  /// Where `path` was given, else where `fallback` was, else the top of the file.
  Location where(const std::string& path, const std::string& fallback = {}) const;
  /// True if an error was already reported at `path` or inside it (to avoid follow-up errors).
  bool failed(const std::string& path) const;
  /// True if an error was reported at exactly `path` (e.g. a missing or mistyped section).
  bool failed_here(const std::string& path) const { return failed_.count(path) != 0; }

  /// Declares that `path` (display form) was set by the override number `index` (1-based)
  /// whose value starts at 1-based column `value_column` of the "key=value" argument.
  void add_override(std::string path, int index, int value_column);

  /// A valid input that is most likely a mistake: reported, never stops the loading.
  void warn(const Location& at, const std::string& path, std::string message);

  /// The errors.
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }
  /// Errors ordered by position: the file first, then the overrides.
  std::vector<Diagnostic> sorted_diagnostics() const { return sorted(diagnostics_); }
  /// Warnings ordered as the errors.
  std::vector<Diagnostic> sorted_warnings() const { return sorted(warnings_); }

 private:
  struct OverrideOrigin {
    std::string path;
    int index;
    int column;
  };
  std::vector<Diagnostic> sorted(const std::vector<Diagnostic>& diagnostics) const;

  std::string file_;
  std::vector<Diagnostic> diagnostics_;
  std::vector<Diagnostic> warnings_;
  std::map<std::string, Location> where_;
  std::set<std::string> failed_;
  std::vector<OverrideOrigin> overrides_;
};

// ---- helpers shared by the tables and the loader ---------------------------------------------

std::string join_path(const std::string& parent, const std::string& key);
std::string index_path(const std::string& parent, std::size_t index);
/// Short description of what a node is, for "expected X, got Y" messages.
std::string describe_node(const YAML::Node& node);
std::string describe_type(const KeyInfo& key);
std::string format_number(double v);
std::string format_vec3(const Vec3& v);
std::string value_text(const Value& v);
/// Optimal-string-alignment distance (insertions, deletions, substitutions, transpositions),
/// case-insensitive.
std::size_t edit_distance(std::string_view a, std::string_view b);
/// The closest candidate if it is close enough to be a likely typo.
std::optional<std::string> closest_match(std::string_view word,
                                         const std::vector<std::string>& candidates);
/// "; did you mean 'x'?" or "".
std::string did_you_mean(std::string_view word, const std::vector<std::string>& candidates);
std::string join_names(const std::vector<std::string>& names);
/// Why `name` cannot name a folder inside results/ (a path separator, "." or "..", a control
/// character); empty when it can.
std::string folder_name_problem(const std::string& name);

/// Reads and checks a leaf value. `at` locates errors about the node itself (the key when the
/// value is empty). Returns nothing (and reports) if the value is invalid.
std::optional<Value> read_value(const KeyInfo& key, const YAML::Node& node, const YAML::Node& at,
                                const std::string& path, Context& ctx);
void emit_value(YAML::Emitter& out, const Value& v);
/// Markdown reference tables of `root` and every section under it.
std::string markdown_reference(const SectionInfo& root, const std::string& root_title);

// ---- binding of keys to struct members --------------------------------------------------------

template <class T>
struct Field {
  KeyInfo info;
  // Leaves: convert a checked value into the struct and back (monostate: omitted in dumps).
  std::function<void(T&, const Value&)> set;
  std::function<Value(const T&)> get;
  // Sections, lists, maps: parse and dump the whole subtree.
  std::function<void(T&, const YAML::Node& node, const YAML::Node& at, const std::string& path,
                     Context&)>
      parse;
  std::function<void(const T&, YAML::Emitter&)> dump;
  // Leaves: whether the key is written by dumps (keys that only apply to some variants).
  std::function<bool(const T&)> include;

  Field required() && {
    info.required = true;
    return std::move(*this);
  }
  Field default_text(std::string text) && {
    info.default_text = std::move(text);
    return std::move(*this);
  }
  Field nonzero() && {
    info.nonzero = true;
    return std::move(*this);
  }
  /// Leaves the key out of dumps when `pred` is false (keys that only apply to some variants).
  Field dump_if(std::function<bool(const T&)> pred) && {
    include = std::move(pred);
    return std::move(*this);
  }
};

template <class T>
class Table {
 public:
  Table(std::string name, std::string doc, std::vector<Field<T>> fields)
      : fields_(std::move(fields)) {
    info_.name = std::move(name);
    info_.doc = std::move(doc);
    const T defaults{};
    for (Field<T>& f : fields_) {
      if (f.info.default_text.empty() && !f.info.required && f.get) {
        const Value v = f.get(defaults);
        f.info.default_text =
            std::holds_alternative<std::monostate>(v) ? std::string("none") : value_text(v);
      }
      info_.keys.push_back(f.info);
    }
  }

  const SectionInfo& info() const { return info_; }

  /// Fills `out` from the map `node`; a null node counts as an empty map. Unknown, duplicate and
  /// missing required keys are reported; every valid key is applied even if others fail.
  void parse(T& out, const YAML::Node& node, const YAML::Node& at, const std::string& path,
             Context& ctx) const {
    if (!node.IsNull() && !node.IsMap()) {
      ctx.error(at, path,
                "expected a map of keys (" + join_names(info_.key_names()) + "), got " +
                    describe_node(node));
      return;
    }
    std::set<std::string> seen;
    if (node.IsMap()) {
      for (auto it = node.begin(); it != node.end(); ++it) {
        const YAML::Node key = it->first;
        const YAML::Node value = it->second;
        if (!key.IsScalar()) {
          ctx.error(key, path, "keys must be plain names, got " + describe_node(key));
          continue;
        }
        const std::string& name = key.Scalar();
        const std::string key_path = join_path(path, name);
        const Field<T>* field = find(name);
        if (field == nullptr) {
          std::string message = "unknown key '" + name + "'";
          const std::string hint = did_you_mean(name, info_.key_names());
          message += hint.empty() ? " (valid keys: " + join_names(info_.key_names()) + ")" : hint;
          ctx.error(key, key_path, std::move(message));
          continue;
        }
        if (!seen.insert(name).second) {
          ctx.error(key, key_path, "duplicate key '" + name + "'");
          continue;
        }
        const YAML::Node& value_at = value.IsNull() ? key : value;
        ctx.remember(key_path, value_at);
        if (field->parse) {
          field->parse(out, value, value_at, key_path, ctx);
        } else if (auto v = read_value(field->info, value, value_at, key_path, ctx)) {
          field->set(out, *v);
        }
      }
    }
    for (const Field<T>& f : fields_) {
      if (f.info.required && seen.count(f.info.name) == 0) {
        const bool is_section = f.info.type == Type::kSection || f.info.type == Type::kList;
        ctx.error(at, join_path(path, f.info.name),
                  std::string("missing required ") + (is_section ? "section" : "key") + " '" +
                      f.info.name + "' (" + f.info.doc + ")");
      }
    }
  }

  void dump(const T& in, YAML::Emitter& out) const {
    out << YAML::BeginMap;
    for (const Field<T>& f : fields_) {
      if (f.include && !f.include(in)) continue;
      if (f.dump) {
        out << YAML::Key << f.info.name << YAML::Value;
        f.dump(in, out);
        continue;
      }
      const Value v = f.get(in);
      if (std::holds_alternative<std::monostate>(v)) continue;
      out << YAML::Key << f.info.name << YAML::Value;
      emit_value(out, v);
    }
    out << YAML::EndMap;
  }

 private:
  const Field<T>* find(std::string_view name) const {
    for (const Field<T>& f : fields_)
      if (f.info.name == name) return &f;
    return nullptr;
  }

  SectionInfo info_;
  std::vector<Field<T>> fields_;
};

inline KeyInfo make_key(std::string name, Type type, std::string unit, std::string doc) {
  KeyInfo k;
  k.name = std::move(name);
  k.type = type;
  k.unit = std::move(unit);
  k.doc = std::move(doc);
  return k;
}

template <class T>
Field<T> number(std::string name, double T::*m, Range range, std::string unit, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kNumber, std::move(unit), std::move(doc));
  f.info.range = range;
  f.set = [m](T& t, const Value& v) { t.*m = std::get<double>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

/// Optional number: absent means "not set" (std::nullopt), left out of dumps.
template <class T>
Field<T> optional_number(std::string name, std::optional<double> T::*m, Range range,
                         std::string unit, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kNumber, std::move(unit), std::move(doc));
  f.info.range = range;
  f.set = [m](T& t, const Value& v) { t.*m = std::get<double>(v); };
  f.get = [m](const T& t) -> Value { return (t.*m) ? Value{*(t.*m)} : Value{}; };
  return f;
}

/// "auto" (std::nullopt) or a number.
template <class T>
Field<T> number_or_auto(std::string name, std::optional<double> T::*m, Range range,
                        std::string unit, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kNumberOrAuto, std::move(unit), std::move(doc));
  f.info.range = range;
  f.set = [m](T& t, const Value& v) {
    if (const double* d = std::get_if<double>(&v))
      t.*m = *d;
    else
      t.*m = std::nullopt;
  };
  f.get = [m](const T& t) -> Value { return (t.*m) ? Value{*(t.*m)} : Value{std::string("auto")}; };
  return f;
}

template <class T>
Field<T> integer(std::string name, int T::*m, Range range, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kInteger, "", std::move(doc));
  f.info.range = range;
  f.set = [m](T& t, const Value& v) { t.*m = static_cast<int>(std::get<std::int64_t>(v)); };
  f.get = [m](const T& t) -> Value { return std::int64_t{t.*m}; };
  return f;
}

template <class T>
Field<T> unsigned_integer(std::string name, std::uint64_t T::*m, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kUnsigned, "", std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<std::uint64_t>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

template <class T>
Field<T> boolean(std::string name, bool T::*m, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kBool, "", std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<bool>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

/// Free text (kString) or the name of something (kName: non-empty).
template <class T>
Field<T> text(std::string name, std::string T::*m, Type type, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), type, "", std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<std::string>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

template <class T>
Field<T> choice(std::string name, std::string T::*m, std::vector<std::string> choices,
                std::string doc) {
  Field<T> f = text(std::move(name), m, Type::kChoice, std::move(doc));
  f.info.choices = std::move(choices);
  return f;
}

template <class T, class E>
Field<T> enum_choice(std::string name, E T::*m, std::vector<std::pair<std::string, E>> choices,
                     std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kChoice, "", std::move(doc));
  for (const auto& c : choices)
    f.info.choices.push_back(c.first);
  f.set = [m, choices](T& t, const Value& v) {
    for (const auto& c : choices)
      if (c.first == std::get<std::string>(v)) t.*m = c.second;
  };
  f.get = [m, choices](const T& t) -> Value {
    for (const auto& c : choices)
      if (c.second == t.*m) return c.first;
    return Value{};
  };
  return f;
}

template <class T>
Field<T> vec3(std::string name, Vec3 T::*m, std::string unit, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kVec3, std::move(unit), std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<Vec3>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

/// Optional vector: absent means "not set" (std::nullopt), left out of dumps.
template <class T>
Field<T> optional_vec3(std::string name, std::optional<Vec3> T::*m, std::string unit,
                       std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kVec3, std::move(unit), std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<Vec3>(v); };
  f.get = [m](const T& t) -> Value { return (t.*m) ? Value{*(t.*m)} : Value{}; };
  return f;
}

template <class T>
Field<T> int_triple(std::string name, std::array<int, 3> T::*m, Range range, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kIntTriple, "", std::move(doc));
  f.info.range = range;
  f.set = [m](T& t, const Value& v) { t.*m = std::get<std::array<int, 3>>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

template <class T>
Field<T> name_pair(std::string name, std::string T::*a, std::string T::*b, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kNamePair, "", std::move(doc));
  f.set = [a, b](T& t, const Value& v) {
    const auto& pair = std::get<std::array<std::string, 2>>(v);
    t.*a = pair[0];
    t.*b = pair[1];
  };
  f.get = [a, b](const T& t) -> Value { return std::array<std::string, 2>{t.*a, t.*b}; };
  return f;
}

/// A list of scalars read as text; `type` is kNameList (each once) or kValueList (repeats allowed).
template <class T>
Field<T> text_list(std::string name, Type type, std::vector<std::string> T::*m, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), type, "", std::move(doc));
  f.set = [m](T& t, const Value& v) { t.*m = std::get<std::vector<std::string>>(v); };
  f.get = [m](const T& t) -> Value { return t.*m; };
  return f;
}

template <class T>
Field<T> name_list(std::string name, std::vector<std::string> T::*m, std::string doc) {
  return text_list(std::move(name), Type::kNameList, m, std::move(doc));
}

/// A list where one value may stand more than once (a sweep's zipped values: the cases differ
/// in another parameter).
template <class T>
Field<T> value_list(std::string name, std::vector<std::string> T::*m, std::string doc) {
  return text_list(std::move(name), Type::kValueList, m, std::move(doc));
}

/// An optional nested map: absent means std::nullopt (left out of dumps); present, it fills a
/// default-constructed U with the table `child`.
template <class T, class U>
Field<T> optional_section(std::string name, std::optional<U> T::*m, const Table<U>& child,
                          std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kSection, "", std::move(doc));
  f.info.child = &child.info();
  f.info.default_text = "none";
  f.parse = [m, &child](T& t, const YAML::Node& node, const YAML::Node& at, const std::string& path,
                        Context& ctx) {
    t.*m = U{};
    child.parse(*(t.*m), node, at, path, ctx);
  };
  f.dump = [m, &child](const T& t, YAML::Emitter& out) { child.dump(*(t.*m), out); };
  f.include = [m](const T& t) { return (t.*m).has_value(); };
  return f;
}

/// A nested map filling the member `m` with the table `child`.
template <class T, class U>
Field<T> section(std::string name, U T::*m, const Table<U>& child, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kSection, "", std::move(doc));
  f.info.child = &child.info();
  f.info.default_text = "all defaults";
  f.parse = [m, &child](T& t, const YAML::Node& node, const YAML::Node& at, const std::string& path,
                        Context& ctx) { child.parse(t.*m, node, at, path, ctx); };
  f.dump = [m, &child](const T& t, YAML::Emitter& out) { child.dump(t.*m, out); };
  return f;
}

/// A nested map whose keys fill the same struct (grouping in the file only).
template <class T>
Field<T> inline_section(std::string name, const Table<T>& child, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kSection, "", std::move(doc));
  f.info.child = &child.info();
  f.info.default_text = "all defaults";
  f.parse = [&child](T& t, const YAML::Node& node, const YAML::Node& at, const std::string& path,
                     Context& ctx) { child.parse(t, node, at, path, ctx); };
  f.dump = [&child](const T& t, YAML::Emitter& out) { child.dump(t, out); };
  return f;
}

/// A list of maps, each filling one element with the table `child`. An empty value is an
/// empty list.
template <class T, class E>
Field<T> list(std::string name, std::vector<E> T::*m, const Table<E>& child, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kList, "", std::move(doc));
  f.info.child = &child.info();
  f.info.default_text = "empty";
  f.parse = [m, &child](T& t, const YAML::Node& node, const YAML::Node& at, const std::string& path,
                        Context& ctx) {
    (t.*m).clear();
    if (node.IsNull()) return;
    if (!node.IsSequence()) {
      ctx.error(at, path,
                "expected a list of maps ('- key: value' entries), got " + describe_node(node));
      return;
    }
    for (std::size_t i = 0; i < node.size(); ++i) {
      const YAML::Node item = node[i];
      const std::string item_path = index_path(path, i);
      ctx.remember(item_path, item);
      E element{};
      child.parse(element, item, item, item_path, ctx);
      (t.*m).push_back(std::move(element));
    }
  };
  f.dump = [m, &child](const T& t, YAML::Emitter& out) {
    if ((t.*m).empty()) {
      out << YAML::Flow << YAML::BeginSeq << YAML::EndSeq;
      return;
    }
    out << YAML::BeginSeq;
    for (const E& element : t.*m)
      child.dump(element, out);
    out << YAML::EndSeq;
  };
  return f;
}

/// A map "name: number" stored as a list of entries {key member, value member}.
template <class T, class E>
Field<T> number_map(std::string name, std::vector<E> T::*m, std::string E::*key_member,
                    double E::*value_member, Range range, std::string doc) {
  Field<T> f;
  f.info = make_key(std::move(name), Type::kNumberMap, "", std::move(doc));
  f.info.range = range;
  f.info.default_text = "empty";
  KeyInfo value_key = make_key("", Type::kNumber, "", "");
  value_key.range = range;
  f.parse = [m, key_member, value_member, value_key](T& t, const YAML::Node& node,
                                                     const YAML::Node& at, const std::string& path,
                                                     Context& ctx) {
    (t.*m).clear();
    if (node.IsNull()) return;
    if (!node.IsMap()) {
      ctx.error(at, path, "expected a map 'name: number', got " + describe_node(node));
      return;
    }
    std::set<std::string> seen;
    for (auto it = node.begin(); it != node.end(); ++it) {
      const YAML::Node key = it->first;
      const YAML::Node value = it->second;
      if (!key.IsScalar() || key.Scalar().empty()) {
        ctx.error(key, path, "keys must be names, got " + describe_node(key));
        continue;
      }
      const std::string entry_path = join_path(path, key.Scalar());
      if (!seen.insert(key.Scalar()).second) {
        ctx.error(key, entry_path, "duplicate key '" + key.Scalar() + "'");
        continue;
      }
      const YAML::Node& value_at = value.IsNull() ? key : value;
      ctx.remember(entry_path, value_at);
      if (auto v = read_value(value_key, value, value_at, entry_path, ctx)) {
        E entry{};
        entry.*key_member = key.Scalar();
        entry.*value_member = std::get<double>(*v);
        (t.*m).push_back(std::move(entry));
      }
    }
  };
  f.dump = [m, key_member, value_member](const T& t, YAML::Emitter& out) {
    if ((t.*m).empty()) {
      out << YAML::Flow << YAML::BeginMap << YAML::EndMap;
      return;
    }
    out << YAML::BeginMap;
    for (const E& entry : t.*m)
      out << YAML::Key << entry.*key_member << YAML::Value << format_number(entry.*value_member);
    out << YAML::EndMap;
  };
  return f;
}

}  // namespace ringdem::schema

// The --set overrides (see CaseOverrides.hpp): key-path parsing and their application to the
// YAML document, checked against the schema tables of CaseSchema.cpp.

#include "io/CaseOverrides.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <optional>
#include <sstream>

#include "io/CaseSchema.hpp"

namespace ringdem {

namespace {

using schema::Context;
using schema::Location;
using schema::Type;

std::string trim(const std::string& s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b])))
    ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1])))
    --e;
  return s.substr(b, e - b);
}

/// "a.b[2].c" and "a.b.2.c" -> {a, b, 2, c}; nothing if malformed.
std::optional<std::vector<std::string>> split_key_path(const std::string& path) {
  std::string normalised;
  for (char ch : path) {
    if (ch == '[') {
      normalised += '.';
    } else if (ch != ']') {
      normalised += ch;
    }
  }
  std::vector<std::string> segments;
  std::stringstream stream(normalised);
  std::string segment;
  while (std::getline(stream, segment, '.')) {
    if (segment.empty()) return std::nullopt;
    segments.push_back(segment);
  }
  if (segments.empty() || normalised.back() == '.') return std::nullopt;
  return segments;
}

std::optional<std::size_t> parse_index(const std::string& s) {
  if (s.empty() || s.size() > 9) return std::nullopt;
  if (!std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c) != 0; }))
    return std::nullopt;
  return static_cast<std::size_t>(std::stoul(s));
}

/// Makes map[key] a map (creating it if absent or empty); false if it holds something else.
bool ensure_map(YAML::Node& map, const std::string& key) {
  const YAML::Node existing = map[key];
  if (!existing.IsDefined() || existing.IsNull()) {
    map[key] = YAML::Node(YAML::NodeType::Map);
    return true;
  }
  return existing.IsMap();
}

/// Applies one "key.path=value" to the document, checking the path against the schema.
void apply_override(YAML::Node& root, const std::string& argument, int index, Context& ctx) {
  const Location at{"--set", index, 1};
  const std::size_t eq = argument.find('=');
  if (eq == std::string::npos) {
    ctx.error(at, "", "expected key.path=value, got '" + argument + "'");
    return;
  }
  const std::string path_text = trim(argument.substr(0, eq));
  const std::string value_text = argument.substr(eq + 1);
  const int value_column = static_cast<int>(eq) + 2;
  const auto segments = split_key_path(path_text);
  if (!segments) {
    ctx.error(at, path_text, "malformed key path '" + path_text + "' (expected e.g. a.b.0.c)");
    return;
  }
  YAML::Node value;
  try {
    value = YAML::Load(value_text);
  } catch (const YAML::ParserException& e) {
    ctx.error(Location{"--set", index, value_column + std::max(0, e.mark.column)}, path_text,
              "cannot parse value '" + value_text + "': " + e.msg);
    return;
  }
  if (!root.IsMap()) return;  // the file itself is reported as not being a map

  const schema::SectionInfo* section = &case_schema().info();
  YAML::Node current = root;
  std::string display;  // path in diagnostic form, e.g. rigid_bodies[0].radius
  for (std::size_t i = 0; i < segments->size(); ++i) {
    const std::string& segment = (*segments)[i];
    const bool last = i + 1 == segments->size();
    const schema::KeyInfo* key = section->find(segment);
    const std::string key_path = schema::join_path(display, segment);
    if (key == nullptr) {
      std::string message = "unknown key '" + segment + "'";
      message += display.empty() ? " at the top level" : " in '" + display + "'";
      const std::string hint = schema::did_you_mean(segment, section->key_names());
      message +=
          hint.empty() ? " (valid keys: " + schema::join_names(section->key_names()) + ")" : hint;
      ctx.error(at, key_path, message);
      return;
    }
    if (last) {
      current[segment] = value;
      ctx.add_override(key_path, index, value_column);
      return;
    }
    switch (key->type) {
      case Type::kSection: {
        if (!ensure_map(current, segment)) {
          ctx.error(at, key_path,
                    "cannot set a key inside '" + key_path + "': it is not a map in the case file");
          return;
        }
        const YAML::Node next = current[segment];
        current.reset(next);
        section = key->child;
        display = key_path;
        break;
      }
      case Type::kList: {
        const std::string& index_text = (*segments)[++i];
        const auto item = parse_index(index_text);
        if (!item) {
          ctx.error(at, key_path,
                    "expected a list index after '" + key_path + "', got '" + index_text + "'");
          return;
        }
        YAML::Node items = current[segment];
        const std::size_t size = items.IsSequence() ? items.size() : 0;
        if (*item >= size) {
          ctx.error(at, schema::index_path(key_path, *item),
                    fmt::format("no entry {} to override: '{}' has {} entries in the case file",
                                *item, key_path, size));
          return;
        }
        display = schema::index_path(key_path, *item);
        if (i + 1 == segments->size()) {
          items[*item] = value;
          ctx.add_override(display, index, value_column);
          return;
        }
        const YAML::Node next = items[*item];
        if (!next.IsMap()) {
          ctx.error(at, display, "cannot set a key inside '" + display + "': it is not a map");
          return;
        }
        current.reset(next);
        section = key->child;
        break;
      }
      case Type::kNumberMap: {
        if (i + 2 != segments->size()) {
          ctx.error(at, key_path, "expected '" + key_path + ".NAME=value'");
          return;
        }
        if (!ensure_map(current, segment)) {
          ctx.error(at, key_path,
                    "cannot set a key inside '" + key_path + "': it is not a map in the case file");
          return;
        }
        YAML::Node entries = current[segment];
        entries[(*segments)[i + 1]] = value;
        ctx.add_override(schema::join_path(key_path, (*segments)[i + 1]), index, value_column);
        return;
      }
      default:
        ctx.error(at, key_path,
                  "'" + key_path + "' is a value, not a section: cannot set '" + path_text + "'");
        return;
    }
  }
}

}  // namespace

void apply_overrides(YAML::Node& root, const std::vector<std::string>& overrides, Context& ctx) {
  for (std::size_t i = 0; i < overrides.size(); ++i)
    apply_override(root, overrides[i], static_cast<int>(i) + 1, ctx);
}

}  // namespace ringdem

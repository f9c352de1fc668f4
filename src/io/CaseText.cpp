#include "io/CaseText.hpp"

#include <yaml-cpp/yaml.h>

#include "io/CaseLoader.hpp"

namespace ringdem {

namespace {

std::string escaped(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (char c : s) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
  return out;
}

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

bool all_scalars(const YAML::Node& seq) {
  for (const auto& item : seq)
    if (!item.IsScalar()) return false;
  return true;
}

std::string flow(const YAML::Node& seq) {
  std::string out = "[";
  for (std::size_t i = 0; i < seq.size(); ++i)
    out += (i ? ", " : "") + escaped(seq[i].Scalar());
  return out + "]";
}

void flatten(const YAML::Node& node, const std::string& path, std::string& out) {
  const auto line = [&](const std::string& value) { out += path + " = " + value + "\n"; };
  switch (node.Type()) {
    case YAML::NodeType::Map:
      if (node.size() == 0) line("{}");
      for (const auto& kv : node)
        flatten(kv.second, join(path, kv.first.Scalar()), out);
      break;
    case YAML::NodeType::Sequence:
      if (all_scalars(node)) {
        line(flow(node));
        break;
      }
      line(std::to_string(node.size()) + " entries");
      for (std::size_t i = 0; i < node.size(); ++i) {
        const YAML::Node item = node[i];
        const bool named = item.IsMap() && item["name"] && item["name"].IsScalar();
        const std::string label = named ? item["name"].Scalar() : std::to_string(i);
        flatten(item, path + "[" + label + "]", out);
      }
      break;
    case YAML::NodeType::Scalar:
      line(escaped(node.Scalar()));
      break;
    default:
      line("null");
      break;
  }
}

}  // namespace

std::string canonical_case_text(const CaseConfig& config) {
  std::string out;
  flatten(YAML::Load(dump_case(config)), "", out);
  return out;
}

std::vector<CaseKey> case_text_keys(const std::string& text) {
  std::vector<CaseKey> keys;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    const std::string line = text.substr(start, end - start);
    const std::size_t eq = line.find(" = ");
    if (eq != std::string::npos) keys.push_back({line.substr(0, eq), line.substr(eq + 3)});
    start = end + 1;
  }
  return keys;
}

}  // namespace ringdem

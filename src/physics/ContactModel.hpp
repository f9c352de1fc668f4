#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace ringdem {

enum class ContactModelKind { kHertzMindlin };

struct ContactModelEntry {
  std::string_view name;
  ContactModelKind kind;
  std::string_view description;
};

/// The one table of particle contact laws selectable by name in a case file.
inline constexpr ContactModelEntry kContactModels[] = {
    {"hertz_mindlin", ContactModelKind::kHertzMindlin,
     "Hertz normal, Mindlin no-slip tangential with Coulomb cap, restitution damping, "
     "constant-torque rolling friction (physics.md §3)"},
};

inline std::optional<ContactModelKind> contact_model_from_name(std::string_view name) {
  for (const auto& e : kContactModels)
    if (e.name == name) return e.kind;
  return std::nullopt;
}

}  // namespace ringdem

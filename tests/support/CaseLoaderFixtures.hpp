#pragma once
// The case text and helpers the case-loader tests share (test_case_loader*.cpp): a valid case
// to mutate, and the lookups that check a diagnostic against the line of the mistake.

#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "io/CaseLoader.hpp"

namespace ringdem::case_fixture {

inline constexpr const char* kValidCase = R"(schema_version: 1
description: "a ring, debris and a boulder"
simulation:
  dt: auto
  end_time: 0.5
  gravity: [0, 0, -9.81]
materials:
  - {name: steel, density: 7800, youngs_modulus: 200e9, poisson_ratio: 0.3}
  - name: rock
    density: 2600
    youngs_modulus: 30e9
    restitution: 0.4
    friction: 0.6
interactions:
  - {materials: [steel, rock], friction: 0.5}
bonds:
  - {name: ring, youngs_modulus: 120e9, radius_multiplier: 0.8, seed: 7}
damping:
  global: 0.05
  groups: {rings: 0.3}
particles:
  rings:
    - group: rings
      centre: [0, 0, 1]
      normal: [0, 2, 0]
      internal_diameter: 0.3
      n_particles: 100
      particle_radius: 0.0045
      material: steel
      bond: ring
  lattices:
    - {group: debris, origin: [0, 0, 2], count: [2, 3, 4], spacing: 0.02, particle_radius: 0.005, material: rock}
  spheres:
    - {position: [1, 1, 1], radius: 0.01, material: rock, motion: fixed}
rigid_bodies:
  - {name: floor, shape: plane, position: [0, 0, 0], normal: [0, 0, 3], material: steel}
  - name: pin
    shape: cylinder
    position: [0, 0, 0.1]
    axis: [2, 0, 0]
    radius: 0.01
    length: 0.1
    motion: prescribed
    velocity: [0, 0, 0.005]
  - {name: boulder, shape: sphere, position: [0, 0, 3], radius: 0.4, motion: free, mass: 825, material: rock}
)";

/// 1-based line of the first occurrence of `needle` in `text` (0 if absent).
inline int line_of(const std::string& text, const std::string& needle) {
  const std::size_t pos = text.find(needle);
  if (pos == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

/// `text` with the first occurrence of `from` replaced by `to`.
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t pos = text.find(from);
  EXPECT_NE(pos, std::string::npos) << "fixture does not contain: " << from;
  if (pos != std::string::npos) text.replace(pos, from.size(), to);
  return text;
}

/// kValidCase with one inlet 'inlet' of rock (box [-1, 0, 0] to [-0.8, 0.5, 0.3], radii 10 to
/// 20 mm) at `velocity` and `discharge`; `more_keys` are further lines of the entry (each
/// "    key: value\n").
inline std::string case_with_inlet(const std::string& velocity, const std::string& discharge,
                                   const std::string& more_keys = "") {
  return replaced(kValidCase, "rigid_bodies:\n",
                  "inflow:\n"
                  "  - name: inlet\n"
                  "    material: rock\n"
                  "    box_min: [-1, 0, 0]\n"
                  "    box_max: [-0.8, 0.5, 0.3]\n"
                  "    velocity: " +
                      velocity + "\n    discharge: " + discharge + "\n" + more_keys +
                      "    sizes: {min_radius: 0.01, max_radius: 0.02}\n"
                      "rigid_bodies:\n");
}

/// The diagnostics of loading `text`; fails the test if it loads.
inline std::vector<Diagnostic> errors_of(const std::string& text,
                                         const std::vector<std::string>& overrides = {}) {
  try {
    load_case_from_string(text, "case.yaml", overrides);
  } catch (const InputError& e) {
    EXPECT_FALSE(e.diagnostics.empty());
    EXPECT_EQ(e.format(), std::string(e.what()));
    return e.diagnostics;
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

/// Loading `text` fails with one error: at `key_path`, on the line of `needle` (line_of), with
/// `message`.
inline void expect_one_error(const std::string& text, const std::string& key_path,
                             const std::string& needle, const std::string& message) {
  const std::vector<Diagnostic> diags = errors_of(text);
  ASSERT_EQ(diags.size(), 1u) << InputError(diags).format();
  EXPECT_EQ(diags[0].key_path, key_path);
  EXPECT_EQ(diags[0].line, line_of(text, needle)) << needle;
  EXPECT_EQ(diags[0].message, message);
}

inline const Diagnostic* find_path(const std::vector<Diagnostic>& diags, const std::string& path) {
  for (const Diagnostic& d : diags)
    if (d.key_path == path) return &d;
  return nullptr;
}

inline std::string all(const std::vector<Diagnostic>& diags) {
  return InputError(diags).format();
}

}  // namespace ringdem::case_fixture

#pragma once

#include <cstdint>
#include <unordered_map>

#include "core/Vec3.hpp"
#include "domain/ContactSpringStore.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// Key of a carried tangential spring: (gid, partner gid) or (gid, rigid-body index).
struct PairKey {
  std::int64_t a, b;
  bool operator==(const PairKey&) const = default;
};
struct PairKeyHash {
  std::size_t operator()(const PairKey& k) const {
    const auto x = static_cast<std::uint64_t>(k.a) * 0x9e3779b97f4a7c15ull;
    return static_cast<std::size_t>(
        x ^ (static_cast<std::uint64_t>(k.b) + 0x7f4a7c159e3779b9ull + (x << 6) + (x >> 2)));
  }
};
using SpringMap = std::unordered_map<PairKey, Vec3, PairKeyHash>;

/// The springs a store carries, by key.
inline SpringMap springs_by_key(const ContactSpringStore& store) {
  SpringMap out;
  for (std::size_t k = 0; k < store.size(); ++k)
    out.emplace(PairKey{store.gid[k], store.partner[k]}, store.spring[k]);
  return out;
}

/// m* of a contact (physics.md §3); a driven particle has infinite mass.
inline double effective_mass(double m_a, Motion motion_a, double m_b, Motion motion_b) {
  const bool inf_a = motion_a != Motion::kFree;
  const bool inf_b = motion_b != Motion::kFree;
  if (inf_a && inf_b) return 0.5 * (m_a + m_b);  // two driven particles: damping irrelevant
  if (inf_a) return m_b;
  if (inf_b) return m_a;
  return m_a * m_b / (m_a + m_b);
}

}  // namespace ringdem

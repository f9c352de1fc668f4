#pragma once

#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// One tangential spring carried between neighbour-list rebuilds and between ranks: the
/// contact of particle `gid` with another particle (its gid, always the higher one) or with a
/// rigid body (its index). Only springs of touching pairs are carried.
struct ContactHistoryEntry {
  enum class Partner : std::uint8_t { kParticle = 0, kRigidBody = 1 };
  Partner partner_kind = Partner::kParticle;
  std::int64_t gid = 0;
  std::int64_t partner = 0;
  Vec3 spring;
};

using ContactHistory = std::vector<ContactHistoryEntry>;

}  // namespace ringdem

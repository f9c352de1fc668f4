#pragma once

#include <cstdint>

namespace ringdem {

/// How the motion of a particle or a rigid body is determined. One enum for the case file,
/// the particle store and the rigid bodies, so no conversion table sits between them.
enum class Motion : std::uint8_t {
  kFree = 0,        ///< integrated from forces
  kFixed = 1,       ///< never moves
  kPrescribed = 2,  ///< moves with its stored (constant) velocity and angular velocity
};

}  // namespace ringdem

#pragma once

#include <cstdint>

namespace ringdem {

/// Which criterion broke a bond (Eq. 3–5, first of tensile, compressive, shear; or the plastic
/// bond's strain limit, docs/physics.md "Plastic bond"), or kNone. Data of the bond store and
/// the frames, decided by the bond laws.
enum class BondFailure : std::uint8_t {
  kNone = 0,
  kTensile = 1,
  kCompressive = 2,
  kShear = 3,
  kPlasticStrain = 4,
};

}  // namespace ringdem

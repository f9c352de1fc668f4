#pragma once

// The set-up shared by the plastic bond's unit tests (test_bond_plastic*.cpp): the beam's and
// the wire bundle's constants recomputed from E, nu, r_b, L0 and n_w, d, f_y (never from the
// evaluator's own coefficients), and a bond along +x with identity orientations at creation.
// Set-up: a 12-winding ring bond as in Table 3 (particle radius 4.5 mm, lambda = 0.43,
// E_b = 288 GPa, L0 = 9.7 mm) along +x from a at the origin; wire d = 3 mm, f_y = 1500 MPa,
// hardening ratio E_t/E = 0.03, E = 200 GPa.

#include <cmath>

#include "SameBits.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"

namespace ringdem::plastic_bond_test {

using Elastic = BondTimoshenko;
using Plastic = BondTimoshenkoPlastic;

constexpr double kRadius = 4.5e-3, kLambda = 0.43, kEb = 288e9, kNu = 0.3, kL0 = 9.7e-3;
constexpr int kWindings = 12;
constexpr double kWire = 3e-3, kFy = 1500e6, kRatio = 0.03, kE = 200e9;

// Beam constants of physics.md §1, computed independently of Section::make.
struct Beam {
  double rb = kLambda * kRadius;
  double area = M_PI * rb * rb;
  double inertia = M_PI * rb * rb * rb * rb / 4.0;
  double g = kEb / (2.0 * (1.0 + kNu));
  double fs = (7.0 + 6.0 * kNu) / (6.0 * (1.0 + kNu));  // Cowper, solid circle
  double phi = 12.0 * kEb * inertia * fs / (g * area * kL0 * kL0);
  double c = kEb * inertia / (1.0 + phi);
  double k_axial = kEb * area / kL0;
  double k_self = (4.0 + phi) * c / kL0;   // end moment per rotation of that end
  double k_cross = (2.0 - phi) * c / kL0;  // ... per rotation of the other end
};

// Wire-bundle limits (physics.md §6), computed here from n_w, d, f_y.
struct Bundle {
  double fy, np, mp, h;
  explicit Bundle(double yield_stress = kFy)
      : fy(yield_stress),
        np(kWindings * fy * M_PI * kWire * kWire / 4.0),   // N_p = n_w f_y pi d^2 / 4
        mp(kWindings * fy * kWire * kWire * kWire / 6.0),  // M_p = n_w f_y d^3 / 6
        h(kE * kRatio / (1.0 - kRatio) / fy) {}            // E_h / f_y, E_h = E E_t / (E - E_t)
};

inline Elastic::Params elastic_params() {
  Elastic::Params p;
  p.youngs_modulus = kEb;
  p.poisson_ratio = kNu;
  p.radius_multiplier = kLambda;
  p.tensile_strength = p.compressive_strength = p.shear_strength = 1e30;
  return p;
}

// A bond along +x from the origin, created with identity orientations.
struct AxisBond {
  Beam beam;
  Bundle bundle;
  Plastic::Section section = Elastic::Section::make(elastic_params(), kRadius, kRadius, kL0);
  Plastic::Reference ref = Elastic::Reference::make(Vec3{}, Quat{}, Vec3{kL0, 0, 0}, Quat{});
  const Plastic::Reference created = ref;  // the frames at creation (a hinge re-bases ref)
  Plastic::Params params;
  Plastic::State state;
  explicit AxisBond(double yield_stress = kFy, double failure_strain = 0.0) : bundle(yield_stress) {
    params = Plastic::Params::from_wire_bundle(kWindings, kWire, yield_stress, kRatio, kE,
                                               failure_strain);
  }
  Plastic::Result at(const Vec3& x_b, const Quat& q_b = Quat{}, const Quat& q_a = Quat{}) {
    return Plastic::compute(section, params, ref, Vec3{}, q_a, x_b, q_b, state);
  }
  double du_yield() const { return bundle.np / beam.k_axial; }
};

inline Quat rot(const Vec3& phi) {
  return quat_from_rotation_vector(phi);
}

using testing::same_bits;
inline bool same_bits(const Quat& a, const Quat& b) {
  return same_bits(a.w, b.w) && same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

// The plastic rotation of an end: the turn from its re-based frame back to its frame at
// creation (the particle's own orientation cancels), in the end frame's components.
inline Vec3 hinge(const Quat& created, const Quat& now) {
  return rotation_vector(conjugate(now) * created);
}

}  // namespace ringdem::plastic_bond_test

// Analytic unit tests of the elastoplastic wire-bundle bond (BondTimoshenkoPlastic; physics.md
// §6, docs/physics.md "Plastic bond", issue 14).
//
// Expectations are derived here from beam theory, the wire-bundle formulas and the closed-form
// solutions of a bilinear (linear-hardening) bar and hinge, never from the evaluator's own
// coefficients: the beam stiffnesses are recomputed from E, nu, r_b, L0, the plastic limits from
// n_w, d, f_y. Each check states its tolerance and why.
//
// Set-up unless stated otherwise: PlasticBondSetup.hpp. The return mapping's robustness (rigid
// motion, far-turned hinges, large steps, failure, bits) is in test_bond_plastic_return.cpp.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "PlasticBondSetup.hpp"
#include "core/Quat.hpp"
#include "core/Vec3.hpp"
#include "physics/BondTimoshenko.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"

namespace ringdem {
namespace {

using namespace plastic_bond_test;

// ---------------------------------------------------------------------------------------------
// 1. The wire-bundle limits: closed forms, and the section moduli by brute-force integration.
TEST(BondPlastic, WireBundleLimitsMatchSectionIntegrals) {
  const auto p = Plastic::Params::from_wire_bundle(kWindings, kWire, kFy, kRatio, kE, 0.05);
  // Section of one wire by strips of height dy: A = int dA, I = int y^2 dA, Z = int |y| dA.
  const double r = 0.5 * kWire;
  const int strips = 200000;
  double area = 0.0, inertia = 0.0, first = 0.0;
  for (int k = 0; k < strips; ++k) {
    const double y = -r + (k + 0.5) * (2.0 * r / strips);
    const double da = 2.0 * std::sqrt(r * r - y * y) * (2.0 * r / strips);
    area += da;
    inertia += y * y * da;
    first += std::abs(y) * da;
  }
  // Midpoint rule on a circle: error ~ (dy)^{3/2} at the edges, below 1e-6 relative here.
  EXPECT_NEAR(p.axial_yield, kWindings * kFy * area, 1e-6 * p.axial_yield);
  EXPECT_NEAR(p.yield_moment, kWindings * kFy * inertia / r, 1e-6 * p.yield_moment);  // I / (d/2)
  EXPECT_NEAR(p.plastic_moment, kWindings * kFy * first, 1e-6 * p.plastic_moment);
  // physics.md §6 example (n_w = 12, f_y = 1500 MPa): 127 kN, 48 N m, 81 N m (3 digits).
  EXPECT_NEAR(p.axial_yield, 127e3, 0.5e3);
  EXPECT_NEAR(p.yield_moment, 48.0, 0.5);
  EXPECT_NEAR(p.plastic_moment, 81.0, 0.5);
  // Shape factor of a solid circle, 16 / (3 pi) = 1.698 (Neal 1977); rounding only.
  EXPECT_NEAR(p.plastic_moment / p.yield_moment, 16.0 / (3.0 * M_PI), 1e-14);
  // h = E_h / f_y with E_h = E b / (1 - b).
  EXPECT_NEAR(p.hardening, kE * kRatio / (1.0 - kRatio) / kFy, 1e-14 * p.hardening);
  EXPECT_EQ(p.failure_strain, 0.05);
  EXPECT_THROW(Plastic::Params::from_wire_bundle(0, kWire, kFy, kRatio), std::invalid_argument);
  EXPECT_THROW(Plastic::Params::from_wire_bundle(12, kWire, kFy, 1.0), std::invalid_argument);
  EXPECT_THROW(Plastic::Params::from_wire_bundle(12, -1.0, kFy, kRatio), std::invalid_argument);
}

// ---------------------------------------------------------------------------------------------
// 2. The yield function against the exact interaction of a fully plastic solid circle.
TEST(BondPlastic, InteractionIsInsideTheExactCircleAndClose) {
  // Fully plastic circle of radius R with the neutral axis at y0: +f_y above, -f_y below.
  // N = f_y (A_above - A_below), M = f_y int |y - 0| sign(y - y0) y dA, by strips.
  const double r = 1.0, np = M_PI * r * r, mp = 4.0 * r * r * r / 3.0;  // f_y = 1
  const int strips = 20000;
  double max_gap = 0.0, max_gauge = 0.0;
  for (int j = 1; j < 100; ++j) {
    const double y0 = -r + j * (2.0 * r / 100);
    double n = 0.0, m = 0.0;
    for (int k = 0; k < strips; ++k) {
      const double y = -r + (k + 0.5) * (2.0 * r / strips);
      const double da = 2.0 * std::sqrt(r * r - y * y) * (2.0 * r / strips);
      const double sigma = y > y0 ? 1.0 : -1.0;
      n += sigma * da;
      m += sigma * y * da;
    }
    n = std::abs(n) / np;
    m = std::abs(m) / mp;
    // The parabola n^2 + m = 1 lies inside (conservative): its moment at this n is below the
    // exact one. Integration error ~1e-6.
    EXPECT_LE(1.0 - n * n, m + 1e-5) << "n = " << n;
    max_gap = std::max(max_gap, m - (1.0 - n * n));
    max_gauge = std::max(max_gauge, Plastic::interaction(n, m));
    EXPECT_GE(Plastic::interaction(n, m), 1.0 - 1e-5);
  }
  // And close: at most 0.024 M_p below (at n = 0.76), 1.6 % radially (evaluated analytically
  // from the parametric form m = cos^3 a, n = (2/pi)(a + sin a cos a)).
  EXPECT_LT(max_gap, 0.025);
  EXPECT_LT(max_gauge, 1.0165);
  // The gauge: on the surface t = 1, homogeneous of degree one, pure cases.
  for (const double n : {0.0, 0.3, 0.7, 1.0})
    EXPECT_NEAR(Plastic::interaction(n, 1.0 - n * n), 1.0, 1e-15);
  EXPECT_NEAR(Plastic::interaction(2.0 * 0.4, 2.0 * 0.3), 2.0 * Plastic::interaction(0.4, 0.3),
              1e-15);
  EXPECT_EQ(Plastic::interaction(-0.8, 0.0), 0.8);
  EXPECT_EQ(Plastic::interaction(0.0, 0.6), 0.6);
}

// ---------------------------------------------------------------------------------------------
// 3. A bar pulled past yield and unloaded: bilinear closed form. Axial stiffness k = E A / L0
// (the surrogate section), yield at N_p, plastic modulus H = dN/d(delta_p) = N_p h / L0 (kappa =
// delta_p / L0), so the elastoplastic slope is k H / (k + H); unloading along k leaves
// delta_p = du_max - N_max / k.
TEST(BondPlastic, BarPulledPastYieldLeavesPredictedPermanentElongation) {
  AxisBond b;
  const double k = b.beam.k_axial, np = b.bundle.np;
  const double hmod = np * b.bundle.h / kL0, slope = k * hmod / (k + hmod);
  const double du_y = np / k, du_max = 3.0 * du_y;
  const int steps = 300;
  // Backward Euler with linear hardening is exact for a monotone 1-D path: the axial force is
  // k (L - L0 - delta_p) with L = |x_b| exact, so only rounding remains (1e-9 of N_p).
  const double tol = 1e-9 * np;
  double n_max = 0.0;
  for (int i = 1; i <= steps; ++i) {
    const double du = du_max * i / steps;
    const auto r = b.at(Vec3{kL0 + du, 0, 0});
    const double expected = du <= du_y ? k * du : np + slope * (du - du_y);
    ASSERT_NEAR(r.axial_force, expected, tol) << "loading step " << i;
    ASSERT_NEAR(r.bending_a + r.bending_b + std::abs(r.torsion), 0.0, 1e-9 * b.bundle.mp);
    n_max = r.axial_force;
  }
  const double dp = du_max - (np + slope * (du_max - du_y)) / k;  // permanent elongation
  EXPECT_NEAR(b.state.elongation, dp, 1e-9 * dp);
  EXPECT_NEAR(b.state.strain, dp / kL0, 1e-9 * dp / kL0);
  // A pure stretch forms no hinge: both end frames as created, to the bit.
  EXPECT_TRUE(same_bits(b.ref.frame_a, b.created.frame_a));
  EXPECT_TRUE(same_bits(b.ref.frame_b, b.created.frame_b));
  // Unloading along the elastic slope k down to zero force at du = delta_p.
  for (int i = 1; i <= steps; ++i) {
    const double du = du_max - (du_max - dp) * i / steps;
    const auto r = b.at(Vec3{kL0 + du, 0, 0});
    ASSERT_NEAR(r.axial_force, n_max - k * (du_max - du), tol) << "unloading step " << i;
    ASSERT_EQ(r.plastic_work, 0.0) << "unloading is elastic";
    // Elastic energy of the elastic part: N^2 / 2k.
    ASSERT_NEAR(r.energy, 0.5 * r.axial_force * r.axial_force / k, 1e-9 * np * du_y);
  }
  EXPECT_NEAR(b.state.elongation, dp, 1e-9 * dp);  // no flow while unloading
  EXPECT_NEAR(b.at(Vec3{kL0 + dp, 0, 0}).axial_force, 0.0, tol);
}

// ---------------------------------------------------------------------------------------------
// 4. Cantilever: a clamped, b turned in place by theta about z (then y). Only b's end yields
// (M_a = k_cross / k_self M_b < M_b, and n = 0): a single hinge. Elastic up to M_p at
// theta_y = M_p / k_self, then M_b = M_p + H_t theta_p with the hinge hardening
// H_t = h M_p^2 / (N_p L0) (dkappa = M_p dtheta_p / (N_p L0) at n = 0), so
// theta_p = (k_self theta - M_p) / (k_self + H_t); unloading along k_self leaves theta_p.
TEST(BondPlastic, CantileverPastPlasticMomentFollowsHingeMomentRotation) {
  for (const int axis : {2, 1}) {  // z, then y
    AxisBond b;
    const double ks = b.beam.k_self, kc = b.beam.k_cross, mp = b.bundle.mp;
    const double ht = b.bundle.h * mp * mp / (b.bundle.np * kL0);
    const double th_y = mp / ks, th_max = 3.0 * th_y;
    auto turn = [&](double th) { return rot(axis == 2 ? Vec3{0, 0, th} : Vec3{0, th, 0}); };
    // The bond measures the end rotation with the cubic arcsine series (BondTimoshenko), whose
    // error is the next term 5 s^7 / 112 (s = sin theta), 1.4e-6 rad at 3 theta_y here; bound
    // by 1.2 times that, through the elastic slope.
    const double s = std::sin(th_max);
    const double tol_m = ks * 1.2 * 5.0 * std::pow(s, 7) / 112.0 + 1e-9 * mp;
    double theta_p = 0.0, m_max = 0.0;
    const int steps = 300;
    for (int i = 1; i <= steps; ++i) {
      const double th = th_max * i / steps;
      const auto r = b.at(Vec3{kL0, 0, 0}, turn(th));
      theta_p = th <= th_y ? 0.0 : (ks * th - mp) / (ks + ht);
      const double m_b = ks * (th - theta_p);
      ASSERT_NEAR(r.bending_b, m_b, tol_m) << "axis " << axis << " step " << i;
      ASSERT_NEAR(r.bending_a, kc * (th - theta_p), tol_m) << "the clamped end stays elastic";
      if (th > th_y) {
        ASSERT_NEAR(r.bending_b, mp + ht * theta_p, tol_m) << "hardening slope";
      }
      ASSERT_NEAR(r.axial_force, 0.0, 1e-9 * b.bundle.np);
      m_max = r.bending_b;
    }
    // The torque the bond puts on b resists the turn: -M_b about the axis.
    const auto r_end = b.at(Vec3{kL0, 0, 0}, turn(th_max));
    EXPECT_NEAR(axis == 2 ? r_end.torque_b.z : r_end.torque_b.y, -m_max, tol_m);
    // Plastic rotation of b's end only, held in its re-based frame (+z turn -> +z, +y -> +y).
    const Vec3 got_b = hinge(b.created.frame_b, b.ref.frame_b);
    EXPECT_NEAR(axis == 2 ? got_b.z : got_b.y, theta_p, tol_m / ks);
    EXPECT_NEAR(axis == 2 ? got_b.y : got_b.z, 0.0, 1e-12);
    EXPECT_NEAR(got_b.x, 0.0, 1e-12);
    EXPECT_TRUE(same_bits(b.ref.frame_a, b.created.frame_a)) << "end a formed no hinge";
    EXPECT_EQ(b.state.elongation, 0.0);  // n = 0: the parabola's normal has no axial part
    EXPECT_NEAR(b.state.strain, mp * theta_p / (b.bundle.np * kL0),
                mp * (tol_m / ks) / (b.bundle.np * kL0));
    // Unloading along k_self: zero moment at the permanent rotation.
    for (int i = 1; i <= steps; ++i) {
      const double th = th_max - (th_max - theta_p) * i / steps;
      const auto r = b.at(Vec3{kL0, 0, 0}, turn(th));
      ASSERT_NEAR(r.bending_b, std::abs(m_max - ks * (th_max - th)), tol_m) << "unloading " << i;
      ASSERT_EQ(r.plastic_work, 0.0);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// 5. A load cycle dissipates the area of its hysteresis loop. Axial path 0 -> +D -> -D -> back
// to zero force, D = 3 du_y. Closed form (isotropic hardening: the reverse yield is at the
// current limit -N_1): delta_p1 = (k D - N_p) / (k + H), kappa_1 = delta_p1 / L0;
// delta_p2 = (N_p (1 + h kappa_1) + H delta_p1 - k D) / (k + H),
// kappa_2 = kappa_1 + (delta_p1 - delta_p2) / L0; loop area = plastic work =
// int N_p (1 + h kappa) L0 dkappa = N_p L0 (kappa_2 + h kappa_2^2 / 2).
TEST(BondPlastic, LoadCycleDissipatesTheAreaOfItsHysteresisLoop) {
  AxisBond b;
  const double k = b.beam.k_axial, np = b.bundle.np, h = b.bundle.h;
  const double hmod = np * h / kL0;
  const double d = 3.0 * b.du_yield();
  const double dp1 = (k * d - np) / (k + hmod), kap1 = dp1 / kL0;
  const double dp2 = (np * (1.0 + h * kap1) + hmod * dp1 - k * d) / (k + hmod);
  const double kap2 = kap1 + (dp1 - dp2) / kL0;
  const double w_exact = np * kL0 * (kap2 + 0.5 * h * kap2 * kap2);

  const int steps = 2000;  // per leg
  const double du_step = d / steps;
  std::vector<double> path;
  for (int i = 0; i <= steps; ++i)
    path.push_back(d * i / steps);
  for (int i = 1; i <= 2 * steps; ++i)
    path.push_back(d - 2.0 * d * i / (2 * steps));
  double area = 0.0, work_sum = 0.0, n_prev = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) {
    const auto r = b.at(Vec3{kL0 + path[i], 0, 0});
    area += 0.5 * (n_prev + r.axial_force) * (path[i] - path[i - 1]);  // trapezoid of N du
    work_sum += r.plastic_work;
    n_prev = r.axial_force;
  }
  // Elastic reloading to zero force, at du = delta_p (the bond's own permanent elongation).
  const double du_end = b.state.elongation;
  for (int i = 1; i <= steps; ++i) {
    const double u0 = -d + (du_end + d) * (i - 1) / steps, u1 = -d + (du_end + d) * i / steps;
    const auto r = b.at(Vec3{kL0 + u1, 0, 0});
    area += 0.5 * (n_prev + r.axial_force) * (u1 - u0);
    work_sum += r.plastic_work;
    n_prev = r.axial_force;
  }
  EXPECT_NEAR(n_prev, 0.0, 1e-9 * np);
  EXPECT_NEAR(b.state.elongation, dp2, 1e-9 * std::abs(dp2));
  EXPECT_NEAR(b.state.strain, kap2, 1e-9 * kap2);
  // The per-call increments add up to the state's tally (same additions, same order).
  EXPECT_EQ(work_sum, b.state.work);
  // Backward Euler books N_p (1 + h kappa_{n+1}) dkappa per step: above the exact integral by
  // N_p L0 h sum dkappa^2 / 2 <= N_p L0 h kappa_2 dkappa_max / 2, dkappa_max <= du_step / L0.
  const double be_bound = 0.5 * np * kL0 * h * kap2 * du_step / kL0;
  EXPECT_GE(b.state.work, w_exact - 1e-9 * w_exact);
  EXPECT_LE(b.state.work, w_exact + be_bound);
  // The trapezoid of N du is exact on each linear piece of the path; the two steps that hold
  // a yield onset err by at most k du_step^2 / 8 each; the reversals lie on steps.
  EXPECT_NEAR(area, w_exact, 2.0 * k * du_step * du_step / 8.0 + 1e-9 * w_exact);
  // The bound is tight enough to see the hardening: without it the work would differ by
  // N_p L0 h kappa_2^2 / 2, far above both tolerances.
  ASSERT_GT(0.5 * np * kL0 * h * kap2 * kap2, 100.0 * be_bound);
}

// ---------------------------------------------------------------------------------------------
// 6. A 3-D load cycle (stretch, bending in both planes at both ends, shear, twist): the work
// done on the bond equals the elastic energy left plus the plastic work. A low yield stress
// (f_y = 15 MPa) keeps the deformations at 1e-3, where the co-rotational kernel is conservative
// to ~1e-6, so what remains is the time discretisation of the plastic work (first order).
double cycle_imbalance(int steps, double* plastic_work) {
  AxisBond b(15e6);
  const double du = b.du_yield(), th = b.bundle.mp / b.beam.k_self;
  auto config = [&](double s, Vec3& x_b, Quat& q_a, Quat& q_b) {
    const double u = 2.0 * M_PI * s;
    x_b = Vec3{kL0 + 2.5 * du * std::sin(u), 0.4 * th * kL0 * std::sin(2.0 * u),
               0.3 * th * kL0 * (1.0 - std::cos(u))};
    q_a = rot(
        Vec3{0.5 * th * std::sin(u), 2.0 * th * std::sin(2.0 * u), 1.5 * th * (1.0 - std::cos(u))});
    q_b = rot(Vec3{-0.5 * th * std::sin(u), -1.5 * th * std::sin(u), 2.5 * th * std::sin(2.0 * u)});
  };
  Vec3 x_prev, x_b;
  Quat qa_prev, qb_prev, q_a, q_b;
  config(0.0, x_prev, qa_prev, qb_prev);
  Plastic::Result r_prev = b.at(x_prev, qb_prev, qa_prev);
  double work_on_bond = 0.0;
  for (int cycle = 0; cycle < 2; ++cycle) {
    for (int i = 1; i <= steps; ++i) {
      config(static_cast<double>(i) / steps, x_b, q_a, q_b);
      const auto r = b.at(x_b, q_b, q_a);
      // Incremental rotations (world frame) and the trapezoid of the loads the bond exerts;
      // the work done on the bond is minus that.
      const Vec3 dphi_a = rotation_vector(q_a * conjugate(qa_prev));
      const Vec3 dphi_b = rotation_vector(q_b * conjugate(qb_prev));
      work_on_bond -= 0.5 * (dot(r.force_b + r_prev.force_b, x_b - x_prev) +
                             dot(r.torque_a + r_prev.torque_a, dphi_a) +
                             dot(r.torque_b + r_prev.torque_b, dphi_b));
      r_prev = r;
      x_prev = x_b;
      qa_prev = q_a;
      qb_prev = q_b;
    }
  }
  *plastic_work = b.state.work;
  return work_on_bond - (r_prev.energy + b.state.work);
}

TEST(BondPlastic, ThreeDimensionalCycleBalancesWorkElasticEnergyAndPlasticWork) {
  double wp1 = 0.0, wp2 = 0.0;
  const double e1 = cycle_imbalance(1000, &wp1);
  const double e2 = cycle_imbalance(2000, &wp2);
  // Both ends and the bar yielded: the plastic work is many times the elastic energy scale.
  ASSERT_GT(wp2, 0.0);
  // First order in the step: the imbalance is small and halves with the step (0.35-0.65
  // allows for the O(dt^2) trapezoid and the ~1e-6 geometric part).
  EXPECT_LT(std::abs(e2), 2e-3 * wp2) << "imbalance " << e2 << " of " << wp2;
  EXPECT_GT(std::abs(e2) / std::abs(e1), 0.35);
  EXPECT_LT(std::abs(e2) / std::abs(e1), 0.65);
  // The plastic work itself converges: the two runs agree to the same order.
  EXPECT_NEAR(wp1, wp2, 4e-3 * wp2);
}

}  // namespace
}  // namespace ringdem

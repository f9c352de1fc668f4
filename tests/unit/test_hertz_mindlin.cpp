// Analytic unit tests of the Hertz–Mindlin contact evaluator (physics.md §3, paper Eq. 6–9).
//
// Every expectation is computed here from the formulas of physics.md, not from the evaluator:
// the material mixing (E*, G*, R*, m*), the damping ratio beta and the reference forces are
// re-derived in this file. Tolerances and their reasons are stated next to each check.

#include <gtest/gtest.h>

#include <cmath>

#include "core/Vec3.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {
namespace {

// Steel spheres of the paper: E = 200 GPa, nu = 0.3, r = 4.5 mm, rho = 7850 kg/m^3.
constexpr double kYoungs = 200e9;
constexpr double kPoisson = 0.3;
constexpr double kSphereRadius = 4.5e-3;
constexpr double kDensity = 7850.0;

double sphere_mass(double r) {
  return kDensity * 4.0 / 3.0 * M_PI * r * r * r;
}

// physics.md §3: 1/E* = (1-nu_i^2)/E_i + (1-nu_j^2)/E_j.
double e_star(double e_i, double nu_i, double e_j, double nu_j) {
  return 1.0 / ((1.0 - nu_i * nu_i) / e_i + (1.0 - nu_j * nu_j) / e_j);
}
// physics.md §3 (Mindlin, not the paper's typo): 1/G* = (2-nu_i)/G_i + (2-nu_j)/G_j.
double g_star(double e_i, double nu_i, double e_j, double nu_j) {
  const double g_i = e_i / (2.0 * (1.0 + nu_i));
  const double g_j = e_j / (2.0 * (1.0 + nu_j));
  return 1.0 / ((2.0 - nu_i) / g_i + (2.0 - nu_j) / g_j);
}
// physics.md §3: beta = ln e / sqrt(ln^2 e + pi^2).
double beta_of(double e) {
  const double l = std::log(e);
  return l / std::sqrt(l * l + M_PI * M_PI);
}
// Eq. 6: F_n = 4/3 E* sqrt(R*) delta^{3/2}.
double hertz_force(double es, double rs, double delta) {
  return 4.0 / 3.0 * es * std::sqrt(rs) * std::pow(delta, 1.5);
}

// A contact with everything zero but the normal, overlap and radii/mass.
HertzMindlin::Input make_input(const Vec3& n, double delta, double r_star, double m_star) {
  HertzMindlin::Input in{};
  in.normal = n;
  in.overlap = delta;
  in.r_star = r_star;
  in.m_star = m_star;
  in.v_rel = Vec3{};
  in.dt = 1e-7;
  in.arm_i = kSphereRadius - 0.5 * delta;
  in.arm_j = kSphereRadius - 0.5 * delta;
  in.omega_i = Vec3{};
  in.omega_j = Vec3{};
  return in;
}

// A unit normal not aligned with any axis, so that component mix-ups show.
const Vec3 kNormal = Vec3{1.0, 2.0, -2.0} / 3.0;

// ---------------------------------------------------------------------------------------------
// 1. Normal force and stiffness of two steel spheres at rest.
TEST(HertzMindlinAnalytic, NormalForceMatchesHertz) {
  const auto p = HertzMindlin::Params::mix(kYoungs, kPoisson, kYoungs, kPoisson, 0.5, 0.3, 0.0);
  const double es = e_star(kYoungs, kPoisson, kYoungs, kPoisson);       // = E / (2 (1 - nu^2))
  const double rs = 1.0 / (1.0 / kSphereRadius + 1.0 / kSphereRadius);  // = r / 2
  const double ms = 0.5 * sphere_mass(kSphereRadius);
  for (const double delta : {1e-7, 1e-6, 1e-5, 5e-5}) {
    Vec3 spring{};
    const auto r = HertzMindlin::compute(p, make_input(kNormal, delta, rs, ms), spring);
    const double expected = hertz_force(es, rs, delta);
    // Closed form evaluated two ways: only rounding differs (a few ulp), so 1e-12 relative.
    const double tol = 1e-12 * expected;
    EXPECT_NEAR(r.normal_force, expected, tol) << "delta = " << delta;
    // Force on i is -F_n n (from j to i), with no tangential part at rest.
    EXPECT_NEAR(r.force_i.x, -expected * kNormal.x, tol);
    EXPECT_NEAR(r.force_i.y, -expected * kNormal.y, tol);
    EXPECT_NEAR(r.force_i.z, -expected * kNormal.z, tol);
    EXPECT_FALSE(r.sliding);
    // Elastic energy of the Hertz spring: integral of F_n d delta = 2/5 F_n delta. Closed form.
    EXPECT_NEAR(r.elastic_energy, 0.4 * expected * delta, 1e-12 * expected * delta);
  }
}

TEST(HertzMindlinAnalytic, NormalStiffnessIsDerivativeOfForce) {
  const auto p = HertzMindlin::Params::mix(kYoungs, kPoisson, kYoungs, kPoisson, 0.5, 0.3, 0.0);
  const double es = e_star(kYoungs, kPoisson, kYoungs, kPoisson);
  const double rs = 0.5 * kSphereRadius;
  const double ms = 0.5 * sphere_mass(kSphereRadius);
  auto force = [&](double delta) {
    Vec3 spring{};
    return HertzMindlin::compute(p, make_input(kNormal, delta, rs, ms), spring).normal_force;
  };
  for (const double delta : {1e-6, 1e-5, 5e-5}) {
    const double h = 1e-4 * delta;
    const double s_fd = (force(delta + h) - force(delta - h)) / (2.0 * h);
    const double s_n = 2.0 * es * std::sqrt(rs * delta);  // S_n = dF/d delta, physics.md §3
    // Central difference: truncation (h/delta)^2 / 24 ~ 1e-10, rounding eps / 1e-4 ~ 1e-12;
    // 1e-7 relative leaves ample margin.
    EXPECT_NEAR(s_fd, s_n, 1e-7 * s_n) << "delta = " << delta;
  }
}

// ---------------------------------------------------------------------------------------------
// 2. Restitution of a head-on collision of two equal spheres, integrated here with RK4.
double measured_restitution(double e) {
  const auto p = HertzMindlin::Params::mix(kYoungs, kPoisson, kYoungs, kPoisson, e, 0.3, 0.0);
  const double m = sphere_mass(kSphereRadius);
  const double rs = 0.5 * kSphereRadius;
  const double ms = 0.5 * m;
  const double es = e_star(kYoungs, kPoisson, kYoungs, kPoisson);
  const double v_in = 1.0;  // approach speed, m/s
  // Hertz contact time t_c = 2.87 (m*^2 / (R* E*^2 v))^{1/5}; 20000 RK4 steps over it.
  const double t_c = 2.87 * std::pow(ms * ms / (rs * es * es * v_in), 0.2);
  const double h = t_c / 20000.0;
  const Vec3 n{1.0, 0.0, 0.0};  // i at the left, j at the right, n from i to j

  // State: positions and velocities of i and j along n. Overlap = 2r - (x_j - x_i).
  struct State {
    double xi, xj, vi, vj;
  };
  // Force on j along n (+F_n repulsive); i gets the opposite. No force without overlap.
  auto accel = [&](const State& s, double& ai, double& aj) {
    const double delta = 2.0 * kSphereRadius - (s.xj - s.xi);
    if (delta <= 0.0) {
      ai = aj = 0.0;
      return;
    }
    HertzMindlin::Input in = make_input(n, delta, rs, ms);
    in.v_rel = n * (s.vj - s.vi);  // j relative to i
    in.dt = h;
    Vec3 spring{};
    const auto r = HertzMindlin::compute(p, in, spring);
    ai = r.force_i.x / m;
    aj = -r.force_i.x / m;
  };
  auto deriv = [&](const State& s) {
    double ai = 0.0, aj = 0.0;
    accel(s, ai, aj);
    return State{s.vi, s.vj, ai, aj};
  };
  auto axpy = [](const State& s, double a, const State& d) {
    return State{s.xi + a * d.xi, s.xj + a * d.xj, s.vi + a * d.vi, s.vj + a * d.vj};
  };

  // Start exactly at touching, approaching symmetrically.
  State s{-kSphereRadius, kSphereRadius, 0.5 * v_in, -0.5 * v_in};
  for (int step = 0; step < 200000; ++step) {
    const State k1 = deriv(s);
    const State k2 = deriv(axpy(s, 0.5 * h, k1));
    const State k3 = deriv(axpy(s, 0.5 * h, k2));
    const State k4 = deriv(axpy(s, h, k3));
    State next = s;
    next.xi += h / 6.0 * (k1.xi + 2.0 * k2.xi + 2.0 * k3.xi + k4.xi);
    next.xj += h / 6.0 * (k1.xj + 2.0 * k2.xj + 2.0 * k3.xj + k4.xj);
    next.vi += h / 6.0 * (k1.vi + 2.0 * k2.vi + 2.0 * k3.vi + k4.vi);
    next.vj += h / 6.0 * (k1.vj + 2.0 * k2.vj + 2.0 * k3.vj + k4.vj);
    const double delta_now = 2.0 * kSphereRadius - (s.xj - s.xi);
    const double delta_next = 2.0 * kSphereRadius - (next.xj - next.xi);
    if (step > 10 && delta_next <= 0.0) {
      // Separation: interpolate the relative velocity linearly to delta = 0.
      const double frac = delta_now / (delta_now - delta_next);
      const double v_rel_now = s.vj - s.vi;
      const double v_rel_next = next.vj - next.vi;
      const double v_out = v_rel_now + frac * (v_rel_next - v_rel_now);
      return v_out / v_in;  // separating relative velocity over approach speed
    }
    s = next;
  }
  ADD_FAILURE() << "spheres did not separate";
  return 0.0;
}

TEST(HertzMindlinAnalytic, RestitutionOfHeadOnCollision) {
  for (const double e : {0.2, 0.5, 0.9}) {
    const double measured = measured_restitution(e);
    // physics.md §3 damping with the sqrt(5/6) factor and an unclamped normal force
    // reproduces e exactly; only the RK4 discretisation (~1e-6 here) differs. The brief and
    // validation.md §1 ask for 2 %. (A force clamped at zero would give e = 0.32, 0.55, 0.90.)
    EXPECT_NEAR(measured, e, 0.02 * e) << "input e = " << e;
  }
}

// ---------------------------------------------------------------------------------------------
// 3. Mindlin stick stiffness and the Coulomb limit (two different materials and radii).
struct TwoMaterials {
  double e_i = 200e9, nu_i = 0.3, r_i = 4.5e-3;
  double e_j = 70e9, nu_j = 0.33, r_j = 6.0e-3;
  double restitution = 0.5, friction = 0.3;
  double es() const { return e_star(e_i, nu_i, e_j, nu_j); }
  double gs() const { return g_star(e_i, nu_i, e_j, nu_j); }
  double rs() const { return 1.0 / (1.0 / r_i + 1.0 / r_j); }
  double ms() const {
    const double m_i = sphere_mass(r_i), m_j = sphere_mass(r_j);
    return m_i * m_j / (m_i + m_j);
  }
  HertzMindlin::Params params(double rolling = 0.0) const {
    return HertzMindlin::Params::mix(e_i, nu_i, e_j, nu_j, restitution, friction, rolling);
  }
};

TEST(HertzMindlinAnalytic, MindlinStickStiffnessAndCoulombLimit) {
  const TwoMaterials mat;
  const auto p = mat.params();
  const double delta = 2e-5;
  const double rs = mat.rs(), ms = mat.ms();
  const double f_n = hertz_force(mat.es(), rs, delta);
  const double s_t = 8.0 * mat.gs() * std::sqrt(rs * delta);  // Eq. 8 with Mindlin's G*
  const double f_cap = mat.friction * f_n;                    // Coulomb, mu_s |F_n|
  const double beta = beta_of(mat.restitution);
  // Tangential viscous force of Eq. 9 for the tangential velocity below (acts while sticking).
  const double c_t = -2.0 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(s_t * ms);

  const Vec3 t = normalized(cross(kNormal, Vec3{0.0, 0.0, 1.0}));  // unit, in the tangent plane
  const double u = 0.01;                                           // tangential speed, m/s
  const double dt = 1e-5;                                          // increment u dt = 1e-7 m
  HertzMindlin::Input in = make_input(kNormal, delta, rs, ms);
  in.v_rel = t * u;  // j slides along +t relative to i
  in.dt = dt;

  // Stick: the elastic spring (the carried history) is S_t delta_t, delta_t = k u dt.
  // Slip begins at delta_t = mu F_n / S_t (~4.4e-6 m here); 10 increments stay well below.
  ASSERT_LT(10 * u * dt * s_t, 0.5 * f_cap);
  Vec3 spring{};
  for (int k = 1; k <= 10; ++k) {
    const auto r = HertzMindlin::compute(p, in, spring);
    const double expected = s_t * (k * u * dt);
    // Sum of k identical increments: rounding only, 1e-12 relative.
    EXPECT_NEAR(norm(spring), expected, 1e-12 * expected) << "k = " << k;
    // The friction on i drags it along j's relative motion (+t).
    EXPECT_NEAR(dot(spring, t), expected, 1e-12 * expected);
    EXPECT_FALSE(r.sliding);
    // Total tangential force = elastic spring + viscous part c_t u along +t (c_t > 0 since
    // beta < 0): both terms closed form, 1e-12 relative to the larger.
    const Vec3 f_tan = r.force_i - kNormal * dot(r.force_i, kNormal);
    const double expected_total = expected + c_t * u;
    EXPECT_NEAR(dot(f_tan, t), expected_total, 1e-12 * expected_total);
    EXPECT_NEAR(norm(f_tan - t * dot(f_tan, t)), 0.0, 1e-12 * expected_total);
    // Normal part unaffected by tangential sliding (v_n = 0).
    EXPECT_NEAR(-dot(r.force_i, kNormal), f_n, 1e-12 * f_n);
  }

  // Slip: keep pushing to 200 increments (2e-5 m, ~5x the slip distance).
  HertzMindlin::Result last{};
  for (int k = 11; k <= 200; ++k)
    last = HertzMindlin::compute(p, in, spring);
  EXPECT_TRUE(last.sliding);
  // Saturated spring: |F_t| = mu F_n exactly (rescaling only, 1e-12 relative).
  EXPECT_NEAR(norm(spring), f_cap, 1e-12 * f_cap);
  EXPECT_NEAR(dot(spring, t), f_cap, 1e-12 * f_cap);
  // Sliding: total tangential force is the Coulomb force (no viscous part is added on top in
  // Coulomb slip); allow 1e-12 relative for rounding.
  const Vec3 f_tan = last.force_i - kNormal * dot(last.force_i, kNormal);
  EXPECT_NEAR(norm(f_tan), f_cap, 1e-12 * f_cap);
}

TEST(HertzMindlinAnalytic, TangentialSpringFollowsContactPlane) {
  // physics.md §3: "the stored spring is rotated with the contact plane each step". With no
  // relative velocity the spring must stay in the new tangent plane with its magnitude kept.
  const TwoMaterials mat;
  const auto p = mat.params();
  const double delta = 2e-5;
  const Vec3 t = normalized(cross(kNormal, Vec3{0.0, 0.0, 1.0}));
  const double f_n = hertz_force(mat.es(), mat.rs(), delta);
  Vec3 spring = t * (0.1 * mat.friction * f_n);  // well below the Coulomb cap
  const double mag = norm(spring);
  // Tilt the normal by 0.01 rad about an axis in the tangent plane but not along t.
  const Vec3 axis = normalized(t + cross(kNormal, t));
  const double a = 0.01;
  const Vec3 n2 = kNormal * std::cos(a) + cross(axis, kNormal) * std::sin(a);
  HertzMindlin::Input in = make_input(n2, delta, mat.rs(), mat.ms());
  HertzMindlin::compute(p, in, spring);
  // Rounding only: 1e-12 relative.
  EXPECT_NEAR(norm(spring), mag, 1e-12 * mag);
  EXPECT_NEAR(dot(spring, n2), 0.0, 1e-12 * mag);
}

// ---------------------------------------------------------------------------------------------
// 4. Rolling friction: tau_r = -mu_r F_n R_i omega_hat_i (EDEM "standard").
TEST(HertzMindlinAnalytic, RollingFrictionTorque) {
  const TwoMaterials mat;
  const double mu_r = 0.05;
  const auto p = mat.params(mu_r);
  const double delta = 1e-5;
  const double f_n = hertz_force(mat.es(), mat.rs(), delta);
  HertzMindlin::Input in = make_input(kNormal, delta, mat.rs(), mat.ms());
  in.arm_i = mat.r_i - 0.5 * delta;
  in.arm_j = mat.r_j - 0.5 * delta;
  in.omega_i = Vec3{0.0, 3.0, 4.0};   // |omega| = 5, hat = (0, 0.6, 0.8)
  in.omega_j = Vec3{-2.0, 0.0, 0.0};  // hat = (-1, 0, 0)
  Vec3 spring{};
  const auto r = HertzMindlin::compute(p, in, spring);
  const double k_i = mu_r * f_n * in.arm_i;
  const double k_j = mu_r * f_n * in.arm_j;
  // Closed form; rounding only, 1e-12 relative to the magnitude.
  EXPECT_NEAR(r.rolling_torque_i.x, 0.0, 1e-12 * k_i);
  EXPECT_NEAR(r.rolling_torque_i.y, -k_i * 0.6, 1e-12 * k_i);
  EXPECT_NEAR(r.rolling_torque_i.z, -k_i * 0.8, 1e-12 * k_i);
  EXPECT_NEAR(r.rolling_torque_j.x, k_j, 1e-12 * k_j);
  EXPECT_NEAR(r.rolling_torque_j.y, 0.0, 1e-12 * k_j);
  EXPECT_NEAR(r.rolling_torque_j.z, 0.0, 1e-12 * k_j);
  // Magnitude independent of the spin rate (constant torque model).
  in.omega_i = in.omega_i * 1e-3;
  Vec3 spring2{};
  const auto r2 = HertzMindlin::compute(p, in, spring2);
  EXPECT_NEAR(norm(r2.rolling_torque_i), k_i, 1e-12 * k_i);
  // Rolling friction must not change the contact force itself.
  EXPECT_NEAR(r.normal_force, f_n, 1e-12 * f_n);
}

TEST(HertzMindlinAnalytic, RollingFrictionZeroWithoutSpin) {
  // omega = 0 has no direction: the torque must be zero and finite (no NaN).
  const TwoMaterials mat;
  const auto p = mat.params(0.05);
  Vec3 spring{};
  const auto r = HertzMindlin::compute(p, make_input(kNormal, 1e-5, mat.rs(), mat.ms()), spring);
  EXPECT_EQ(norm(r.rolling_torque_i), 0.0);
  EXPECT_EQ(norm(r.rolling_torque_j), 0.0);
}

// ---------------------------------------------------------------------------------------------
// 5. Directions: repulsion from j to i; normal damping opposes the normal relative motion.
TEST(HertzMindlinAnalytic, ForceDirectionAndNormalDamping) {
  const TwoMaterials mat;
  const auto p = mat.params();
  const double delta = 1e-5;
  const double rs = mat.rs(), ms = mat.ms();
  const double f_spring = hertz_force(mat.es(), rs, delta);
  const double s_n = 2.0 * mat.es() * std::sqrt(rs * delta);
  const double beta = beta_of(mat.restitution);
  ASSERT_LT(beta, 0.0);

  // At rest: force on i is along -n, i.e. from j towards i (n points from i to j).
  {
    Vec3 spring{};
    const auto r = HertzMindlin::compute(p, make_input(kNormal, delta, rs, ms), spring);
    EXPECT_LT(dot(r.force_i, kNormal), 0.0);
    EXPECT_NEAR(norm(cross(r.force_i, kNormal)), 0.0, 1e-12 * f_spring);  // parallel to n
  }
  for (const double v_n : {-0.5, 0.5}) {  // approaching (-) and separating (+)
    HertzMindlin::Input in = make_input(kNormal, delta, rs, ms);
    in.v_rel = kNormal * v_n;
    Vec3 spring{};
    const auto r = HertzMindlin::compute(p, in, spring);
    // Eq. 7: F_n^d = -2 sqrt(5/6) beta sqrt(S_n m*) v_n^rel with v_n^rel the approach speed
    // (-v_n here): repulsive (positive) when approaching, attractive when separating.
    const double f_damp = -2.0 * std::sqrt(5.0 / 6.0) * beta * std::sqrt(s_n * ms) * (-v_n);
    // Closed form; rounding only, 1e-12 relative.
    EXPECT_NEAR(r.normal_force, f_spring + f_damp, 1e-12 * (f_spring + std::abs(f_damp)));
    const double damp_on_i_along_n = dot(r.damping_force_i, kNormal);
    EXPECT_NEAR(damp_on_i_along_n, -f_damp, 1e-12 * std::abs(f_damp));
    // Opposes the relative motion: the damping force on j (= -damping_force_i) has the sign
    // opposite to j's normal velocity relative to i.
    EXPECT_LT(-damp_on_i_along_n * v_n, 0.0) << "v_n = " << v_n;
  }
}

}  // namespace
}  // namespace ringdem

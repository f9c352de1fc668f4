#include "physics/BondTimoshenkoPlastic.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace ringdem {

namespace {

double norm2d(double x, double y) {  // |(x, y)| of O(1) values: no scaling needed (unlike hypot)
  return std::sqrt(x * x + y * y);
}

// The closest-point problem of one step, in the resultants normalised by the plastic limits,
// n = N / N_p and mu_i = M_i / M_p (chord y, z components of the moment at end i = a, b):
//   minimise 1/2 |s - s_tr|_C^2 over s = (n, mu_a, mu_b) subject to t(n, |mu_i|) <= Y,
//   Y = Y0 + w (lambda_a + lambda_b),
// where C is the elastic compliance in these units [J]: c_n on n and [[c_s, c_c], [c_c, c_s]]
// on (mu_a, mu_b), per component (the inverse of the bending rows of K). Optimality (Simo &
// Hughes 1998, ch. 3, several active surfaces):
//   C (s - s_tr) + sum_i lambda_i grad t_i = 0,  lambda_i >= 0,  t_i <= Y,  lambda_i (t_i - Y) = 0.
struct Problem {
  double cn, cs, cc;   ///< compliances [J]
  double w;            ///< dY / dlambda = h / (N_p L0) [1/J]
  double y0;           ///< Y at the start of the step
  double n_tr;         ///< trial n
  double mu_tr[2][2];  ///< trial mu, [end][component]
};

// On the surface t_i = Y the gradient is grad t_i = (2 n, Y mu_i / m_i) / (2 Y - m_i),
// m_i = |mu_i|. With the multipliers nu_i = lambda_i Y / (m_i (2 Y - m_i)) the conditions read
//   (C_mu + diag(nu)) mu = C_mu mu_tr                  (one 2x2 solve per component)
//   n (c_n + 2 S / Y) = c_n n_tr,                      S = sum_i nu_i m_i
//   Y = Y0 + w sum_i nu_i m_i (2 Y - m_i) / Y,         i.e. Y^2 - (Y0 + 2 w S) Y + w Q = 0,
//                                                      Q = sum_i nu_i m_i^2
//   f_i = m_i - (Y - n^2 / Y) = 0 at an active end (t_i = Y), nu_i = 0 at the other.
// Given nu, everything else is explicit, so only f(nu) = 0 is solved, in one or two unknowns.
// In nu the moments only shrink towards the apex mu = 0 as nu grows without bound: the
// iteration never meets the ridge of the surface at mu_i = 0, where grad t is undefined; the
// apex itself is solved in closed form (project()).

// mu(nu) and d mu / d nu: per component c, (mu_a, mu_b)_c = A^-1 C_mu mu_tr,c with
// A = C_mu + diag(nu_a, nu_b), and dA/dnu_j = e_j e_j^T, so d mu / d nu_j = -A^-1 e_j mu_j.
struct Moments {
  double mu[2][2];      ///< [end][component]
  double dmu[2][2][2];  ///< d mu[end][component] / d nu[j]
};

Moments moments(const Problem& pb, const double nu[2]) {
  const double a11 = pb.cs + nu[0], a22 = pb.cs + nu[1], a12 = pb.cc;
  const double inv_det = 1.0 / (a11 * a22 - a12 * a12);
  const double i11 = a22 * inv_det, i22 = a11 * inv_det, i12 = -a12 * inv_det;
  Moments r;
  for (int c = 0; c < 2; ++c) {
    const double ra = pb.cs * pb.mu_tr[0][c] + pb.cc * pb.mu_tr[1][c];
    const double rb = pb.cc * pb.mu_tr[0][c] + pb.cs * pb.mu_tr[1][c];
    const double ma = i11 * ra + i12 * rb, mb = i12 * ra + i22 * rb;
    r.mu[0][c] = ma;
    r.mu[1][c] = mb;
    r.dmu[0][c][0] = -i11 * ma;
    r.dmu[1][c][0] = -i12 * ma;
    r.dmu[0][c][1] = -i12 * mb;
    r.dmu[1][c][1] = -i22 * mb;
  }
  return r;
}

// The state a pair of multipliers gives, the residuals f_i and their derivatives.
struct Eval {
  Moments ms;
  double m[2];       ///< |mu_i|
  double n, y;       ///< axial resultant and yield factor
  double lambda[2];  ///< lambda_a, lambda_b [J]
  double f[2];       ///< m_i - (Y - n^2 / Y)
  double df[2][2];   ///< d f_i / d nu_j
};

Eval evaluate(const Problem& pb, const double nu[2]) {
  Eval e;
  e.ms = moments(pb, nu);
  double dm[2][2];  // d m_i / d nu_j
  for (int i = 0; i < 2; ++i) {
    e.m[i] = norm2d(e.ms.mu[i][0], e.ms.mu[i][1]);
    for (int j = 0; j < 2; ++j)
      dm[i][j] =
          e.m[i] > 0.0
              ? (e.ms.mu[i][0] * e.ms.dmu[i][0][j] + e.ms.mu[i][1] * e.ms.dmu[i][1][j]) / e.m[i]
              : 0.0;
  }
  const double sum = nu[0] * e.m[0] + nu[1] * e.m[1];
  const double sq = nu[0] * e.m[0] * e.m[0] + nu[1] * e.m[1] * e.m[1];
  const double b = pb.y0 + 2.0 * pb.w * sum;
  const double root = std::sqrt(std::max(0.0, b * b - 4.0 * pb.w * sq));  // = 2Y - Y0 - 2wS
  const double y = 0.5 * (b + root);
  const double den = pb.cn * y + 2.0 * sum;
  const double n = pb.cn * pb.n_tr * y / den;
  e.n = n;
  e.y = y;
  for (int i = 0; i < 2; ++i) {
    e.lambda[i] = nu[i] * e.m[i] * (2.0 * y - e.m[i]) / y;  // lambda_i = nu_i m_i (2Y - m_i) / Y
    e.f[i] = e.m[i] - (y - n * n / y);
  }
  for (int j = 0; j < 2; ++j) {
    const double ds = e.m[j] + nu[0] * dm[0][j] + nu[1] * dm[1][j];
    const double dq =
        e.m[j] * e.m[j] + 2.0 * (nu[0] * e.m[0] * dm[0][j] + nu[1] * e.m[1] * dm[1][j]);
    const double dy = root > 0.0 ? pb.w * (2.0 * y * ds - dq) / root : 0.0;
    const double dn = 2.0 * pb.cn * pb.n_tr * (sum * dy - y * ds) / (den * den);
    for (int i = 0; i < 2; ++i)
      e.df[i][j] = dm[i][j] - dy + 2.0 * n * dn / y - n * n * dy / (y * y);
  }
  return e;
}

constexpr int kMaxIterations = 60;

// Newton's method on f_i(nu) = 0 for the active ends (nu_i = 0 at the other), from nu, with a
// backtracking line search on |f|^2 and the multipliers kept above a floor that keeps A
// positive definite. Returns true when converged; `e` is then the state at nu (for accept(),
// which would otherwise evaluate it again).
bool newton(const Problem& pb, const bool active[2], double nu[2], Eval& e,
            int max_iterations = kMaxIterations) {
  const double floor = -0.5 * (pb.cs - std::abs(pb.cc));  // C_mu's eigenvalues: c_s +- c_c
  auto merit = [&](const Eval& x) {
    return (active[0] ? x.f[0] * x.f[0] : 0.0) + (active[1] ? x.f[1] * x.f[1] : 0.0);
  };
  e = evaluate(pb, nu);
  for (int it = 0; it < max_iterations; ++it) {
    // Converged to round-off (f_i is a difference of terms of order Y).
    if (merit(e) <= 1e-28 * e.y * e.y) return true;
    double d[2] = {0.0, 0.0};
    if (active[0] && active[1]) {
      const double det = e.df[0][0] * e.df[1][1] - e.df[0][1] * e.df[1][0];
      if (!(std::abs(det) > 0.0)) return false;
      d[0] = -(e.df[1][1] * e.f[0] - e.df[0][1] * e.f[1]) / det;
      d[1] = -(e.df[0][0] * e.f[1] - e.df[1][0] * e.f[0]) / det;
    } else {
      const int i = active[0] ? 0 : 1;
      if (!(std::abs(e.df[i][i]) > 0.0)) return false;
      d[i] = -e.f[i] / e.df[i][i];
    }
    const double m0 = merit(e);
    double alpha = 1.0;
    for (; alpha > 1e-12; alpha *= 0.5) {
      const double trial[2] = {nu[0] + alpha * d[0], nu[1] + alpha * d[1]};
      if (trial[0] < floor || trial[1] < floor) continue;
      const Eval et = evaluate(pb, trial);
      if (merit(et) <= (1.0 - 1e-4 * alpha) * m0 || merit(et) == 0.0) {
        nu[0] = trial[0];
        nu[1] = trial[1];
        e = et;
        break;
      }
    }
    if (!(alpha > 1e-12)) return false;
    // No root: the multiplier grows without bound (the end alone cannot reach the surface).
    if (std::max(nu[0], nu[1]) > 1e15 * pb.cs) return false;
    const double step = std::max(std::abs(d[0]) / (std::abs(nu[0]) + pb.cs),
                                 std::abs(d[1]) / (std::abs(nu[1]) + pb.cs));
    if (!std::isfinite(step)) return false;
    // Quadratic convergence: after a full step of 1e-10 the error is far below round-off.
    if (alpha == 1.0 && step < 1e-10) return true;
  }
  return false;
}

// Closest point for one trial: s = (n, mu_a, mu_b) and the multipliers lambda_a, lambda_b [J]
// (zero for an end that does not flow). Returns false where Newton's method did not converge.
bool project(const Problem& pb, double s[5], double lambda[2]) {
  const double n_tr = pb.n_tr;
  const double m_tr[2] = {norm2d(pb.mu_tr[0][0], pb.mu_tr[0][1]),
                          norm2d(pb.mu_tr[1][0], pb.mu_tr[1][1])};
  // Apex of full axial yield, N = +-Y N_p, M_a = M_b = 0, in closed form: the axial row gives
  // Lambda = (|n_tr| - Y0) / (1/c_n + w); the moments vanish if the rotations they release,
  // (C mu_tr)_i / M_p, fit the subdifferential of t at mu = 0, a disc of radius 1/2:
  // 2 |(C mu_tr)_i| <= lambda_i for some lambda_a + lambda_b = Lambda.
  const double g[2] = {norm2d(pb.cs * pb.mu_tr[0][0] + pb.cc * pb.mu_tr[1][0],
                              pb.cs * pb.mu_tr[0][1] + pb.cc * pb.mu_tr[1][1]),
                       norm2d(pb.cc * pb.mu_tr[0][0] + pb.cs * pb.mu_tr[1][0],
                              pb.cc * pb.mu_tr[0][1] + pb.cs * pb.mu_tr[1][1])};
  if (std::abs(n_tr) > pb.y0) {
    const double big = (std::abs(n_tr) - pb.y0) / (1.0 / pb.cn + pb.w);
    if (2.0 * (g[0] + g[1]) <= big) {
      s[0] = std::copysign(pb.y0 + pb.w * big, n_tr);
      s[1] = s[2] = s[3] = s[4] = 0.0;
      // Only the sum is defined there; any split with 2 |g_i| <= lambda_i will do.
      const double spare = 0.5 * (big - 2.0 * (g[0] + g[1]));
      lambda[0] = 2.0 * g[0] + spare;
      lambda[1] = 2.0 * g[1] + spare;
      return true;
    }
  }
  // Smooth part. The solution is unique, so exactly one active set satisfies the optimality
  // conditions (multipliers >= 0, an inactive end inside the surface). Active sets are tried
  // as an active-set method adds constraints: each end beyond the surface alone, the most
  // violated first, then both ends, started from the best one-end solution.
  const double tol = 1.0 + BondTimoshenkoPlastic::kYieldTolerance;
  const double t_tr[2] = {BondTimoshenkoPlastic::interaction(n_tr, m_tr[0]),
                          BondTimoshenkoPlastic::interaction(n_tr, m_tr[1])};
  if (!(std::max(t_tr[0], t_tr[1]) > pb.y0 * tol)) {  // inside (a sub-step, see return_map)
    s[0] = n_tr;
    s[1] = pb.mu_tr[0][0];
    s[2] = pb.mu_tr[0][1];
    s[3] = pb.mu_tr[1][0];
    s[4] = pb.mu_tr[1][1];
    lambda[0] = lambda[1] = 0.0;
    return true;
  }
  // The solution of Newton's method on an active set (its state `e` at multipliers nu), if it
  // satisfies the optimality conditions.
  Eval e;
  auto accept = [&](const bool active[2], const double nu[2]) {
    for (int i = 0; i < 2; ++i) {
      if (active[i] ? nu[i] < 0.0 : BondTimoshenkoPlastic::interaction(e.n, e.m[i]) > e.y * tol)
        return false;
    }
    s[0] = e.n;
    s[1] = e.ms.mu[0][0];
    s[2] = e.ms.mu[0][1];
    s[3] = e.ms.mu[1][0];
    s[4] = e.ms.mu[1][1];
    lambda[0] = active[0] ? e.lambda[0] : 0.0;
    lambda[1] = active[1] ? e.lambda[1] : 0.0;
    return true;
  };
  // Both ends beyond: most often both stay on the surface (a step of a bond that flows at both
  // hinges), which a few iterations from nu = 0 find.
  const bool both[2] = {true, true};
  if (t_tr[0] > pb.y0 * tol && t_tr[1] > pb.y0 * tol) {
    double nu[2] = {0.0, 0.0};
    if (newton(pb, both, nu, e, 8) && accept(both, nu)) return true;
  }
  double start[2] = {0.0, 0.0};
  const int first = t_tr[0] >= t_tr[1] ? 0 : 1;
  for (const int i : {first, 1 - first}) {
    if (!(t_tr[i] > pb.y0 * tol)) continue;
    const bool active[2] = {i == 0, i == 1};
    double nu[2] = {0.0, 0.0};
    if (!newton(pb, active, nu, e)) continue;
    if (accept(active, nu)) return true;
    if (start[0] == 0.0 && start[1] == 0.0) std::copy(nu, nu + 2, start);
  }
  // Both ends, from the single-end solution, then from the near-apex estimate: for large
  // multipliers mu_i ~ g_i / nu_i with g_i = (C_mu mu_tr)_i, so sum_i nu_i m_i ~ |g_a| + |g_b|
  // fixes n and Y, both ends sit at m = Y - n^2 / Y, and nu_i ~ |g_i| / m.
  if ((start[0] != 0.0 || start[1] != 0.0) && newton(pb, both, start, e) && accept(both, start))
    return true;
  const double y_apex = pb.y0 + 2.0 * pb.w * (g[0] + g[1]);  // lambda_i ~ 2 nu_i m_i ~ 2 |g_i|
  const double n_apex = pb.cn * n_tr * y_apex / (pb.cn * y_apex + 2.0 * (g[0] + g[1]));
  const double m_apex = y_apex - n_apex * n_apex / y_apex;
  if (m_apex > 0.0) {
    double nu[2] = {g[0] / m_apex, g[1] / m_apex};
    if (newton(pb, both, nu, e) && accept(both, nu)) return true;
  }
  double zero[2] = {0.0, 0.0};
  if (newton(pb, both, zero, e) && accept(both, zero)) return true;
  // Rare: the solution loads only an end that was inside the surface at the trial.
  for (int i = 0; i < 2; ++i) {
    if (t_tr[i] > pb.y0 * tol) continue;
    const bool active[2] = {i == 0, i == 1};
    double nu[2] = {0.0, 0.0};
    if (newton(pb, active, nu, e) && accept(active, nu)) return true;
  }
  return false;
}

}  // namespace

BondTimoshenkoPlastic::Params BondTimoshenkoPlastic::Params::from_wire_bundle(
    int windings, double wire_diameter, double yield_stress, double hardening_ratio,
    double youngs_modulus, double failure_strain) {
  if (windings <= 0 || !(wire_diameter > 0.0) || !(yield_stress > 0.0) || !(youngs_modulus > 0.0))
    throw std::invalid_argument(
        "wire bundle: windings, wire diameter, yield stress and Young's modulus must be positive");
  if (!(hardening_ratio >= 0.0 && hardening_ratio < 1.0))
    throw std::invalid_argument("wire bundle: hardening ratio E_t/E must be in [0, 1), got " +
                                std::to_string(hardening_ratio));
  const double nw = windings, d = wire_diameter, fy = yield_stress;
  Params p;
  p.axial_yield = nw * fy * M_PI * d * d / 4.0;        // area pi d^2 / 4 per wire
  p.plastic_moment = nw * fy * d * d * d / 6.0;        // plastic modulus d^3 / 6 per wire
  p.yield_moment = nw * fy * M_PI * d * d * d / 32.0;  // elastic modulus pi d^3 / 32
  const double plastic_modulus =
      youngs_modulus * hardening_ratio / (1.0 - hardening_ratio);  // E_h = E E_t / (E - E_t)
  p.hardening = plastic_modulus / fy;
  p.failure_strain = failure_strain;
  return p;
}

double BondTimoshenkoPlastic::series_sine(double m, double guess) {
  // s (1 + s^2/6 + 3 s^4/40) = m is monotone in s for s in [0, 1] (the series reaches 1.24 at
  // s = 1). Newton's method converges in a few steps for the elastic rotations (m < 0.2) it is
  // used on, from s = m, and in one or two from the last root of a nearby m.
  double s = std::clamp(guess, 0.0, 1.0);
  for (int it = 0; it < 8; ++it) {
    const double s2 = s * s;
    const double g = s * (1.0 + s2 * (1.0 / 6.0 + s2 * (3.0 / 40.0))) - m;
    const double dg = 1.0 + s2 * (0.5 + s2 * (3.0 / 8.0));
    const double next = std::min(1.0, s - g / dg);
    const bool converged = std::abs(next - s) <= 0x1p-52 * s;  // within an ulp or two
    s = next;
    if (converged) break;
  }
  return s;
}

namespace {

// A turn about `axis` (unit) by an angle of sine `sine` and cosine `cosine`, with 1 - cosine
// computed without cancellation.
struct Turn {
  Vec3 axis;
  double sine = 0.0, cosine = 1.0, versine = 0.0;
  bool past_series_range = false;  ///< no sine maps to |t|: the angle is |t| itself
  double angle = 0.0;              ///< that angle, where past_series_range
};

// The turn the kernel measures as t (BondTimoshenkoPlastic::turn()); `guess` is the sine of a
// nearby turn, or |t| (updated to this one's sine).
Turn measured_turn(const Vec3& t, double& guess) {
  Turn r;
  const double m = norm(t);
  if (!(m > 0.0)) return r;
  r.axis = t / m;
  const double s = BondTimoshenkoPlastic::series_sine(m, guess);
  guess = s;
  if (s < 1.0) {
    r.sine = s;
    r.cosine = std::sqrt((1.0 - s) * (1.0 + s));
    r.versine = s * s / (1.0 + r.cosine);  // 1 - cos = sin^2 / (1 + cos)
  } else {
    r.past_series_range = true;
    r.angle = m;
    r.sine = std::sin(m);
    r.cosine = std::cos(m);
    r.versine = 1.0 - r.cosine;
  }
  return r;
}

// z component of R y, R the turn: Rodrigues, R y = y cos + (k x y) sin + k (k . y)(1 - cos),
// with k x y = (-k_z, 0, k_x).
double y_axis_height(const Turn& r) {
  return r.axis.x * r.sine + r.axis.z * r.axis.y * r.versine;
}

}  // namespace

Quat BondTimoshenkoPlastic::turn(const Vec3& t) {
  double guess = norm(t);
  const Turn r = measured_turn(t, guess);
  if (r.past_series_range) return quat_from_rotation_vector(r.axis * r.angle);
  if (r.sine == 0.0) return Quat{};
  // Half angles of an angle in [0, pi/2]: cos(a/2) = sqrt((1 + cos a) / 2), sin(a/2) =
  // sin a / (2 cos(a/2)).
  const double w = std::sqrt(0.5 * (1.0 + r.cosine));
  const double half_sine = 0.5 * r.sine / w;
  return {w, r.axis.x * half_sine, r.axis.y * half_sine, r.axis.z * half_sine};
}

double BondTimoshenkoPlastic::bisector_twist(const BondTimoshenko::LocalRotation& ta,
                                             const BondTimoshenko::LocalRotation& tb) {
  double guess_a = norm(Vec3{ta.x, ta.y, ta.z});
  double guess_b = norm(Vec3{tb.x, tb.y, tb.z});
  const auto height = [&](double twist) {
    return y_axis_height(measured_turn({ta.x + twist, ta.y, ta.z}, guess_a)) +
           y_axis_height(measured_turn({tb.x + twist, tb.y, tb.z}, guess_b));
  };
  double d0 = 0.0, z0 = height(d0);
  if (z0 == 0.0) return d0;
  double d1 = -0.5 * z0, z1 = height(d1);
  // Converged when a step is below 1e-16 rad: a tilt of the bisector far under the
  // kernel's round-off (z itself is only known to ~1e-17, so steps of round-off size go on
  // without end).
  for (int it = 0; it < 8 && z1 != 0.0 && z1 != z0; ++it) {
    const double d2 = d1 - z1 * (d1 - d0) / (z1 - z0);
    const bool converged = std::abs(d2 - d1) <= 1e-16;
    d0 = d1;
    z0 = z1;
    d1 = d2;
    if (converged) break;
    z1 = height(d1);
  }
  return d1;
}

double BondTimoshenkoPlastic::yield_ratio(const Params& p, const State& st,
                                          const BondTimoshenko::Result& r) {
  const double n = r.axial_force / p.axial_yield;
  return std::max(interaction(n, r.bending_a / p.plastic_moment),
                  interaction(n, r.bending_b / p.plastic_moment)) /
         yield_factor(p, st);
}

BondTimoshenkoPlastic::Return BondTimoshenkoPlastic::return_map(const Section& s, const Params& p,
                                                                const Deformation& q, State& st,
                                                                double& work) {
  const double np = p.axial_yield, mp = p.plastic_moment;
  const double ks = s.k_bend_self, kc = s.k_bend_cross;
  const double det = ks * ks - kc * kc;  // > 0: (ks - kc)(ks + kc) = (2 + 2 Phi) c/L * 6 c/L
  Problem pb;
  pb.cn = np * np / s.k_axial;
  pb.cs = mp * mp * ks / det;
  pb.cc = -mp * mp * kc / det;
  pb.w = p.hardening / (np * s.length0);
  pb.y0 = yield_factor(p, st);

  // Trial: the elastic predictor with the plastic deformations of the last step (the
  // rotations' in the end frames already).
  const EndLoads f = BondTimoshenko::end_loads(s, elastic_part(q, st));
  pb.n_tr = f.fx_b / np;
  pb.mu_tr[0][0] = f.my_a / mp;
  pb.mu_tr[0][1] = f.mz_a / mp;
  pb.mu_tr[1][0] = f.my_b / mp;
  pb.mu_tr[1][1] = f.mz_b / mp;

  // One closest-point step from the trial. Should Newton's method not converge, the trial
  // increment is split: its elastic share up to the surface, then 2, 4, ... equal sub-steps
  // along the same straight path in the resultants, each a closest-point return from where
  // the previous one ended.
  double sol[5] = {};
  double lambda[2] = {0.0, 0.0};
  bool scaled = false;  // the last resort below: kappa then follows from the work
  if (!project(pb, sol, lambda)) {
    const double alpha =
        pb.y0 / std::max(interaction(pb.n_tr, norm2d(pb.mu_tr[0][0], pb.mu_tr[0][1])),
                         interaction(pb.n_tr, norm2d(pb.mu_tr[1][0], pb.mu_tr[1][1])));
    const double tr[5] = {pb.n_tr, pb.mu_tr[0][0], pb.mu_tr[0][1], pb.mu_tr[1][0], pb.mu_tr[1][1]};
    bool done = false;
    for (int parts = 2; !done && parts <= 1024; parts *= 2) {
      double cur[5];
      for (int k = 0; k < 5; ++k)
        cur[k] = alpha * tr[k];
      double sum[2] = {0.0, 0.0};
      done = true;
      for (int part = 0; part < parts && done; ++part) {
        Problem sub = pb;
        sub.y0 = pb.y0 + pb.w * (sum[0] + sum[1]);
        const double share = (1.0 - alpha) / parts;
        sub.n_tr = cur[0] + share * tr[0];
        for (int k = 0; k < 4; ++k)
          sub.mu_tr[k / 2][k % 2] = cur[1 + k] + share * tr[1 + k];
        double lam[2] = {0.0, 0.0};
        done = project(sub, cur, lam);
        sum[0] += lam[0];
        sum[1] += lam[1];
      }
      if (done) {
        std::copy(cur, cur + 5, sol);
        std::copy(sum, sum + 2, lambda);
      }
    }
    if (!done) {
      // Not met in the tests (10^5 random steps of up to 200 times the yield deformation);
      // keeps the step admissible all the same: the trial scaled back onto the surface.
      for (int k = 0; k < 5; ++k)
        sol[k] = alpha * tr[k];
      lambda[0] = lambda[1] = 1.0;  // both ends move (kappa from the work, below)
      scaled = true;
    }
  }

  // New elastic deformation C s, hence the plastic increments: the trial minus C s (torsion
  // stays elastic). An end that did not flow keeps its trial rotation to the bit (C (s_tr - s)
  // vanishes there, up to round-off), and its frame is left as it is.
  const State start = st;
  State next = start;
  next.elongation = q.du - sol[0] * np / s.k_axial;
  Return ret;
  ret.elastic = {q.du - next.elongation, q.ta, q.tb};
  ret.hinge_a = lambda[0] > 0.0;
  ret.hinge_b = lambda[1] > 0.0;
  if (ret.hinge_a) {
    ret.elastic.ta.y = (pb.cs * sol[1] + pb.cc * sol[3]) / mp;
    ret.elastic.ta.z = (pb.cs * sol[2] + pb.cc * sol[4]) / mp;
  }
  if (ret.hinge_b) {
    ret.elastic.tb.y = (pb.cc * sol[1] + pb.cs * sol[3]) / mp;
    ret.elastic.tb.z = (pb.cc * sol[2] + pb.cs * sol[4]) / mp;
  }
  // dkappa = sum_i lambda_i / (N_p L0)
  next.strain = start.strain + (lambda[0] + lambda[1]) / (np * s.length0);

  // Plastic work of the step, s_{n+1} . (q_p,n+1 - q_p,n) (backward Euler), with the loads K
  // acts with from now on; the plastic rotation increments are the trial minus the elastic.
  const Deformation& e = ret.elastic;
  const EndLoads g = BondTimoshenko::end_loads(s, e);
  work = g.fx_b * (next.elongation - start.elongation) + g.my_a * (q.ta.y - e.ta.y) +
         g.mz_a * (q.ta.z - e.ta.z) + g.my_b * (q.tb.y - e.tb.y) + g.mz_b * (q.tb.z - e.tb.z);
  if (scaled) next.strain = start.strain + std::max(0.0, work) / (pb.y0 * np * s.length0);
  next.work = start.work + work;
  st = next;
  return ret;
}

}  // namespace ringdem

#include "physics/RingMesh.hpp"

#include <algorithm>
#include <cmath>

namespace ringdem {

RingMesh::Plane RingMesh::plane(const Vec3* bead, std::size_t n) {
  Plane pl;
  Vec3 sum;
  for (std::size_t i = 0; i < n; ++i)
    sum += bead[i];
  pl.centre = sum / static_cast<double>(n);
  // A = 1/2 sum_i q_i x q_(i+1): the polygon's vector area (Eq. M1's normal)
  Vec3 area;
  double reach2 = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 q = bead[i] - pl.centre;
    const Vec3 q_next = bead[i + 1 == n ? 0 : i + 1] - pl.centre;
    area += cross(q, q_next);
    reach2 = std::max(reach2, norm2(q));
  }
  area *= 0.5;
  pl.area = norm(area);
  pl.normal = pl.area > 0.0 ? area / pl.area : Vec3{};
  pl.reach = std::sqrt(reach2);
  pl.radius = std::sqrt(pl.area / M_PI);
  return pl;
}

RingMesh::Motion RingMesh::motion(const Vec3* bead_position, const Vec3* bead_velocity,
                                  std::size_t n) {
  Motion m;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3& before = bead_position[i == 0 ? n - 1 : i - 1];
    const Vec3& after = bead_position[i + 1 == n ? 0 : i + 1];
    m.velocity_sum += bead_velocity[i];
    m.chord_moment += cross(before - after, bead_velocity[i]);
  }
  return m;
}

RingMesh::Band RingMesh::band(const Vec3* bead, std::size_t n, const Plane& plane, double move) {
  Band b;
  if (!(plane.area > 0.0)) {
    b.offset = 2.0 * move;
    b.tilt = 2.0;  // a unit normal turns by at most 2
    return b;
  }
  double spans = 0.0;  // sum_i |b_(i+1) - b_(i-1)|
  for (std::size_t i = 0; i < n; ++i)
    spans += norm(bead[(i + 1) % n] - bead[(i + n - 1) % n]);
  const double area_change = 0.5 * move * spans + 0.5 * static_cast<double>(n) * move * move;
  // A thousandth more for the rounding of the sums above.
  b.offset = 2.0 * move * 1.001;
  b.tilt = std::min(2.0, 2.0 * area_change / plane.area) * 1.001;
  return b;
}

bool RingMesh::compute(const Params& params, const Plane& plane, const Motion& motion,
                       const Input& in, Output& out, BeadLoads& bead_force,
                       BeadLoads& bead_damping) {
  if (!(plane.area > 0.0)) return false;
  const Vec3& n = plane.normal;
  const Vec3 e = in.position - plane.centre;
  const double d = dot(e, n);
  const double overlap = in.radius - std::abs(d);  // Eq. M1
  if (overlap <= 0.0) return false;
  const Vec3 e_perp = e - n * d;
  const double rho = norm(e_perp);
  const double a = plane.radius;
  const double width = std::min(in.radius, 0.5 * a);
  const double t = (a - rho) / width;
  if (t <= 0.0) return false;
  // The fade at the rim: s = S(t), S(t) = 3 t^2 - 2 t^3, and S'(t) (Eq. M1)
  const double weight = t >= 1.0 ? 1.0 : t * t * (3.0 - 2.0 * t);
  const double slope = t >= 1.0 ? 0.0 : 6.0 * t * (1.0 - t);
  // Eq. M3: g_i = d(d)/d(p_i) = -n / N + 1/2 w x c_i, w = e_perp / |A|; with Eq. M6,
  // d' = n . v + sum_i g_i . v_i = n . (v - V / N) + 1/2 w . K.
  const Vec3 w = e_perp / plane.area;
  const double inv_n = 1.0 / static_cast<double>(in.n);
  const double d_rate =
      dot(n, in.velocity - motion.velocity_sum * inv_n) + 0.5 * dot(w, motion.chord_moment);
  const double side = d >= 0.0 ? 1.0 : -1.0;
  const double overlap_rate = -side * d_rate;
  // Eq. M5: a spring and a dashpot along the gradient of delta, never pulling
  const double k = params.stiffness;
  const double viscous = 2.0 * params.damping_ratio * std::sqrt(k * in.m_star);
  const double elastic = k * weight * overlap;
  const double normal = std::max(0.0, elastic + viscous * weight * overlap_rate);
  const double damping = normal - elastic;
  // Eq. M4: minus the gradient of E through s: L (d(rho) - d(a)) with L = k delta^2 S' / (2 w);
  // L / rho is taken only in the fade, where rho > a - w > 0.
  const double fade = 0.5 * k * overlap * overlap * slope / width;
  const double fade_per_rho = fade > 0.0 ? fade / rho : 0.0;
  out.overlap = overlap;
  out.weight = weight;
  out.elastic_energy = 0.5 * k * weight * overlap * overlap;
  out.outward = n * side;
  out.damping = n * (side * damping);
  out.force = n * (side * normal);
  if (fade > 0.0) out.force += e_perp * fade_per_rho;
  // The beads' loads of Eq. M4 in the form of Eq. M6: f sigma g_i gives -f sigma n / N and
  // 1/2 f sigma w x c_i; L d(rho)/d(p_i) gives -L (e_perp / N + 1/2 d w x c_i) / rho (its
  // -n / N part cancels d n / N of e / N); L d(a)/d(p_i) gives n x c_i L / (4 pi a).
  const double pushed = side * normal;
  bead_force.uniform = (n * pushed + e_perp * fade_per_rho) * (-inv_n);
  bead_force.turning = w * (0.5 * (pushed - fade_per_rho * d)) - n * (fade / (4.0 * M_PI * a));
  bead_damping.uniform = n * (-side * damping * inv_n);
  bead_damping.turning = w * (0.5 * side * damping);
  return true;
}

double RingMesh::time_step_limit(double stiffness, double grain_mass, double ring_mass) {
  return std::sqrt(1.0 / (4.0 * stiffness * (1.0 / grain_mass + 3.0 / ring_mass)));
}

}  // namespace ringdem

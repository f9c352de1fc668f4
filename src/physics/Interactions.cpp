#include "physics/Interactions.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <tuple>
#include <unordered_map>

#include "physics/HertzMindlin.hpp"

namespace ringdem {

namespace {

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

// Rigid bodies sort after every particle partner in the gather order.
constexpr std::int64_t kBodyKeyBase = std::int64_t{1} << 62;

/// The orientation a particle had one step earlier: the inverse of the integrator's Cayley
/// update q <- dq(omega dt) q (Integrator.cpp), which dq(-omega dt) undoes.
inline Quat rotated_back(const Quat& q, const Vec3& omega, double dt) {
  const Vec3 h = omega * (-0.5 * dt);
  const double s = 1.0 / std::sqrt(1.0 + norm2(h));
  return renormalized(Quat{s, h.x * s, h.y * s, h.z * s} * q);
}

inline double effective_mass(double m_a, Motion motion_a, double m_b, Motion motion_b) {
  const bool inf_a = motion_a != Motion::kFree;
  const bool inf_b = motion_b != Motion::kFree;
  if (inf_a && inf_b) return 0.5 * (m_a + m_b);  // two driven particles: damping irrelevant
  if (inf_a) return m_b;
  if (inf_b) return m_a;
  return m_a * m_b / (m_a + m_b);
}

}  // namespace

ContactHistory Interactions::export_history() const {
  ContactHistory out;
  for (std::size_t m = 0; m < pairs_.size(); ++m)
    if (norm2(pair_spring_[m]) > 0.0)
      out.push_back({ContactHistoryEntry::Partner::kParticle, pair_gid_a_[m], pair_gid_b_[m],
                     pair_spring_[m]});
  for (std::size_t w = 0; w < wall_particle_.size(); ++w)
    if (norm2(wall_spring_[w]) > 0.0)
      out.push_back(
          {ContactHistoryEntry::Partner::kRigidBody, wall_gid_[w], wall_body_[w], wall_spring_[w]});
  return out;
}

void Interactions::rebuild(const ParticleStore& p, BondStore& bonds,
                           const std::vector<RigidBody>& bodies, double skin,
                           const ContactHistory& history) {
  const std::size_t n_total = p.n_total();
  const std::size_t n_local = p.n_local();

  // Bond ends and the exclusion lists (intact bonds only: a broken pair may touch).
  std::vector<std::uint32_t> count(n_total + 1, 0);
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    const std::int64_t ia = p.index_of(bonds.gid_a[k]);
    const std::int64_t ib = p.index_of(bonds.gid_b[k]);
    // An intact bond has both ends here (block width >= bond length). The ends of a broken
    // bond drift apart: a missing end borrows the other's index, which the bond loop only
    // reads and then masks.
    if ((ia < 0 || ib < 0) && (!bonds.broken[k] || (ia < 0 && ib < 0)))
      throw std::runtime_error("bond " + std::to_string(bonds.gid_a[k]) + "-" +
                               std::to_string(bonds.gid_b[k]) + " has an end this rank lacks");
    bonds.index_a[k] = static_cast<std::uint32_t>(ia >= 0 ? ia : ib);
    bonds.index_b[k] = static_cast<std::uint32_t>(ib >= 0 ? ib : ia);
    if (!bonds.broken[k]) {
      ++count[ia + 1];
      ++count[ib + 1];
    }
  }
  exclusions_.offset.assign(n_total + 1, 0);
  for (std::size_t k = 0; k < n_total; ++k)
    exclusions_.offset[k + 1] = exclusions_.offset[k] + count[k + 1];
  exclusions_.partner_gid.assign(exclusions_.offset[n_total], 0);
  {
    std::vector<std::uint32_t> fill(exclusions_.offset.begin(), exclusions_.offset.end() - 1);
    for (std::size_t k = 0; k < bonds.size(); ++k) {
      if (bonds.broken[k]) continue;
      exclusions_.partner_gid[fill[bonds.index_a[k]]++] = bonds.gid_b[k];
      exclusions_.partner_gid[fill[bonds.index_b[k]]++] = bonds.gid_a[k];
    }
  }

  // Carried tangential springs, by gid pair (particle pairs) or (gid, body) (rigid bodies).
  std::unordered_map<PairKey, Vec3, PairKeyHash> old_springs, old_wall_springs;
  for (const auto& h : history)
    (h.partner_kind == ContactHistoryEntry::Partner::kParticle ? old_springs : old_wall_springs)
        .emplace(PairKey{h.gid, h.partner}, h.spring);

  search_.build(p, skin, exclusions_, pairs_);
  pair_spring_.assign(pairs_.size(), Vec3{});
  pair_gid_a_.resize(pairs_.size());
  pair_gid_b_.resize(pairs_.size());
  for (std::size_t m = 0; m < pairs_.size(); ++m) {
    pair_gid_a_[m] = p.gid[pairs_.i[m]];
    pair_gid_b_[m] = p.gid[pairs_.j[m]];
    const auto it = old_springs.find(PairKey{pair_gid_a_[m], pair_gid_b_[m]});
    if (it != old_springs.end()) pair_spring_[m] = it->second;
  }

  // Particle–rigid-body candidates (owned particles only).
  wall_particle_.clear();
  wall_body_.clear();
  wall_gid_.clear();
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (std::size_t k = 0; k < n_local; ++k)
      if (bodies[b].closest(p.position[k]).distance < p.radius[k] + skin) {
        wall_particle_.push_back(static_cast<std::uint32_t>(k));
        wall_body_.push_back(static_cast<std::uint32_t>(b));
        wall_gid_.push_back(p.gid[k]);
      }
  wall_spring_.assign(wall_particle_.size(), Vec3{});
  for (std::size_t w = 0; w < wall_particle_.size(); ++w) {
    const auto it = old_wall_springs.find(PairKey{wall_gid_[w], wall_body_[w]});
    if (it != old_wall_springs.end()) wall_spring_[w] = it->second;
  }

  const std::size_t nb = bonds.size();
  const std::size_t np = pairs_.size();
  const std::size_t nw = wall_particle_.size();
  slots_.assign(2 * nb + 2 * np + nw);

  // Gather map: for each owned particle, its slots ordered by (partner key, kind).
  struct Entry {
    std::uint32_t particle;
    std::int64_t key;
    std::uint32_t kind;
    std::uint32_t slot;
  };
  std::vector<Entry> entries;
  entries.reserve(slots_.size());
  auto add = [&](std::uint32_t particle, std::int64_t key, std::uint32_t kind, std::size_t slot) {
    if (particle < n_local)
      entries.push_back({particle, key, kind, static_cast<std::uint32_t>(slot)});
  };
  for (std::size_t k = 0; k < nb; ++k) {
    if (bonds.broken[k]) continue;  // exerts nothing; a bond breaking later forces a rebuild
    add(bonds.index_a[k], bonds.gid_b[k], 0, k);
    add(bonds.index_b[k], bonds.gid_a[k], 0, nb + k);
  }
  for (std::size_t m = 0; m < np; ++m) {
    add(pairs_.i[m], p.gid[pairs_.j[m]], 1, 2 * nb + m);
    add(pairs_.j[m], p.gid[pairs_.i[m]], 1, 2 * nb + np + m);
  }
  for (std::size_t w = 0; w < nw; ++w)
    add(wall_particle_[w], kBodyKeyBase + wall_body_[w], 2, 2 * nb + 2 * np + w);
  std::sort(entries.begin(), entries.end(), [](const Entry& x, const Entry& y) {
    return std::tie(x.particle, x.key, x.kind) < std::tie(y.particle, y.key, y.kind);
  });
  gather_offset_.assign(n_local + 1, 0);
  gather_slot_.resize(entries.size());
  for (std::size_t e = 0; e < entries.size(); ++e) {
    ++gather_offset_[entries[e].particle + 1];
    gather_slot_[e] = entries[e].slot;
  }
  for (std::size_t k = 0; k < n_local; ++k)
    gather_offset_[k + 1] += gather_offset_[k];

  // Energy ledger: the owned particles with contact slots (in gather order) or driven motion.
  ledger_particle_.clear();
  ledger_offset_.assign(1, 0);
  ledger_slot_.clear();
  for (std::size_t e = 0, k = 0; k < n_local; ++k) {
    const std::size_t first = ledger_slot_.size();
    for (; e < entries.size() && entries[e].particle == k; ++e)
      if (entries[e].kind != 0) ledger_slot_.push_back(entries[e].slot);
    if (ledger_slot_.size() > first || p.motion[k] != Motion::kFree) {
      ledger_particle_.push_back(static_cast<std::uint32_t>(k));
      ledger_offset_.push_back(static_cast<std::uint32_t>(ledger_slot_.size()));
    }
  }
  // The contact kernel writes each record where the ledger pass reads it, so that pass reads
  // one contiguous stream.
  work_.assign(ledger_slot_.size() + 1, ContactWork{});
  work_index_.assign(2 * np + nw, static_cast<std::uint32_t>(ledger_slot_.size()));
  for (std::size_t e = 0; e < ledger_slot_.size(); ++e)
    work_index_[ledger_slot_[e] - 2 * nb] = static_cast<std::uint32_t>(e);
  ledger_list_changed_ = true;
}

void Interactions::compute_bonds(const ParticleStore& p, BondStore& bonds, double time, double dt) {
  bonds_broke_ = false;
  const std::size_t nb = bonds.size();
  bond_failed_.resize(nb);
  // Bonds (physics.md §1): forces and the failure test of Eq. 3–5 every step, written so the
  // loop vectorises: bond data in contiguous arrays, particle data gathered by index, no
  // branches (broken or failing bonds are masked to zero force). Output quantities are
  // recomputed on demand by update_bond_diagnostics().
  const Vec3* const pos = p.position.data();
  const Quat* const rot = p.orientation.data();
  const std::uint32_t* const ia = bonds.index_a.data();
  const std::uint32_t* const ib = bonds.index_b.data();
  const std::uint8_t* const broken = bonds.broken.data();
  std::uint8_t* __restrict__ const failed = bond_failed_.data();
  double* __restrict__ const fx = slots_.fx.data();
  double* __restrict__ const fy = slots_.fy.data();
  double* __restrict__ const fz = slots_.fz.data();
  double* __restrict__ const tx = slots_.tx.data();
  double* __restrict__ const ty = slots_.ty.data();
  double* __restrict__ const tz = slots_.tz.data();
  // Raw pointers, read once: the vectoriser needs loop-invariant bases it can prove.
  const double* const l0 = bonds.length0.data();
  const double* const k_ax = bonds.k_axial.data();
  const double* const k_tor = bonds.k_torsion.data();
  const double* const k_self = bonds.k_bend_self.data();
  const double* const k_cross = bonds.k_bend_cross.data();
  const double* const inv_area = bonds.inv_area.data();
  const double* const bend_factor = bonds.bend_factor.data();
  const Quat* const frame_a = bonds.frame_a.data();
  const Quat* const frame_b = bonds.frame_b.data();
  const double* const sigma_t = bonds.tensile_strength.data();
  const double* const sigma_c = bonds.compressive_strength.data();
  const double* const tau = bonds.shear_strength.data();
  // Bonds in chunks: a scalar pass copies the end particles' positions and orientations
  // into contiguous scratch arrays, so the vector loop that follows loads everything
  // contiguously instead of gathering it element by element.
  constexpr std::size_t kChunk = 256;
  BondScratch& g = bond_scratch_;
  for (std::size_t start = 0; start < nb; start += kChunk) {
    const std::size_t n = std::min(kChunk, nb - start);
    for (std::size_t c = 0; c < n; ++c) {
      const Vec3& xa = pos[ia[start + c]];
      const Vec3& xb = pos[ib[start + c]];
      const Quat& qa = rot[ia[start + c]];
      const Quat& qb = rot[ib[start + c]];
      g.xa[0][c] = xa.x, g.xa[1][c] = xa.y, g.xa[2][c] = xa.z;
      g.xb[0][c] = xb.x, g.xb[1][c] = xb.y, g.xb[2][c] = xb.z;
      g.qa[0][c] = qa.w, g.qa[1][c] = qa.x, g.qa[2][c] = qa.y, g.qa[3][c] = qa.z;
      g.qb[0][c] = qb.w, g.qb[1][c] = qb.x, g.qb[2][c] = qb.y, g.qb[3][c] = qb.z;
    }
#pragma GCC ivdep
    for (std::size_t c = 0; c < n; ++c) {
      const std::size_t k = start + c;
      BondTimoshenko::Section sec;
      sec.length0 = l0[k];
      sec.k_axial = k_ax[k];
      sec.k_torsion = k_tor[k];
      sec.k_bend_self = k_self[k];
      sec.k_bend_cross = k_cross[k];
      sec.inv_area = inv_area[k];
      sec.bend_factor = bend_factor[k];
      const BondTimoshenko::Reference ref{frame_a[k], frame_b[k]};
      const auto r = BondTimoshenko::compute(sec, ref, Vec3{g.xa[0][c], g.xa[1][c], g.xa[2][c]},
                                             Quat{g.qa[0][c], g.qa[1][c], g.qa[2][c], g.qa[3][c]},
                                             Vec3{g.xb[0][c], g.xb[1][c], g.xb[2][c]},
                                             Quat{g.qb[0][c], g.qb[1][c], g.qb[2][c], g.qb[3][c]});
      const auto st = BondTimoshenko::stresses(sec, r);
      const int fails =
          (st.tensile > sigma_t[k]) | (st.compressive > sigma_c[k]) | (st.shear > tau[k]);
      failed[k] = static_cast<std::uint8_t>(fails & (broken[k] == 0));
      // A select, not a product: a broken bond's state may be NaN (ends far apart or borrowed).
      const bool keep = !(fails | broken[k]);
      fx[k] = keep ? r.force_a.x : 0.0;
      fy[k] = keep ? r.force_a.y : 0.0;
      fz[k] = keep ? r.force_a.z : 0.0;
      tx[k] = keep ? r.torque_a.x : 0.0;
      ty[k] = keep ? r.torque_a.y : 0.0;
      tz[k] = keep ? r.torque_a.z : 0.0;
      fx[nb + k] = keep ? r.force_b.x : 0.0;
      fy[nb + k] = keep ? r.force_b.y : 0.0;
      fz[nb + k] = keep ? r.force_b.z : 0.0;
      tx[nb + k] = keep ? r.torque_b.x : 0.0;
      ty[nb + k] = keep ? r.torque_b.y : 0.0;
      tz[nb + k] = keep ? r.torque_b.z : 0.0;
    }
  }
  if (std::find(bond_failed_.begin(), bond_failed_.end(), 1) == bond_failed_.end()) return;
  for (std::size_t k = 0; k < nb; ++k) {
    if (!failed[k]) continue;
    const auto r = BondTimoshenko::compute(bonds.section(k), bonds.reference(k), pos[ia[k]],
                                           rot[ia[k]], pos[ib[k]], rot[ib[k]]);
    bonds.broken[k] = 1;
    bonds.failure[k] = BondTimoshenko::check_failure(BondTimoshenko::stresses(bonds.section(k), r),
                                                     bonds.strength(k));
    bonds.break_time[k] = time;
    // Energy ledger: the bond's force acted through the first half of this step and is zero
    // from this evaluation on, so the energy it takes out of the books is its mean over the
    // step (trapezoid; second order, docs/physics.md "Energy ledger"). The start of the step
    // is x - v dt, q rotated back by omega dt (the mid-step velocities the drift used).
    const std::uint32_t a = ia[k], b = ib[k];
    const auto r0 =
        BondTimoshenko::compute(bonds.section(k), bonds.reference(k), pos[a] - p.velocity[a] * dt,
                                rotated_back(rot[a], p.omega[a], dt), pos[b] - p.velocity[b] * dt,
                                rotated_back(rot[b], p.omega[b], dt));
    bonds.break_energy[k] = 0.5 * (r0.energy + r.energy);
    bonds_broke_ = true;
  }
}

double Interactions::update_bond_diagnostics(const ParticleStore& p, BondStore& bonds) const {
  double total = 0.0;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (bonds.broken[k]) {
      bonds.axial_force[k] = bonds.bending_moment[k] = bonds.utilisation[k] = 0.0;
      bonds.energy[k] = 0.0;
      continue;
    }
    const std::uint32_t a = bonds.index_a[k];
    const std::uint32_t b = bonds.index_b[k];
    const auto r = BondTimoshenko::compute(bonds.section(k), bonds.reference(k), p.position[a],
                                           p.orientation[a], p.position[b], p.orientation[b]);
    bonds.axial_force[k] = r.axial_force;
    bonds.bending_moment[k] = std::max(r.bending_a, r.bending_b);
    bonds.utilisation[k] = BondTimoshenko::utilisation(
        BondTimoshenko::stresses(bonds.section(k), r), bonds.strength(k));
    bonds.energy[k] = r.energy;
    total += r.energy;
  }
  return total;
}

void Interactions::compute_contacts(const ParticleStore& p, std::vector<RigidBody>& bodies,
                                    const MaterialTable& materials, double dt) {
  contact_energy_ = 0.0;
  // Particle contacts (physics.md §3).
  const std::size_t np = pairs_.size();
  const std::size_t base = slots_.size() - 2 * np - wall_particle_.size();
  for (std::size_t m = 0; m < np; ++m) {
    const std::uint32_t a = pairs_.i[m];
    const std::uint32_t b = pairs_.j[m];
    const std::size_t slot_a = base + m;
    const std::size_t slot_b = base + np + m;
    const Vec3 d = p.position[b] - p.position[a];
    const double reach = p.radius[a] + p.radius[b];
    const double dist2 = norm2(d);
    if (dist2 >= reach * reach) {
      pair_spring_[m] = {};
      slots_.set(slot_a, {}, {});
      slots_.set(slot_b, {}, {});
      work_[work_index_[m]] = {};
      work_[work_index_[np + m]] = {};
      continue;
    }
    const double dist = std::sqrt(dist2);
    const Vec3 n = d / dist;
    const double overlap = reach - dist;
    const double arm_a = p.radius[a] - 0.5 * overlap;
    const double arm_b = p.radius[b] - 0.5 * overlap;
    HertzMindlin::Input in;
    in.normal = n;
    in.overlap = overlap;
    in.r_star = p.radius[a] * p.radius[b] / reach;
    in.m_star = effective_mass(p.mass[a], p.motion[a], p.mass[b], p.motion[b]);
    in.v_rel = (p.velocity[b] + cross(p.omega[b], n * (-arm_b))) -
               (p.velocity[a] + cross(p.omega[a], n * arm_a));
    in.dt = dt;
    in.arm_i = arm_a;
    in.arm_j = arm_b;
    in.omega_i = p.omega[a];
    in.omega_j = p.omega[b];
    const auto r =
        HertzMindlin::compute(materials.pair(p.material[a], p.material[b]), in, pair_spring_[m]);
    slots_.set(slot_a, r.force_i, cross(n * arm_a, r.force_i) + r.rolling_torque_i);
    slots_.set(slot_b, -r.force_i, cross(n * arm_b, r.force_i) + r.rolling_torque_j);
    // Ledger: each end's loads; the tangential energy half to each end.
    const Vec3& spring = pair_spring_[m];
    work_[work_index_[m]] = {
        r.damping_force_i,     spring, n * arm_a, r.rolling_torque_i, 0.5 * r.tangential_energy,
        0.5 * r.elastic_energy};
    work_[work_index_[np + m]] = {
        -r.damping_force_i,    -spring, n * (-arm_b), r.rolling_torque_j, 0.5 * r.tangential_energy,
        0.5 * r.elastic_energy};
    if (a < p.n_local()) contact_energy_ += r.elastic_energy;  // once, by the owner of a
  }

  // Particle–rigid-body contacts; the body load is summed in (body, particle gid) order.
  for (auto& body : bodies) {
    body.force = {};
    body.torque = {};
  }
  body_loads_.clear();
  const std::size_t wbase = base + 2 * np;
  for (std::size_t w = 0; w < wall_particle_.size(); ++w) {
    const std::uint32_t k = wall_particle_[w];
    RigidBody& body = bodies[wall_body_[w]];
    const auto sp = body.closest(p.position[k]);
    const double overlap = p.radius[k] - sp.distance;
    if (overlap <= 0.0) {
      wall_spring_[w] = {};
      slots_.set(wbase + w, {}, {});
      work_[work_index_[2 * np + w]] = {};
      continue;
    }
    const Vec3 n = -sp.normal;  // from the particle to the body
    const double arm = p.radius[k] - 0.5 * overlap;
    const Vec3 contact = p.position[k] + n * arm;
    const double r_body = body.contact_radius();
    HertzMindlin::Input in;
    in.normal = n;
    in.overlap = overlap;
    in.r_star = std::isinf(r_body) ? p.radius[k] : p.radius[k] * r_body / (p.radius[k] + r_body);
    in.m_star =
        body.has_finite_mass() ? p.mass[k] * body.mass / (p.mass[k] + body.mass) : p.mass[k];
    in.v_rel = body.velocity_at(contact) - (p.velocity[k] + cross(p.omega[k], n * arm));
    in.dt = dt;
    in.arm_i = arm;
    in.arm_j = 0.0;
    in.omega_i = p.omega[k];
    in.omega_j = body.omega;
    const auto r =
        HertzMindlin::compute(materials.pair(p.material[k], body.material), in, wall_spring_[w]);
    slots_.set(wbase + w, r.force_i, cross(n * arm, r.force_i) + r.rolling_torque_i);
    work_[work_index_[2 * np + w]] = {r.damping_force_i,  wall_spring_[w],     n * arm,
                                      r.rolling_torque_i, r.tangential_energy, r.elastic_energy};
    const Vec3 torque_on_body = cross(contact - body.position, -r.force_i);
    body.force -= r.force_i;
    body.torque += torque_on_body;
    body_loads_.push_back(
        {p.gid[k], static_cast<std::int32_t>(wall_body_[w]), -r.force_i, torque_on_body});
    contact_energy_ += r.elastic_energy;
  }
}

void Interactions::gather(ParticleStore& p, const Vec3& gravity) {
  const std::size_t n_local = p.n_local();
  // Raw pointers, read once (nothing in the loop can move them).
  const double* const mass = p.mass.data();
  const Vec3* const external = p.external_force.data();
  Vec3* const force = p.force.data();
  Vec3* const torque = p.torque.data();
  const std::uint32_t* const offset = gather_offset_.data();
  const std::uint32_t* const slot = gather_slot_.data();
  const double *const fx = slots_.fx.data(), *const fy = slots_.fy.data(),
                      *const fz = slots_.fz.data();
  const double *const tx = slots_.tx.data(), *const ty = slots_.ty.data(),
                      *const tz = slots_.tz.data();
  bool any_external = false;
  for (std::size_t k = 0; k < n_local; ++k) {
    const Vec3 f_ext = external[k];
    any_external |= (f_ext.x != 0.0) | (f_ext.y != 0.0) | (f_ext.z != 0.0);
    Vec3 f = gravity * mass[k] + f_ext;
    Vec3 t;
    for (std::uint32_t e = offset[k]; e < offset[k + 1]; ++e) {
      const std::uint32_t s = slot[e];
      f += Vec3{fx[s], fy[s], fz[s]};
      t += Vec3{tx[s], ty[s], tz[s]};
    }
    force[k] = f;
    torque[k] = t;
  }
  // Energy ledger: external forces on free particles and their power at the mid-step
  // velocity (the drift x += v dt used it), for accumulate_ledger().
  external_.clear();
  if (any_external)
    for (std::size_t k = 0; k < n_local; ++k)
      if ((external[k].x != 0.0 || external[k].y != 0.0 || external[k].z != 0.0) &&
          p.motion[k] == Motion::kFree)
        external_.push_back({static_cast<std::uint32_t>(k), dot(external[k], p.velocity[k])});
}

void Interactions::accumulate_ledger(ParticleStore& p, const std::vector<RigidBody>& bodies,
                                     double dt, bool initial) {
  // The tallies (docs/physics.md "Energy ledger"; physics.md §3 for the contact loads, §4
  // for the integrator). Velocity Verlet applies a load F^n, computed at t_n, in two half
  // kicks v^{n-1/2} -> v^n -> v^{n+1/2}; the kinetic energy they change is exactly
  // dt F^n . v^n with v^n the synchronised velocity (the mean of the two half-step
  // velocities), i.e. the load's power at the end of this step's second half kick, which is
  // where this runs. Summing dt P^n is the trapezoidal rule in time for the work: the same
  // as the mid-step form dt (F^n + F^{n+1})/2 . v^{n+1/2} summed over steps. The current
  // step's second kick is only half done, so the reported tally is accumulated - dt/2 P^n
  // (ParticleStore::ledger_value), and the ledger closes to O(dt^2) at every step, the order
  // of velocity Verlet's own energy error. (The work of F^n with the half-step velocity the
  // contact law saw, F^n . v^{n-1/2} dt, would be only first order.)
  const std::size_t np = pairs_.size();
  const std::size_t contact_base = slots_.size() - work_index_.size();
  const std::size_t wall_base = contact_base + 2 * np;
  auto add = [&](double& accumulated, double& last_power, double power) {
    accumulated = initial
                      ? ParticleStore::ledger_value(accumulated, last_power, dt) + 0.5 * dt * power
                      : accumulated + dt * power;
    last_power = power;
  };
  if (ledger_list_changed_) {
    // Particles off the list have no contact and are not driven: zero power from now on. A
    // tangential spring energy still booked to one (its contact gone) is released as friction.
    for (std::size_t i = 0, k = 0; k < p.n_local(); ++k) {
      if (i < ledger_particle_.size() && ledger_particle_[i] == k) {
        ++i;
        continue;
      }
      p.power_damping[k] = p.power_friction[k] = p.power_boundary[k] = 0.0;
      if (!initial) p.dissipated_friction[k] += p.tangential_energy[k];
      p.tangential_energy[k] = 0.0;
      p.contact_energy[k] = 0.0;
    }
    ledger_list_changed_ = false;
  }
  for (std::size_t i = 0; i < ledger_particle_.size(); ++i) {
    const std::uint32_t k = ledger_particle_[i];
    const Vec3 v = p.velocity[k];
    const Vec3 w = p.omega[k];
    double damping = 0.0, friction = 0.0, boundary = 0.0, tangential = 0.0, elastic = 0.0;
    // Contacts, in gather order (the same sum on any rank count). Each particle books the
    // work its own contact loads do; over both ends of a pair this is the pair's dissipation.
    // A rigid body's end is booked to the particle: against a driven body its surface
    // velocity enters the relative velocity and the total contact load's power on the body
    // is boundary work; a free body's own kinetic energy is in the ledger.
    for (std::uint32_t e = ledger_offset_[i]; e < ledger_offset_[i + 1]; ++e) {
      const std::uint32_t s = ledger_slot_[e];
      const ContactWork& c = work_[e];
      if (c.arm.x == 0.0 && c.arm.y == 0.0 && c.arm.z == 0.0) continue;  // not touching
      Vec3 rel = v + cross(w, c.arm);  // velocity of the particle's contact point
      if (s >= wall_base) {
        const RigidBody& body = bodies[wall_body_[s - wall_base]];
        if (body.motion != RigidMotion::kFixed) {
          const Vec3 vb = body.velocity_at(p.position[k] + c.arm);
          rel -= vb;
          if (body.motion == RigidMotion::kPrescribed)
            boundary += dot(Vec3{slots_.fx[s], slots_.fy[s], slots_.fz[s]}, vb);
        }
      }
      damping -= dot(c.damping, rel);
      friction -= dot(c.friction, rel) + dot(c.rolling, w);
      tangential += c.tangential_energy;
      elastic += c.elastic_energy;
    }
    if (p.motion[k] != Motion::kFree) {
      // A driven particle: whatever its interactions push against, the driver supplies.
      Vec3 f, t;
      for (std::uint32_t e = gather_offset_[k]; e < gather_offset_[k + 1]; ++e) {
        const std::uint32_t s = gather_slot_[e];
        f += Vec3{slots_.fx[s], slots_.fy[s], slots_.fz[s]};
        t += Vec3{slots_.tx[s], slots_.ty[s], slots_.tz[s]};
      }
      boundary -= dot(f, v) + dot(t, w);
    }
    add(p.dissipated_damping[k], p.power_damping[k], damping);
    add(p.dissipated_friction[k], p.power_friction[k], friction);
    add(p.boundary_work[k], p.power_boundary[k], boundary);
    // Friction is what the tangential springs took in and do not hold any more.
    if (!initial) p.dissipated_friction[k] -= tangential - p.tangential_energy[k];
    p.tangential_energy[k] = tangential;
    p.contact_energy[k] = elastic;  // summed in gather order: the same bits on any rank count
  }
  // External forces: F_ext . (x^{n+1} - x^n), exact for a constant force.
  if (!initial)
    for (const auto& x : external_)
      p.boundary_work[x.particle] += dt * x.power;
}

}  // namespace ringdem

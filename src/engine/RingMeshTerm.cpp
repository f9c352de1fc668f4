#include "engine/RingMeshTerm.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "core/CellKeys.hpp"

namespace ringdem {

namespace {

/// The mesh (index into `meshes`) whose rings include body id `body`, or -1.
int mesh_of(const std::vector<RingMeshSpec>& meshes, std::int32_t body) {
  if (body < 0) return -1;
  for (std::size_t m = 0; m < meshes.size(); ++m)
    if (body >= meshes[m].first_body && body - meshes[m].first_body < meshes[m].n_rings)
      return static_cast<int>(m);
  return -1;
}

}  // namespace

std::optional<FarGhostRule> RingMeshTerm::far_ghosts(const ParticleStore& p) const {
  if (meshes_.empty()) return std::nullopt;
  double ring_span = 0.0, opening = std::numeric_limits<double>::infinity();
  for (const RingMeshSpec& m : meshes_) {
    ring_span = std::max(ring_span, 1.1 * M_PI * m.centreline_radius);
    opening = std::min(opening, m.params.opening);
  }
  double r_max = 0.0;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    r_max = std::max(r_max, p.radius[k]);
  FarGhostRule rule;
  rule.reach = ring_span + r_max;
  rule.anchor = [meshes = meshes_](const ParticleStore& q, std::size_t k) {
    return mesh_of(meshes, q.body[k]) >= 0;
  };
  // As rebuild() takes its candidates: grains (of no ring) a mesh can hold.
  rule.partner = [opening](const ParticleStore& q, std::size_t k) {
    return q.body[k] < 0 && 2.0 * q.radius[k] >= opening;
  };
  return rule;
}

double RingMeshTerm::time_step_limit(const Model& model) {
  double lightest_density = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < model.materials.size(); ++i)
    lightest_density = std::min(lightest_density, model.materials[i].density);
  double limit = std::numeric_limits<double>::infinity();
  for (const RingMeshSpec& m : model.ring_meshes) {
    const double d = m.params.opening;
    const double grain_mass = lightest_density * M_PI / 6.0 * d * d * d;
    limit = std::min(limit, RingMesh::time_step_limit(m.params.stiffness, grain_mass, m.ring_mass));
  }
  return limit;
}

void RingMeshTerm::rebuild(RebuildContext& ctx) {
  const ParticleStore& p = ctx.particles;
  const std::size_t n_total = p.n_total();
  rings_.clear();
  bead_.clear();
  grain_.clear();
  // The beads of meshed rings present here (owned or ghost), by ring and round it by gid.
  struct Bead {
    std::int32_t body;
    std::int64_t gid;
    std::uint32_t index;
  };
  std::vector<Bead> beads;
  for (std::size_t k = 0; k < n_total; ++k)
    if (mesh_of(meshes_, p.body[k]) >= 0)
      beads.push_back({p.body[k], p.gid[k], static_cast<std::uint32_t>(k)});
  std::sort(beads.begin(), beads.end(), [](const Bead& a, const Bead& b) {
    return a.body != b.body ? a.body < b.body : a.gid < b.gid;
  });
  std::vector<char> ring_owned;
  for (std::size_t start = 0; start < beads.size();) {
    std::size_t end = start;
    while (end < beads.size() && beads[end].body == beads[start].body)
      ++end;
    const auto mesh = static_cast<std::uint32_t>(mesh_of(meshes_, beads[start].body));
    // A ring with a bead out of reach here has no owned particle in contact with it (the
    // ghost width): it is another rank's.
    if (end - start == static_cast<std::size_t>(meshes_[mesh].beads_per_ring)) {
      rings_.push_back({mesh, static_cast<std::uint32_t>(bead_.size()), beads[start].gid});
      bool owned = false;
      for (std::size_t b = start; b < end; ++b) {
        bead_.push_back(beads[b].index);
        owned = owned || beads[b].index < p.n_local();
      }
      ring_owned.push_back(owned);
    }
    start = end;
  }
  // Candidates, ring by ring and by grain gid: grains (particles of no ring) of at least the
  // opening's diameter whose centre lies within the ring's reach, their radius and twice the
  // skin of its centroid (the beads and the grain each move at most half the skin before the
  // next rebuild), and within the band about the ring's plane that the plane can reach before
  // then (RingMesh::band), evaluated here when the grain or a bead is owned.
  std::vector<std::pair<std::int64_t, std::uint32_t>> near;  // (gid, index)
  std::uint32_t n_slots = 0;
  std::vector<RingMesh::Plane> planes;
  std::vector<RingMesh::Band> bands;
  planes.reserve(rings_.size());
  bands.reserve(rings_.size());
  double widest = 0.0, opening = std::numeric_limits<double>::infinity();
  for (const MeshRing& ring : rings_) {
    const auto n = static_cast<std::size_t>(meshes_[ring.mesh].beads_per_ring);
    position_.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      position_[i] = p.position[bead_[ring.first_bead + i]];
    planes.push_back(RingMesh::plane(position_.data(), n));
    // Every particle moves at most half the skin before the next rebuild.
    bands.push_back(RingMesh::band(position_.data(), n, planes.back(), 0.5 * ctx.skin));
    widest = std::max(widest, planes.back().reach);
    opening = std::min(opening, meshes_[ring.mesh].params.opening);
  }
  // The grains a mesh here can hold, in cubes at least one ring's reach wide: a ring's
  // candidates lie in the 27 cubes around its centre's (a scan of every particle for every
  // ring was rings x particles at each rebuild, some 10^7 on a rank at a full case's net).
  double r_max = 0.0;
  for (std::size_t k = 0; k < n_total && !rings_.empty(); ++k)
    if (p.body[k] < 0 && 2.0 * p.radius[k] >= opening) r_max = std::max(r_max, p.radius[k]);
  const double cube = widest + r_max + 2.0 * ctx.skin;
  const auto cube_of = [cube](const Vec3& x) {
    return cell_keys::pack(static_cast<std::int64_t>(std::floor(x.x / cube)),
                           static_cast<std::int64_t>(std::floor(x.y / cube)),
                           static_cast<std::int64_t>(std::floor(x.z / cube)));
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> grains_in;
  for (std::size_t k = 0; k < n_total && !rings_.empty(); ++k)
    if (p.body[k] < 0 && 2.0 * p.radius[k] >= opening)
      grains_in[cube_of(p.position[k])].push_back(static_cast<std::uint32_t>(k));
  for (MeshRing& ring : rings_) {
    const RingMeshSpec& mesh = meshes_[ring.mesh];
    const auto n = static_cast<std::size_t>(mesh.beads_per_ring);
    const std::size_t r = static_cast<std::size_t>(&ring - rings_.data());
    const RingMesh::Plane& plane = planes[r];
    const bool owned = ring_owned[r];
    const RingMesh::Band& band = bands[r];
    near.clear();
    cell_keys::for_each_neighbour(cube_of(plane.centre), [&](std::uint64_t key) {
      const auto it = grains_in.find(key);
      if (it == grains_in.end()) return;
      for (const std::uint32_t k : it->second) {
        if (2.0 * p.radius[k] < mesh.params.opening) continue;
        if (k >= p.n_local() && !owned) continue;
        const double reach = plane.reach + p.radius[k] + 2.0 * ctx.skin;
        const Vec3 e = p.position[k] - plane.centre;
        if (norm2(e) < reach * reach &&
            std::abs(dot(e, plane.normal)) < p.radius[k] + band.offset + band.tilt * norm(e))
          near.emplace_back(p.gid[k], k);
      }
    });
    std::sort(near.begin(), near.end());
    ring.first_contact = static_cast<std::uint32_t>(grain_.size());
    ring.n_contacts = static_cast<std::uint32_t>(near.size());
    for (const auto& [gid, k] : near)
      grain_.push_back(k);
    // The grains' slots, then one per bead (none without contacts).
    ring.first_slot = n_slots + ring.n_contacts;
    n_slots += near.empty() ? 0 : ring.n_contacts + static_cast<std::uint32_t>(n);
    ring.loaded = false;
  }
  touching_.assign(grain_.size(), 0);
  slots_ = ctx.allocator.take(n_slots);
  // A grain's slots sort by the ring's first bead, a bead's one slot by its ring's: each key
  // once per particle in this term (GatherMap).
  for (const MeshRing& ring : rings_) {
    if (ring.n_contacts == 0) continue;
    const std::uint32_t grain_slots = slots_.begin + ring.first_slot - ring.n_contacts;
    for (std::uint32_t c = 0; c < ring.n_contacts; ++c)
      ctx.gather.add(grain_[ring.first_contact + c], ring.key, ctx.term_number, grain_slots + c,
                     true);
    const int n = meshes_[ring.mesh].beads_per_ring;
    for (int i = 0; i < n; ++i)
      ctx.gather.add(bead_[ring.first_bead + static_cast<std::size_t>(i)], ring.key,
                     ctx.term_number,
                     slots_.begin + ring.first_slot + static_cast<std::uint32_t>(i), true);
  }
}

void RingMeshTerm::compute(ComputeContext& ctx) {
  const ParticleStore& p = ctx.particles;
  for (MeshRing& ring : rings_) {
    if (ring.n_contacts == 0) continue;
    const RingMeshSpec& mesh = meshes_[ring.mesh];
    const auto n = static_cast<std::size_t>(mesh.beads_per_ring);
    // The ring's plane and mass once a step, from its beads in gid order.
    position_.resize(n);
    velocity_.resize(n);
    double m_ring = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t b = bead_[ring.first_bead + i];
      position_[i] = p.position[b];
      velocity_[i] = p.velocity[b];
      m_ring += p.mass[b];
    }
    const RingMesh::Plane plane = RingMesh::plane(position_.data(), n);
    const RingMesh::Motion motion = RingMesh::motion(position_.data(), velocity_.data(), n);
    // The beads' loads summed over the ring's contacts by grain gid, as the two vectors of
    // Eq. M6 (a sum over the beads for each contact had been a seventh of the net's rank in the
    // 10^5-grain channel: docs/performance.md, forty-third round).
    RingMesh::BeadLoads ring_force, ring_damping;
    bool loaded = false;
    const std::uint32_t grain_slots = slots_.begin + ring.first_slot - ring.n_contacts;
    for (std::uint32_t c = 0; c < ring.n_contacts; ++c) {
      const std::size_t contact = ring.first_contact + c;
      const std::uint32_t k = grain_[contact];
      const std::uint32_t slot = grain_slots + c;
      RingMesh::Input in;
      in.n = n;
      in.position = p.position[k];
      in.velocity = p.velocity[k];
      in.radius = p.radius[k];
      in.m_star = p.mass[k] * m_ring / (p.mass[k] + m_ring);
      RingMesh::Output out;
      RingMesh::BeadLoads bead_force, bead_damping;
      if (!RingMesh::compute(mesh.params, plane, motion, in, out, bead_force, bead_damping)) {
        if (touching_[contact]) {  // (slots and records start at zero at a rebuild)
          ctx.slots.set(slot, {}, {});
          ctx.ledger.clear_record(slot);
          touching_[contact] = 0;
        }
        continue;
      }
      touching_[contact] = 1;
      loaded = true;
      // The grain: its load through its centre (no moment), and all of the contact's elastic
      // energy (its slot is booked once over the ranks, where the grain is owned).
      ctx.slots.set(slot, out.force, {});
      DissipationRecord& record = ctx.ledger.record(slot);
      record = {};
      record.damping = out.damping;
      record.arm = out.outward * (-in.radius);  // along the viscous load: no moment
      record.elastic_energy = out.elastic_energy;
      ring_force += bead_force;
      ring_damping += bead_damping;
    }
    if (!loaded && !ring.loaded) continue;  // its bead slots hold zeros already
    ring.loaded = loaded;
    for (std::size_t i = 0; i < n; ++i) {
      const std::uint32_t slot = slots_.begin + ring.first_slot + static_cast<std::uint32_t>(i);
      ctx.slots.set(slot, ring_force.at(position_.data(), n, i), {});
      DissipationRecord& record = ctx.ledger.record(slot);
      record = {};
      // The viscous load acts at the bead's centre: the record's arm lies along it, so that it
      // has no moment (a zero arm would mark the record idle).
      record.damping = ring_damping.at(position_.data(), n, i);
      const double length = norm(record.damping);
      if (length > 0.0)
        record.arm = record.damping * (p.radius[bead_[ring.first_bead + i]] / length);
    }
  }
}

void RingMeshTerm::mark_net_contacts(const ParticleStore& p,
                                     std::vector<std::uint8_t>& touching) const {
  for (std::size_t c = 0; c < grain_.size(); ++c) {
    const std::uint32_t k = grain_[c];
    if (touching_[c] != 0 && k < touching.size() && !is_net_particle(p, k)) touching[k] = 1;
  }
}

}  // namespace ringdem

#include "engine/BodyContactTerm.hpp"

#include <cmath>

#include "engine/ContactKeys.hpp"
#include "engine/Loop.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {

void BodyContactTerm::find_overlaps(const ParticleStore& p, const std::vector<RigidBody>& bodies,
                                    double fraction, std::vector<ContactOverlap>& out) const {
  for (std::size_t w = 0; w < particle_.size(); ++w) {
    const std::uint32_t k = particle_[w];
    const double depth = p.radius[k] - bodies[body_[w]].closest(p.position[k]).distance;
    if (depth > fraction * p.radius[k]) out.push_back({k, body_[w], true, depth});
  }
}

void BodyContactTerm::rebuild(RebuildContext& ctx) {
  const ParticleStore& p = ctx.particles;
  // Candidates: owned particles within the skin of a body's surface (a body is on every rank,
  // so each particle's contacts are evaluated once, where it is owned).
  // The store's rows (the springs carried across the migration) become the new candidates.
  const auto old_springs = springs_by_key(springs_);
  particle_.clear();
  body_.clear();
  fast_.clear();
  springs_.resize(0);
  // A held particle and a held body never touch (compute() below): no candidate, so that a
  // net's fixed shackles beside its posts leave a sub-stepped run without fast body contacts
  // (whose loads every sub-step would reduce over the ranks).
  for (std::size_t b = 0; b < ctx.bodies.size(); ++b)
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (!(ctx.bodies[b].motion != Motion::kFree && p.motion[k] != Motion::kFree) &&
          ctx.bodies[b].closest(p.position[k]).distance < p.radius[k] + ctx.skin) {
        particle_.push_back(static_cast<std::uint32_t>(k));
        body_.push_back(static_cast<std::uint32_t>(b));
        fast_.push_back(is_fast_particle(p, k) ? 1 : 0);
        const auto it = old_springs.find(PairKey{p.gid[k], static_cast<std::int64_t>(b)});
        springs_.append(p.gid[k], static_cast<std::int64_t>(b),
                        it != old_springs.end() ? it->second : Vec3{});
      }
  list_fast_candidates();
  slots_ = ctx.allocator.take(particle_.size());
  for (std::size_t w = 0; w < particle_.size(); ++w)
    ctx.gather.add(particle_[w], GatherMap::kBodyKeyBase + body_[w], ctx.term_number,
                   slots_.begin + static_cast<std::uint32_t>(w), true, fast_[w] != 0);
}

void BodyContactTerm::list_fast_candidates() {
  fast_list_.clear();
  for (std::size_t w = 0; w < fast_.size(); ++w)
    if (fast_[w] != 0) fast_list_.push_back(static_cast<std::uint32_t>(w));
}

void BodyContactTerm::change_rates(const ParticleStore& p, GatherMap& gather) {
  for (std::size_t w = 0; w < particle_.size(); ++w) {
    const std::uint8_t fast = is_fast_particle(p, particle_[w]) ? 1 : 0;
    if (fast == fast_[w]) continue;
    fast_[w] = fast;
    gather.set_rate(slots_.begin + static_cast<std::uint32_t>(w), fast != 0);
  }
  list_fast_candidates();
}

void BodyContactTerm::compute(ComputeContext& ctx) {
  const ParticleStore& p = ctx.particles;
  ForceSlots& slots = ctx.slots;
  EnergyLedger& ledger = ctx.ledger;
  body_load_sums_.assign(kLoadColumns * ctx.bodies.size(), ExactSum{});
  std::vector<Vec3>& spring = springs_.spring;
  BodyContactChunk& chunk = chunk_;
  // Particle–body contacts (physics.md §3, with R_j and m_j of the body), a chunk of
  // candidates at a time: the touching ones' inputs into the chunk's columns, the contact law
  // over them vectorised, then each one's loads in candidate order.
  // Multi-rate stepping: a fast evaluation visits its candidates from their list, a slow one
  // skips them.
  const bool fast_only = ctx.rate == ForceRate::kFast;
  const bool slow_only = ctx.rate == ForceRate::kSlow;
  const std::size_t n_visit = fast_only ? fast_list_.size() : particle_.size();
  for_each_chunk(IndexRange{0, n_visit}, BodyContactChunk::kSize, [&](IndexRange range) {
    chunk.n = 0;
    chunk.any_rolling = false;
    for (std::size_t i = range.begin; i < range.end; ++i) {
      const std::size_t w = fast_only ? fast_list_[i] : i;
      if (slow_only && fast_[w] != 0) continue;
      const std::uint32_t k = particle_[w];
      const RigidBody& body = ctx.bodies[body_[w]];
      // A plane's distance and normal without the closest point: the aggregate went through
      // the stack in pieces that a wide load read back (a store-forwarding stall, most of the
      // body contacts' time in a debris channel, whose bed and walls are planes).
      Vec3 outward;
      double distance = 0.0;
      if (body.shape == RigidShape::kPlane) {
        outward = body.plane_normal();
        distance = dot(p.position[k] - body.position, outward);
      } else {
        const auto sp = body.closest(p.position[k]);
        outward = sp.normal;
        distance = sp.distance;
      }
      const double overlap = p.radius[k] - distance;
      // A held particle (fixed or prescribed) on a held body: neither moves by the force, which
      // would only be reported (a constant load on the body and contact energy, such as a
      // net's fixed shackle inside its post): no contact, as the start's overlap check has it.
      if (overlap <= 0.0 || (p.motion[k] != Motion::kFree && body.motion != Motion::kFree)) {
        const std::uint32_t slot = slots_.begin + static_cast<std::uint32_t>(w);
        spring[w] = {};
        slots.set(slot, {}, {});
        ledger.clear_record(slot);
        continue;
      }
      const Vec3 n = -outward;  // from the particle to the body
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
      in.arm_i = arm;
      in.arm_j = 0.0;
      in.omega_i = p.omega[k];
      in.omega_j = body.omega;
      chunk.add(static_cast<std::uint32_t>(w), in, ctx.materials.pair(p.material[k], body.material),
                spring[w]);
    }
    chunk.compute(ctx.dt);
    for (std::size_t c = 0; c < chunk.n; ++c) {
      const std::uint32_t w = chunk.candidate[c];
      const std::uint32_t k = particle_[w];
      const std::uint32_t slot = slots_.begin + w;
      const RigidBody& body = ctx.bodies[body_[w]];
      const Vec3 n = chunk.normal.get(c);
      const double arm = chunk.arm[c];
      const Vec3 force = chunk.force.get(c);
      spring[w] = chunk.spring.get(c);
      slots.set(slot, force, chunk.torque.get(c));
      // Member by member: an aggregate went through the stack in pieces that wide loads read
      // back, a store-forwarding stall (as the pair loop's springs, docs/performance.md).
      DissipationRecord& record = ledger.record(slot);
      record.damping = chunk.damping.get(c);
      record.friction = spring[w];
      record.arm = n * arm;
      record.rolling = chunk.rolling.get(c);
      record.tangential_energy = chunk.tangential_energy[c];
      record.elastic_energy = chunk.elastic_energy[c];
      record.body = static_cast<std::int32_t>(body_[w]);
      const Vec3 contact = p.position[k] + n * arm;
      const Vec3 torque_on_body = cross(contact - body.position, -force);
      ExactSum* const sums = &body_load_sums_[kLoadColumns * body_[w]];
      sums[kForceX].add(-force.x);
      sums[kForceY].add(-force.y);
      sums[kForceZ].add(-force.z);
      sums[kTorqueX].add(torque_on_body.x);
      sums[kTorqueY].add(torque_on_body.y);
      sums[kTorqueZ].add(torque_on_body.z);
    }
  });
}

}  // namespace ringdem

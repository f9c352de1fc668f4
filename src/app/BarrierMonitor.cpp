#include "app/BarrierMonitor.hpp"

#include <algorithm>
#include <stdexcept>

#include "app/GroupExtent.hpp"
#include "comm/ExactSum.hpp"
#include "engine/FrameRestraints.hpp"
#include "engine/Simulation.hpp"

namespace ringdem {

namespace {

int group_or_throw(const Model& model, const std::string& name) {
  const int id = model.group_id(name);
  if (id < 0) throw std::invalid_argument("barrier: no particle group '" + name + "'");
  return id;
}

std::size_t body_or_throw(const Model& model, const std::string& name) {
  for (std::size_t i = 0; i < model.bodies.size(); ++i)
    if (model.bodies[i].name == name) return i;
  throw std::invalid_argument("barrier: no rigid body '" + name + "'");
}

}  // namespace

BarrierMonitor::BarrierMonitor(const BarrierConfig& config, const Simulation& sim)
    : config_(config) {
  const Model& model = sim.model();
  config_.direction = normalized(config_.direction);
  for (const std::string& g : config_.grain_groups)
    grain_groups_.push_back(group_or_throw(model, g));
  if (!config_.net_group.empty()) net_group_ = group_or_throw(model, config_.net_group);
  if (!config_.frame_group.empty()) frame_group_ = group_or_throw(model, config_.frame_group);
  for (const std::string& name : config_.posts)
    posts_.push_back(body_or_throw(model, name));
  shackle_bodies_ = restrained_bodies(model);
  bed_ = body_or_throw(model, config_.bed);
  if (model.bodies[bed_].shape != RigidShape::kPlane)
    throw std::invalid_argument("barrier: the bed '" + config_.bed + "' is not a plane");
}

bool BarrierMonitor::is_grain(const Simulation& sim, std::size_t k) const {
  const ParticleStore& p = sim.model().particles;
  if (grain_groups_.empty()) return p.motion[k] == Motion::kFree && p.body[k] < 0;
  return std::find(grain_groups_.begin(), grain_groups_.end(), p.group[k]) != grain_groups_.end();
}

BarrierMonitor::Impulse BarrierMonitor::impulse(const MomentumBalance& balance) const {
  // The ledger books what the particles received: the barrier's share is the opposite.
  Impulse out;
  out.net = -dot(balance.held, config_.direction);
  for (const std::int32_t b : shackle_bodies_)  // what the net passes to its shackle tori
    out.net -= dot(balance.bodies.at(static_cast<std::size_t>(b)), config_.direction);
  for (const std::size_t b : posts_)
    out.posts -= dot(balance.bodies.at(b), config_.direction);
  return out;
}

BarrierSample BarrierMonitor::sample(const Simulation& sim) const {
  const Model& model = sim.model();
  const ParticleStore& p = model.particles;
  const Communicator& comm = sim.comm();
  const Vec3 d = config_.direction;
  const RigidBody& bed = model.bodies[bed_];
  const Vec3 up = rotate(bed.orientation, Vec3{0, 0, 1});  // a plane's normal is its body z
  const double gauge_hi = -config_.gauge_distance, gauge_lo = gauge_hi - config_.gauge_length;

  // Exact sums: gauge mass, gauge momentum along d, retained mass, overflow mass, gauge mass
  // moment of height above the bed.
  std::vector<ExactSum> sums(5);
  double depth = 0.0, gauge_radius = 0.0, front = -std::numeric_limits<double>::infinity();
  double reach = -std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const double s = dot(p.position[k] - config_.position, d);
    if (net_group_ >= 0 && p.group[k] == net_group_) reach = std::max(reach, s);
    if (!is_grain(sim, k)) continue;
    front = std::max(front, s + p.radius[k]);
    if (s > 0.0) sums[3].add(p.mass[k]);
    if (s >= -config_.retention_length && s <= 0.0) sums[2].add(p.mass[k]);
    if (s >= gauge_lo && s <= gauge_hi) {
      sums[0].add(p.mass[k]);
      sums[1].add(p.mass[k] * dot(p.velocity[k], d));
      const double height = dot(p.position[k] - bed.position, up);
      sums[4].add(p.mass[k] * height);
      depth = std::max(depth, height + p.radius[k]);
      gauge_radius = std::max(gauge_radius, p.radius[k]);
    }
  }
  const std::vector<double> total = comm.sum_exact(sums);
  BarrierSample out;
  out.gauge_mass = total[0];
  out.flow_velocity = total[0] > 0.0 ? total[1] / total[0] : 0.0;
  out.retained_mass = total[2];
  out.overflow_mass = total[3];
  out.flow_depth = comm.max(depth);
  out.largest_gauge_radius = comm.max(gauge_radius);
  out.flow_depth_centroid = total[0] > 0.0 ? 2.0 * total[4] / total[0] : 0.0;
  out.front = comm.max(front);
  out.net_reach = comm.max(reach);
  if (config_.width > 0.0 && out.flow_depth > 0.0)
    out.bulk_density = out.gauge_mass / (config_.gauge_length * config_.width * out.flow_depth);

  // Loads: the frame's contact load (summed exactly), the posts' contact forces (global).
  if (frame_group_ >= 0)
    out.net_force = dot(frame_load(sim, frame_group_, sim.settings().gravity), d);
  for (const std::size_t b : posts_)
    out.posts_force += dot(model.bodies[b].force, d);

  // Largest utilisation of the net's intact bonds, counted by the rank owning end a; among
  // equals the lowest gid pair; its midpoint from that rank.
  const BondStore& bonds = model.bonds;
  const auto net_bond = [&](std::size_t k) {
    return !bonds.broken[k] && bonds.index_a[k] < p.n_local() && net_group_ >= 0 &&
           p.group[bonds.index_a[k]] == net_group_;
  };
  double best = 0.0;
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (net_bond(k)) best = std::max(best, bonds.utilisation[k]);
  out.max_utilisation = comm.max(best);
  std::int64_t gid_a = std::numeric_limits<std::int64_t>::max(), gid_b = gid_a;
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (net_bond(k) && bonds.utilisation[k] == out.max_utilisation && bonds.gid_a[k] < gid_a)
      gid_a = bonds.gid_a[k];
  gid_a = comm.min(gid_a);
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (net_bond(k) && bonds.utilisation[k] == out.max_utilisation && bonds.gid_a[k] == gid_a)
      gid_b = std::min(gid_b, bonds.gid_b[k]);
  gid_b = comm.min(gid_b);
  std::vector<ExactSum> at(3);
  for (std::size_t k = 0; k < bonds.size(); ++k)
    if (net_bond(k) && bonds.gid_a[k] == gid_a && bonds.gid_b[k] == gid_b) {
      const Vec3 mid = 0.5 * (p.position[bonds.index_a[k]] + p.position[bonds.index_b[k]]);
      at[0].add(mid.x);
      at[1].add(mid.y);
      at[2].add(mid.z);
    }
  const std::vector<double> where = comm.sum_exact(at);
  out.utilisation_at = {where[0], where[1], where[2]};
  return out;
}

}  // namespace ringdem

#include "domain/ParticleStore.hpp"

#include <cmath>
#include <stdexcept>

namespace ringdem {

void ParticleStore::resize_all(std::size_t n) {
  for_each_field([n](const FieldInfo&, auto& v) { v.resize(n); });
}

void ParticleStore::reserve(std::size_t n) {
  for_each_field([n](const FieldInfo&, auto& v) { v.reserve(n); });
}

void ParticleStore::reserve_share(std::size_t n, int ranks) {
  reserve(ranks > 1 ? static_cast<std::size_t>(static_cast<double>(n) * kDistributedHeadroom) : n);
}

std::size_t ParticleStore::add(const NewParticle& p) {
  if (n_ghost_ != 0) throw std::logic_error("ParticleStore::add with ghosts present");
  if (!(p.radius > 0.0)) throw std::invalid_argument("particle radius must be positive");
  const std::size_t i = n_local_;
  resize_all(i + 1);
  n_local_ = i + 1;
  gid[i] = p.gid;
  position[i] = p.position;
  // A fixed particle never moves: the integrator relies on its velocities being zero.
  const bool fixed = p.motion == Motion::kFixed;
  velocity[i] = fixed ? Vec3{} : p.velocity;
  omega[i] = fixed ? Vec3{} : p.omega;
  if (tracks_orientation_) orientation[i] = p.orientation;
  force[i] = {};
  torque[i] = {};
  radius[i] = p.radius;
  mass[i] = p.density * 4.0 / 3.0 * M_PI * p.radius * p.radius * p.radius;
  if (tracks_damping_)
    damping[i] = p.damping;
  else if (p.damping != 0.0)
    throw std::logic_error("a damped particle in a store that keeps no damping coefficients");
  material[i] = p.material;
  body[i] = p.body;
  group[i] = p.group;
  motion[i] = p.motion;
  sort_bin[i] = 0;  // in gid order among the unbinned until the next re-sort
  index_.set(static_cast<std::uint32_t>(i), gid.data(), gid.size());
  return i;
}

void ParticleStore::set_tracks_orientation(bool on) {
  if (on == tracks_orientation_) return;
  tracks_orientation_ = on;
  if (on)
    orientation.assign(n_total(), Quat{});
  else
    std::vector<Quat>().swap(orientation);  // the memory goes back, not only the size
}

void ParticleStore::set_tracks_ledger(bool on) {
  if (on == tracks_ledger_) return;
  tracks_ledger_ = on;
  resize_ledger_columns();
}

void ParticleStore::set_tracks_damping(bool on) {
  if (on == tracks_damping_) return;
  tracks_damping_ = on;
  if (on)
    damping.assign(n_total(), 0.0);
  else
    std::vector<double>().swap(damping);
  resize_ledger_columns();
}

void ParticleStore::set_tracks_slow_loads(bool on) {
  if (on == tracks_slow_loads_) return;
  tracks_slow_loads_ = on;
  for (auto* v : {&slow_force, &slow_torque})
    if (on)
      v->assign(n_total(), Vec3{});
    else
      std::vector<Vec3>().swap(*v);
  if (on)
    net_contact.assign(n_total(), 0);
  else
    std::vector<std::uint8_t>().swap(net_contact);
}

void ParticleStore::resize_ledger_columns() {
  if (books_global_damping())
    for_each_ledger_field([n = n_total()](const FieldInfo&, auto& v) { v.assign(n, 0.0); });
  else  // the memory goes back, not only the size
    for_each_ledger_field([](const FieldInfo&, auto& v) { std::vector<double>().swap(v); });
}

void ParticleStore::resize_local(std::size_t n) {
  n_local_ = n;
  n_ghost_ = 0;
  resize_all(n);
}

std::size_t ParticleStore::remove_owned(const std::vector<char>& keep_owned) {
  if (keep_owned.size() != n_local_) throw std::invalid_argument("remove_owned: wrong size");
  std::vector<char> keep(n_local_ + n_ghost_, 1);
  std::copy(keep_owned.begin(), keep_owned.end(), keep.begin());
  const std::size_t kept = compact_rows(*this, keep);
  const std::size_t removed = n_local_ + n_ghost_ - kept;
  n_local_ -= removed;
  resize_all(kept);
  rebuild_index();
  return removed;
}

void ParticleStore::resize_ghosts(std::size_t n) {
  n_ghost_ = n;
  resize_all(n_local_ + n_ghost_);
}

void ParticleStore::permute_local(const std::vector<std::size_t>& order) {
  if (order.size() != n_local_) throw std::invalid_argument("permute_local: wrong size");
  for_each_field([&](const FieldInfo&, auto& v) {
    auto old = v;
    for (std::size_t i = 0; i < order.size(); ++i)
      v[i] = old[order[i]];
  });
}

void ParticleStore::rebuild_index() {
  index_.reset(n_total());
  for (std::size_t i = 0; i < n_total(); ++i)
    index_.set(static_cast<std::uint32_t>(i), gid.data(), gid.size());
}

}  // namespace ringdem

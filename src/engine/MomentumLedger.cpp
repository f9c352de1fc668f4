#include "engine/MomentumLedger.hpp"

#include <stdexcept>

namespace ringdem {

MomentumLedger::MomentumLedger(std::size_t n_bodies, bool enabled)
    : n_bodies_(n_bodies), enabled_(enabled), totals_(3 * n_sources()), pending_(3 * n_sources()) {}

void MomentumLedger::book_initial_momentum(const ParticleStore& p) {
  if (!enabled_) return;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.motion[k] == Motion::kFree) add(totals_, kInitial, p.velocity[k] * p.mass[k]);
}

void MomentumLedger::rebuild(const ParticleStore& p, double free_mass) {
  held_.clear();
  if (!enabled_) return;
  for (std::size_t k = 0; k < p.n_local(); ++k)
    if (p.motion[k] != Motion::kFree) held_.push_back(static_cast<std::uint32_t>(k));
  free_mass_ = free_mass;
}

void MomentumLedger::book_evaluation(const ParticleStore& p,
                                     const std::vector<Vec3>& body_contact_loads,
                                     const std::vector<PointLoad>& point_loads, const Vec3& gravity,
                                     double half_dt, bool root, bool initial,
                                     const std::vector<Vec3>* loads) {
  if (!enabled_) return;
  const std::vector<Vec3>& force = loads ? *loads : p.force;
  for (ExactSum& s : pending_)
    s = ExactSum{};
  if (root) {
    add(pending_, kGravity, gravity * (free_mass_ * half_dt));
    // Bodies are replicated: their reduced loads are the same bits on every rank.
    for (std::size_t b = 0; b < body_contact_loads.size() && b < n_bodies_; ++b)
      add(pending_, kFixedSources + b, body_contact_loads[b] * -half_dt);
  }
  // Point loads are few (a list by gid): the loads on held particles come off their sums.
  for (const PointLoad& load : point_loads) {
    const std::int64_t k = p.index_of(load.gid);
    if (k < 0 || static_cast<std::size_t>(k) >= p.n_local()) continue;
    if (p.motion[static_cast<std::size_t>(k)] == Motion::kFree)
      add(pending_, kPointLoads, load.force * half_dt);
  }
  for (const std::uint32_t k : held_) {
    Vec3 received = force[k] - gravity * p.mass[k];
    for (const PointLoad& load : point_loads)
      if (load.gid == p.gid[k]) received -= load.force;
    add(pending_, kHeld, received * -half_dt);
  }
  if (initial) return;
  for (std::size_t c = 0; c < totals_.size(); ++c)
    totals_[c] += pending_[c];
}

void MomentumLedger::book_leaving(const ParticleStore& p, std::size_t k, double half_dt,
                                  const std::vector<Vec3>* loads) {
  if (!enabled_) return;
  add(totals_, kExchange, (loads ? *loads : p.force)[k] * -half_dt);
}

void MomentumLedger::book_arrivals(const ParticleStore& p, std::size_t first, std::size_t last,
                                   double half_dt) {
  if (!enabled_) return;
  for (std::size_t k = first; k < last; ++k)
    if (p.motion[k] == Motion::kFree) add(totals_, kExchange, p.force[k] * half_dt);
}

void MomentumLedger::book_first_half() {
  if (!enabled_) return;
  for (std::size_t c = 0; c < totals_.size(); ++c)
    totals_[c] += pending_[c];
}

MomentumBalance MomentumLedger::balance(const ParticleStore& p, const Communicator& comm) const {
  std::vector<ExactSum> partial = totals_;
  const std::size_t now = partial.size();
  partial.resize(now + 3);
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    if (p.motion[k] != Motion::kFree) continue;
    const Vec3 q = p.velocity[k] * p.mass[k];
    partial[now].add(q.x);
    partial[now + 1].add(q.y);
    partial[now + 2].add(q.z);
  }
  const std::vector<double> sums = comm.sum_exact(partial);
  const auto column = [&sums](std::size_t c) { return Vec3{sums[c], sums[c + 1], sums[c + 2]}; };
  MomentumBalance b;
  b.momentum = column(now);
  b.initial = column(3 * kInitial);
  b.gravity = column(3 * kGravity);
  b.point_loads = column(3 * kPointLoads);
  b.held = column(3 * kHeld);
  b.exchange = column(3 * kExchange);
  for (std::size_t i = 0; i < n_bodies_; ++i)
    b.bodies.push_back(column(3 * (kFixedSources + i)));
  return b;
}

std::vector<std::int64_t> MomentumLedger::export_state(const Communicator& comm) const {
  std::vector<ExactSum> both = totals_;
  both.insert(both.end(), pending_.begin(), pending_.end());
  return words_of_sums(comm.reduce_exact(both));
}

void MomentumLedger::import_state(const std::vector<std::int64_t>& words, bool root) {
  const std::size_t columns = totals_.size();
  totals_.assign(columns, ExactSum{});
  pending_.assign(columns, ExactSum{});
  if (!root) return;
  const std::vector<ExactSum> sums = sums_of_words(words, 2 * columns, "momentum record");
  for (std::size_t c = 0; c < sums.size(); ++c)
    (c < columns ? totals_[c] : pending_[c - columns]) = sums[c];
}

}  // namespace ringdem

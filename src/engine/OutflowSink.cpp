#include "engine/OutflowSink.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace ringdem {

OutflowSink::OutflowSink(std::vector<OutflowBox> boxes)
    : boxes_(std::move(boxes)), partial_(kColumns) {}

bool OutflowSink::leaving(const ParticleStore& p, std::size_t k) const {
  if (p.motion[k] != Motion::kFree || p.body[k] >= 0) return false;
  const Vec3& x = p.position[k];
  for (const OutflowBox& b : boxes_) {
    if (!b.groups.empty() &&
        std::find(b.groups.begin(), b.groups.end(), p.group[k]) == b.groups.end())
      continue;
    // A position that is not a number is never outside: the divergence guard must see it.
    const bool outside = x.x < b.lo.x || x.x > b.hi.x || x.y < b.lo.y || x.y > b.hi.y ||
                         x.z < b.lo.z || x.z > b.hi.z;
    if (outside) return true;
  }
  return false;
}

void OutflowSink::note_positions(const ParticleStore& p) {
  double least = std::numeric_limits<double>::infinity();
  for (const OutflowBox& b : boxes_)
    for (std::size_t k = 0; k < p.n_local(); ++k) {
      if (p.motion[k] != Motion::kFree || p.body[k] >= 0) continue;
      if (!b.groups.empty() &&
          std::find(b.groups.begin(), b.groups.end(), p.group[k]) == b.groups.end())
        continue;
      const Vec3& x = p.position[k];
      // A position that is not a number never leaves (leaving()), and std::min keeps `least`
      // against a NaN.
      least = std::min({least, x.x - b.lo.x, b.hi.x - x.x, x.y - b.lo.y, b.hi.y - x.y, x.z - b.lo.z,
                        b.hi.z - x.z});
    }
  // Each drift's x += v dt rounds to about 1e-15 m; a micrometre covers a million steps
  // between two rebuilds many times over. A grain outside already gives a clearance below 0.
  clearance_ = least - kClearanceMargin;
}

bool OutflowSink::any_leaving(const ParticleStore& p, double moved) const {
  if (boxes_.empty()) return false;
  // Between two rebuilds a grain moves at most `moved`: while that is less than every grain's
  // distance to its box's faces, none is outside (a debris channel's grains reach the outflow
  // box only now and then; the scan below was 2 % of the debris demo).
  if (moved < clearance_) return false;
  // Every step, and nearly always no: first a branch-free pass over the positions alone (a
  // NaN compares false, never outside, as in leaving()). Only when some position is outside
  // a box are the particle's motion, body and group read.
  const Vec3* const x = p.position.data();
  const std::size_t n = p.n_local();
  bool some_outside = false;
  for (const OutflowBox& b : boxes_) {
    int outside = 0;
#pragma omp simd reduction(| : outside)
    for (std::size_t k = 0; k < n; ++k)
      outside |= static_cast<int>(x[k].x < b.lo.x) | static_cast<int>(x[k].x > b.hi.x) |
                 static_cast<int>(x[k].y < b.lo.y) | static_cast<int>(x[k].y > b.hi.y) |
                 static_cast<int>(x[k].z < b.lo.z) | static_cast<int>(x[k].z > b.hi.z);
    some_outside = some_outside || outside != 0;
  }
  if (!some_outside) return false;
  for (std::size_t k = 0; k < n; ++k)
    if (leaving(p, k)) return true;
  return false;
}

std::size_t OutflowSink::remove_leaving(ParticleStore& p, const Vec3& gravity, double dt,
                                        const ExactSum& contact_energy,
                                        const ExactSum& tangential_energy) {
  const std::size_t n = p.n_local();
  std::vector<char> keep(n, 1);
  std::size_t removed = 0;
  for (std::size_t k = 0; k < n; ++k) {
    if (!leaving(p, k)) continue;
    keep[k] = 0;
    ++removed;
    const double m = p.mass[k];
    const Vec3 v = p.velocity[k];
    partial_[kCount].add(1.0);
    partial_[kMass].add(m);
    partial_[kMomentumX].add(m * v.x);
    partial_[kMomentumY].add(m * v.y);
    partial_[kMomentumZ].add(m * v.z);
    // The same terms as Simulation::energies() sums for a particle still in the model.
    partial_[kEnergy].add(p.kinetic_energy(k));
    partial_[kEnergy].add(p.potential_energy(k, gravity));
    if (!p.books_global_damping()) continue;  // nothing booked (no ledger, or nothing damped)
    partial_[kGlobalDamping].add(p.global_damping_tally(k, dt));
  }
  if (removed == 0) return 0;
  // What their contacts held after the last step (zero where the ledger is off).
  partial_[kEnergy] += contact_energy;
  partial_[kTangentialEnergy] += tangential_energy;
  return p.remove_owned(keep);
}

std::vector<std::int64_t> OutflowSink::export_totals(const Communicator& comm) const {
  return words_of_sums(comm.reduce_exact(partial_));
}

void OutflowSink::import_totals(const std::vector<std::int64_t>& words, bool root) {
  partial_.assign(kColumns, ExactSum{});
  if (words.empty() || !root) return;
  partial_ = sums_of_words(words, kColumns, "outflow totals");
}

}  // namespace ringdem

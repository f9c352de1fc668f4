#include "engine/InflowSource.hpp"

#include <algorithm>
#include <stdexcept>

#include "engine/Model.hpp"

namespace ringdem {

InflowSource::InflowSource(std::vector<InflowSpec> inlets) : partial_(kColumns) {
  for (InflowSpec& s : inlets) {
    GrainSource packing(s.batch);
    const double first = s.start_time;
    inlets_.push_back({std::move(s), std::move(packing), 0, first});
  }
}

bool InflowSource::due(std::size_t i, double time) const {
  const Inlet& in = inlets_[i];
  // A tolerance of a millionth of an interval: times are sums of steps.
  return time + 1e-6 * in.spec.interval >= in.next_due && time < in.spec.end_time;
}

bool InflowSource::occupied(std::size_t i, const ParticleStore& p) const {
  const GrainSource::Spec& b = inlets_.at(i).spec.batch;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const Vec3& x = p.position[k];
    const double r = p.radius[k];
    if (x.x + r > b.box_min.x && x.x - r < b.box_max.x && x.y + r > b.box_min.y &&
        x.y - r < b.box_max.y && x.z + r > b.box_min.z && x.z - r < b.box_max.z)
      return true;
  }
  return false;
}

std::size_t InflowSource::emit(std::size_t i, ParticleStore& p, double time, const Vec3& gravity,
                               int rank, int ranks) {
  Inlet& in = inlets_.at(i);
  const std::int64_t range = in.packing.gid_range();
  const SourceBases bases{in.spec.gid_base + in.batches * range, 0, 0};
  // Each batch is a packing of its own seed: the batch number mixed into the inlet's seed.
  GrainSource::Spec spec = in.spec.batch;
  spec.seed = in.spec.batch.seed * 0x9E3779B97F4A7C15ULL + static_cast<std::uint64_t>(in.batches);
  const GrainSource batch(spec);
  p.resize_local(p.n_local());  // drop the ghosts: new owned rows go before them
  const std::size_t first_new = p.n_local();
  Model scratch;  // the source appends to a model's store
  std::swap(scratch.particles, p);
  batch.emit(ParticleSource::slice_begin(range, rank, ranks),
             ParticleSource::slice_begin(range, rank + 1, ranks), bases, scratch);
  std::swap(scratch.particles, p);
  for (std::size_t k = first_new; k < p.n_local(); ++k) {
    const double m = p.mass[k];
    const Vec3 v = p.velocity[k];
    p.force[k] = gravity * m;  // free flight: the inlet box holds nothing else
    p.torque[k] = {};
    partial_[kCount].add(1.0);
    partial_[kMass].add(m);
    partial_[kMomentumX].add(m * v.x);
    partial_[kMomentumY].add(m * v.y);
    partial_[kMomentumZ].add(m * v.z);
    partial_[kEnergy].add(0.5 * m * norm2(v));
    partial_[kEnergy].add(-m * dot(gravity, p.position[k]));
  }
  p.rebuild_index();
  ++in.batches;
  in.next_due = time + in.spec.interval;
  return p.n_local() - first_new;
}

std::vector<std::int64_t> InflowSource::batches() const {
  std::vector<std::int64_t> out;
  for (const Inlet& in : inlets_)
    out.push_back(in.batches);
  return out;
}

std::vector<double> InflowSource::next_due() const {
  std::vector<double> out;
  for (const Inlet& in : inlets_)
    out.push_back(in.next_due);
  return out;
}

std::vector<std::int64_t> InflowSource::export_totals(const Communicator& comm) const {
  return words_of_sums(comm.reduce_exact(partial_));
}

void InflowSource::restore(const std::vector<std::int64_t>& batches,
                           const std::vector<double>& next_due,
                           const std::vector<std::int64_t>& totals, bool root) {
  partial_.assign(kColumns, ExactSum{});
  if (batches.empty() && next_due.empty() && totals.empty()) return;
  if (batches.size() != inlets_.size() || next_due.size() != inlets_.size() ||
      totals.size() != static_cast<std::size_t>(kColumns) * ExactSum::kWords)
    throw std::runtime_error("checkpoint: inflow state does not match the case's inlets");
  for (std::size_t i = 0; i < inlets_.size(); ++i) {
    inlets_[i].batches = batches[i];
    inlets_[i].next_due = next_due[i];
  }
  if (root) partial_ = sums_of_words(totals, kColumns, "inflow totals");
}

}  // namespace ringdem

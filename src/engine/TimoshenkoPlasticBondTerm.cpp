#include "engine/TimoshenkoPlasticBondTerm.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "engine/Loop.hpp"
#include "engine/TimoshenkoBondTerm.hpp"

namespace ringdem {

namespace {

using Plastic = BondTimoshenkoPlastic;
using Beam = TimoshenkoBondTerm;  // the beam's columns and store helpers

// The State members the term reads besides the deformations: their model column numbers.
constexpr std::size_t kElongationColumn = 0;
constexpr std::size_t kStrainColumn = 1;
constexpr std::size_t kWorkColumn = 2;
static_assert(Plastic::State::kNames[kElongationColumn] == "plastic_elongation");
static_assert(Plastic::State::kNames[kStrainColumn] == "plastic_strain");
static_assert(Plastic::State::kNames[kWorkColumn] == "plastic_work");

}  // namespace

TimoshenkoPlasticBondTerm::TimoshenkoPlasticBondTerm(BondStore& bonds,
                                                     std::vector<Plastic::Params> plastic)
    : BondTerm(bonds), plastic_(std::move(plastic)) {
  if (bonds_.n_model_columns() != State::kSize)
    throw std::invalid_argument(
        "timoshenko_plastic: the bond store lacks the plastic state columns (declare "
        "state_columns() before the first bond)");
}

std::vector<BondStore::ModelColumn> TimoshenkoPlasticBondTerm::state_columns() {
  using namespace field_flag;
  std::vector<BondStore::ModelColumn> columns;
  for (std::size_t c = 0; c < State::kSize; ++c) {
    const bool output = c == kStrainColumn || c == kWorkColumn;
    columns.push_back(
        {std::string(State::kNames[c]), kMigrate | kCheckpoint | (output ? kOutput : 0u)});
  }
  return columns;
}

TimoshenkoPlasticBondTerm::State TimoshenkoPlasticBondTerm::state(std::size_t k) const {
  State st;
  for (std::size_t c = 0; c < State::kSize; ++c)
    st[c] = bonds_.model_column(c)[k];
  return st;
}

void TimoshenkoPlasticBondTerm::store_state(std::size_t k, const State& st) {
  for (std::size_t c = 0; c < State::kSize; ++c)
    bonds_.model_column(c)[k] = st[c];
}

const std::vector<double>* TimoshenkoPlasticBondTerm::plastic_work() const {
  return &bonds_.model_column(kWorkColumn);
}

double TimoshenkoPlasticBondTerm::ghost_width(const ParticleStore&) const {
  return Beam::bond_reach(bonds_);
}

void TimoshenkoPlasticBondTerm::rebuild(RebuildContext& ctx) {
  for (std::size_t k = 0; k < bonds_.size(); ++k)
    if (bonds_.type[k] < 0 || static_cast<std::size_t>(bonds_.type[k]) >= plastic_.size())
      throw std::runtime_error("bond " + std::to_string(bonds_.gid_a[k]) + "-" +
                               std::to_string(bonds_.gid_b[k]) + " has type " +
                               std::to_string(bonds_.type[k]) + " without plastic limits");
  Beam::register_bonds(bonds_, ctx, slots_a_, slots_b_);
}

void TimoshenkoPlasticBondTerm::compute(ComputeContext& ctx) {
  broke_ = false;
  const ParticleStore& p = ctx.particles;
  BondStore& bonds = bonds_;
  const std::size_t nb = bonds.size();
  failed_.resize(nb);
  yielding_.resize(nb);
  // Two passes. The first, a vector loop like the elastic term's, runs the elastic predictor
  // of every bond (its measured deformation less its plastic elongation; the hinges are in its
  // frames), the yield test and, where no end is beyond yield, the failure test: for such a
  // bond that is the whole step, since BondTimoshenkoPlastic::compute() returns these very
  // bits and changes neither its state nor its frames. Most bonds, most steps, are such. The
  // second pass runs the full step, return mapping included, for the others one at a time.
  {
    const BeamColumns col(bonds);
    BeamSlots out(ctx.slots, slots_a_, slots_b_);
    const double* const elongation = bonds.model_column(kElongationColumn).data();
    const double* const strain = bonds.model_column(kStrainColumn).data();
    std::int64_t* __restrict__ const failed = failed_.data();
    std::int64_t* __restrict__ const yielding = yielding_.data();
    BeamChunk& g = scratch_;
    ChunkLimits& lim = limits_;
    for_each_chunk(IndexRange{0, nb}, BeamChunk::kSize, [&](IndexRange chunk) {
      g.load(p, bonds, chunk);
      for (std::size_t c = 0; c < chunk.size(); ++c)
        lim.load(c, params(chunk.begin + c));
      for_each(chunk, [&](std::size_t k) {
        const std::size_t c = k - chunk.begin;
        const Plastic::Params pp = lim[c];
        const auto sec = col.section(k);
        const double delta_p = elongation[k];
        const auto r = BondTimoshenko::compute(
            sec, col.reference(k), g.x_a(c), g.q_a(c), g.x_b(c), g.q_b(c),
            [delta_p](const BondTimoshenko::Deformation& q, const BondTimoshenko::ChordFrame&) {
              return Plastic::elastic_part(q, State{delta_p});
            });
        const std::int64_t intact = g.broken[c] == 0;
        const std::int64_t beyond =
            Plastic::beyond_yield(pp, strain[k], r.axial_force, r.bending_a, r.bending_b);
        // Plastic::check_failure() with the state unchanged: Eq. 3–5, or the strain limit.
        const std::int64_t fails =
            col.fails(k, sec, r) | ((pp.failure_strain > 0.0) & (strain[k] >= pp.failure_strain));
        yielding[k] = beyond & intact;
        failed[k] = fails & intact & !beyond;
        out.write(k, intact & !beyond & !fails, r);
      });
    });
  }
  // The bonds beyond yield: one backward-Euler step each. One that fails keeps its state of
  // the step's start, and book_failures() redoes its step from it (the same bits) for the
  // bookkeeping.
  for (std::size_t k = 0; k < nb; ++k) {
    if (!yielding_[k]) continue;
    const std::uint32_t a = bonds.index_a[k], b = bonds.index_b[k];
    const auto sec = Beam::section(bonds, k);
    const Plastic::Params& pp = params(k);
    State st = state(k);
    auto ref = Beam::reference(bonds, k);  // a hinge that forms re-bases its end frame
    const auto r = Plastic::compute(sec, pp, ref, p.position[a], p.orientation[a], p.position[b],
                                    p.orientation[b], st);
    Vec3 fa, ta, fb, tb;  // zero: failing
    if (Plastic::check_failure(sec, pp, Beam::strength(bonds, k), r, st).broken()) {
      failed_[k] = 1;
    } else {
      store_state(k, st);
      bonds.frame_a[k] = ref.frame_a;
      bonds.frame_b[k] = ref.frame_b;
      fa = r.force_a;
      ta = r.torque_a;
      fb = r.force_b;
      tb = r.torque_b;
    }
    ctx.slots.set(slots_a_.begin + k, fa, ta);
    ctx.slots.set(slots_b_.begin + k, fb, tb);
  }
  if (std::find(failed_.begin(), failed_.end(), 1) != failed_.end())
    book_failures(p, ctx.time, ctx.dt);
}

void TimoshenkoPlasticBondTerm::book_failures(const ParticleStore& p, double time, double dt) {
  BondStore& bonds = bonds_;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!failed_[k]) continue;
    const std::uint32_t a = bonds.index_a[k], b = bonds.index_b[k];
    const auto sec = Beam::section(bonds, k);
    const auto ref = Beam::reference(bonds, k);  // the frames of the step's start
    const Plastic::Params& pp = params(k);
    const State before = state(k);
    State st = before;
    auto frames = ref;  // a broken bond keeps the frames it had (no force acts on them again)
    const auto r = Plastic::compute(sec, pp, frames, p.position[a], p.orientation[a], p.position[b],
                                    p.orientation[b], st);
    const auto fail = Plastic::check_failure(sec, pp, Beam::strength(bonds, k), r, st);
    bonds.broken[k] = 1;
    bonds.failure[k] =
        fail.stress != BondFailure::kNone ? fail.stress : BondFailure::kPlasticStrain;
    bonds.break_time[k] = time;
    // Energy ledger (docs/physics.md "Energy ledger"): the force acted through the first half
    // of this step and is zero from this evaluation on. Over the step it would have done the
    // change of elastic energy plus the step's plastic work; half of that happened, so the bond
    // books the mean of its elastic energy at the two ends of the step (the start: x - v dt,
    // q rotated back, the state of the start, as the elastic term) and half the step's plastic
    // work.
    const auto r0 = Plastic::evaluate(sec, pp, ref, p.position[a] - p.velocity[a] * dt,
                                      Beam::rotated_back(p.orientation[a], p.omega[a], dt),
                                      p.position[b] - p.velocity[b] * dt,
                                      Beam::rotated_back(p.orientation[b], p.omega[b], dt), before);
    bonds.break_energy[k] = 0.5 * (r0.energy + r.energy);
    st.work = before.work + 0.5 * (st.work - before.work);
    store_state(k, st);
    broke_ = true;
  }
}

double TimoshenkoPlasticBondTerm::update_diagnostics(const ParticleStore& p) const {
  return Beam::write_diagnostics(bonds_, [&](std::size_t k) {
    const std::uint32_t a = bonds_.index_a[k];
    const std::uint32_t b = bonds_.index_b[k];
    const auto sec = Beam::section(bonds_, k);
    const Plastic::Params& pp = params(k);
    const State st = state(k);
    // Right after the step's compute() at these positions: no flow, the step's resultants.
    const auto r = Plastic::evaluate(sec, pp, Beam::reference(bonds_, k), p.position[a],
                                     p.orientation[a], p.position[b], p.orientation[b], st);
    double utilisation =
        BondTimoshenko::utilisation(BondTimoshenko::stresses(sec, r), Beam::strength(bonds_, k));
    if (pp.failure_strain > 0.0) utilisation = std::max(utilisation, st.strain / pp.failure_strain);
    return Beam::Diagnostics{r.axial_force, std::max(r.bending_a, r.bending_b), utilisation,
                             r.energy};
  });
}

}  // namespace ringdem

// The plastic bond model through the step loop (model timoshenko_plastic, issue 14): a bond
// between a fixed and a driven particle, pulled past yield along its axis and unloaded, against
// the closed-form bar with linear hardening (docs/physics.md "Plastic bond": in tension
// N = N_p (1 + h kappa), kappa = delta_p / L0, so k (u - delta_p) = N_p (1 + h delta_p / L0)),
// against the evaluator replayed on the same trajectory, and the energy ledger.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "BondChain.hpp"
#include "TestCases.hpp"
#include "engine/EnergyLedger.hpp"
#include "engine/GatherMap.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "engine/TimoshenkoBondTerm.hpp"
#include "engine/TimoshenkoPlasticBondTerm.hpp"
#include "physics/BondTimoshenkoPlastic.hpp"

namespace ringdem {
namespace {

using testing::self_comm;
using Plastic = BondTimoshenkoPlastic;

constexpr double kYieldStress = 1500e6, kHardeningRatio = 0.05, kSteel = 200e9;
constexpr int kWindings = 12;
constexpr double kWire = 0.003;

/// A fixed sphere at the origin and a prescribed one at (l0, 0, 0) moving at `speed` along x,
/// bonded with the plastic model (strengths far above what the pull reaches: no Eq. 3–5 break).
CaseConfig pulled_pair(double l0, double speed, double failure_strain) {
  CaseConfig c = testing::base_case();
  BondConfig& bond = c.bonds[0];
  bond.model = "timoshenko_plastic";
  bond.tensile_strength = bond.compressive_strength = bond.shear_strength = 1e13;
  BondPlasticConfig plastic;
  plastic.yield_stress = kYieldStress;
  plastic.hardening_ratio = kHardeningRatio;
  plastic.failure_strain = failure_strain;
  plastic.windings = kWindings;
  plastic.wire_diameter = kWire;
  bond.plastic = plastic;
  SphereConfig a, b;
  a.motion = Motion::kFixed;
  b.position = {l0, 0, 0};
  b.velocity = {speed, 0, 0};
  b.motion = Motion::kPrescribed;
  c.spheres = {a, b};
  return c;
}

struct Pair {
  double n_p = 0.0;  ///< axial yield, n_w f_y pi d^2 / 4 (independent of the code's Params)
  double h = 0.0;    ///< hardening modulus over f_y: E_h / f_y, E_h = E b / (1 - b)
  double k = 0.0;    ///< axial stiffness of the bond (its store column)
  double l0 = 0.0;
};

Pair expected_pair(const Simulation& sim) {
  Pair p;
  p.n_p = kWindings * kYieldStress * M_PI * kWire * kWire / 4.0;
  p.h = kSteel * kHardeningRatio / (1.0 - kHardeningRatio) / kYieldStress;
  p.k = sim.model().bonds.k_axial[0];
  p.l0 = sim.model().bonds.length0[0];
  return p;
}

/// The bar's closed form after a pull to extension u (u beyond yield): plastic elongation and
/// the work of N over it, int N_p (1 + h d / L0) dd.
double plastic_elongation(const Pair& p, double u) {
  return (p.k * u - p.n_p) / (p.k + p.n_p * p.h / p.l0);
}
double plastic_work(const Pair& p, double dp) {
  return p.n_p * (dp + 0.5 * p.h * dp * dp / p.l0);
}

double extension(const Simulation& sim) {
  const ParticleStore& p = sim.model().particles;
  return norm(p.position[1] - p.position[0]);
}

// Pulled to three times the yield extension, then driven back until the bond force is zero:
// the extension at zero force is the permanent elongation of the closed form (within the
// step's travel), the state column holds it, the ledger's plastic work is the evaluator's
// accumulated work on the same trajectory to the bit and the closed form's within backward
// Euler's first-order error, and the ledger closes.
TEST(PlasticBondTerm, PulledPastYieldAndUnloadedKeepsThePermanentElongation) {
  const double l0 = 0.0097, speed = 0.5;
  CaseConfig c = pulled_pair(l0, speed, 0.0);
  Model model = build_model(c);
  add_bond(model, 0, 1, 0, 1);
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 1e-7;
  Simulation sim(std::move(model), comm, st);
  const Pair pair = expected_pair(sim);
  const BondStore& bonds = sim.model().bonds;
  ASSERT_EQ(bonds.size(), 1u);
  ASSERT_EQ(bonds.n_model_columns(), Plastic::State::kSize);
  const double step_travel = speed * sim.dt();

  // The evaluator on its own, replayed on the positions the run reaches (the same inputs).
  const auto sec = TimoshenkoBondTerm::section(bonds, 0);
  auto ref = TimoshenkoBondTerm::reference(bonds, 0);  // a pure pull forms no hinge
  const Plastic::Params params = sim.model().plastic_bond_types[0];
  Plastic::State replay;
  const auto replay_step = [&] {
    const ParticleStore& p = sim.model().particles;
    return Plastic::compute(sec, params, ref, p.position[0], p.orientation[0], p.position[1],
                            p.orientation[1], replay);
  };
  replay_step();  // the force evaluation of the constructor

  const Energies e0 = sim.energies();
  double worst_balance = 0.0, max_work = 0.0;
  const auto book = [&] {
    const Energies e = sim.energies();
    worst_balance = std::max(worst_balance, std::abs(e.balance_error(e0)));
    max_work = std::max(max_work, std::abs(e.boundary_work));
    return e;
  };

  const double u_yield = pair.n_p / pair.k;
  const double u_max = 3.0 * u_yield;
  while (extension(sim) - pair.l0 < u_max) {
    sim.step();
    replay_step();
    book();
  }
  const double u_reached = extension(sim) - pair.l0;
  double u_prev = u_reached, n_prev = 0.0, u_zero = 0.0;
  {
    const Energies e = book();
    n_prev = bonds.axial_force[0];
    EXPECT_GT(e.plastic_work, 0.0);
  }
  // Pulling: boundary work = elastic energy + plastic work, up to the difference between the
  // trapezoid of the driven particle's power and backward Euler's plastic work,
  // 1/2 sum dN d(delta_p) (first order in dt; 1e-5 of the work here, measured 9e-6).
  EXPECT_LT(worst_balance, 2e-5 * max_work);
  // The reversal: the trapezoid books the step after it with the power of the velocity before
  // the jump, an error of at most N v dt once.
  const double reversal = n_prev * speed * sim.dt();
  sim.model().particles.velocity[1] = {-speed, 0, 0};
  Energies e;
  for (int guard = 0;; ++guard) {
    ASSERT_LT(guard, 10000000) << "the bond force never reached zero";
    sim.step();
    replay_step();
    e = book();
    const double u = extension(sim) - pair.l0, n = bonds.axial_force[0];
    if (n <= 0.0) {
      u_zero = u_prev + (u - u_prev) * n_prev / (n_prev - n);  // linear between the two steps
      break;
    }
    u_prev = u;
    n_prev = n;
  }
  const double dp = plastic_elongation(pair, u_reached);
  ASSERT_GT(dp, 1.5 * u_yield) << "the pull should have gone well past yield";
  // Interpolated zero crossing; the elastic slope is exact, so only round-off and the step's
  // travel in the peak (u_reached is a sampled extension) remain.
  EXPECT_NEAR(u_zero, dp, 0.01 * step_travel) << "u_yield " << u_yield;
  EXPECT_NEAR(bonds.model_column(0)[0], dp, 0.01 * step_travel);  // plastic_elongation
  EXPECT_NEAR(bonds.model_column(1)[0], dp / pair.l0, 0.01 * step_travel / pair.l0);  // kappa
  // The ledger sums the bond's column exactly; the replay books the same steps.
  EXPECT_EQ(e.plastic_work, replay.work);
  EXPECT_EQ(bonds.model_column(2)[0], replay.work);
  // Backward Euler books N_{n+1} d(delta_p): above the integral by about
  // 1/2 N_p h / L0 * delta_p * (travel per step) = 1e-4 relative here.
  EXPECT_NEAR(e.plastic_work / plastic_work(pair, dp), 1.0, 1e-3);
  // Unloaded: the work put in is the plastic work plus the little elastic energy left.
  EXPECT_GT(e.boundary_work, e.plastic_work);
  EXPECT_LT(e.bond_elastic, 1e-6 * e.plastic_work);
  EXPECT_LT(worst_balance, 2e-5 * max_work + reversal);  // measured 0.9 reversal
}

// With a plastic strain limit, the pulled bond breaks where kappa = delta_p / L0 reaches it
// (BondFailure::kPlasticStrain), keeps its plastic work (half of the breaking step's
// included), the broken-bond tally takes its elastic energy, and the ledger closes.
TEST(PlasticBondTerm, StrainLimitBreaksTheBondWhichKeepsItsPlasticWork) {
  const double l0 = 0.0097, speed = 0.5, kappa_f = 0.01;
  CaseConfig c = pulled_pair(l0, speed, kappa_f);
  Model model = build_model(c);
  add_bond(model, 0, 1, 0, 1);
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 1e-7;
  Simulation sim(std::move(model), comm, st);
  const Pair pair = expected_pair(sim);
  const BondStore& bonds = sim.model().bonds;
  const Energies e0 = sim.energies();
  double worst_balance = 0.0, max_work = 0.0, elastic_before = 0.0;
  Energies e = e0;
  std::int64_t steps = 0;
  while (!bonds.broken[0]) {
    ASSERT_LT(++steps, 10000000) << "the bond never broke";
    elastic_before = e.bond_elastic;
    sim.step();
    e = sim.energies();
    worst_balance = std::max(worst_balance, std::abs(e.balance_error(e0)));
    max_work = std::max(max_work, std::abs(e.boundary_work));
  }
  EXPECT_EQ(bonds.failure[0], BondFailure::kPlasticStrain);
  // The closed form: delta_p = kappa_f L0 at u = delta_p + N_p (1 + h kappa_f) / k.
  const double dp = kappa_f * pair.l0;
  const double u_break = dp + pair.n_p * (1.0 + pair.h * kappa_f) / pair.k;
  EXPECT_NEAR(extension(sim) - pair.l0, u_break, 1.01 * speed * sim.dt());
  EXPECT_GE(bonds.model_column(1)[0], kappa_f);
  // Kept after the break: plastic work within the step's share of it of the closed form.
  const double work = plastic_work(pair, dp);
  EXPECT_NEAR(e.plastic_work / work, 1.0, 1e-3);
  EXPECT_EQ(e.bond_elastic, 0.0);
  EXPECT_NEAR(e.broken_bonds / elastic_before, 1.0, 1e-3);  // half a step of loading more
  // As in the pull above (measured 6e-6): the break books the mean elastic energy and half the
  // step's plastic work, which is what the force did through the first half of the step.
  EXPECT_LT(worst_balance, 2e-5 * max_work);
  sim.run_steps(100);
  EXPECT_EQ(sim.energies().plastic_work, e.plastic_work) << "the broken bond keeps its work";
}

// A free particle whipped about its fixed partner, undamped: in the first 0.2 ms the bond turns
// plastically by about 16 degrees, bending in both planes and twisting, and takes up 80 % of the
// kinetic energy as plastic work; then it rings elastically about its permanent shape for
// 3.8 ms (dozens of periods). Nothing else acts, so kinetic + elastic energy + plastic work
// must stay the initial kinetic energy, and the ringing must neither gain energy nor flow on.
// Tolerances: the imbalance after the whip was measured at 8e-4 of the kinetic energy (bound
// 2e-3), and its change while the bond rings at 5.6e-4 (bound 1.5e-3); both are the same at
// half the step, so they are the co-rotational kernel's geometry at rotations of the yield
// rotation (0.06 rad), not the time step. The plastic work may grow by 1e-3 of itself while
// ringing (measured 5e-5). With the plastic rotations
// kept as angles beside the large total rotation (before the hinges moved into the end
// frames), the loads of the bent hinge were not conservative: the ringing gained 40 % of the
// energy and the plastic work grew past the energy put in.
TEST(PlasticBondTerm, AWhippedHingeRingsWithoutGainingEnergy) {
  const double l0 = 0.0097;
  CaseConfig c = pulled_pair(l0, 0.0, 0.0);
  c.spheres[1].motion = Motion::kFree;
  c.spheres[1].velocity = {9.0, 135.0, -90.0};
  c.spheres[1].omega = {27000.0, 12000.0, -18000.0};
  Model model = build_model(c);
  add_bond(model, 0, 1, 0, 1);
  const Communicator comm = self_comm();
  SimulationSettings st = settings_from_case(c);
  st.dt = 2e-8;
  Simulation sim(std::move(model), comm, st);
  const Energies e0 = sim.energies();
  const double kinetic = e0.kinetic;
  ASSERT_GT(kinetic, 0.0);
  const int whip = 10000, steps = 200000;
  sim.run_steps(whip);
  const Energies whipped = sim.energies();
  const double whip_error = std::abs(whipped.balance_error(e0));
  double ringing_error = 0.0;
  for (int i = whip; i < steps; i += 100) {
    sim.run_steps(100);
    ringing_error = std::max(
        ringing_error, std::abs(sim.energies().balance_error(e0) - whipped.balance_error(e0)));
  }
  const Energies e = sim.energies();
  ASSERT_FALSE(sim.model().bonds.broken[0]);
  const ParticleStore& p = sim.model().particles;
  EXPECT_GT(norm(rotation_vector(conjugate(p.orientation[0]) * p.orientation[1])), 0.2)
      << "a hinge of over 11 degrees";
  EXPECT_GT(whipped.plastic_work, 0.5 * kinetic) << "the whip went far into the plastic range";
  EXPECT_LT(whip_error, 2e-3 * kinetic);
  EXPECT_LT(ringing_error, 1.5e-3 * kinetic);
  EXPECT_LT(e.plastic_work - whipped.plastic_work, 1e-3 * whipped.plastic_work);
}

// The term's step (a vector pass of the elastic predictor with the yield and failure tests,
// then the full step of the bonds beyond yield) against BondTimoshenkoPlastic::compute() and
// check_failure() called bond by bond on copies of the state: the same loads, states, frames
// and failures to the bit. A chain of 700 bonds (chunks of 256, the last partial) with random
// end turns and shifts of mixed size and random plastic states, so that both passes and
// every failure path are taken: some bonds already broken, some weak in tension (Eq. 4), some
// at their plastic strain limit.
TEST(PlasticBondTerm, TheVectorPassGivesTheBondByBondStepsBits) {
  constexpr std::size_t kBonds = 700;
  const double l0 = 0.0097, radius = 0.0045;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0), size(0.0, 1.0);
  ParticleStore p = testing::straight_chain(kBonds, l0, radius);
  BondTimoshenko::Params beam;
  beam.youngs_modulus = 288.4e9;
  beam.radius_multiplier = 0.43;
  beam.tensile_strength = beam.compressive_strength = 41e9;
  beam.shear_strength = 12e9;
  const Plastic::Params limits =
      Plastic::Params::from_wire_bundle(kWindings, kWire, kYieldStress, kHardeningRatio, kSteel,
                                        /*failure_strain=*/0.035);
  BondStore bonds;
  bonds.declare_model_columns(TimoshenkoPlasticBondTerm::state_columns());
  testing::bond_chain(bonds, p, kBonds, beam);
  TimoshenkoPlasticBondTerm term(bonds, {limits});
  for (std::size_t k = 0; k < kBonds; ++k) {
    Plastic::State st;
    if (k % 3 != 0) {  // an earlier plastic history
      st.elongation = 2e-4 * unit(rng);
      st.strain = 0.02 * size(rng);
      st.work = 10.0 * size(rng);
    }
    if (k % 41 == 5) st.strain = limits.failure_strain;
    term.store_state(k, st);
    if (k % 53 == 7) bonds.broken[k] = 1;
    if (k % 37 == 11) bonds.tensile_strength[k] = 1e6;
  }
  // Turns of up to 0.25 rad and shifts of up to 1 mm, scaled per particle by s^3 (s uniform
  // in [0, 1]): the yield rotation is about 0.06 rad, so some bonds stay elastic and some flow.
  for (std::size_t k = 0; k <= kBonds; ++k) {
    const double s = size(rng), scale = s * s * s;
    p.position[k] += Vec3{unit(rng), unit(rng), unit(rng)} * (1e-3 * scale);
    p.orientation[k] =
        quat_from_rotation_vector(Vec3{unit(rng), unit(rng), unit(rng)} * (0.25 * scale));
  }

  // Before: the bond-by-bond reference, on copies.
  struct Expected {
    Vec3 fa, ta, fb, tb;
    Plastic::State state;
    Quat frame_a, frame_b;
    bool broken = false;
  };
  std::vector<Expected> expected(kBonds);
  std::size_t flowing = 0, elastic = 0, failing = 0;
  for (std::size_t k = 0; k < kBonds; ++k) {
    Expected& e = expected[k];
    const Plastic::State before = term.state(k);
    e.state = before;
    e.frame_a = bonds.frame_a[k];
    e.frame_b = bonds.frame_b[k];
    e.broken = bonds.broken[k] != 0;
    if (e.broken) continue;
    const auto sec = TimoshenkoBondTerm::section(bonds, k);
    auto ref = TimoshenkoBondTerm::reference(bonds, k);
    Plastic::State st = before;
    const auto r = Plastic::compute(sec, limits, ref, p.position[k], p.orientation[k],
                                    p.position[k + 1], p.orientation[k + 1], st);
    (r.plastic_work > 0.0 ? flowing : elastic) += 1;
    if (Plastic::check_failure(sec, limits, TimoshenkoBondTerm::strength(bonds, k), r, st)
            .broken()) {
      ++failing;
      e.broken = true;  // no loads; the state of the step with half its plastic work
      e.state = st;
      e.state.work = before.work + 0.5 * (st.work - before.work);
      continue;
    }
    e.fa = r.force_a;
    e.ta = r.torque_a;
    e.fb = r.force_b;
    e.tb = r.torque_b;
    e.state = st;
    e.frame_a = ref.frame_a;
    e.frame_b = ref.frame_b;
  }
  ASSERT_GT(flowing, 100u);
  ASSERT_GT(elastic, 100u);
  ASSERT_GT(failing, 20u);

  testing::TermBench bench;
  bench.rebuild(term, p);
  const ForceSlots& slots = bench.slots;
  ASSERT_EQ(slots.fx.size(), 2 * kBonds);  // end a's slots, then end b's
  bench.compute(term, p, 1e-6);

  const auto same = [](const Vec3& a, const Vec3& b) {
    return a.x == b.x && a.y == b.y && a.z == b.z;
  };
  const auto same_quat = [](const Quat& a, const Quat& b) {
    return a.w == b.w && a.x == b.x && a.y == b.y && a.z == b.z;
  };
  std::size_t differ = 0;
  for (std::size_t k = 0; k < kBonds; ++k) {
    const Expected& e = expected[k];
    const Plastic::State st = term.state(k);
    const bool ok = same(slots.force(k), e.fa) && same(slots.torque(k), e.ta) &&
                    same(slots.force(kBonds + k), e.fb) && same(slots.torque(kBonds + k), e.tb) &&
                    st.elongation == e.state.elongation && st.strain == e.state.strain &&
                    st.work == e.state.work && same_quat(bonds.frame_a[k], e.frame_a) &&
                    same_quat(bonds.frame_b[k], e.frame_b) && (bonds.broken[k] != 0) == e.broken;
    if (!ok && ++differ <= 5) ADD_FAILURE() << "bond " << k << " differs";
  }
  EXPECT_EQ(differ, 0u) << "of " << kBonds << " bonds (" << flowing << " flowing, " << elastic
                        << " elastic, " << failing << " failing)";
}

// The case's plastic section, with the wire bundle from derive_from, sets the limits of
// docs/physics.md (per wire: area pi d^2 / 4, plastic modulus d^3 / 6).
TEST(PlasticBondTerm, LimitsComeFromTheCaseAndDeriveFrom) {
  CaseConfig c = pulled_pair(0.0097, 0.0, 0.02);
  BondPlasticConfig& pl = *c.bonds[0].plastic;
  pl.windings = 0;  // from derive_from
  pl.wire_diameter.reset();
  c.bonds[0].derive_from = BondDerivationConfig{19, 0.0025, 210e9};
  const Model m = build_model(c);
  ASSERT_EQ(m.plastic_bond_types.size(), 1u);
  const Plastic::Params& p = m.plastic_bond_types[0];
  const double d = 0.0025;
  EXPECT_NEAR(p.axial_yield, 19 * kYieldStress * M_PI * d * d / 4.0, 1e-9 * p.axial_yield);
  EXPECT_NEAR(p.plastic_moment, 19 * kYieldStress * d * d * d / 6.0, 1e-9 * p.plastic_moment);
  EXPECT_NEAR(p.hardening, 210e9 * kHardeningRatio / (1.0 - kHardeningRatio) / kYieldStress,
              1e-9 * p.hardening);
  EXPECT_EQ(p.failure_strain, 0.02);
  // The elastic model has no plastic limits and its store no model columns.
  CaseConfig elastic = testing::base_case();
  elastic.spheres = c.spheres;
  const Model e = build_model(elastic);
  EXPECT_TRUE(e.plastic_bond_types.empty());
  EXPECT_EQ(e.bonds.n_model_columns(), 0u);
  EXPECT_EQ(build_model(c).bonds.n_model_columns(), Plastic::State::kSize);
}

}  // namespace
}  // namespace ringdem

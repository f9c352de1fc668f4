// The particle-pair contact term sums each particle's contact loads itself (no slot per pair):
// each owned particle must get exactly the loads of its touching partners, added one by one in
// ascending partner key (sort bin, gid) after gravity (DESIGN §4, the gather order), whatever
// the storage order and whether the partner is a ghost. The reference below is an independent
// brute-force loop over partners sorted by key, calling the Hertz–Mindlin evaluator directly;
// the comparison is bit for bit, since the order of the additions is the contract.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <ostream>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

#include "domain/SpatialBins.hpp"
#include "engine/ContactKeys.hpp"
#include "engine/PairContactTerm.hpp"
#include "physics/HertzMindlin.hpp"

namespace ringdem {
namespace {

// A dense cloud (many overlaps) with gids shuffled against the storage order; the last
// `n_ghost` particles are ghosts. `bin_width` > 0: every particle binned by space (SpatialBins),
// as after a re-sort, the store left in neither gid nor key order. `side`: the cube the centres
// fill (a wider one, a loose cloud where most candidates do not touch).
ParticleStore dense_cloud(int n, int n_ghost, unsigned seed, double bin_width = 0.0,
                          double side = 0.03) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> pos(0.0, side), rad(0.002, 0.004), vel(-0.5, 0.5);
  std::vector<std::int64_t> gids(static_cast<std::size_t>(n));
  for (int k = 0; k < n; ++k)
    gids[static_cast<std::size_t>(k)] = 10 + 3 * k;
  std::shuffle(gids.begin(), gids.end(), rng);
  ParticleStore p;
  for (int k = 0; k < n; ++k) {
    ParticleStore::NewParticle np;
    np.gid = gids[static_cast<std::size_t>(k)];
    np.position = {pos(rng), pos(rng), pos(rng)};
    np.velocity = {vel(rng), vel(rng), vel(rng)};
    np.omega = {100 * vel(rng), 100 * vel(rng), 100 * vel(rng)};
    np.radius = rad(rng);
    np.density = 2600.0;
    p.add(np);
  }
  if (bin_width > 0.0) SpatialBins::assign(p, {bin_width});
  // Ghosts: the last particles become ghosts, every field copied back (as the comm layer would).
  ParticleStore all = p;
  p.resize_local(static_cast<std::size_t>(n - n_ghost));
  p.resize_ghosts(static_cast<std::size_t>(n_ghost));
  p.for_each_field([&](const FieldInfo& info, auto& field) {
    all.for_each_field([&](const FieldInfo& other, auto& source) {
      if constexpr (std::is_same_v<std::decay_t<decltype(field)>, std::decay_t<decltype(source)>>)
        if (info.name == other.name)
          for (std::size_t k = p.n_local(); k < p.n_total(); ++k)
            field[k] = source[k];
    });
  });
  p.rebuild_index();
  return p;
}

struct CloudCase {
  const char* name;         ///< in the test's name
  double bin_width;         ///< 0: unbinned
  double side;              ///< of the cube the centres fill
  double skin;              ///< of the neighbour lists
  std::size_t touching;     ///< at least this many touching contact ends
  double touching_at_most;  ///< of the candidates, at most this fraction touching
};

// The case's name where gtest (and ctest's discovery) print the parameter.
void PrintTo(const CloudCase& cloud, std::ostream* out) {
  *out << cloud.name;
}

class PairContactTermOrder : public ::testing::TestWithParam<CloudCase> {};

// Unbinned (every key (0, gid): gid order) and binned in cubes of 6 mm (5 a side of the cloud);
// and a loose cloud, where most candidates of a chunk do not touch and the kernel visits only
// those that the distance filter picks (PairContactTerm.cpp, touching_mask()).
INSTANTIATE_TEST_SUITE_P(Clouds, PairContactTermOrder,
                         ::testing::Values(CloudCase{"Unbinned", 0.0, 0.03, 0.0005, 500, 1.0},
                                           CloudCase{"Binned", 0.006, 0.03, 0.0005, 500, 1.0},
                                           CloudCase{"LooseBinned", 0.006, 0.06, 0.004, 60, 0.3}),
                         [](const ::testing::TestParamInfo<CloudCase>& param_info) {
                           return std::string(param_info.param.name);
                         });

TEST_P(PairContactTermOrder, EachParticleGetsItsContactsInAscendingPartnerKey) {
  const CloudCase cloud = GetParam();
  ParticleStore p = dense_cloud(400, 120, 11, cloud.bin_width, cloud.side);
  ASSERT_EQ(p.n_local(), 280u);
  ASSERT_EQ(p.n_total(), 400u);
  const MaterialTable materials({Material{"rock", 2600.0, 1e9, 0.25, 0.3, 0.5, 0.1}}, {});
  const Vec3 gravity{0.0, 0.0, -9.81};
  const double dt = 1e-6, skin = cloud.skin;

  PairContactTerm term;
  std::vector<ExcludedPair> excluded;
  SlotAllocator allocator;
  GatherMap gather;
  gather.begin(p.n_local());
  std::vector<RigidBody> bodies;
  RebuildContext rebuild{p, bodies, skin, excluded, allocator, gather, 0};
  term.rebuild(rebuild);
  EXPECT_EQ(allocator.size(), 0u) << "the pair term takes no slots";
  ForceSlots slots;
  EnergyLedger ledger;
  gather.finish(p);
  GatherMap::initialise_loads(p, gravity);
  ledger.begin_step(p.n_local(), {});
  ComputeContext ctx{
      p,      bodies, materials, slots,
      ledger, 0.0,    dt,        ParticleLoads{p.force.data(), p.torque.data(), p.n_local()}};
  term.compute(ctx);

  // Reference: every partner of k (owned or ghost) in ascending key, each contact evaluated
  // with the lower gid as end i, from a fresh tangential spring.
  std::size_t touching = 0, with_ghost = 0;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    std::vector<std::size_t> partners;
    for (std::size_t j = 0; j < p.n_total(); ++j)
      if (j != k && norm(p.position[j] - p.position[k]) < p.radius[j] + p.radius[k])
        partners.push_back(j);
    std::sort(partners.begin(), partners.end(), [&](std::size_t x, std::size_t y) {
      return p.sort_bin[x] != p.sort_bin[y] ? p.sort_bin[x] < p.sort_bin[y] : p.gid[x] < p.gid[y];
    });
    Vec3 f = gravity * p.mass[k];
    Vec3 t;
    for (const std::size_t j : partners) {
      const bool k_is_i = p.gid[k] < p.gid[j];
      const std::size_t a = k_is_i ? k : j, b = k_is_i ? j : k;
      const Vec3 d = p.position[b] - p.position[a];
      const double reach = p.radius[a] + p.radius[b];
      const double dist = std::sqrt(norm2(d));
      const Vec3 n = d / dist;
      const double overlap = reach - dist;
      const double arm_a = p.radius[a] - 0.5 * overlap, arm_b = p.radius[b] - 0.5 * overlap;
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
      Vec3 spring;
      const auto r = HertzMindlin::compute(materials.pair(0, 0), in, spring);
      if (k_is_i) {
        f += r.force_i;
        t += cross(n * arm_a, r.force_i) + r.rolling_torque_i;
      } else {
        f += -r.force_i;
        t += cross(n * arm_b, r.force_i) + r.rolling_torque_j;
      }
      ++touching;
      with_ghost += j >= p.n_local();
    }
    EXPECT_EQ(p.force[k].x, f.x) << "particle " << k;
    EXPECT_EQ(p.force[k].y, f.y) << "particle " << k;
    EXPECT_EQ(p.force[k].z, f.z) << "particle " << k;
    EXPECT_EQ(p.torque[k].x, t.x) << "particle " << k;
    EXPECT_EQ(p.torque[k].y, t.y) << "particle " << k;
    EXPECT_EQ(p.torque[k].z, t.z) << "particle " << k;
  }
  ASSERT_GT(touching, cloud.touching) << "the cloud must be dense enough to test anything";
  EXPECT_GT(with_ghost, cloud.touching / 25);
  EXPECT_LE(static_cast<double>(touching),
            cloud.touching_at_most * 2.0 * static_cast<double>(term.n_candidates()))
      << "a loose cloud: most candidates must not touch";
  if (cloud.bin_width > 0.0) {
    // The bins must reorder: some particle's partners in key order are out of gid order.
    std::size_t reordered = 0;
    for (std::size_t k = 0; k + 1 < p.n_total(); ++k)
      reordered += p.sorts_before(k, k + 1) != (p.gid[k] < p.gid[k + 1]);
    EXPECT_GT(reordered, p.n_total() / 4);
  }
}

/// A dense cloud's touching springs after one evaluation, packed for a rebuild; `between`
/// then changes the keyed rows and the particles as the step between pack and rebuild might
/// (migration, a re-sort), and the rebuild must give every pair that touched its own spring
/// back, and nothing else. Of two rows with one key the first is taken.
template <class Between>
void expect_every_spring_carried(ParticleStore& p, Between&& between) {
  const MaterialTable materials({Material{"rock", 2600.0, 1e9, 0.25, 0.3, 0.5, 0.0}}, {});
  PairContactTerm term;
  std::vector<ExcludedPair> excluded;
  std::vector<RigidBody> bodies;
  const auto rebuild = [&] {
    SlotAllocator allocator;
    GatherMap gather;
    gather.begin(p.n_local());
    RebuildContext ctx{p, bodies, 0.0005, excluded, allocator, gather, 0};
    term.rebuild(ctx);
  };
  rebuild();
  ForceSlots slots;
  EnergyLedger ledger;
  ledger.begin_step(p.n_local(), {});
  ComputeContext ctx{
      p,      bodies, materials, slots,
      ledger, 0.0,    1e-6,      ParticleLoads{p.force.data(), p.torque.data(), p.n_local()}};
  term.compute(ctx);
  const ContactSpringStore touching = term.touching_springs(p, ForceTerm::SpringRows::kAll);
  std::map<std::pair<std::int64_t, std::int64_t>, Vec3> before;
  for (std::size_t m = 0; m < touching.size(); ++m)
    before[{touching.gid[m], touching.partner[m]}] = touching.spring[m];
  ASSERT_GT(before.size(), 100u);
  // A checkpoint's: those whose first particle is owned here, each once.
  std::map<std::pair<std::int64_t, std::int64_t>, Vec3> owned_first;
  for (const auto& [key, spring] : before) {
    const std::int64_t a = p.index_of(key.first);
    if (a >= 0 && static_cast<std::size_t>(a) < p.n_local()) owned_first[key] = spring;
  }
  ASSERT_LT(owned_first.size(), before.size()) << "the cloud must have pairs led by a ghost";
  const ContactSpringStore counted = term.touching_springs(p, ForceTerm::SpringRows::kCounted);
  EXPECT_EQ(counted.size(), owned_first.size());
  for (std::size_t m = 0; m < counted.size(); ++m) {
    const auto it = owned_first.find({counted.gid[m], counted.partner[m]});
    ASSERT_NE(it, owned_first.end()) << "a counted spring led by a ghost, or none at all";
    EXPECT_EQ(counted.spring[m].x, it->second.x);
  }
  term.pack_springs(p);
  ContactSpringStore& store = *term.springs();
  ASSERT_EQ(store.size(), before.size());
  between(store);
  rebuild();
  EXPECT_EQ(term.springs()->size(), 0u) << "the keyed rows are read back and released";
  const ContactSpringStore after = term.touching_springs(p, ForceTerm::SpringRows::kAll);
  std::size_t carried = 0;
  for (std::size_t m = 0; m < after.size(); ++m) {
    const auto it = before.find({after.gid[m], after.partner[m]});
    ASSERT_NE(it, before.end()) << "a spring that was not there before";
    ++carried;
    EXPECT_EQ(after.spring[m].x, it->second.x);
    EXPECT_EQ(after.spring[m].y, it->second.y);
    EXPECT_EQ(after.spring[m].z, it->second.z);
  }
  EXPECT_EQ(carried, before.size());
}

// At a rebuild the carried springs (touching contacts, in whatever order migration left them)
// must go back to their pairs by key. Here the rows are reversed, as arrivals appended after
// migration would leave them out of order.
TEST(PairContactTerm, RebuildGivesEveryPairItsCarriedSpring) {
  ParticleStore p = dense_cloud(400, 120, 12);
  expect_every_spring_carried(p, [](ContactSpringStore& store) {
    ContactSpringStore reversed = store;
    for (std::size_t m = 0; m < store.size(); ++m) {
      const std::size_t r = store.size() - 1 - m;
      reversed.gid[m] = store.gid[r];
      reversed.partner[m] = store.partner[r];
      reversed.spring[m] = store.spring[r];
    }
    store = reversed;
  });
}

// A re-sort between the pack and the rebuild (SpatialBins, then the owned particles stored in
// the new key order, as migration does): the keyed rows, packed in the old candidate order, are
// in no order of the new candidates. Every spring must still go back to its pair; of two rows
// with one key the first is taken, and a row whose partner is not held here gives nothing.
TEST(PairContactTerm, RebuildAfterAReSortGivesEveryPairItsCarriedSpring) {
  ParticleStore p = dense_cloud(400, 120, 14);
  expect_every_spring_carried(p, [&p](ContactSpringStore& store) {
    // A second row of the first key, with another spring (it must lose), and a row of a
    // partner held nowhere (it must be ignored).
    store.append(store.gid[0], store.partner[0], Vec3{1.0, 2.0, 3.0});
    store.append(store.gid[1], 999999, Vec3{4.0, 5.0, 6.0});
    // The re-sort: bins of 6 mm on every particle (the ghosts' come from their owners), the
    // owned ones stored in key order.
    for (std::size_t k = 0; k < p.n_total(); ++k)
      p.sort_bin[k] = SpatialBins::bin_of(p.position[k], {0.006});
    std::vector<std::size_t> order(p.n_local());
    for (std::size_t k = 0; k < order.size(); ++k)
      order[k] = k;
    std::sort(order.begin(), order.end(),
              [&](std::size_t x, std::size_t y) { return p.sorts_before(x, y); });
    p.permute_local(order);
    p.rebuild_index();
  });
}

// A contact that opens forgets its spring (physics.md §3): the cloud is pulled apart so that no
// candidate touches (its candidates kept), then put back. Its loads must then be those of its first
// evaluation, from fresh springs, bit for bit, and nothing may be carried while it is apart.
TEST(PairContactTerm, AnOpenedContactForgetsItsSpring) {
  ParticleStore p = dense_cloud(300, 0, 13);
  const MaterialTable materials({Material{"rock", 2600.0, 1e9, 0.25, 0.3, 0.5, 0.1}}, {});
  const Vec3 gravity{0.0, 0.0, -9.81};
  PairContactTerm term;
  std::vector<ExcludedPair> excluded;
  std::vector<RigidBody> bodies;
  SlotAllocator allocator;
  GatherMap gather;
  gather.begin(p.n_local());
  RebuildContext rebuild{p, bodies, 0.0005, excluded, allocator, gather, 0};
  term.rebuild(rebuild);
  gather.finish(p);
  ForceSlots slots;
  EnergyLedger ledger;
  const auto compute = [&] {
    GatherMap::initialise_loads(p, gravity);
    ledger.begin_step(p.n_local(), {});
    ComputeContext ctx{
        p,      bodies, materials, slots,
        ledger, 0.0,    1e-6,      ParticleLoads{p.force.data(), p.torque.data(), p.n_local()}};
    term.compute(ctx);
  };
  compute();
  const std::vector<Vec3> first_force = p.force, first_torque = p.torque;
  ASSERT_GT(term.touching_springs(p, ForceTerm::SpringRows::kAll).size(), 100u);
  const std::vector<Vec3> together = p.position;
  for (std::size_t k = 0; k < p.n_total(); ++k)  // in a row 10 cm apart: nothing touches
    p.position[k] = Vec3{0.1 * static_cast<double>(k), 0.0, 0.0};
  compute();
  EXPECT_EQ(term.touching_springs(p, ForceTerm::SpringRows::kAll).size(), 0u)
      << "an open contact keeps no spring";
  p.position = together;
  compute();
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    EXPECT_EQ(p.force[k].x, first_force[k].x) << "particle " << k;
    EXPECT_EQ(p.force[k].y, first_force[k].y) << "particle " << k;
    EXPECT_EQ(p.force[k].z, first_force[k].z) << "particle " << k;
    EXPECT_EQ(p.torque[k].x, first_torque[k].x) << "particle " << k;
    EXPECT_EQ(p.torque[k].y, first_torque[k].y) << "particle " << k;
    EXPECT_EQ(p.torque[k].z, first_torque[k].z) << "particle " << k;
  }
}

// A table of one material gives every lane its parameters once (MaterialTable::uniform_pair(),
// PairContactChunk::fill_params()) instead of each contact's looked up by its ends' materials.
// The forces, torques and springs must be the same bits as the lookup's: here the same rock
// particles with a second, unused material in the table, which makes the term look up each
// pair. Rolling friction on, so that the chunks' rolling flag comes from the uniform pair too.
TEST(PairContactTerm, OneMaterialTableGivesTheForcesOfTheLookedUpParameters) {
  const Material rock{"rock", 2600.0, 1e9, 0.25, 0.3, 0.5, 0.1};
  const Material steel{"steel", 7800.0, 2e11, 0.3, 0.5, 0.3, 0.0};
  const MaterialTable one({rock}, {});
  const MaterialTable two({rock, steel}, {});
  Material rock_again = rock;
  rock_again.name = "rock2";
  ASSERT_NE(one.uniform_pair(), nullptr);
  ASSERT_EQ(two.uniform_pair(), nullptr) << "rock and steel make three different pairs";
  ASSERT_NE(MaterialTable({rock, rock_again}, {}).uniform_pair(), nullptr)
      << "two names of one rock make one pair";
  struct Outcome {
    ParticleStore p;
    ContactSpringStore springs;
  };
  const auto evaluate = [](const MaterialTable& materials) {
    Outcome out{dense_cloud(400, 120, 23),
                ContactSpringStore{ContactSpringStore::Partner::kParticle}};
    ParticleStore& p = out.p;
    PairContactTerm term;
    std::vector<ExcludedPair> excluded;
    std::vector<RigidBody> bodies;
    SlotAllocator allocator;
    GatherMap gather;
    gather.begin(p.n_local());
    RebuildContext rebuild{p, bodies, 0.0005, excluded, allocator, gather, 0};
    term.rebuild(rebuild);
    ForceSlots slots;
    EnergyLedger ledger;
    ledger.set_pair_booking(EnergyLedger::PairBooking::kPerContact);
    for (int step = 0; step < 3; ++step) {  // the carried loads' work from the second on
      EnergyLedger::EvaluationBooking booking;
      booking.initial = step == 0;
      ledger.begin_step(p.n_local(), booking);
      std::fill(p.force.begin(), p.force.end(), Vec3{});
      std::fill(p.torque.begin(), p.torque.end(), Vec3{});
      ComputeContext ctx{
          p,      bodies, materials, slots,
          ledger, 0.0,    1e-6,      ParticleLoads{p.force.data(), p.torque.data(), p.n_local()}};
      term.compute(ctx);
    }
    out.springs = term.touching_springs(p, ForceTerm::SpringRows::kAll);
    return out;
  };
  const Outcome uniform = evaluate(one), looked_up = evaluate(two);
  double largest_torque = 0.0;
  for (std::size_t k = 0; k < uniform.p.n_local(); ++k) {
    EXPECT_EQ(uniform.p.force[k].x, looked_up.p.force[k].x) << k;
    EXPECT_EQ(uniform.p.force[k].y, looked_up.p.force[k].y) << k;
    EXPECT_EQ(uniform.p.force[k].z, looked_up.p.force[k].z) << k;
    EXPECT_EQ(uniform.p.torque[k].x, looked_up.p.torque[k].x) << k;
    EXPECT_EQ(uniform.p.torque[k].y, looked_up.p.torque[k].y) << k;
    EXPECT_EQ(uniform.p.torque[k].z, looked_up.p.torque[k].z) << k;
    largest_torque = std::max(largest_torque, norm(uniform.p.torque[k]));
  }
  EXPECT_GT(largest_torque, 0.0);
  ASSERT_GT(uniform.springs.size(), 100u);
  ASSERT_EQ(uniform.springs.size(), looked_up.springs.size());
  for (std::size_t m = 0; m < uniform.springs.size(); ++m) {
    EXPECT_EQ(uniform.springs.spring[m].x, looked_up.springs.spring[m].x) << m;
    EXPECT_EQ(uniform.springs.spring[m].y, looked_up.springs.spring[m].y) << m;
    EXPECT_EQ(uniform.springs.spring[m].z, looked_up.springs.spring[m].z) << m;
  }
}

}  // namespace
}  // namespace ringdem

#include "app/Simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "physics/Integrator.hpp"

namespace ringdem {

namespace {

class PhaseTimer {
 public:
  explicit PhaseTimer(double& sink) : sink_(sink), start_(std::chrono::steady_clock::now()) {}
  ~PhaseTimer() {
    sink_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  PhaseTimer(const PhaseTimer&) = delete;
  PhaseTimer& operator=(const PhaseTimer&) = delete;

 private:
  double& sink_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

SimulationSettings settings_from_case(const CaseConfig& c) {
  SimulationSettings s;
  s.dt = c.simulation.dt.value_or(0.0);
  s.dt_safety = c.simulation.dt_safety;
  s.skin = c.simulation.skin;
  s.gravity = c.simulation.gravity;
  s.imbalance_threshold = c.simulation.imbalance_threshold;
  return s;
}

const char* Simulation::phase_name(int phase) {
  static const char* names[] = {"integrate", "neighbour", "bonds", "contacts", "gather"};
  return names[phase];
}

namespace {

/// Block width of the decomposition: a bond partner or a contact partner of a particle, up
/// to the next rebuild, must lie in a neighbouring block. Bonds may stretch 25 % before the
/// block is too small (steel bonds break at a few per cent).
double block_size_for(const Model& m, double skin) {
  double r_max = 0.0;
  for (double r : m.particles.radius)
    r_max = std::max(r_max, r);
  double bond_max = 0.0;
  for (double l : m.bonds.length0)
    bond_max = std::max(bond_max, l);
  const double reach = std::max(2.0 * r_max, 1.25 * bond_max) + skin;
  return reach > 0.0 ? reach : 1.0;
}

}  // namespace

Simulation::Simulation(Model model, const Communicator& comm, const SimulationSettings& settings)
    : model_(std::move(model)),
      comm_(comm),
      settings_(settings),
      decomposition_(comm, block_size_for(model_, settings.skin), settings.imbalance_threshold) {
  ParticleStore& p = model_.particles;
  p.rebuild_index();
  limits_ = stability_limits(p, model_.bonds, model_.materials);
  limits_.rayleigh = comm_.min(limits_.rayleigh);
  limits_.bond_axial = comm_.min(limits_.bond_axial);
  limits_.bond_shear = comm_.min(limits_.bond_shear);
  limits_.bond_rotation = comm_.min(limits_.bond_rotation);
  dt_ = settings_.dt > 0.0 ? settings_.dt : settings_.dt_safety * limits_.min();
  if (!(dt_ > 0.0) || !std::isfinite(dt_))
    throw std::runtime_error("cannot choose a time step: give simulation.dt explicitly");
  // Every rank built the whole model; keep this rank's share.
  decomposition_.distribute_initial(p, model_.bonds);
  rebuild();
  compute_forces();  // loads of the initial state, for the first half kick
  apply_global_damping(model_.particles);
}

void Simulation::rebuild() {
  ParticleStore& p = model_.particles;
  ContactHistory history = interactions_.export_history();
  decomposition_.redistribute(p, model_.bonds, history);
  interactions_.rebuild(p, model_.bonds, model_.bodies, settings_.skin, history);
  position_at_rebuild_.assign(p.position.begin(),
                              p.position.begin() + static_cast<std::ptrdiff_t>(p.n_local()));
  body_position_at_rebuild_.clear();
  body_orientation_at_rebuild_.clear();
  for (const auto& b : model_.bodies) {
    body_position_at_rebuild_.push_back(b.position);
    body_orientation_at_rebuild_.push_back(b.orientation);
  }
  force_rebuild_ = false;
  ++rebuilds_;
}

bool Simulation::needs_rebuild() {
  // How far any rigid surface point moved: translation plus rotation angle times extent.
  double body_move = 0.0;
  for (std::size_t b = 0; b < model_.bodies.size(); ++b) {
    const RigidBody& body = model_.bodies[b];
    if (body.motion == RigidMotion::kFixed) continue;
    const double angle =
        norm(rotation_vector(body.orientation * conjugate(body_orientation_at_rebuild_[b])));
    const double turn = angle > 0.0 ? angle * body.extent() : 0.0;
    body_move = std::max(body_move, norm(body.position - body_position_at_rebuild_[b]) + turn);
  }
  // One reduction per step for both triggers: the largest move, and whether a bond broke
  // anywhere in the last force evaluation (its pair may now touch).
  const auto global = comm_.max(
      std::array<double, 2>{std::sqrt(max_move2_), interactions_.bonds_broke() ? 1.0 : 0.0});
  const double particle_move = global[0];
  const bool bond_broke = global[1] > 0.0;
  bonds_broke_anywhere_ = bond_broke;
  // Two particles close by at most twice the largest move; a particle and a surface by the
  // sum of the two.
  return force_rebuild_ || bond_broke || 2.0 * particle_move > settings_.skin ||
         particle_move + body_move > settings_.skin;
}

void Simulation::compute_forces() {
  ParticleStore& p = model_.particles;
  {
    PhaseTimer t(phase_seconds_[kBonds]);
    interactions_.compute_bonds(p, model_.bonds, time_);
  }
  {
    PhaseTimer t(phase_seconds_[kContacts]);
    interactions_.compute_contacts(p, model_.bodies, model_.materials, dt_);
    reduce_body_loads();
  }
  {
    PhaseTimer t(phase_seconds_[kGather]);
    interactions_.gather(p, settings_.gravity);
  }
}

void Simulation::reduce_body_loads() {
  if (model_.bodies.empty()) return;
  // Every rank sums all contributions in (body, gid) order: the same bits for any rank count.
  auto loads = comm_.allgather(interactions_.body_loads());
  std::sort(loads.begin(), loads.end(), [](const auto& x, const auto& y) {
    return x.body < y.body || (x.body == y.body && x.gid < y.gid);
  });
  for (auto& b : model_.bodies) {
    b.force = {};
    b.torque = {};
  }
  for (const auto& l : loads) {
    RigidBody& b = model_.bodies[static_cast<std::size_t>(l.body)];
    b.force += l.force;
    b.torque += l.torque;
  }
}

void Simulation::step() {
  ParticleStore& p = model_.particles;
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    max_move2_ = Integrator::first_half(p, dt_, position_at_rebuild_);
    Integrator::first_half(model_.bodies, dt_, settings_.gravity);
  }
  time_ += dt_;
  {
    PhaseTimer t(phase_seconds_[kNeighbour]);
    decomposition_.update_ghosts(p);
    if (needs_rebuild()) rebuild();
  }
  compute_forces();
  {
    PhaseTimer t(phase_seconds_[kIntegrate]);
    Integrator::second_half(p, dt_);
    Integrator::second_half(model_.bodies, dt_, settings_.gravity);
  }
  ++steps_;
}

void Simulation::run_steps(std::int64_t n) {
  for (std::int64_t k = 0; k < n; ++k)
    step();
}

std::int64_t Simulation::global_particles() const {
  return comm_.sum(static_cast<std::int64_t>(model_.particles.n_local()));
}

std::int64_t Simulation::global_bonds() const {
  return comm_.sum(static_cast<std::int64_t>(model_.bonds.size()));
}

std::int64_t Simulation::global_broken_bonds() const {
  return comm_.sum(static_cast<std::int64_t>(model_.bonds.count_broken()));
}

Energies Simulation::energies() {
  interactions_.update_bond_diagnostics(model_.particles, model_.bonds);
  const ParticleStore& p = model_.particles;
  std::vector<std::int64_t> keys;
  std::vector<double> kin, pot;
  keys.reserve(p.n_local());
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    keys.push_back(p.gid[k]);
    if (p.motion[k] == Motion::kFree) {
      kin.push_back(0.5 * p.mass[k] * norm2(p.velocity[k]) +
                    0.5 * p.inertia[k] * norm2(p.omega[k]));
      pot.push_back(-p.mass[k] * dot(settings_.gravity, p.position[k]));
    } else {
      kin.push_back(0.0);
      pot.push_back(0.0);
    }
  }
  Energies e;
  e.kinetic = comm_.sum_by_key(keys, kin);
  e.potential = comm_.sum_by_key(keys, pot);
  std::vector<std::int64_t> bond_keys;
  std::vector<double> bond_energy;
  const BondStore& bonds = model_.bonds;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    const std::int64_t a = p.index_of(bonds.gid_a[k]);
    if (a < 0 || static_cast<std::size_t>(a) >= p.n_local()) continue;  // once: owner of end a
    bond_keys.push_back(bonds.gid_a[k]);
    bond_energy.push_back(bonds.energy[k]);
  }
  e.bond_elastic = comm_.sum_by_key(bond_keys, bond_energy);
  e.contact_elastic =
      comm_.sum_by_key({static_cast<std::int64_t>(comm_.rank())}, {interactions_.contact_energy()});
  for (const auto& b : model_.bodies) {
    if (b.motion != RigidMotion::kFree) continue;
    const Mat3 r = rotation_matrix(b.orientation);
    const Vec3 wb = r.transpose_times(b.omega);
    e.kinetic += 0.5 * b.mass * norm2(b.velocity) +
                 0.5 * (b.principal_inertia.x * wb.x * wb.x + b.principal_inertia.y * wb.y * wb.y +
                        b.principal_inertia.z * wb.z * wb.z);
    if (b.gravity) e.potential += -b.mass * dot(settings_.gravity, b.position);
  }
  return e;
}

}  // namespace ringdem

#pragma once

#include <array>
#include <cstdint>

#include "app/ModelBuilder.hpp"
#include "comm/Communicator.hpp"
#include "comm/DomainDecomposition.hpp"
#include "io/CaseConfig.hpp"
#include "physics/Interactions.hpp"
#include "physics/TimeStep.hpp"

namespace ringdem {

struct SimulationSettings {
  double dt = 0.0;  ///< <= 0: automatic, dt_safety times the smallest stability limit
  double dt_safety = 0.3;
  double skin = 0.001;
  Vec3 gravity{0, 0, -9.81};
  double imbalance_threshold = 0.1;  ///< repartition when max/mean particles - 1 exceeds it
};

/// The settings a case file asks for.
SimulationSettings settings_from_case(const CaseConfig& config);

/// Global energies (summed over ranks in gid order).
struct Energies {
  double kinetic = 0.0;    ///< particles (translation + rotation) and free rigid bodies
  double potential = 0.0;  ///< -m g.x of free particles and free bodies
  double bond_elastic = 0.0;
  double contact_elastic = 0.0;
  double total() const { return kinetic + potential + bond_elastic + contact_elastic; }
};

/// The time-step loop of DESIGN §3 over one Model.
class Simulation {
 public:
  Simulation(Model model, const Communicator& comm, const SimulationSettings& settings);

  /// Advances one step of dt.
  void step();
  /// Advances n steps.
  void run_steps(std::int64_t n);

  double time() const { return time_; }
  double dt() const { return dt_; }
  std::int64_t steps() const { return steps_; }
  std::int64_t rebuilds() const { return rebuilds_; }
  const StabilityLimits& limits() const { return limits_; }
  const SimulationSettings& settings() const { return settings_; }
  Model& model() { return model_; }
  const Model& model() const { return model_; }
  const Interactions& interactions() const { return interactions_; }
  const Communicator& comm() const { return comm_; }
  const DomainDecomposition& decomposition() const { return decomposition_; }

  /// True on every rank when a bond broke on any rank in the force evaluation of the
  /// previous step (known from the step's one reduction, so it costs no communication).
  bool bonds_broke_anywhere() const { return bonds_broke_anywhere_; }

  std::int64_t global_particles() const;
  std::int64_t global_bonds() const;
  std::int64_t global_broken_bonds() const;
  /// Refreshes the bond diagnostics (forces, utilisation, energy) and sums the energies.
  Energies energies();

  /// Seconds spent per phase since the start (this rank).
  enum Phase { kIntegrate, kNeighbour, kBonds, kContacts, kGather, kPhaseCount };
  static const char* phase_name(int phase);
  const std::array<double, kPhaseCount>& phase_seconds() const { return phase_seconds_; }

 private:
  void rebuild();
  void compute_forces();
  void reduce_body_loads();
  bool needs_rebuild();

  Model model_;
  const Communicator& comm_;
  SimulationSettings settings_;
  DomainDecomposition decomposition_;
  Interactions interactions_;
  StabilityLimits limits_{};
  double dt_ = 0.0;
  double time_ = 0.0;
  std::int64_t steps_ = 0;
  std::int64_t rebuilds_ = 0;
  bool force_rebuild_ = false;
  bool bonds_broke_anywhere_ = false;
  std::vector<Vec3> position_at_rebuild_;
  double max_move2_ = 0.0;  ///< largest squared particle move since the rebuild (this rank)
  std::vector<Vec3> body_position_at_rebuild_;
  std::vector<Quat> body_orientation_at_rebuild_;
  std::array<double, kPhaseCount> phase_seconds_{};
};

}  // namespace ringdem

#pragma once

// Small cases built in code (no YAML), shared by tests and benchmarks.

#include <mpi.h>

#include "comm/Communicator.hpp"
#include "io/CaseConfig.hpp"

namespace ringdem::testing {

/// A one-rank communicator; initialises MPI on first use (the test main finalises it).
inline Communicator self_comm() {
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) MPI_Init(nullptr, nullptr);
  return Communicator(MPI_COMM_SELF);
}

/// Steel (Table 1) and the Table 1 bond, no gravity, no damping.
inline CaseConfig base_case() {
  CaseConfig c;
  c.name = "test";
  c.simulation.gravity = {0, 0, 0};
  c.simulation.end_time = 1.0;
  MaterialConfig steel;
  steel.name = "steel";
  c.materials.push_back(steel);
  BondConfig bond;
  bond.name = "ring";
  c.bonds.push_back(bond);
  return c;
}

/// One ring of the paper: 300 mm internal diameter, 100 particles of 4.5 mm.
inline RingConfig paper_ring(const Vec3& centre = {}, const Vec3& normal = {0, 1, 0}) {
  RingConfig r;
  r.centre = centre;
  r.normal = normal;
  r.reference = {1, 0, 0};
  return r;
}

}  // namespace ringdem::testing

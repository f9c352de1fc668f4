// The schema tables of every case-file section (see CaseSchema.hpp). Only declarations of
// keys live here; checks that relate keys to each other are in CaseValidation.cpp.

#include "io/CaseSchema.hpp"

#include "io/DebrisSchema.hpp"
#include "io/ShackleSchema.hpp"

#include "engine/ModelTable.hpp"

#include <string>
#include <utility>
#include <vector>

namespace ringdem {

namespace {

using schema::above;
using schema::at_least;
using schema::interval;
using schema::Table;
using schema::Type;

std::vector<std::pair<std::string, Motion>> motions() {
  return {{"free", Motion::kFree}, {"fixed", Motion::kFixed}, {"prescribed", Motion::kPrescribed}};
}

const Table<SimulationConfig>& simulation_table() {
  using S = SimulationConfig;
  static const Table<S> table{
      "simulation",
      "Time integration and global settings.",
      {
          schema::number_or_auto("dt", &S::dt, above(0), "s",
                                 "Time step; `auto`: dt_safety times the smallest stability "
                                 "limit of contacts and bonds"),
          schema::number("dt_safety", &S::dt_safety, interval(0, false, 1, true), "",
                         "Fraction of the stability limit used when dt is `auto`"),
          schema::number("end_time", &S::end_time, above(0), "s",
                         "Simulated end time; a tensile test or rockfall that has not ended by "
                         "then stops there")
              .required(),
          schema::vec3("gravity", &S::gravity, "m/s^2", "Gravitational acceleration"),
          schema::number("skin", &S::skin, above(0), "m", "Verlet skin of the neighbour lists"),
          schema::number("progress_interval", &S::progress_interval, above(0), "s (wall)",
                         "Wall-clock time between progress lines"),
          schema::number("series_interval", &S::series_interval, above(0), "s",
                         "Simulated time between rows of series.csv"),
          schema::choice("contact_model", &S::contact_model, contact_model_names(),
                         "Particle contact law"),
          schema::number("imbalance_threshold", &S::imbalance_threshold, at_least(0), "",
                         "Repartition the ranks (METIS) at a neighbour-list rebuild when the "
                         "largest rank holds more than (1 + this) times the mean load (what "
                         "the partition balances: particles, bonds twice, one per cell; "
                         "docs/parallel.md)"),
          schema::number("initial_overlap_tolerance", &S::initial_overlap_tolerance,
                         interval(0, true, 1, true), "",
                         "A fresh start refuses (exit code 2) particles that overlap another "
                         "particle or a rigid body by more than this fraction of the smaller "
                         "radius at creation (bonded pairs and pairs of two non-free sides do "
                         "not count)"),
          schema::boolean("allow_initial_overlap", &S::allow_initial_overlap,
                          "Accept overlaps at creation (they start with contact forces and "
                          "energy)"),
          schema::boolean("energy_ledger", &S::energy_ledger,
                          "Book the energy ledger: the dissipation by contact damping, friction "
                          "and global damping, the boundary work and the contacts' elastic "
                          "energy. `false` (free runs only) writes null in those series.csv "
                          "columns, turns the energy guard off, steps a flow of many grains "
                          "faster and keeps 64-72 bytes less a grain in contact (16 more a "
                          "particle where something is damped); the motion is the same bits"),
          schema::integer(
              "sort_every", &S::sort_every, at_least(0),
              "Steps between re-sorts of the grains (particles of no ring or clump) "
              "by space: at set-up and at every multiple the neighbour lists are built with the "
              "grains stored and their contacts summed in the order of bins of twice "
              "the smallest grain radius (numbered slowest along the grains' longest "
              "extent: docs/architecture.md), so that a flow whose grains have mixed keeps "
              "its neighbours near in memory. The results are the same bits on any "
              "rank count and change at round-off with this value; 0: never (gid "
              "order)"),
          schema::integer(
              "substeps", &S::substeps, at_least(1),
              "Multi-rate stepping (docs/physics.md \"Two time scales\"): the net's bonds and "
              "every contact of a net particle step dt, the grains' contacts with each other "
              "and with rigid bodies, and gravity, once every `substeps` steps of dt, as "
              "impulses (r-RESPA). Rows, frames and checkpoints come at those grain steps; a "
              "restart keeps this value. Free runs only, without free or driven bodies, "
              "brakes, ropes or damping. 1: one rate"),
      }};
  return table;
}

const Table<MaterialConfig>& material_table() {
  using M = MaterialConfig;
  static const Table<M> table{
      "materials[]",
      "Contact materials of particles and rigid bodies; names must be unique.",
      {
          schema::text("name", &M::name, Type::kName, "Name the other sections refer to")
              .required(),
          schema::number("density", &M::density, above(0), "kg/m^3", "Density"),
          schema::number("youngs_modulus", &M::youngs_modulus, above(0), "Pa",
                         "Young's modulus (contact stiffness)"),
          schema::number("poisson_ratio", &M::poisson_ratio, interval(-1, false, 0.5, false), "",
                         "Poisson's ratio"),
          schema::number("restitution", &M::restitution, interval(0, false, 1, true), "",
                         "Coefficient of restitution (normal contact damping)"),
          schema::number("friction", &M::friction, at_least(0), "", "Sliding friction coefficient"),
          schema::number("rolling_friction", &M::rolling_friction, at_least(0), "",
                         "Rolling friction coefficient"),
      }};
  return table;
}

const Table<InteractionConfig>& interaction_table() {
  using I = InteractionConfig;
  const std::string mean = "mean of the two materials";
  static const Table<I> table{
      "interactions[]",
      "Coefficients of one pair of materials; pairs not listed use the mean of the two "
      "materials' values. Each pair may appear once.",
      {
          schema::name_pair("materials", &I::material_a, &I::material_b,
                            "The two materials (both must be defined; may be equal)")
              .required(),
          schema::optional_number("restitution", &I::restitution, interval(0, false, 1, true), "",
                                  "Coefficient of restitution of the pair")
              .default_text(mean),
          schema::optional_number("friction", &I::friction, at_least(0), "",
                                  "Sliding friction coefficient of the pair")
              .default_text(mean),
          schema::optional_number("rolling_friction", &I::rolling_friction, at_least(0), "",
                                  "Rolling friction coefficient of the pair")
              .default_text(mean),
      }};
  return table;
}

const Table<BondDerivationConfig>& bond_derivation_table() {
  using D = BondDerivationConfig;
  static const Table<D> table{
      "bonds[].derive_from",
      "The real ring the bond stands for. The bond modulus is then derived from the reduction "
      "factors (physics.md §2, Eq. 10-17): R_eq = sqrt(windings) * wire_diameter / 2, gamma = "
      "radius_multiplier * r_eq / R_eq with r_eq the particle radius of the rings using the "
      "bond, eta = 1 / (5 gamma^2), youngs_modulus = eta * steel_youngs_modulus. All rings "
      "using such a bond must have the same particle_radius.",
      {
          schema::integer("windings", &D::windings, at_least(1), "Number of wire windings n_w")
              .required(),
          schema::number("wire_diameter", &D::wire_diameter, above(0), "m",
                         "Diameter of the wire (2 r_w)")
              .required(),
          schema::number("steel_youngs_modulus", &D::steel_youngs_modulus, above(0), "Pa",
                         "Young's modulus E of the wire steel"),
      }};
  return table;
}

const Table<BondPlasticConfig>& bond_plastic_table() {
  using P = BondPlasticConfig;
  static const Table<P> table{
      "bonds[].plastic",
      "Plastic limits of the wire bundle the bond stands for (model timoshenko_plastic; "
      "docs/physics.md \"Plastic bond\"): n_w wires of diameter d in parallel yield at "
      "N_p = n_w f_y pi d^2 / 4 in tension and form hinges at M_p = n_w f_y d^3 / 6, on a "
      "parabolic N-M interaction, with linear isotropic hardening. windings, wire_diameter and "
      "steel_youngs_modulus come from the bond's derive_from when it has one (then they must not "
      "be given here); without derive_from, windings and wire_diameter are required.",
      {
          schema::number("yield_stress", &P::yield_stress, above(0), "Pa",
                         "Yield stress f_y of the wire (0.2 % proof stress)")
              .required(),
          schema::number("hardening_ratio", &P::hardening_ratio, interval(0, true, 1, false), "",
                         "Post-yield tangent over Young's modulus, b = E_t / E, of a bilinear "
                         "wire; E_h = E b / (1 - b) is the slope of stress over plastic strain"),
          schema::number("failure_strain", &P::failure_strain, at_least(0), "",
                         "Plastic strain limit: the bond breaks when its work-equivalent plastic "
                         "strain reaches it (in tension the wire's plastic strain; with bilinear "
                         "hardening f_u is reached at (f_u / f_y - 1) f_y / E_h); 0: no limit, "
                         "only Eq. 3-5"),
          schema::integer("windings", &P::windings, at_least(1), "Number of wire windings n_w")
              .default_text("derive_from.windings")
              .dump_if([](const P& p) { return p.windings > 0; }),
          schema::optional_number("wire_diameter", &P::wire_diameter, above(0), "m",
                                  "Diameter of the wire d")
              .default_text("derive_from.wire_diameter"),
          schema::optional_number("steel_youngs_modulus", &P::steel_youngs_modulus, above(0), "Pa",
                                  "Young's modulus E of the wire steel (for E_h)")
              .default_text("derive_from's, else 2e11"),
      }};
  return table;
}

const Table<BondConfig>& bond_table() {
  using B = BondConfig;
  static const Table<B> table{
      "bonds[]",
      "Parallel-bond properties of the ring wire; names must be unique.",
      {
          schema::text("name", &B::name, Type::kName, "Name the rings refer to").required(),
          schema::choice("model", &B::model, bond_model_names(), "Bond beam model"),
          schema::number("youngs_modulus", &B::youngs_modulus, above(0), "Pa",
                         "Young's modulus of the bond beam; not with `derive_from`")
              .dump_if([](const B& b) { return !b.derive_from; }),
          schema::optional_section("derive_from", &B::derive_from, bond_derivation_table(),
                                   "Derive youngs_modulus from the ring's windings and wire "
                                   "(physics.md §2) instead of giving it"),
          schema::optional_section("plastic", &B::plastic, bond_plastic_table(),
                                   "Plastic limits of the wire bundle: required by model "
                                   "timoshenko_plastic, refused by the elastic model"),
          schema::number("poisson_ratio", &B::poisson_ratio, interval(-1, false, 0.5, false), "",
                         "Poisson's ratio of the bond beam (shear modulus)"),
          schema::number("radius_multiplier", &B::radius_multiplier, interval(0, false, 2, true),
                         "", "Bond radius as a multiple of the particle radius"),
          schema::number("tensile_strength", &B::tensile_strength, above(0), "Pa",
                         "Mean tensile strength (normal + bending stress)"),
          schema::number("compressive_strength", &B::compressive_strength, above(0), "Pa",
                         "Mean compressive strength"),
          schema::number("shear_strength", &B::shear_strength, above(0), "Pa",
                         "Mean shear strength (shear + torsion stress)"),
          schema::number("strength_cov", &B::strength_cov, interval(0, true, 1, false), "",
                         "Coefficient of variation of the strengths (0: deterministic)"),
          schema::unsigned_integer("seed", &B::seed, "Random seed of the strength scatter"),
      }};
  return table;
}

const Table<DampingConfig>& damping_table() {
  using D = DampingConfig;
  static const Table<D> table{
      "damping",
      "Cundall non-viscous damping of particle motion.",
      {
          schema::number("global", &D::global, interval(0, true, 1, false), "",
                         "Coefficient of every particle group not listed in `groups`"),
          schema::number_map("groups", &D::groups, &DampingGroupConfig::group,
                             &DampingGroupConfig::coefficient, interval(0, true, 1, false),
                             "Coefficient per particle group (`group: coefficient`); each group "
                             "must be used by some particles"),
      }};
  return table;
}

const Table<RingConfig>& ring_table() {
  using R = RingConfig;
  static const Table<R> table{
      "particles.rings[]",
      "A ring of bonded spheres on a circle (centreline radius = internal_diameter / 2 + "
      "particle_radius), bonds between consecutive particles.",
      {
          schema::text("group", &R::group, Type::kName, "Particle group (damping, output)"),
          schema::vec3("centre", &R::centre, "m", "Centre of the ring"),
          schema::vec3("normal", &R::normal, "", "Ring axis (normalised)").nonzero(),
          schema::vec3("reference", &R::reference, "",
                       "Direction of the first particle from the centre (projected onto the "
                       "ring plane and normalised; must not be parallel to normal)")
              .nonzero(),
          schema::number("internal_diameter", &R::internal_diameter, above(0), "m",
                         "Clear inside diameter of the ring"),
          schema::integer("n_particles", &R::n_particles, at_least(3), "Spheres in the ring"),
          schema::number("particle_radius", &R::particle_radius, above(0), "m",
                         "Radius of the bonded spheres (the wire radius)"),
          schema::number("contact_radius", &R::contact_radius, above(0), "m",
                         "EDEM's bond-detection radius, kept for the clearance check between "
                         "rings at creation (contacts act at particle_radius); must be >= "
                         "particle_radius")
              .default_text("max(0.008, particle_radius)"),
          schema::text("material", &R::material, Type::kName, "Material (from `materials`)"),
          schema::text("bond", &R::bond, Type::kName, "Bond properties (from `bonds`)"),
          schema::optional_number("mass", &R::mass, above(0), "kg",
                                  "Real mass of the ring: the particle density is set so that "
                                  "the particles together weigh this much")
              .default_text("material density x particle volume"),
          schema::enum_choice("motion", &R::motion, motions(),
                              "free: integrated; fixed: never moves; prescribed: moves at "
                              "`velocity`"),
          schema::vec3("velocity", &R::velocity, "m/s", "Initial or prescribed velocity"),
      }};
  return table;
}

const Table<NetMeshConfig>& net_mesh_table() {
  using Mesh = NetMeshConfig;
  static const Table<Mesh> table{
      "particles.nets[].mesh",
      "A secondary mesh spanning every ring of the net, as the chain-link or hexagonal mesh of "
      "a debris-flow barrier (docs/physics.md \"Secondary mesh\"): a disc in the plane of "
      "each ring's beads, of the area of their polygon, which holds every grain of `opening` "
      "diameter or more whose centre lies on it, by a frictionless spring and dashpot on its "
      "overlap with the plane, fading out at the rim. Its loads on the ring's beads are "
      "gradients of its energy, so force and moment balance. Finer grains pass, as through "
      "the rings without a mesh. Its beads and the grains it can hold reach the ranks that "
      "need them half a ring's perimeter away (far ghosts); the other grains keep their "
      "one-block ghost layer.",
      {
          schema::number("opening", &Mesh::opening, above(0), "m",
                         "Mesh opening: grains of this diameter or more are held")
              .required(),
          schema::number("stiffness", &Mesh::stiffness, above(0), "N/m",
                         "Normal stiffness k of the mesh under one grain")
              .required(),
          schema::number("damping_ratio", &Mesh::damping_ratio, at_least(0), "",
                         "Damping ratio zeta of the mesh's dashpot, c = 2 zeta sqrt(k m*)"),
      }};
  return table;
}

const Table<RingNetConfig>& net_table() {
  using N = RingNetConfig;
  static const Table<N> table{
      "particles.nets[]",
      "A chain-mail net of rings like `rings` entries. The rings sit on a square "
      "lattice of pitch link_distance / sqrt(2) centred on `centre`, at the sites (column m, "
      "row n) with m + n odd; each is linked with its four diagonal neighbours. Ring planes are "
      "tilted about the net's x by +-tilt, alternating row by row, so that linked rings start "
      "clear of each other. The net's x, y and normal are the world's by default (a horizontal "
      "net); `normal` and `x_axis` turn it about `centre`, e.g. to stand across a channel. "
      "Defaults: the paper's net, 180 rings, 3.88 m x 3.87 m, with shackles.",
      {
          schema::text("group", &N::group, Type::kName, "Particle group of the net rings"),
          schema::integer("rows", &N::rows, at_least(2),
                          "Lattice rows (along the net's y); not with `length`")
              .dump_if([](const N& n) { return !n.length; }),
          schema::integer("columns", &N::columns, at_least(2),
                          "Lattice columns (along the net's x); not with `width`")
              .dump_if([](const N& n) { return !n.width; }),
          schema::optional_number(
              "width", &N::width, above(0), "m",
              "Target extent along the net's x (outer ring surfaces): sets `columns` "
              "to the closest fit, at least 2")
              .default_text("none (columns)"),
          schema::optional_number(
              "length", &N::length, above(0), "m",
              "Target extent along the net's y: sets `rows` to the closest fit, at "
              "least 2")
              .default_text("none (rows)"),
          schema::number("link_distance", &N::link_distance, above(0), "m",
                         "Centre distance of linked rings; must be < internal_diameter + 2 * "
                         "particle_radius"),
          schema::number("tilt", &N::tilt, interval(0, false, 1.5, true), "rad",
                         "Tilt of the ring planes about the net's x, alternating in sign row by "
                         "row"),
          schema::vec3("centre", &N::centre, "m",
                       "Centre of the net (the ring centres lie in its plane)"),
          schema::vec3("normal", &N::normal, "",
                       "Normal of the net's plane (normalised); rows and columns and `tilt` are "
                       "described for the default, a horizontal net")
              .nonzero(),
          schema::vec3("x_axis", &N::x_axis, "",
                       "Direction of the columns' spacing, the net's x (projected onto its "
                       "plane and normalised; must not be parallel to normal); its y is "
                       "normal x x_axis")
              .nonzero()
              .default_text("[1, 0, 0], or [0, 1, 0] for a net normal to x"),
          schema::number("internal_diameter", &N::internal_diameter, above(0), "m",
                         "Clear inside diameter of a ring"),
          schema::integer("n_particles", &N::n_particles, at_least(3), "Spheres per ring"),
          schema::number("particle_radius", &N::particle_radius, above(0), "m",
                         "Radius of the bonded spheres (the wire radius)"),
          schema::number("contact_radius", &N::contact_radius, above(0), "m",
                         "Clearance kept between the net's rings at creation (EDEM's "
                         "bond-detection radius; contacts act at particle_radius); must be >= "
                         "particle_radius")
              .default_text("max(0.008, particle_radius)"),
          schema::text("material", &N::material, Type::kName, "Material (from `materials`)"),
          schema::text("bond", &N::bond, Type::kName, "Bond properties (from `bonds`)"),
          schema::optional_number("mass", &N::mass, above(0), "kg",
                                  "Real mass of one ring (sets the particle density, as for "
                                  "`rings`)")
              .default_text("material density x particle volume"),
          schema::section("shackles", &N::shackles, shackle_table(),
                          "Rigid shackles holding the outer rings"),
          schema::optional_section("mesh", &N::mesh, net_mesh_table(),
                                   "A secondary mesh on every ring that holds finer grains"),
      }};
  return table;
}

const Table<LatticeConfig>& lattice_table() {
  using L = LatticeConfig;
  static const Table<L> table{
      "particles.lattices[]",
      "Free, unbonded spheres on a regular lattice.",
      {
          schema::text("group", &L::group, Type::kName, "Particle group (damping, output)"),
          schema::vec3("origin", &L::origin, "m", "Centre of the first sphere"),
          schema::int_triple("count", &L::count, at_least(1), "Spheres along x, y and z"),
          schema::number("spacing", &L::spacing, above(0), "m",
                         "Centre distance; must be >= 2 * particle_radius"),
          schema::number("particle_radius", &L::particle_radius, above(0), "m", "Sphere radius"),
          schema::text("material", &L::material, Type::kName, "Material (from `materials`)"),
          schema::vec3("velocity", &L::velocity, "m/s", "Initial velocity"),
          schema::number("jitter", &L::jitter, interval(0, true, 1, false), "",
                         "Random offset as a fraction of the gap between spheres"),
          schema::unsigned_integer("seed", &L::seed, "Random seed of the jitter"),
      }};
  return table;
}

const Table<SphereConfig>& sphere_table() {
  using P = SphereConfig;
  static const Table<P> table{
      "particles.spheres[]",
      "Explicitly listed spheres.",
      {
          schema::text("group", &P::group, Type::kName, "Particle group (damping, output)"),
          schema::vec3("position", &P::position, "m", "Centre"),
          schema::vec3("velocity", &P::velocity, "m/s", "Initial or prescribed velocity"),
          schema::vec3("omega", &P::omega, "rad/s", "Initial angular velocity"),
          schema::number("radius", &P::radius, above(0), "m", "Radius"),
          schema::text("material", &P::material, Type::kName, "Material (from `materials`)"),
          schema::enum_choice("motion", &P::motion, motions(),
                              "free: integrated; fixed: never moves; prescribed: moves at "
                              "`velocity`"),
      }};
  return table;
}

const Table<CaseConfig>& particles_table() {
  using C = CaseConfig;
  static const Table<C> table{
      "particles",
      "Particle generators; together they must create at least one particle.",
      {
          schema::list("rings", &C::rings, ring_table(), "Rings of bonded spheres"),
          schema::list("nets", &C::nets, net_table(), "Chain-mail nets of rings with shackles"),
          schema::list("lattices", &C::lattices, lattice_table(), "Lattices of free spheres"),
          schema::list("grains", &C::grains, grains_table(),
                       "Polydisperse grains filling boxes (debris)"),
          schema::list("spheres", &C::spheres, sphere_table(), "Single spheres"),
          schema::list("sphere_files", &C::sphere_files, sphere_file_table(),
                       "Spheres read from CSV files"),
      }};
  return table;
}

const Table<RigidBodyConfig>& rigid_body_table() {
  using B = RigidBodyConfig;
  static const Table<B> table{
      "rigid_bodies[]",
      "Walls, pins and boulders interacting with the particles; names must be unique. Keys that "
      "do not apply to the shape are rejected.",
      {
          schema::text("name", &B::name, Type::kName, "Name (output, series)").required(),
          schema::enum_choice("shape", &B::shape,
                              {{"plane", ShapeKind::kPlane},
                               {"cylinder", ShapeKind::kCylinder},
                               {"sphere", ShapeKind::kSphere}},
                              "Geometry")
              .required(),
          schema::vec3("position", &B::position, "m",
                       "plane: a point on it; cylinder, sphere: centre"),
          schema::vec3("normal", &B::normal, "",
                       "plane only: normal, pointing to the particle side (normalised)")
              .nonzero()
              .dump_if([](const B& b) { return b.shape == ShapeKind::kPlane; }),
          schema::vec3("axis", &B::axis, "", "cylinder only: axis (normalised)")
              .nonzero()
              .dump_if([](const B& b) { return b.shape == ShapeKind::kCylinder; }),
          schema::number("radius", &B::radius, above(0), "m", "cylinder, sphere: radius")
              .default_text("required for cylinder and sphere")
              .dump_if([](const B& b) { return b.shape != ShapeKind::kPlane; }),
          schema::number("length", &B::length, above(0), "m", "cylinder only: length (capped ends)")
              .default_text("required for cylinder")
              .dump_if([](const B& b) { return b.shape == ShapeKind::kCylinder; }),
          schema::text("material", &B::material, Type::kName, "Material (from `materials`)"),
          schema::enum_choice("motion", &B::motion, motions(),
                              "fixed: never moves; prescribed: moves at `velocity`/`omega`; "
                              "free: integrated from contact forces (not for planes)"),
          schema::vec3("velocity", &B::velocity, "m/s", "Prescribed or initial velocity"),
          schema::vec3("omega", &B::omega, "rad/s", "Prescribed or initial angular velocity"),
          schema::optional_number("mass", &B::mass, above(0), "kg",
                                  "Free body: mass (overrides material density x volume)")
              .default_text("from the material density"),
          schema::boolean("gravity", &B::gravity, "Free body: whether gravity acts on it"),
      }};
  return table;
}

const Table<TensileTestConfig>& tensile_test_table() {
  using T = TensileTestConfig;
  static const Table<T> table{
      "scenario.tensile_test",
      "Quasi-static tensile test (docs/tensile.md): the pins of the moving plate are driven at "
      "`loading_rate` along `pull_direction`; load = contact force on them against the pull "
      "direction, displacement = plate travel.",
      {
          schema::name_list("moving_bodies", &T::moving_bodies,
                            "Rigid bodies on the moving plate (`motion: prescribed`, no "
                            "`velocity`: the scenario sets it)")
              .required(),
          schema::vec3("pull_direction", &T::pull_direction, "",
                       "Direction the moving plate travels (normalised)")
              .nonzero(),
          schema::number("loading_rate", &T::loading_rate, above(0), "m/s",
                         "Plate speed (Table 1: 0.005)"),
          schema::number("max_displacement", &T::max_displacement, above(0), "m",
                         "Stop when the plate has travelled this far"),
          schema::number("failure_load_fraction", &T::failure_load_fraction,
                         interval(0, false, 1, false), "",
                         "Failure: once a bond has broken, stop when the load falls below "
                         "this fraction of its peak"),
          schema::number("record_interval", &T::record_interval, above(0), "m",
                         "Plate travel between rows of series.csv"),
          schema::optional_number("unload_at", &T::unload_at, above(0), "m",
                                  "Unloading: at this displacement the plate reverses at "
                                  "`loading_rate` until the load falls to zero; the test then "
                                  "ends and reports the residual displacement (below "
                                  "`max_displacement`)")
              .default_text("no unloading"),
      }};
  return table;
}

const Table<RockfallConfig>& rockfall_table() {
  using R = RockfallConfig;
  static const Table<R> table{
      "scenario.rockfall",
      "Rockfall impact test (docs/rockfall.md): the net sags under gravity to rest, then a "
      "spherical boulder is released drop_height above it. Time 0 of the results is the first "
      "contact.",
      {
          schema::number("boulder_mass", &R::boulder_mass, above(0), "kg",
                         "Boulder mass (paper: 825)"),
          schema::number("boulder_density", &R::boulder_density, above(0), "kg/m^3",
                         "Boulder density; the radius follows from mass and density"),
          schema::text("boulder_material", &R::boulder_material, Type::kName,
                       "Contact material of the boulder"),
          schema::number("drop_height", &R::drop_height, above(0), "m",
                         "Free fall from rest to the top of the sagged net (paper: 3 m)"),
          schema::optional_vec3("drop_point", &R::drop_point, "m",
                                "x, y of the drop axis (z ignored)")
              .default_text("centre of the net group"),
          schema::text("net_group", &R::net_group, Type::kName,
                       "Particle group of the net (sag, deflection, rest test)"),
          schema::text("frame_group", &R::frame_group, Type::kName,
                       "Particle group whose contact load is the force on the frame (the "
                       "shackles; braked shackles pass their brakes' loads to it instead)"),
          schema::number("sag_max_time", &R::sag_max_time, above(0), "s",
                         "Stop with an error when the net is not at rest by then"),
          schema::number("sag_min_time", &R::sag_min_time, at_least(0), "s", "Shortest sag phase"),
          schema::number("sag_kinetic_energy", &R::sag_kinetic_energy, above(0), "J",
                         "The net is at rest when the kinetic energy of all particles is below "
                         "this and below half its peak during the sag"),
          schema::number("sag_check_interval", &R::sag_check_interval, above(0), "s",
                         "Simulated time between rest checks"),
          schema::optional_number("sag_damping", &R::sag_damping, interval(0, true, 1, false), "",
                                  "Cundall coefficient of the net group while it sags")
              .default_text("as the damping section sets it"),
          schema::optional_number("sag_dt", &R::sag_dt, above(0), "s",
                                  "Time step while the net sags and re-settles (no boulder in "
                                  "play); the release goes back to simulation.dt. At most the "
                                  "smallest stability limit (the run refuses more); the settled "
                                  "state is the same within the rest test (docs/rockfall.md)")
              .default_text("simulation.dt"),
          schema::optional_number("impact_damping", &R::impact_damping, interval(0, true, 1, false),
                                  "", "Cundall coefficient of the net group from the release on")
              .default_text("as the damping section sets it"),
          schema::boolean("integrate_free_fall", &R::integrate_free_fall,
                          "Step through the whole fall (false: advance it analytically, exact "
                          "for a fall in vacuum, to release_gap above the net)"),
          schema::number("release_gap", &R::release_gap, above(0), "m",
                         "Boulder bottom above the net top where stepping resumes"),
          schema::number("duration", &R::duration, above(0), "s",
                         "Simulated time after the first contact"),
          schema::number("record_interval", &R::record_interval, above(0), "s",
                         "Simulated time between rows of series.csv (loads are averaged over "
                         "it)"),
          schema::integer("impacts", &R::impacts, at_least(1),
                          "Impacts on the same net without repair (the service energy level "
                          "test of EAD 340059-00-0106 has 2): with more than one, the boulder "
                          "is removed `duration` after each contact, the net re-settles to "
                          "rest (with sag_damping and the sag's rest test) and the next "
                          "boulder falls drop_height onto the deformed net"),
          schema::number("resettle_max_time", &R::resettle_max_time, above(0), "s",
                         "Stop with an error when the net is not at rest this long after a "
                         "boulder was removed (impacts > 1)"),
      }};
  return table;
}

const Table<ScenarioConfig>& scenario_table() {
  using S = ScenarioConfig;
  static const Table<S> table{
      "scenario",
      "What the run does and measures.",
      {
          schema::choice("type", &S::type, {"free_run", "tensile_test", "rockfall"},
                         "free_run: step to simulation.end_time, series of energies and "
                         "rigid-body forces; tensile_test: see scenario.tensile_test; "
                         "rockfall: see scenario.rockfall"),
          schema::section("tensile_test", &S::tensile_test, tensile_test_table(),
                          "Settings of a tensile test (required when type is tensile_test)")
              .dump_if([](const S& sc) { return sc.type == "tensile_test"; }),
          schema::section("rockfall", &S::rockfall, rockfall_table(),
                          "Settings of a rockfall impact test")
              .dump_if([](const S& sc) { return sc.type == "rockfall"; }),
          schema::optional_section("barrier", &S::barrier, barrier_table(),
                                   "free_run only: measures of a barrier in a debris flow"),
      }};
  return table;
}

const Table<OutputConfig>& output_table() {
  using O = OutputConfig;
  static const Table<O> table{
      "output",
      "Frame files for ParaView and checkpoints (docs/output.md). Frames: "
      "<output>/frames_NNNN.h5 with an XDMF sidecar, one pair per run segment; checkpoints: "
      "<output>/checkpoints/.",
      {
          schema::number("frame_interval", &O::frame_interval, at_least(0), "s",
                         "Simulated time between frames (0: no frames by time)"),
          schema::integer("frame_interval_steps", &O::frame_interval_steps, schema::at_least(0),
                          "Steps between frames (0: no frames by steps)"),
          schema::integer("compression", &O::compression, schema::interval(0, true, 9, true),
                          "Deflate level of the frame datasets (0: none; 1-3 saves about a "
                          "third on positions at a few per cent of run time)"),
          schema::number("checkpoint_interval", &O::checkpoint_interval, at_least(0), "s",
                         "Simulated time between checkpoints (0: only on SIGUSR1 or "
                         "--max-walltime)"),
          schema::number("checkpoint_wall_interval", &O::checkpoint_wall_interval, at_least(0),
                         "s (wall)", "Wall-clock time between checkpoints (0: none)"),
          schema::integer("checkpoints_kept", &O::checkpoints_kept, schema::at_least(1),
                          "Newest checkpoints kept; older ones are deleted"),
      }};
  return table;
}

}  // namespace

const schema::Table<CaseConfig>& case_schema() {
  using C = CaseConfig;
  static const schema::Table<C> table{
      "",
      "Top level of a case file.",
      {
          schema::integer("schema_version", &C::schema_version, schema::exactly(1),
                          "Version of this file format")
              .required(),
          schema::text("name", &C::name, Type::kString,
                       "Case name: the output folder results/<name> (no '/', '\\', '.' or "
                       "'..') and the banner")
              .default_text("file name without extension"),
          schema::text("description", &C::description, Type::kString, "Free text"),
          schema::section("simulation", &C::simulation, simulation_table(),
                          "Time integration settings")
              .required(),
          schema::list("materials", &C::materials, material_table(), "Contact materials")
              .required(),
          schema::list("interactions", &C::interactions, interaction_table(),
                       "Pair-specific contact coefficients"),
          schema::list("bonds", &C::bonds, bond_table(), "Bond properties of the rings"),
          schema::section("damping", &C::damping, damping_table(), "Numerical damping"),
          schema::inline_section("particles", particles_table(), "Particle generators").required(),
          schema::list("rigid_bodies", &C::rigid_bodies, rigid_body_table(),
                       "Rigid walls, pins, boulders"),
          schema::list("outflow", &C::outflow, outflow_table(),
                       "Outflow boxes: grains that leave them are taken out"),
          schema::list("inflow", &C::inflow, inflow_table(), "Inlets that add grains"),
          schema::section("scenario", &C::scenario, scenario_table(),
                          "Scenario driver and its measurements"),
          schema::section("output", &C::output, output_table(),
                          "Frame files (HDF5 + XDMF) and checkpoints"),
      }};
  return table;
}

}  // namespace ringdem

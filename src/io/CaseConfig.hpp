#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/Motion.hpp"
#include "core/Vec3.hpp"

namespace ringdem {

/// The validated contents of a case file (SI units). CaseLoader fills it; nothing here is
/// read from YAML directly by the solver. Every field has the default a user gets when the
/// key is left out. docs/case-file.md documents every key.

struct MaterialConfig {
  std::string name;
  double density = 7800.0;
  double youngs_modulus = 200e9;
  double poisson_ratio = 0.3;
  double restitution = 0.5;
  double friction = 1.0;
  double rolling_friction = 0.0;
};

/// Pair-specific contact coefficients; pairs not listed use the mean of the two materials.
struct InteractionConfig {
  std::string material_a, material_b;
  std::optional<double> restitution, friction, rolling_friction;
};

/// The ring the bond models, for deriving E_b from the reduction factors (physics.md §2).
struct BondDerivationConfig {
  int windings = 12;
  double wire_diameter = 0.003;
  double steel_youngs_modulus = 200e9;
};

/// Plastic limits of the wire bundle a bond stands for (model timoshenko_plastic,
/// docs/physics.md "Plastic bond"); windings, wire diameter and the steel's modulus come from
/// `derive_from` when the bond has it.
struct BondPlasticConfig {
  double yield_stress = 0.0;                   ///< f_y of the wire [Pa]
  double hardening_ratio = 0.0;                ///< b = E_t / E of a bilinear wire, in [0, 1)
  double failure_strain = 0.0;                 ///< plastic strain limit kappa_f; 0: none
  int windings = 0;                            ///< n_w; 0: derive_from.windings
  std::optional<double> wire_diameter;         ///< d; none: derive_from.wire_diameter
  std::optional<double> steel_youngs_modulus;  ///< E; none: derive_from's, else 200 GPa
};

struct BondConfig {
  std::string name;
  std::string model = "timoshenko";
  /// E_b; when `derive_from` is set the loader replaces it by eta E (Eq. 17) with r_eq the
  /// particle radius of the rings that use this bond.
  double youngs_modulus = 120e9;
  std::optional<BondDerivationConfig> derive_from;
  std::optional<BondPlasticConfig> plastic;  ///< required by timoshenko_plastic, else refused
  double derived_particle_radius = 0.0;      ///< r_eq used for the derivation (0: not derived)
  double poisson_ratio = 0.3;
  double radius_multiplier = 0.8;
  double tensile_strength = 16e9;
  double compressive_strength = 16e9;
  double shear_strength = 10e9;
  double strength_cov = 0.0;
  std::uint64_t seed = 1;
};

/// A ring of bonded spheres on a circle (centreline radius = internal_diameter/2 + particle
/// radius), bonds between consecutive particles only.
struct RingConfig {
  std::string group = "rings";
  Vec3 centre;
  Vec3 normal{0, 1, 0};     ///< ring axis
  Vec3 reference{1, 0, 0};  ///< direction of the first particle from the centre
  double internal_diameter = 0.3;
  int n_particles = 100;
  double particle_radius = 0.0045;
  double contact_radius = 0.008;
  std::string material = "steel";
  std::string bond = "ring";
  /// Real mass of the ring; when set, the particle density is chosen so that the particles
  /// weigh this much together (the material density is then used for contacts only).
  std::optional<double> mass;
  Motion motion = Motion::kFree;
  Vec3 velocity;
};

/// A brake element holding each shackle of a net to the frame (docs/physics.md "Brake
/// elements"); the shackles are then free rigid tori instead of fixed rings of spheres.
struct ShackleBrakeConfig {
  double activation_force = 0.0;  ///< F_b [N]
  double stroke = 1.0;            ///< [m]
  double stiffness = 1.0e7;       ///< k [N/m]
};

/// The brakes at a support rope's two ends (docs/physics.md "Support ropes"): they pay out rope
/// at the activation force until `stroke` of it has run through them in all.
struct RopeBrakeConfig {
  double activation_force = 0.0;  ///< F_b [N]
  double stroke = 1.0;            ///< [m]
};

/// Support ropes along the sides of a net, one per side, that its shackles slide on (docs/
/// physics.md "Support ropes"); the shackles are then free rigid tori.
struct ShackleRopeConfig {
  double axial_stiffness = 0.0;  ///< EA [N]
  double anchor_offset = 0.2;    ///< [m]: the ends' anchors beyond the side's outer shackles
  double pretension = 0.0;       ///< [N]: the tension at creation
  double friction = 0.0;         ///< mu between the rope and the shackles it runs through
  std::optional<RopeBrakeConfig> brake;
};

/// Rigid shackles holding the outer rings of a net (domain/RingNet.hpp): fixed rings of
/// unbonded spheres, one per boundary ring and side, or rigid tori held by brakes or ropes.
struct ShackleConfig {
  bool enabled = true;
  std::string group = "shackles";
  double internal_diameter = 0.06;
  int n_particles = 14;
  double particle_radius = 0.008;
  std::string material = "steel";
  std::optional<ShackleBrakeConfig> brake;
  std::optional<ShackleRopeConfig> ropes;
  /// With brakes or ropes the shackles are free rigid tori, not fixed rings of spheres.
  bool rigid_tori() const { return brake.has_value() || ropes.has_value(); }
};

/// A net's secondary mesh (`particles.nets[].mesh`; physics/RingMesh.hpp).
struct NetMeshConfig {
  double opening = 0.0;    ///< required
  double stiffness = 0.0;  ///< required
  double damping_ratio = 0.3;
};

/// A horizontal chain-mail net of rings (domain/RingNet.hpp); the defaults are the paper's
/// 180-ring net. `width` / `length`, when given, set `columns` / `rows` (the loader does).
struct RingNetConfig {
  std::string group = "net";
  int rows = 19;
  int columns = 19;
  std::optional<double> width;
  std::optional<double> length;
  double link_distance = 0.28;
  double tilt = 0.28;
  Vec3 centre;
  Vec3 normal{0, 0, 1};  ///< the net plane's normal (normalised by the loader)
  Vec3 x_axis{1, 0, 0};  ///< direction of the columns (projected onto the plane, normalised)
  double internal_diameter = 0.3;
  int n_particles = 100;
  double particle_radius = 0.0045;
  double contact_radius = 0.008;
  std::string material = "steel";
  std::string bond = "ring";
  std::optional<double> mass;  ///< per ring, as RingConfig::mass
  ShackleConfig shackles;
  std::optional<NetMeshConfig> mesh;
};

/// Free spheres on a regular lattice (debris, packing tests).
struct LatticeConfig {
  std::string group = "spheres";
  Vec3 origin;
  std::array<int, 3> count{1, 1, 1};
  double spacing = 0.01;
  double particle_radius = 0.0045;
  std::string material = "steel";
  Vec3 velocity;
  double jitter = 0.0;  ///< random offset as a fraction of the gap, seeded
  std::uint64_t seed = 1;
};

/// One size class of a grain mix: a radius and its share of the solid volume.
struct GrainFractionConfig {
  double radius = 0.0;
  double fraction = 0.0;
};

enum class GrainDistribution { kUniform, kLogNormal, kFractions };

/// The radii of a grain mix (domain/GrainSizeDistribution.hpp).
struct GrainSizesConfig {
  GrainDistribution distribution = GrainDistribution::kUniform;
  double min_radius = 0.0025;
  double max_radius = 0.025;
  double median_radius = 0.0;  ///< log_normal
  double sigma = 0.0;          ///< log_normal: standard deviation of ln r
  std::vector<GrainFractionConfig> fractions;
};

/// Polydisperse grains filling a box at a solid fraction (debris; engine/GrainSource.hpp).
struct GrainsConfig {
  std::string group = "grains";
  std::string material;
  Vec3 box_min;
  Vec3 box_max;
  double solid_fraction = 0.3;
  GrainSizesConfig sizes;
  Vec3 velocity;
  std::uint64_t seed = 1;
};

/// One explicitly listed sphere.
struct SphereConfig {
  std::string group = "spheres";
  Vec3 position;
  Vec3 velocity;
  Vec3 omega;
  double radius = 0.0045;
  std::string material = "steel";
  Motion motion = Motion::kFree;
};

/// Free spheres read from a CSV packing, x,y,z,radius a line (io/SphereFile.hpp).
struct SphereFileConfig {
  std::string path;  ///< as given; relative to the case file's folder
  std::string group = "spheres";
  std::string material;
  Vec3 velocity;
  std::int64_t count = 0;  ///< spheres in the file (validation reads it; not a case key)
};

enum class ShapeKind { kPlane, kCylinder, kSphere };

struct RigidBodyConfig {
  std::string name;
  ShapeKind shape = ShapeKind::kPlane;
  Vec3 position;         ///< plane: a point on it; cylinder, sphere: centre
  Vec3 normal{0, 0, 1};  ///< plane normal (pointing to the side particles are on)
  Vec3 axis{0, 0, 1};    ///< cylinder axis
  double radius = 0.0;   ///< cylinder, sphere
  double length = 0.0;   ///< cylinder length (finite, capped)
  std::string material = "steel";
  Motion motion = Motion::kFixed;
  Vec3 velocity;  ///< prescribed velocity or initial velocity of a free body
  Vec3 omega;
  std::optional<double> mass;  ///< free body: mass (else from the material density)
  bool gravity = true;         ///< free body feels gravity
};

struct DampingGroupConfig {
  std::string group;
  double coefficient = 0.0;
};

struct DampingConfig {
  double global = 0.0;  ///< Cundall coefficient for every particle group not listed below
  std::vector<DampingGroupConfig> groups;
};

struct SimulationConfig {
  std::optional<double> dt;  ///< fixed time step; empty: auto
  double dt_safety = 0.3;    ///< dt = safety * min(stability limits) when automatic
  double end_time = 1.0;
  Vec3 gravity{0, 0, -9.81};
  double skin = 0.001;             ///< Verlet skin of the neighbour lists
  double progress_interval = 2.0;  ///< wall seconds between progress lines
  double series_interval = 1e-3;   ///< simulated seconds between series.csv rows
  std::string contact_model = "hertz_mindlin";
  double imbalance_threshold = 0.1;  ///< repartition when max/mean particles - 1 exceeds it
  /// A fresh start refuses contacts that overlap by more than this fraction of the smaller
  /// radius (Simulation::overlaps), unless allow_initial_overlap.
  double initial_overlap_tolerance = 1e-3;
  bool allow_initial_overlap = false;
  /// Book the energy ledger (SimulationSettings::energy_ledger); only a free run may go without.
  bool energy_ledger = true;
  /// Steps between re-sorts of the grains by space (SimulationSettings::sort_every); 0: never.
  int sort_every = 1000;
  /// Fast sub-steps per grain step (SimulationSettings::substeps); 1: one rate.
  int substeps = 1;
};

/// Quasi-static tensile test of ring elements (the paper's "DEM Modeling of a Tensile Test"):
/// the rigid bodies named in `moving_bodies` (pins on the moving plate) are driven at
/// `loading_rate` along `pull_direction`; load = contact force on them against that direction,
/// displacement = their travel.
struct TensileTestConfig {
  std::vector<std::string> moving_bodies;
  Vec3 pull_direction{0, 0, 1};
  double loading_rate = 0.005;         ///< plate speed (Table 1)
  double max_displacement = 0.5;       ///< stop when the plate has travelled this far
  double failure_load_fraction = 0.5;  ///< after a bond broke, stop once load < this x peak
  double record_interval = 2e-4;       ///< plate travel between rows of series.csv
  /// Unloading: at this plate travel the plate reverses at loading_rate until the load falls to
  /// zero; the test then ends and reports the residual displacement. Empty: no unloading.
  std::optional<double> unload_at;
};

/// Rockfall impact test (the paper's "Modeling of Rockfall Impact Tests", docs/rockfall.md):
/// the net sags under gravity until it is at rest, then a spherical boulder is released
/// `drop_height` above the sagged net and falls onto it.
struct RockfallConfig {
  double boulder_mass = 825.0;
  double boulder_density = 2600.0;  ///< radius = (3 m / (4 pi rho))^(1/3)
  std::string boulder_material = "steel";
  double drop_height = 3.0;        ///< free fall from rest to first contact (24.3 kJ for 825 kg)
  std::optional<Vec3> drop_point;  ///< x, y of the drop axis; default: centre of the net group
  std::string net_group = "net";   ///< particles whose sag and deflection are measured
  std::string frame_group = "shackles";  ///< particles whose contact load is the frame force
  double sag_max_time = 2.0;             ///< give up waiting for rest (error) after this
  double sag_min_time = 0.05;
  double sag_kinetic_energy = 0.05;   ///< J: at rest below this and half its peak
  double sag_check_interval = 1e-3;   ///< simulated seconds between rest checks
  std::optional<double> sag_damping;  ///< Cundall coefficient of the net while it sags
  std::optional<double> sag_dt;       ///< time step while the net sags or re-settles (default: dt)
  std::optional<double> impact_damping;  ///< of the net from the release on (default: as set)
  bool integrate_free_fall = false;  ///< false: the fall is advanced analytically to release_gap
  double release_gap = 0.005;        ///< boulder bottom above the net top when stepping resumes
  double duration = 0.6;             ///< simulated time after first contact
  double record_interval = 1e-4;     ///< simulated seconds between rows of series.csv
  int impacts = 1;                   ///< impacts on the same net without repair (EAD 340059 SEL)
  double resettle_max_time = 2.0;    ///< give up waiting for the net to rest after an impact
};

/// What a free run measures of a barrier in a flow (app/BarrierMonitor): the loads on the net
/// (through the fixed frame that holds it) and on posts, the flow upstream, what is retained
/// and what went over, and the net's deflection.
struct BarrierConfig {
  Vec3 direction{1, 0, 0};                ///< the flow direction the barrier holds (normalised)
  Vec3 position;                          ///< a point of the barrier plane (normal to direction)
  std::vector<std::string> grain_groups;  ///< empty: every free particle in no ring
  std::string net_group;                  ///< empty: no net
  std::string frame_group;                ///< fixed particles holding the net; empty: none
  std::vector<std::string> posts;         ///< rigid bodies of the barrier
  std::string bed;                        ///< plane rigid body the flow runs on
  double gauge_distance = 1.0;            ///< upstream end of the gauge section [m]
  double gauge_length = 0.5;              ///< its length along direction [m]
  double retention_length = 2.0;          ///< upstream reach counted as retained [m]
  double width = 0.0;  ///< flow width at the gauge, for the bulk density (0: not computed) [m]
};

struct ScenarioConfig {
  std::string type = "free_run";  ///< free_run | tensile_test | rockfall
  TensileTestConfig tensile_test;
  RockfallConfig rockfall;
  std::optional<BarrierConfig> barrier;  ///< free_run only
};

/// Frame files and checkpoints (DESIGN §5).
struct OutputConfig {
  double frame_interval = 0.0;            ///< simulated seconds between frames (0: by steps or off)
  int frame_interval_steps = 0;           ///< steps between frames (0: by time or off)
  int compression = 0;                    ///< deflate level of frame datasets, 0-9
  double checkpoint_interval = 0.0;       ///< simulated seconds between checkpoints (0: none)
  double checkpoint_wall_interval = 0.0;  ///< wall seconds between checkpoints (0: none)
  int checkpoints_kept = 2;
};

/// A box that grains may not leave: those whose centre goes out are taken out of the model
/// (engine/OutflowSink.hpp).
struct OutflowConfig {
  std::string name;
  Vec3 box_min;
  Vec3 box_max;
  std::vector<std::string> groups;  ///< empty: every free grain in no ring
};

/// An inlet that adds grains during the run at a discharge (engine/InflowSource.hpp).
struct InflowConfig {
  std::string name;
  std::string group = "grains";
  std::string material;
  Vec3 box_min;
  Vec3 box_max;
  Vec3 velocity;
  double discharge = 0.0;  ///< m^3/s of solid
  double start_time = 0.0;
  std::optional<double> end_time;  ///< none: as long as the run
  GrainSizesConfig sizes;
  std::uint64_t seed = 1;
};

struct CaseConfig {
  int schema_version = 1;
  std::string name;
  std::string description;
  SimulationConfig simulation;
  std::vector<MaterialConfig> materials;
  std::vector<InteractionConfig> interactions;
  std::vector<BondConfig> bonds;
  DampingConfig damping;
  std::vector<RingConfig> rings;
  std::vector<RingNetConfig> nets;
  std::vector<LatticeConfig> lattices;
  std::vector<GrainsConfig> grains;
  std::vector<SphereConfig> spheres;
  std::vector<SphereFileConfig> sphere_files;
  std::vector<RigidBodyConfig> rigid_bodies;
  std::vector<OutflowConfig> outflow;
  std::vector<InflowConfig> inflow;
  ScenarioConfig scenario;
  OutputConfig output;
  std::string source_path;  ///< the file it came from, for messages
};

}  // namespace ringdem

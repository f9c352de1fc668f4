// The schema tables of the debris entries (see DebrisSchema.hpp).

#include "io/DebrisSchema.hpp"

namespace ringdem {

namespace {

using schema::above;
using schema::at_least;
using schema::interval;
using schema::Table;
using schema::Type;

const Table<GrainFractionConfig>& grain_fraction_table() {
  using F = GrainFractionConfig;
  static const Table<F> table{
      "particles.grains[].sizes.fractions[]",
      "One size class of a grain mix.",
      {
          schema::number("radius", &F::radius, above(0), "m", "Radius of the class").required(),
          schema::number("fraction", &F::fraction, interval(0, false, 1, true), "",
                         "Share of the solid volume (mass at one density); the shares sum to 1")
              .required(),
      }};
  return table;
}

const Table<GrainSizesConfig>& grain_sizes_table() {
  using S = GrainSizesConfig;
  static const Table<S> table{
      "particles.grains[].sizes",
      "Radius distribution of the grains. Keys that do not apply to the distribution are "
      "rejected.",
      {
          schema::enum_choice("distribution", &S::distribution,
                              {{"uniform", GrainDistribution::kUniform},
                               {"log_normal", GrainDistribution::kLogNormal},
                               {"fractions", GrainDistribution::kFractions}},
                              "uniform: radius uniform in [min_radius, max_radius] by number; "
                              "log_normal: ln r normal (median_radius, sigma) by number, "
                              "truncated to [min_radius, max_radius]; fractions: size classes "
                              "by volume share"),
          schema::number("min_radius", &S::min_radius, above(0), "m",
                         "Smallest radius (uniform, log_normal)"),
          schema::number("max_radius", &S::max_radius, above(0), "m",
                         "Largest radius (uniform, log_normal)"),
          schema::number("median_radius", &S::median_radius, above(0), "m",
                         "Median radius by number (log_normal)")
              .default_text("none (log_normal needs it)"),
          schema::number("sigma", &S::sigma, above(0), "",
                         "Standard deviation of ln r (log_normal)")
              .default_text("none (log_normal needs it)"),
          schema::list("fractions", &S::fractions, grain_fraction_table(),
                       "Size classes (fractions)"),
      }};
  return table;
}

}  // namespace

const schema::Table<GrainsConfig>& grains_table() {
  using G = GrainsConfig;
  static const Table<G> table{
      "particles.grains[]",
      "Polydisperse free grains filling a box at a solid fraction without overlaps, built per "
      "rank (docs/physics.md \"Debris grains\").",
      {
          schema::text("group", &G::group, Type::kName, "Particle group (damping, output)"),
          schema::text("material", &G::material, Type::kName, "Material (from `materials`)")
              .required(),
          schema::vec3("box_min", &G::box_min, "m", "Lower corner of the box the grains fill")
              .required(),
          schema::vec3("box_max", &G::box_max, "m", "Upper corner of the box the grains fill")
              .required(),
          schema::number("solid_fraction", &G::solid_fraction, interval(0, false, 0.35, true), "",
                         "Solid volume over box volume; random sequential addition cannot "
                         "reach more than about 0.35 (the grains pack denser as they settle)"),
          schema::section("sizes", &G::sizes, grain_sizes_table(), "Radius distribution")
              .required(),
          schema::vec3("velocity", &G::velocity, "m/s", "Initial velocity of every grain"),
          schema::unsigned_integer("seed", &G::seed, "Random seed of radii and positions"),
      }};
  return table;
}

const schema::Table<SphereFileConfig>& sphere_file_table() {
  using F = SphereFileConfig;
  static const Table<F> table{
      "particles.sphere_files[]",
      "Free spheres read from a CSV file: a header line `x,y,z,radius`, then one sphere a line "
      "(m); empty lines and lines starting with `#` are skipped. Each rank reads only its share "
      "of the lines, so a packing of millions of spheres (from another code, or a settled bed "
      "of an earlier run) costs no rank the whole list.",
      {
          schema::text("path", &F::path, Type::kName,
                       "The CSV file; a relative path is taken from the case file's folder")
              .required(),
          schema::text("group", &F::group, Type::kName, "Particle group (damping, output)"),
          schema::text("material", &F::material, Type::kName, "Material (from `materials`)")
              .required(),
          schema::vec3("velocity", &F::velocity, "m/s", "Initial velocity of every sphere"),
      }};
  return table;
}

const schema::Table<OutflowConfig>& outflow_table() {
  using O = OutflowConfig;
  static const Table<O> table{
      "outflow[]",
      "Boxes that grains may not leave: a free grain in no ring whose centre goes out of one is "
      "taken out of the model, and the ledger counts what it carries out (docs/physics.md "
      "\"Outflow\"); names must be unique.",
      {
          schema::text("name", &O::name, Type::kName, "Name (output)").required(),
          schema::vec3("box_min", &O::box_min, "m", "Lower corner of the box").required(),
          schema::vec3("box_max", &O::box_max, "m", "Upper corner of the box").required(),
          schema::name_list("groups", &O::groups,
                            "Particle groups it takes out (empty: every free grain in no ring)"),
      }};
  return table;
}

const schema::Table<InflowConfig>& inflow_table() {
  using I = InflowConfig;
  static const Table<I> table{
      "inflow[]",
      "Inlets that add grains during the run: a batch fills the inlet box at the solid fraction "
      "that gives the discharge, each time the batch before has moved one box depth on "
      "(docs/physics.md \"Inflow\"); names must be unique.",
      {
          schema::text("name", &I::name, Type::kName, "Name (output)").required(),
          schema::text("group", &I::group, Type::kName, "Particle group (damping, output)"),
          schema::text("material", &I::material, Type::kName, "Material (from `materials`)")
              .required(),
          schema::vec3("box_min", &I::box_min, "m", "Lower corner of the inlet box").required(),
          schema::vec3("box_max", &I::box_max, "m", "Upper corner of the inlet box").required(),
          schema::vec3("velocity", &I::velocity, "m/s", "Velocity of the entering grains")
              .required(),
          schema::number("discharge", &I::discharge, above(0), "m^3/s", "Solid volume per second")
              .required(),
          schema::number("start_time", &I::start_time, at_least(0), "s", "First batch"),
          schema::optional_number("end_time", &I::end_time, above(0), "s",
                                  "No batch from this time on")
              .default_text("none (the whole run)"),
          schema::section("sizes", &I::sizes, grain_sizes_table(), "Radius distribution")
              .required(),
          schema::unsigned_integer("seed", &I::seed, "Random seed of radii and positions"),
      }};
  return table;
}

const schema::Table<BarrierConfig>& barrier_table() {
  using B = BarrierConfig;
  static const Table<B> table{
      "scenario.barrier",
      "What a free run measures of a barrier in a debris flow, every series_interval, into "
      "series.csv and summary.json (docs/debris.md \"Barrier measures\"). Distances are along "
      "`direction` from the barrier plane through `position`: upstream is negative.",
      {
          schema::vec3("direction", &B::direction, "",
                       "Flow direction the barrier holds (normalised); forces are reported "
                       "along it")
              .nonzero()
              .required(),
          schema::vec3("position", &B::position, "m", "A point of the barrier plane").required(),
          schema::name_list("grain_groups", &B::grain_groups,
                            "Particle groups of the flow (empty: every free particle in no ring)"),
          schema::text("net_group", &B::net_group, Type::kName,
                       "Group of the net rings (deflection, bond utilisation), none of "
                       "grain_groups; empty: none"),
          schema::text("frame_group", &B::frame_group, Type::kName,
                       "Group of the fixed particles that hold the net (the net's load is their "
                       "contact load), none of grain_groups; empty: none"),
          schema::name_list("posts", &B::posts,
                            "Rigid bodies of the barrier (posts, frame), not the bed"),
          schema::text("bed", &B::bed, Type::kName,
                       "Plane rigid body the flow runs on (flow depth is measured normal to it)")
              .required(),
          schema::number("gauge_distance", &B::gauge_distance, above(0), "m",
                         "Distance of the gauge section's downstream end from the barrier"),
          schema::number("gauge_length", &B::gauge_length, above(0), "m",
                         "Length of the gauge section (flow depth, velocity, bulk density)"),
          schema::number("retention_length", &B::retention_length, above(0), "m",
                         "Grains this far upstream of the barrier or nearer count as retained"),
          schema::number("width", &B::width, at_least(0), "m",
                         "Width of the flow at the gauge section, for its bulk density (0: not "
                         "computed)"),
      }};
  return table;
}

}  // namespace ringdem

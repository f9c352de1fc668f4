// The schema tables of a net's shackles (see ShackleSchema.hpp).

#include "io/ShackleSchema.hpp"

namespace ringdem {

namespace {

using schema::above;
using schema::at_least;
using schema::Table;
using schema::Type;

const Table<ShackleBrakeConfig>& shackle_brake_table() {
  using Brake = ShackleBrakeConfig;
  static const Table<Brake> table{
      "particles.nets[].shackles.brake",
      "A brake element holding each shackle to the frame at its centre (docs/physics.md \"Brake "
      "elements\"): a spring of `stiffness` in series with a slider that moves along the load "
      "at `activation_force` until it has slid `stroke`, then holds elastically. With it the "
      "shackles are free rigid tori (centreline and tube of the shackle spheres, mass from the "
      "material's density) instead of fixed spheres; the brakes' work is the ledger's "
      "brake_work, and the frame receives their loads.",
      {
          schema::number("activation_force", &Brake::activation_force, above(0), "N",
                         "Load F_b at which a brake slides")
              .required(),
          schema::number("stroke", &Brake::stroke, above(0), "m",
                         "Path a brake can slide before it locks"),
          schema::number("stiffness", &Brake::stiffness, above(0), "N/m",
                         "Spring stiffness k of a brake and its rope"),
      }};
  return table;
}

const Table<RopeBrakeConfig>& rope_brake_table() {
  using RopeBrake = RopeBrakeConfig;
  static const Table<RopeBrake> table{
      "particles.nets[].shackles.ropes.brake",
      "The brakes at each rope's two ends: they pay out rope once its tension reaches "
      "`activation_force`, until `stroke` of rope has run through them in all, then hold.",
      {
          schema::number("activation_force", &RopeBrake::activation_force, above(0), "N",
                         "Rope tension F_b at which the brakes pay out rope")
              .required(),
          schema::number("stroke", &RopeBrake::stroke, above(0), "m",
                         "Rope the brakes of one rope can pay out before they lock"),
      }};
  return table;
}

const Table<ShackleRopeConfig>& shackle_rope_table() {
  using Rope = ShackleRopeConfig;
  static const Table<Rope> table{
      "particles.nets[].shackles.ropes",
      "A support rope along each side of the net that the side's shackles slide on (docs/"
      "physics.md \"Support ropes\"): it runs from an anchor `anchor_offset` beyond the side's "
      "first shackle through the shackles' centres to one beyond its last. Each segment between "
      "two of these points has the tension T = EA (l - lambda) / lambda of its length l and its "
      "share lambda of the unstretched rope (slack at l <= lambda); rope slides through a shackle "
      "where the tensions on its two sides differ by more than the capstan factor exp(friction "
      "x turn) allows, and without friction the tension is the same along the rope. With it the "
      "shackles are free rigid tori; the frame receives the anchors' loads, the ledger's "
      "brake_elastic holds the ropes' elastic energy, brake_work their brakes' work and friction "
      "their sliding's.",
      {
          schema::number("axial_stiffness", &Rope::axial_stiffness, above(0), "N",
                         "Axial rigidity EA of the rope (its metallic area times its modulus)")
              .required(),
          schema::number("anchor_offset", &Rope::anchor_offset, above(0), "m",
                         "Distance of each end's anchor beyond the side's outermost shackle"),
          schema::number("pretension", &Rope::pretension, at_least(0), "N",
                         "Tension of the rope at creation"),
          schema::number("friction", &Rope::friction, at_least(0), "",
                         "Coulomb friction coefficient mu between the rope and the shackles"),
          schema::optional_section("brake", &Rope::brake, rope_brake_table(),
                                   "Brakes at the rope's ends"),
      }};
  return table;
}

}  // namespace

const Table<ShackleConfig>& shackle_table() {
  using Shackle = ShackleConfig;
  static const Table<Shackle> table{
      "particles.nets[].shackles",
      "Rigid shackles holding the net's outer rings: one per boundary ring and side it is on "
      "(two on a corner ring), centred on the ring's outermost wire with the wire through its "
      "middle, so the ring can rotate and slide in it. Shackle particles are fixed and not "
      "bonded (they never move); neighbouring particles must not overlap, and must be close "
      "enough that no net particle (contact_radius) slips between them. With `brake`, each "
      "shackle is instead a free rigid torus held to the frame by a brake element; with "
      "`ropes`, a free rigid torus that slides on its side's support rope.",
      {
          schema::boolean("enabled", &Shackle::enabled, "Create the shackles"),
          schema::text("group", &Shackle::group, Type::kName, "Particle group (damping, output)"),
          schema::number("internal_diameter", &Shackle::internal_diameter, above(0), "m",
                         "Clear inside diameter of a shackle"),
          schema::integer("n_particles", &Shackle::n_particles, at_least(3), "Spheres per shackle"),
          schema::number("particle_radius", &Shackle::particle_radius, above(0), "m",
                         "Radius of the shackle spheres (also their contact radius)"),
          schema::text("material", &Shackle::material, Type::kName, "Material (from `materials`)"),
          schema::optional_section("brake", &Shackle::brake, shackle_brake_table(),
                                   "Hold each shackle by a brake element instead of fixing it"),
          schema::optional_section("ropes", &Shackle::ropes, shackle_rope_table(),
                                   "Let the shackles slide on a support rope along each side"),
      }};
  return table;
}

}  // namespace ringdem

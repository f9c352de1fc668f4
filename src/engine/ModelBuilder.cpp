#include "engine/ModelBuilder.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <stdexcept>

#include "domain/RingGenerator.hpp"
#include "domain/RingNet.hpp"
#include "engine/GrainSource.hpp"
#include "engine/LatticeSource.hpp"
#include "engine/ModelTable.hpp"
#include "engine/RingSource.hpp"
#include "engine/SphereFileSource.hpp"
#include "engine/SphereListSource.hpp"
#include "io/GrainsInput.hpp"
#include "physics/SlidingRope.hpp"

namespace ringdem {

int Model::group_id(const std::string& name) const {
  const auto it = std::find(group_names.begin(), group_names.end(), name);
  return it == group_names.end() ? -1 : static_cast<int>(it - group_names.begin());
}

double group_damping(const CaseConfig& c, const std::string& group) {
  for (const auto& g : c.damping.groups)
    if (g.group == group) return g.coefficient;
  return c.damping.global;
}

bool case_damps_particles(const CaseConfig& c) {
  bool any = c.damping.global != 0.0;
  for (const auto& g : c.damping.groups)
    any = any || g.coefficient != 0.0;
  return any;
}

namespace {

int material_index(const MaterialTable& t, const std::string& name) {
  const int m = t.find(name);
  if (m < 0) throw std::invalid_argument("unknown material '" + name + "'");
  return m;
}

int ensure_group(Model& model, const std::string& name) {
  int g = model.group_id(name);
  if (g < 0) {
    model.group_names.push_back(name);
    g = static_cast<int>(model.group_names.size()) - 1;
  }
  return g;
}

/// Rotation taking the body z axis onto the unit vector n.
Quat orientation_for_axis(const Vec3& n) {
  return quat_between({0, 0, 1}, normalized(n));
}

/// A support rope along each side of a net through the side's shackles (the bodies from
/// `first_body` on, in layout order), in order along the side, anchored `anchor_offset` beyond
/// the outermost ones (docs/physics.md "Support ropes"). Its rest length gives the pretension.
void add_support_ropes(Model& model, const RingNetConfig& net, const RingNetLayout& layout,
                       std::size_t first_body) {
  const ShackleRopeConfig& rope = *net.shackles.ropes;
  const Vec3 y_axis = cross(net.normal, net.x_axis);
  for (const NetSide side :
       {NetSide::kMinusX, NetSide::kPlusX, NetSide::kMinusY, NetSide::kPlusY}) {
    // The sides x = const run along the net's y axis, the sides y = const along its x axis.
    const bool along_y = side == NetSide::kMinusX || side == NetSide::kPlusX;
    const Vec3 along = along_y ? y_axis : net.x_axis;
    std::vector<std::pair<double, std::int32_t>> on_side;  // (place along the side, body)
    for (std::size_t s = 0; s < layout.shackles.size(); ++s) {
      if (layout.shackles[s].side != side) continue;
      on_side.emplace_back(dot(layout.shackles[s].centre, along),
                           static_cast<std::int32_t>(first_body + s));
    }
    if (on_side.empty()) continue;
    std::sort(on_side.begin(), on_side.end());
    std::vector<std::int32_t> bodies;
    std::vector<Vec3> path;
    for (const auto& [place, body] : on_side) {
      bodies.push_back(body);
      path.push_back(model.bodies[static_cast<std::size_t>(body)].position);
    }
    const Vec3 first = path.front() - along * rope.anchor_offset;
    const Vec3 last = path.back() + along * rope.anchor_offset;
    path.insert(path.begin(), first);
    path.push_back(last);
    // T0 = EA (l_j - lambda_j) / lambda_j in every segment: lambda_j = l_j EA / (EA + T0).
    const double ea = rope.axial_stiffness;
    std::vector<double> rest(path.size() - 1);
    SlidingRope::lay(ea, rope.pretension, path, rest);
    const double force =
        rope.brake ? rope.brake->activation_force : std::numeric_limits<double>::infinity();
    model.ropes.append(bodies, first, last, rest, rope.pretension, ea, rope.friction, force,
                       rope.brake ? rope.brake->stroke : 0.0);
  }
}

/// A net's shackles as free rigid tori, each held to the frame by a brake element at its
/// centre (docs/physics.md "Brake elements") or sliding on its side's support rope ("Support
/// ropes"): the shackle rings' centreline and tube, the material's density for their mass.
void add_shackle_tori(Model& model, const RingNetConfig& net, const RingNetLayout& layout) {
  const ShackleConfig& s = net.shackles;
  const int material = material_index(model.materials, s.material);
  const double big_r = 0.5 * s.internal_diameter + s.particle_radius, small_r = s.particle_radius;
  const double density = model.materials[static_cast<std::size_t>(material)].density;
  const double mass = density * 2.0 * M_PI * M_PI * big_r * small_r * small_r;
  const double axial = mass * (big_r * big_r + 0.75 * small_r * small_r);
  const double diametral = mass * (0.5 * big_r * big_r + 0.625 * small_r * small_r);
  const std::size_t first_body = model.bodies.size();
  // Numbered on from the tori of earlier nets, so that the names stay unique.
  const std::size_t earlier = model.brakes.size() + model.ropes.nodes.size();
  for (const ShacklePlacement& placement : layout.shackles) {
    RigidBody b;
    b.name = s.group + "_" + std::to_string(earlier + model.bodies.size() - first_body);
    b.shape = RigidShape::kTorus;
    b.motion = Motion::kFree;
    b.material = material;
    b.radius = big_r;
    b.tube_radius = small_r;
    b.position = placement.centre;
    b.orientation = orientation_for_axis(placement.normal);
    b.mass = mass;
    b.principal_inertia = {diametral, diametral, axial};
    if (s.brake)
      model.brakes.append(static_cast<std::int32_t>(model.bodies.size()), b.position,
                          s.brake->stiffness, s.brake->activation_force, s.brake->stroke);
    model.bodies.push_back(b);
  }
  if (s.ropes) add_support_ropes(model, net, layout, first_body);
}

RingSpec ring_spec(Model& model, const CaseConfig& c, const RingConfig& ring, int bond_type,
                   std::uint64_t bond_seed) {
  RingSpec s;
  s.geometry.centre = ring.centre;
  s.geometry.normal = ring.normal;
  s.geometry.reference = ring.reference;
  s.geometry.internal_diameter = ring.internal_diameter;
  s.geometry.particle_radius = ring.particle_radius;
  s.geometry.n_particles = ring.n_particles;
  s.group = ensure_group(model, ring.group);
  s.material = material_index(model.materials, ring.material);
  // A given ring mass sets the particle density (the particles stand for the whole wire).
  const double particle_volume = 4.0 / 3.0 * M_PI * std::pow(ring.particle_radius, 3);
  s.density = ring.mass ? *ring.mass / (ring.n_particles * particle_volume)
                        : model.materials[static_cast<std::size_t>(s.material)].density;
  s.damping = group_damping(c, ring.group);
  s.motion = ring.motion;
  s.velocity = ring.velocity;
  s.bond_type = bond_type;
  s.bond_seed = bond_seed;
  return s;
}

/// The model without particles and bonds, plus the sources that create them, in case order:
/// the `rings` entries, each net, the lattices, the grains, the listed spheres, the sphere files.
/// Groups are numbered in the order the sources first name them.
struct ModelPlan {
  Model model;
  std::vector<std::unique_ptr<ParticleSource>> sources;
};

ModelPlan plan_model(const CaseConfig& c) {
  ModelPlan plan;
  Model& model = plan.model;
  std::vector<Material> materials;
  for (const auto& m : c.materials)
    materials.push_back({m.name, m.density, m.youngs_modulus, m.poisson_ratio, m.restitution,
                         m.friction, m.rolling_friction});
  std::vector<MaterialTable::PairOverride> overrides;
  {
    const MaterialTable names(materials, {});
    for (const auto& i : c.interactions) {
      MaterialTable::PairOverride o;
      o.a = material_index(names, i.material_a);
      o.b = material_index(names, i.material_b);
      o.restitution = i.restitution.value_or(-1.0);
      o.friction = i.friction.value_or(-1.0);
      o.rolling_friction = i.rolling_friction.value_or(-1.0);
      overrides.push_back(o);
    }
  }
  model.materials = MaterialTable(materials, overrides);

  std::vector<std::uint64_t> bond_seeds;
  for (const auto& b : c.bonds) {
    BondTimoshenko::Params p;
    p.youngs_modulus = b.youngs_modulus;
    p.poisson_ratio = b.poisson_ratio;
    p.radius_multiplier = b.radius_multiplier;
    p.tensile_strength = b.tensile_strength;
    p.compressive_strength = b.compressive_strength;
    p.shear_strength = b.shear_strength;
    p.strength_cov = b.strength_cov;
    model.bond_type_names.push_back(b.name);
    model.bond_types.push_back(p);
    if (b.plastic) {
      // The wire bundle: from `plastic`, else from `derive_from` (the loader checked that one
      // of them gives it).
      const BondPlasticConfig& pl = *b.plastic;
      const auto from_ring = [&](auto member, auto fallback) {
        return b.derive_from ? (*b.derive_from).*member : fallback;
      };
      model.plastic_bond_types.push_back(BondTimoshenkoPlastic::Params::from_wire_bundle(
          pl.windings > 0 ? pl.windings : from_ring(&BondDerivationConfig::windings, 0),
          pl.wire_diameter.value_or(from_ring(&BondDerivationConfig::wire_diameter, 0.0)),
          pl.yield_stress, pl.hardening_ratio,
          pl.steel_youngs_modulus.value_or(
              from_ring(&BondDerivationConfig::steel_youngs_modulus, 200e9)),
          pl.failure_strain));
    }
    bond_seeds.push_back(b.seed);
    // One bond model per case (the loader checks that all types agree).
    model.bond_model = b.model;
  }
  model.contact_model = c.simulation.contact_model;
  if (const BondModelEntry* law = find_bond_model(model.bond_model))
    model.bonds.declare_model_columns(law->state_columns);

  const auto bond_type_of = [&](const std::string& name) {
    const auto it = std::find(model.bond_type_names.begin(), model.bond_type_names.end(), name);
    if (it == model.bond_type_names.end())
      throw std::invalid_argument("unknown bond '" + name + "'");
    return static_cast<int>(it - model.bond_type_names.begin());
  };
  const auto seed_of = [&](int bond_type) {
    return bond_seeds[static_cast<std::size_t>(bond_type)];
  };

  if (!c.rings.empty()) {
    std::vector<RingSpec> rings;
    for (const auto& ring : c.rings) {
      const int bond_type = bond_type_of(ring.bond);
      rings.push_back(ring_spec(model, c, ring, bond_type, seed_of(bond_type)));
    }
    plan.sources.push_back(std::make_unique<RingSource>("rings", std::move(rings)));
  }

  // Nets: each ring is a `rings` entry; the shackles are fixed rings without bonds, or rigid
  // tori on brakes or ropes.
  for (const auto& net : c.nets) {
    const RingNetLayout layout = generate_ring_net(net_parameters(net));
    const int bond_type = bond_type_of(net.bond);
    std::vector<RingSpec> rings;
    rings.reserve(layout.rings.size() + layout.shackles.size());
    for (const RingPlacement& placement : layout.rings) {
      RingConfig ring;
      ring.group = net.group;
      ring.centre = placement.centre;
      ring.normal = placement.normal;
      ring.reference = placement.reference;
      ring.internal_diameter = net.internal_diameter;
      ring.n_particles = net.n_particles;
      ring.particle_radius = net.particle_radius;
      ring.material = net.material;
      ring.mass = net.mass;
      rings.push_back(ring_spec(model, c, ring, bond_type, seed_of(bond_type)));
    }
    if (net.shackles.rigid_tori()) {
      add_shackle_tori(model, net, layout);
      // The group stays: the rockfall's frame group, without particles, its load the
      // restraints'.
      ensure_group(model, net.shackles.group);
    } else {
      for (const ShacklePlacement& placement : layout.shackles) {
        RingConfig shackle;
        shackle.group = net.shackles.group;
        shackle.centre = placement.centre;
        shackle.normal = placement.normal;
        shackle.reference = placement.reference;
        shackle.internal_diameter = net.shackles.internal_diameter;
        shackle.n_particles = net.shackles.n_particles;
        shackle.particle_radius = net.shackles.particle_radius;
        shackle.material = net.shackles.material;
        shackle.motion = Motion::kFixed;
        rings.push_back(ring_spec(model, c, shackle, RingSpec::kNoBond, 0));
      }
    }
    if (net.mesh && !layout.rings.empty()) {
      // The net's rings are the first bodies of its source, after those of the sources before.
      RingMeshSpec mesh;
      for (const auto& src : plan.sources)
        mesh.first_body += src->body_count();
      mesh.n_rings = static_cast<std::int32_t>(layout.rings.size());
      const RingGeometry& ring = rings.front().geometry;
      mesh.beads_per_ring = ring.n_particles;
      mesh.centreline_radius = ring.centreline_radius();
      mesh.ring_mass = rings.front().density * ring.n_particles * 4.0 / 3.0 * M_PI *
                       std::pow(ring.particle_radius, 3);
      mesh.params = {net.mesh->opening, net.mesh->stiffness, net.mesh->damping_ratio};
      model.ring_meshes.push_back(mesh);
    }
    plan.sources.push_back(std::make_unique<RingSource>("net", std::move(rings)));
  }

  for (const auto& lat : c.lattices) {
    LatticeSource::Spec s;
    s.group = ensure_group(model, lat.group);
    s.material = material_index(model.materials, lat.material);
    s.origin = lat.origin;
    s.count = lat.count;
    s.spacing = lat.spacing;
    s.radius = lat.particle_radius;
    s.jitter = lat.jitter;
    s.seed = lat.seed;
    s.velocity = lat.velocity;
    s.density = model.materials[static_cast<std::size_t>(s.material)].density;
    s.damping = group_damping(c, lat.group);
    plan.sources.push_back(std::make_unique<LatticeSource>(s));
  }

  for (std::size_t i = 0; i < c.grains.size(); ++i) {
    const GrainsConfig& g = c.grains[i];
    GrainSource::Spec s;
    s.name = "particles.grains[" + std::to_string(i) + "]";
    s.group = ensure_group(model, g.group);
    s.material = material_index(model.materials, g.material);
    s.box_min = g.box_min;
    s.box_max = g.box_max;
    s.sizes = grain_size_distribution(g.sizes);
    s.solid_fraction = g.solid_fraction;
    s.seed = g.seed;
    s.velocity = g.velocity;
    s.density = model.materials[static_cast<std::size_t>(s.material)].density;
    s.damping = group_damping(c, g.group);
    plan.sources.push_back(std::make_unique<GrainSource>(s));
  }

  if (!c.spheres.empty()) {
    std::vector<ParticleStore::NewParticle> spheres;
    for (const auto& s : c.spheres) {
      ParticleStore::NewParticle np;
      np.group = ensure_group(model, s.group);
      np.material = material_index(model.materials, s.material);
      np.position = s.position;
      np.velocity = s.velocity;
      np.omega = s.omega;
      np.radius = s.radius;
      np.density = model.materials[static_cast<std::size_t>(np.material)].density;
      np.damping = group_damping(c, s.group);
      np.motion = s.motion;
      spheres.push_back(np);
    }
    plan.sources.push_back(std::make_unique<SphereListSource>(std::move(spheres)));
  }

  for (const auto& f : c.sphere_files) {
    ParticleStore::NewParticle prototype;
    prototype.group = ensure_group(model, f.group);
    prototype.material = material_index(model.materials, f.material);
    prototype.velocity = f.velocity;
    prototype.density = model.materials[static_cast<std::size_t>(prototype.material)].density;
    prototype.damping = group_damping(c, f.group);
    plan.sources.push_back(std::make_unique<SphereFileSource>(
        SphereFile(SphereFile::resolve(f.path, c.source_path)), prototype));
  }

  for (const auto& src : plan.sources) {
    model.initial_particles += src->count();
    model.initial_bonds += src->bond_count();
  }
  // Only bonds read orientations, and only the start-up sources create bonds (inlets emit
  // grains): the same answer on every rank, at start-up and on restart.
  model.particles.set_tracks_orientation(model.initial_bonds > 0);
  // The ledger's columns only where it is booked (set before the store is reserved, and
  // before a checkpoint is read into it).
  model.particles.set_tracks_ledger(c.simulation.energy_ledger);
  // Damping coefficients only where the case damps something: the grains of a debris flow
  // carry none (a scenario that sets one later turns them on: Simulation::set_group_damping).
  model.particles.set_tracks_damping(case_damps_particles(c));

  // Inlets: gids above every start-up source's, 2^48 apart per inlet (batches of a million
  // items each leave room for 2.8e8 batches).
  std::int64_t gid_top = 0;
  for (const auto& src : plan.sources)
    gid_top += src->gid_range();
  for (std::size_t i = 0; i < c.inflow.size(); ++i) {
    const InflowConfig& in = c.inflow[i];
    InflowSpec spec;
    spec.name = in.name;
    GrainFill& b = spec.batch;
    b.name = "inflow[" + std::to_string(i) + "]";
    b.group = ensure_group(model, in.group);
    b.material = material_index(model.materials, in.material);
    b.box_min = in.box_min;
    b.box_max = in.box_max;
    b.sizes = grain_size_distribution(in.sizes);
    b.solid_fraction = inflow_batch(in).solid_fraction;
    b.seed = in.seed;
    b.velocity = in.velocity;
    b.density = model.materials[static_cast<std::size_t>(b.material)].density;
    b.damping = group_damping(c, in.group);
    spec.interval = inflow_batch(in).interval;
    spec.start_time = in.start_time;
    spec.end_time = in.end_time.value_or(std::numeric_limits<double>::infinity());
    spec.gid_base = gid_top + static_cast<std::int64_t>(i) * (std::int64_t{1} << 48);
    model.inflow.push_back(std::move(spec));
  }

  for (const OutflowConfig& o : c.outflow) {
    OutflowBox box{o.name, o.box_min, o.box_max, {}};
    for (const std::string& g : o.groups)
      box.groups.push_back(model.group_id(g));
    model.outflow.push_back(std::move(box));
  }

  for (const auto& rb : c.rigid_bodies) {
    RigidBody b;
    b.name = rb.name;
    b.material = material_index(model.materials, rb.material);
    b.position = rb.position;
    b.velocity = rb.velocity;
    b.omega = rb.omega;
    b.gravity = rb.gravity;
    b.radius = rb.radius;
    b.half_length = 0.5 * rb.length;
    const double density = model.materials[static_cast<std::size_t>(b.material)].density;
    switch (rb.shape) {
      case ShapeKind::kPlane:
        b.shape = RigidShape::kPlane;
        b.orientation = orientation_for_axis(rb.normal);
        break;
      case ShapeKind::kCylinder: {
        b.shape = RigidShape::kCylinder;
        b.orientation = orientation_for_axis(rb.axis);
        b.mass = rb.mass.value_or(density * M_PI * rb.radius * rb.radius * rb.length);
        const double ixx = b.mass * (3.0 * rb.radius * rb.radius + rb.length * rb.length) / 12.0;
        b.principal_inertia = {ixx, ixx, 0.5 * b.mass * rb.radius * rb.radius};
        break;
      }
      case ShapeKind::kSphere: {
        b.shape = RigidShape::kSphere;
        b.mass = rb.mass.value_or(density * 4.0 / 3.0 * M_PI * std::pow(rb.radius, 3));
        const double i = 0.4 * b.mass * rb.radius * rb.radius;
        b.principal_inertia = {i, i, i};
        break;
      }
    }
    b.motion = rb.motion;
    if (b.motion == Motion::kFixed) {
      b.velocity = {};
      b.omega = {};
    }
    if (b.motion == Motion::kFree && b.shape == RigidShape::kPlane)
      throw std::invalid_argument("rigid body '" + b.name + "': a plane cannot be free");
    model.bodies.push_back(b);
  }

  return plan;
}

}  // namespace

RingNetParameters net_parameters(const RingNetConfig& net) {
  RingNetParameters g;
  g.rows = net.rows;
  g.columns = net.columns;
  g.link_distance = net.link_distance;
  g.tilt = net.tilt;
  g.centre = net.centre;
  g.normal = net.normal;  // unit and perpendicular after validation
  g.x_axis = net.x_axis;
  g.internal_diameter = net.internal_diameter;
  g.particle_radius = net.particle_radius;
  g.n_particles = net.n_particles;
  g.shackles = net.shackles.enabled;
  g.shackle_internal_diameter = net.shackles.internal_diameter;
  g.shackle_particle_radius = net.shackles.particle_radius;
  g.shackle_n_particles = net.shackles.n_particles;
  return g;
}

void add_bond(Model& model, std::int64_t id, const BondEnd& a, const BondEnd& b, int bond_type,
              std::uint64_t seed) {
  const BondModelEntry* entry = find_bond_model(model.bond_model);
  if (!entry) throw std::invalid_argument("unknown bond model '" + model.bond_model + "'");
  entry->create(model.bonds, model.bond_types[static_cast<std::size_t>(bond_type)], bond_type, id,
                a, b, seed);
}

void add_bond(Model& model, std::size_t index_a, std::size_t index_b, int bond_type,
              std::uint64_t seed) {
  // A model built without bonds keeps no orientations: its particles sit at the identity.
  model.particles.set_tracks_orientation(true);
  const ParticleStore& p = model.particles;
  const auto end = [&](std::size_t i) {
    return BondEnd{p.gid[i], p.position[i], p.orientation[i], p.radius[i]};
  };
  std::int64_t next_id = 0;
  for (std::int64_t id : model.bonds.id)
    next_id = std::max(next_id, id + 1);
  add_bond(model, next_id, end(index_a), end(index_b), bond_type, seed);
}

Model build_model(const CaseConfig& config, int rank, int ranks) {
  if (ranks < 1 || rank < 0 || rank >= ranks)
    throw std::invalid_argument("build_model: rank outside 0..ranks-1");
  ModelPlan plan = plan_model(config);
  // Room for this rank's particles before the first is added (each source's count in
  // proportion to its slice of gids, a few more for sparse ones): a store grown one particle
  // at a time frees a trail of smaller columns that the heap keeps resident (about 60 MiB at
  // 10^6 grains; docs/performance.md, seventh round). On several ranks also room for what the
  // first distribution leaves (ParticleStore::reserve_share).
  std::int64_t expected = 0;
  for (const auto& src : plan.sources) {
    const std::int64_t n = src->gid_range();
    const std::int64_t items = ParticleSource::slice_begin(n, rank + 1, ranks) -
                               ParticleSource::slice_begin(n, rank, ranks);
    if (n > 0)
      expected += static_cast<std::int64_t>(
          std::ceil(static_cast<double>(src->count()) * static_cast<double>(items) /
                    static_cast<double>(n) * (src->count() < n && items < n ? 1.05 : 1.0)));
  }
  plan.model.particles.reserve_share(static_cast<std::size_t>(expected), ranks);
  SourceBases bases;
  for (const auto& src : plan.sources) {
    const std::int64_t n = src->gid_range();
    src->emit(ParticleSource::slice_begin(n, rank, ranks),
              ParticleSource::slice_begin(n, rank + 1, ranks), bases, plan.model);
    bases.gid += n;
    bases.bond_id += src->bond_count();
    bases.body += src->body_count();
  }
  plan.model.particles.rebuild_index();
  return std::move(plan.model);
}

Model build_model(const CaseConfig& config, const Communicator& comm) {
  return build_model(config, comm.rank(), comm.size());
}

Model build_model_without_particles(const CaseConfig& config) {
  return std::move(plan_model(config).model);
}

}  // namespace ringdem

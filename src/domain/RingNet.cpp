#include "domain/RingNet.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace ringdem {

double RingNetParameters::lattice_pitch() const {
  return link_distance / std::sqrt(2.0);
}

double RingNetParameters::width() const {
  return (columns - 1) * lattice_pitch() + 2.0 * (centreline_radius() + particle_radius);
}

double RingNetParameters::length() const {
  return (rows - 1) * lattice_pitch() +
         2.0 * (centreline_radius() * std::cos(tilt) + particle_radius);
}

LatticeSize lattice_size_for(double width, double length, const RingNetParameters& shape) {
  const double s = shape.lattice_pitch();
  const double ring_width = 2.0 * (shape.centreline_radius() + shape.particle_radius);
  const double ring_length =
      2.0 * (shape.centreline_radius() * std::cos(shape.tilt) + shape.particle_radius);
  LatticeSize size;
  size.columns = std::max(2, static_cast<int>(std::lround((width - ring_width) / s)) + 1);
  size.rows = std::max(2, static_cast<int>(std::lround((length - ring_length) / s)) + 1);
  return size;
}

RingGeometry RingNetLayout::ring_geometry(std::size_t ring) const {
  const RingPlacement& r = rings.at(ring);
  RingGeometry g;
  g.centre = r.centre;
  g.normal = r.normal;
  g.reference = r.reference;
  g.internal_diameter = parameters.internal_diameter;
  g.particle_radius = parameters.particle_radius;
  g.n_particles = parameters.n_particles;
  return g;
}

RingGeometry RingNetLayout::shackle_geometry(std::size_t shackle) const {
  const ShacklePlacement& s = shackles.at(shackle);
  RingGeometry g;
  g.centre = s.centre;
  g.normal = s.normal;
  g.reference = s.reference;
  g.internal_diameter = parameters.shackle_internal_diameter;
  g.particle_radius = parameters.shackle_particle_radius;
  g.n_particles = parameters.shackle_n_particles;
  return g;
}

std::size_t RingNetLayout::n_particles() const {
  return rings.size() * static_cast<std::size_t>(parameters.n_particles) +
         shackles.size() * static_cast<std::size_t>(parameters.shackle_n_particles);
}

namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("ring net: " + what);
}

Vec3 outward(NetSide side) {
  switch (side) {
    case NetSide::kMinusX:
      return {-1, 0, 0};
    case NetSide::kPlusX:
      return {1, 0, 0};
    case NetSide::kMinusY:
      return {0, -1, 0};
    case NetSide::kPlusY:
      break;
  }
  return {0, 1, 0};
}

/// The shackle on `side` of ring `r`: centred on the ring's wire where it reaches furthest
/// out, its axis along the wire there, so the wire threads the shackle through its middle.
ShacklePlacement shackle_for(const RingPlacement& r, std::size_t ring_index, NetSide side,
                             double ring_centreline_radius) {
  const Vec3 u = outward(side);
  const Vec3 out = normalized(u - dot(u, r.normal) * r.normal);  // in the ring plane
  ShacklePlacement s;
  s.centre = r.centre + ring_centreline_radius * out;
  s.normal = normalized(cross(r.normal, out));  // tangent of the wire circle at that point
  s.reference = out;
  s.net_ring = ring_index;
  s.side = side;
  return s;
}

}  // namespace

RingNetLayout generate_ring_net(const RingNetParameters& p) {
  require(p.rows >= 2 && p.columns >= 2, "the lattice needs at least 2 rows and 2 columns");
  require(p.internal_diameter > 0.0 && p.particle_radius > 0.0 && p.n_particles >= 3,
          "rings need a positive diameter and particle radius and at least 3 particles");
  require(p.link_distance > 0.0 && p.link_distance < 2.0 * p.centreline_radius(),
          "link_distance must be in (0, 2 x centreline radius): farther rings cannot interlink");
  require(p.tilt > 0.0 && p.tilt < 0.5 * M_PI, "tilt must be in (0, pi/2)");
  require(std::abs(norm(p.normal) - 1.0) < 1e-9 && std::abs(norm(p.x_axis) - 1.0) < 1e-9 &&
              std::abs(dot(p.normal, p.x_axis)) < 1e-9,
          "normal and x_axis must be unit vectors normal to each other");
  if (p.shackles)
    require(p.shackle_internal_diameter > 0.0 && p.shackle_particle_radius > 0.0 &&
                p.shackle_n_particles >= 3,
            "shackles need a positive diameter and particle radius and at least 3 particles");

  RingNetLayout net;
  net.parameters = p;
  const double s = p.lattice_pitch();
  // Built in the net's frame about its centre, then placed (place(), below).
  const Vec3 first_site = Vec3{-0.5 * (p.columns - 1) * s, -0.5 * (p.rows - 1) * s, 0.0};
  std::vector<std::int64_t> ring_at(static_cast<std::size_t>(p.rows) * p.columns, -1);
  const auto site = [&](int row, int column) {
    return static_cast<std::size_t>(row) * p.columns + static_cast<std::size_t>(column);
  };
  for (int row = 0; row < p.rows; ++row) {
    const double tilt_sign = row % 2 == 1 ? 1.0 : -1.0;
    for (int column = 0; column < p.columns; ++column) {
      if ((row + column) % 2 == 0) continue;
      RingPlacement r;
      r.centre = first_site + Vec3{column * s, row * s, 0.0};
      r.normal = {0.0, tilt_sign * std::sin(p.tilt), std::cos(p.tilt)};
      r.reference = {1.0, 0.0, 0.0};
      r.row = row;
      r.column = column;
      ring_at[site(row, column)] = static_cast<std::int64_t>(net.rings.size());
      net.rings.push_back(r);
    }
  }

  // Each link is found once, from its lower row; the ring indices grow with the row.
  for (std::size_t i = 0; i < net.rings.size(); ++i) {
    const RingPlacement& r = net.rings[i];
    if (r.row + 1 >= p.rows) continue;
    for (const int dc : {-1, 1}) {
      const int column = r.column + dc;
      if (column < 0 || column >= p.columns) continue;
      const std::int64_t j = ring_at[site(r.row + 1, column)];
      if (j >= 0) net.links.emplace_back(i, static_cast<std::size_t>(j));
    }
  }

  if (p.shackles) {
    for (std::size_t i = 0; i < net.rings.size(); ++i) {
      const RingPlacement& r = net.rings[i];
      if (r.column == 0)
        net.shackles.push_back(shackle_for(r, i, NetSide::kMinusX, p.centreline_radius()));
      if (r.column == p.columns - 1)
        net.shackles.push_back(shackle_for(r, i, NetSide::kPlusX, p.centreline_radius()));
      if (r.row == 0)
        net.shackles.push_back(shackle_for(r, i, NetSide::kMinusY, p.centreline_radius()));
      if (r.row == p.rows - 1)
        net.shackles.push_back(shackle_for(r, i, NetSide::kPlusY, p.centreline_radius()));
    }
  }

  // The net's frame into the world: x_axis, normal x x_axis, normal; about the centre.
  const Vec3 ex = p.x_axis, ez = p.normal, ey = cross(ez, ex);
  const auto turn = [&](const Vec3& v) { return ex * v.x + ey * v.y + ez * v.z; };
  for (RingPlacement& r : net.rings) {
    r.centre = p.centre + turn(r.centre);
    r.normal = turn(r.normal);
    r.reference = turn(r.reference);
  }
  for (ShacklePlacement& sh : net.shackles) {
    sh.centre = p.centre + turn(sh.centre);
    sh.normal = turn(sh.normal);
    sh.reference = turn(sh.reference);
  }
  return net;
}

RingNetClearance smallest_clearance(const RingNetLayout& layout, double net_radius,
                                    double shackle_radius, double search_gap) {
  std::vector<Vec3> position;
  std::vector<double> radius;
  std::vector<std::uint32_t> ring;
  const auto add_ring = [&](const RingGeometry& g, double r, std::size_t index) {
    for (const Vec3& x : g.positions()) {
      position.push_back(x);
      radius.push_back(r);
      ring.push_back(static_cast<std::uint32_t>(index));
    }
  };
  for (std::size_t i = 0; i < layout.rings.size(); ++i)
    add_ring(layout.ring_geometry(i), net_radius, i);
  for (std::size_t k = 0; k < layout.shackles.size(); ++k)
    add_ring(layout.shackle_geometry(k), shackle_radius, layout.rings.size() + k);

  // Any pair with a gap <= search_gap lies in the same or an adjacent cell.
  const double cell = 2.0 * std::max(net_radius, shackle_radius) + std::max(search_gap, 0.0);
  const auto cell_of = [&](const Vec3& x) {
    return std::array<std::int64_t, 3>{static_cast<std::int64_t>(std::floor(x.x / cell)),
                                       static_cast<std::int64_t>(std::floor(x.y / cell)),
                                       static_cast<std::int64_t>(std::floor(x.z / cell))};
  };
  // 21 bits per coordinate: a net of a million cells along each axis.
  const auto key_of = [](const std::array<std::int64_t, 3>& c) {
    constexpr std::int64_t kOffset = std::int64_t{1} << 20;
    constexpr std::uint64_t kMask = (std::uint64_t{1} << 21) - 1;
    return ((static_cast<std::uint64_t>(c[0] + kOffset) & kMask) << 42) |
           ((static_cast<std::uint64_t>(c[1] + kOffset) & kMask) << 21) |
           (static_cast<std::uint64_t>(c[2] + kOffset) & kMask);
  };
  std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> cells;
  for (std::size_t k = 0; k < position.size(); ++k)
    cells[key_of(cell_of(position[k]))].push_back(static_cast<std::uint32_t>(k));

  RingNetClearance best;
  for (std::size_t k = 0; k < position.size(); ++k) {
    const auto c = cell_of(position[k]);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        for (std::int64_t dz = -1; dz <= 1; ++dz) {
          const auto it = cells.find(key_of({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells.end()) continue;
          for (const std::uint32_t j : it->second) {
            if (j <= k || ring[j] == ring[k]) continue;
            const double gap = norm(position[j] - position[k]) - radius[j] - radius[k];
            if (gap <= search_gap && gap < best.gap) {
              best.gap = gap;
              best.ring_a = std::min(ring[j], ring[k]);
              best.ring_b = std::max(ring[j], ring[k]);
            }
          }
        }
  }
  return best;
}

}  // namespace ringdem

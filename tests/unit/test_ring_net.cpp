// Ring net generator (domain/RingNet.hpp): the Gauss linking number against analytic links,
// the paper's 180-ring net at creation (no two rings touch, exactly the lattice neighbours and
// the shackles are linked), lattice counts, and the `particles.nets` case-file entry.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "domain/LinkingNumber.hpp"
#include "domain/RingNet.hpp"
#include "engine/ModelBuilder.hpp"
#include "io/CaseLoader.hpp"

namespace ringdem {
namespace {

/// n points on a circle of radius r about `centre` in the plane spanned by unit e1, e2.
std::vector<Vec3> circle(const Vec3& centre, const Vec3& e1, const Vec3& e2, double r, int n) {
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) {
    const double phi = 2.0 * M_PI * k / n;
    out.push_back(centre + e1 * (r * std::cos(phi)) + e2 * (r * std::sin(phi)));
  }
  return out;
}

/// Component j (0 or 1) of the torus link T(2, 2q): it winds once along the torus (major
/// radius 1, minor 0.4) and q times around its tube, half a turn of the tube behind the other.
std::vector<Vec3> torus_link_component(int j, int q, int n) {
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) {
    const double t = 2.0 * M_PI * k / n;
    const double v = q * t + M_PI * j;
    out.push_back({(1.0 + 0.4 * std::cos(v)) * std::cos(t), (1.0 + 0.4 * std::cos(v)) * std::sin(t),
                   0.4 * std::sin(v)});
  }
  return out;
}

// The linking number of polygons is exact (a sum of solid angles), so an analytic integer is
// matched to rounding: tolerance 1e-9.
constexpr double kLinkTolerance = 1e-9;

TEST(RingNetLinkingNumber, HopfLinkIsPlusOrMinusOne) {
  // Ring a in the x-y plane; ring b in the x-z plane through a's centre line at (R, 0, 0).
  const double r = 0.1545;
  const auto a = circle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, r, 100);
  const auto b = circle({r, 0, 0}, {1, 0, 0}, {0, 0, 1}, r, 100);
  const double lk = gauss_linking_number(a, b);
  EXPECT_NEAR(std::abs(lk), 1.0, kLinkTolerance);
  // Symmetric in its arguments; reversing one curve's orientation flips the sign.
  EXPECT_NEAR(gauss_linking_number(b, a), lk, kLinkTolerance);
  const auto b_reversed = std::vector<Vec3>(b.rbegin(), b.rend());
  EXPECT_NEAR(gauss_linking_number(a, b_reversed), -lk, kLinkTolerance);
  // A coarse shackle-sized square through the ring's wire is a Hopf link too.
  const auto square = circle({r, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0.04, 4);
  EXPECT_NEAR(std::abs(gauss_linking_number(a, square)), 1.0, kLinkTolerance);
}

TEST(RingNetLinkingNumber, SeparatedRingsAreUnlinked) {
  const auto a = circle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.15, 100);
  // Perpendicular ring beside a (its plane cuts a's plane outside a): no threading.
  const auto b = circle({0.5, 0, 0}, {1, 0, 0}, {0, 0, 1}, 0.15, 100);
  EXPECT_NEAR(gauss_linking_number(a, b), 0.0, kLinkTolerance);
  // Parallel rings stacked above each other.
  const auto c = circle({0.05, 0, 0.2}, {1, 0, 0}, {0, 1, 0}, 0.15, 37);
  EXPECT_NEAR(gauss_linking_number(a, c), 0.0, kLinkTolerance);
}

TEST(RingNetLinkingNumber, CoplanarRingsAreUnlinked) {
  // In the plane z = 0: side by side, and a small ring inside a large one.
  const auto a = circle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.15, 100);
  EXPECT_NEAR(gauss_linking_number(a, circle({0.4, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.15, 100)), 0.0,
              kLinkTolerance);
  EXPECT_NEAR(gauss_linking_number(a, circle({0.02, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0.05, 14)), 0.0,
              kLinkTolerance);
  // The same in a tilted plane, where the coplanarity holds only to rounding.
  const Vec3 e1 = normalized({1, 1, 0.3});
  const Vec3 e2 = normalized(cross(normalized({0.2, -0.5, 1}), e1));
  const Vec3 o{0.3, -0.2, 0.7};
  const auto t = circle(o, e1, e2, 0.15, 100);
  EXPECT_NEAR(gauss_linking_number(t, circle(o + 0.4 * e1, e1, e2, 0.15, 100)), 0.0,
              kLinkTolerance);
  EXPECT_NEAR(gauss_linking_number(t, circle(o + 0.02 * e2, e1, e2, 0.05, 14)), 0.0,
              kLinkTolerance);
}

TEST(RingNetLinkingNumber, TorusLinksT24AndT26) {
  // The torus link T(2, 2q) has linking number q (each component goes q times around the
  // other): 2 for T(2, 4), 3 for T(2, 6).
  for (const int q : {2, 3}) {
    const double lk =
        gauss_linking_number(torus_link_component(0, q, 400), torus_link_component(1, q, 400));
    EXPECT_NEAR(std::abs(lk), q, kLinkTolerance) << "T(2, " << 2 * q << ")";
  }
}

// ---- layout counts ------------------------------------------------------------------------------

TEST(RingNetLayout, CountsFromRowsAndColumns) {
  // 3 rows x 4 columns: sites with row + column odd are (row 0: columns 1, 3), (row 1: 0, 2),
  // (row 2: 1, 3) = 6 rings. Links (diagonal neighbours): (0,1)-(1,0), (0,1)-(1,2),
  // (0,3)-(1,2), (1,0)-(2,1), (1,2)-(2,1), (1,2)-(2,3) = 6. Shackles per ring = sides it is on:
  // (0,1): -y; (0,3): -y, +x; (1,0): -x; (1,2): none; (2,1): +y; (2,3): +y, +x = 7.
  RingNetParameters p;
  p.rows = 3;
  p.columns = 4;
  const RingNetLayout net = generate_ring_net(p);
  ASSERT_EQ(net.rings.size(), 6u);
  std::set<std::pair<int, int>> sites;
  for (const RingPlacement& r : net.rings)
    sites.insert({r.row, r.column});
  EXPECT_EQ(sites, (std::set<std::pair<int, int>>{{0, 1}, {0, 3}, {1, 0}, {1, 2}, {2, 1}, {2, 3}}));
  std::set<std::pair<std::pair<int, int>, std::pair<int, int>>> links;
  for (const auto& [a, b] : net.links)
    links.insert(
        {{net.rings[a].row, net.rings[a].column}, {net.rings[b].row, net.rings[b].column}});
  EXPECT_EQ(
      links, (std::set<std::pair<std::pair<int, int>, std::pair<int, int>>>{{{0, 1}, {1, 0}},
                                                                            {{0, 1}, {1, 2}},
                                                                            {{0, 3}, {1, 2}},
                                                                            {{1, 0}, {2, 1}},
                                                                            {{1, 2}, {2, 1}},
                                                                            {{1, 2}, {2, 3}}}));
  EXPECT_EQ(net.shackles.size(), 7u);
  EXPECT_EQ(net.n_particles(), 6u * 100u + 7u * 14u);

  // The paper's net: 19 x 19 sites, 180 with row + column odd (the 4 corners are empty). 36
  // boundary rings (9 per side) with 2 links each, 144 inner rings with 4: (36 * 2 + 144 * 4)
  // / 2 = 324 links; one shackle per boundary ring.
  const RingNetLayout paper = generate_ring_net(RingNetParameters{});
  EXPECT_EQ(paper.rings.size(), 180u);
  EXPECT_EQ(paper.links.size(), 324u);
  EXPECT_EQ(paper.shackles.size(), 36u);
  EXPECT_EQ(paper.n_particles(), 18000u + 36u * 14u);
  std::map<NetSide, int> per_side;
  for (const ShacklePlacement& s : paper.shackles)
    ++per_side[s.side];
  for (const NetSide side : {NetSide::kMinusX, NetSide::kPlusX, NetSide::kMinusY, NetSide::kPlusY})
    EXPECT_EQ(per_side[side], 9);

  // Without shackles: none.
  p.shackles = false;
  EXPECT_TRUE(generate_ring_net(p).shackles.empty());
}

/// Extent along x and y of the particle surfaces of the net rings (shackles left out).
std::pair<double, double> measured_extent(const RingNetLayout& net) {
  double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
  const double r = net.parameters.particle_radius;
  for (std::size_t i = 0; i < net.rings.size(); ++i)
    for (const Vec3& x : net.ring_geometry(i).positions()) {
      lo_x = std::min(lo_x, x.x - r);
      hi_x = std::max(hi_x, x.x + r);
      lo_y = std::min(lo_y, x.y - r);
      hi_y = std::max(hi_y, x.y + r);
    }
  return {hi_x - lo_x, hi_y - lo_y};
}

TEST(RingNetLayout, CountsFromTargetSize) {
  const RingNetParameters shape;  // link distance 0.28 m: pitch s = 0.19799 m
  // 3.9 m: columns = round((3.9 - 0.318) / s) + 1 = round(18.09) + 1 = 19; rows = round((3.9 -
  // 2 (0.1545 cos 0.28 + 0.0045)) / s) + 1 = round(18.15) + 1 = 19: the paper's 180 rings.
  const LatticeSize paper = lattice_size_for(3.9, 3.9, shape);
  EXPECT_EQ(paper.columns, 19);
  EXPECT_EQ(paper.rows, 19);
  // 2.5 m x 1.5 m: columns = round(2.182 / s) + 1 = 12, rows = round(1.194 / s) + 1 = 7;
  // 7 rows of 6 rings (every other site of 12) = 42 rings.
  const LatticeSize small = lattice_size_for(2.5, 1.5, shape);
  EXPECT_EQ(small.columns, 12);
  EXPECT_EQ(small.rows, 7);
  RingNetParameters p = shape;
  p.rows = small.rows;
  p.columns = small.columns;
  const RingNetLayout net = generate_ring_net(p);
  EXPECT_EQ(net.rings.size(), 42u);
  // The measured extent is the documented one (particles 0, 25, 50, 75 sit on the extremes of
  // each ring), and within half a pitch of the target; tolerance 1e-9 m for rounding.
  const auto [width, length] = measured_extent(net);
  EXPECT_NEAR(width, p.width(), 1e-9);
  EXPECT_NEAR(length, p.length(), 1e-9);
  EXPECT_LE(std::abs(width - 2.5), 0.5 * shape.lattice_pitch());
  EXPECT_LE(std::abs(length - 1.5), 0.5 * shape.lattice_pitch());
  // A target smaller than two sites still gives the smallest net, 2 x 2.
  const LatticeSize tiny = lattice_size_for(0.1, 0.1, shape);
  EXPECT_EQ(tiny.columns, 2);
  EXPECT_EQ(tiny.rows, 2);
}

// ---- the paper's net at creation ----------------------------------------------------------------

struct RingCurve {
  std::vector<Vec3> points;  ///< particle centres
  Vec3 centre;
  double bounding_radius = 0.0;  ///< every point lies within this distance of `centre`
  double particle_radius = 0.0;
  double contact_radius = 0.0;
};

/// Net rings first (index = ring index), then shackles, as smallest_clearance numbers them.
std::vector<RingCurve> curves_of(const RingNetLayout& net, double net_contact_radius) {
  std::vector<RingCurve> out;
  for (std::size_t i = 0; i < net.rings.size(); ++i) {
    const RingGeometry g = net.ring_geometry(i);
    out.push_back(
        {g.positions(), g.centre, g.centreline_radius(), g.particle_radius, net_contact_radius});
  }
  for (std::size_t k = 0; k < net.shackles.size(); ++k) {
    const RingGeometry g = net.shackle_geometry(k);
    out.push_back(
        {g.positions(), g.centre, g.centreline_radius(), g.particle_radius, g.particle_radius});
  }
  return out;
}

TEST(RingNetPaperNet, NoTwoRingsTouchAtCreation) {
  const auto start = std::chrono::steady_clock::now();
  const RingNetLayout net = generate_ring_net(RingNetParameters{});
  const double contact_radius = 0.008;  // the rings' contact radius (case-file default)
  const auto curves = curves_of(net, contact_radius);
  // Brute force over the particles of every pair of rings whose bounding spheres, grown by
  // the contact radii and a 5 cm margin (to see the clearance itself), intersect; pairs
  // farther apart are farther apart than that margin.
  constexpr double kClearanceMargin = 0.05;
  double smallest_gap = 1e9, smallest_contact_gap = 1e9;
  double smallest_centre_distance = 1e9;
  for (std::size_t a = 0; a < curves.size(); ++a)
    for (std::size_t b = a + 1; b < curves.size(); ++b) {
      const RingCurve& ca = curves[a];
      const RingCurve& cb = curves[b];
      if (norm(ca.centre - cb.centre) > ca.bounding_radius + cb.bounding_radius +
                                            ca.contact_radius + cb.contact_radius +
                                            kClearanceMargin)
        continue;
      for (const Vec3& x : ca.points)
        for (const Vec3& y : cb.points) {
          const double d = norm(x - y);
          smallest_gap = std::min(smallest_gap, d - ca.particle_radius - cb.particle_radius);
          smallest_contact_gap =
              std::min(smallest_contact_gap, d - ca.contact_radius - cb.contact_radius);
          smallest_centre_distance = std::min(smallest_centre_distance, d);
        }
    }
  // Expectation: wires apart (gap >= 0 with the particle radii), and even the contact
  // spheres apart, so that no contact force acts at the start. Exact inequalities.
  EXPECT_GE(smallest_gap, 0.0);
  EXPECT_GE(smallest_contact_gap, 0.0);
  // The library's cell-grid search finds the same smallest gap (rounding: 1e-12 m).
  const RingNetClearance c = smallest_clearance(net, contact_radius, 0.008, kClearanceMargin);
  EXPECT_NEAR(c.gap, smallest_contact_gap, 1e-12);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf(
      "paper net: %zu rings, %zu shackles; smallest centre distance between particles of "
      "different rings %.2f mm, gap %.2f mm (particle radii), %.2f mm (contact radii); %.2f s\n",
      net.rings.size(), net.shackles.size(), 1e3 * smallest_centre_distance, 1e3 * smallest_gap,
      1e3 * smallest_contact_gap, seconds);
  EXPECT_LT(seconds, 5.0);
}

TEST(RingNetPaperNet, ExactlyNeighboursAndShacklesAreLinked) {
  const auto start = std::chrono::steady_clock::now();
  const RingNetLayout net = generate_ring_net(RingNetParameters{});
  const auto curves = curves_of(net, 0.008);
  const std::size_t n_rings = net.rings.size();
  const int rows = net.parameters.rows, columns = net.parameters.columns;
  // Independent expectation from the lattice sites: net rings are linked when their rows and
  // columns both differ by 1; a shackle with the ring it was made for.
  const auto expected_linked = [&](std::size_t a, std::size_t b) {
    if (a >= n_rings) return false;  // two shackles
    if (b >= n_rings) return net.shackles[b - n_rings].net_ring == a;
    return std::abs(net.rings[a].row - net.rings[b].row) == 1 &&
           std::abs(net.rings[a].column - net.rings[b].column) == 1;
  };
  std::vector<int> net_links(n_rings, 0), shackle_links(n_rings, 0);
  std::vector<int> links_of_shackle(net.shackles.size(), 0);
  std::set<std::pair<std::size_t, std::size_t>> found_links;
  int computed = 0;
  for (std::size_t a = 0; a < curves.size(); ++a)
    for (std::size_t b = a + 1; b < curves.size(); ++b) {
      // Two closed curves inside disjoint balls cannot link (a cone over one curve from its
      // ball's centre is a surface it bounds that the other curve does not cross), so their
      // linking number is 0 without computing it. Every pair of intersecting balls is computed.
      if (norm(curves[a].centre - curves[b].centre) >=
          curves[a].bounding_radius + curves[b].bounding_radius) {
        EXPECT_FALSE(expected_linked(a, b)) << a << " " << b;
        continue;
      }
      ++computed;
      const double lk = gauss_linking_number(curves[a].points, curves[b].points);
      const long integer = std::lround(lk);
      EXPECT_NEAR(lk, integer, 1e-6) << a << " " << b;  // an integer up to rounding
      EXPECT_EQ(std::abs(integer), expected_linked(a, b) ? 1 : 0) << a << " " << b << ": " << lk;
      if (std::abs(integer) != 1) continue;
      if (b < n_rings) {
        ++net_links[a];
        ++net_links[b];
        found_links.insert({a, b});
      } else {
        ++shackle_links[a];  // a is a net ring: two shackles are never within reach
        ++links_of_shackle[b - n_rings];
      }
    }
  EXPECT_GE(computed, 324 + 36);  // at least every link

  // The generator's link list is exactly the links found.
  const std::set<std::pair<std::size_t, std::size_t>> listed(net.links.begin(), net.links.end());
  EXPECT_EQ(listed, found_links);
  for (std::size_t i = 0; i < n_rings; ++i) {
    const RingPlacement& r = net.rings[i];
    const int sides =
        (r.row == 0) + (r.row == rows - 1) + (r.column == 0) + (r.column == columns - 1);
    if (sides == 0) {
      EXPECT_EQ(net_links[i], 4) << "inner ring " << i;
    } else {
      // On the paper's odd lattice no ring sits on a corner: 2 links inwards, 1 shackle.
      EXPECT_EQ(net_links[i], 2) << "boundary ring " << i;
    }
    EXPECT_EQ(shackle_links[i], sides) << "ring " << i;
  }
  for (std::size_t k = 0; k < net.shackles.size(); ++k)
    EXPECT_EQ(links_of_shackle[k], 1) << "shackle " << k;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("paper net: %d ring pairs with intersecting bounding spheres computed, %.2f s\n",
              computed, seconds);
  EXPECT_LT(seconds, 5.0);
}

// ---- case file ---------------------------------------------------------------------------------

constexpr const char* kNetCase = R"(schema_version: 1
simulation: {end_time: 0.1}
materials:
  - {name: steel}
  - {name: shackle_steel, density: 7850}
bonds:
  - {name: ring12, youngs_modulus: 292e9, radius_multiplier: 0.43}
damping:
  groups: {net: 0.2, holders: 0.0}
particles:
  nets:
    - rows: 3
      columns: 4
      centre: [1, 2, 3]
      contact_radius: 0.009
      bond: ring12
      mass: 1.2
      shackles: {group: holders, material: shackle_steel}
)";

TEST(RingNetCase, NetEntryLoadsAndBuilds) {
  const CaseConfig c = load_case_from_string(kNetCase, "net.yaml");
  ASSERT_EQ(c.nets.size(), 1u);
  const RingNetConfig& n = c.nets[0];
  EXPECT_EQ(n.group, "net");
  EXPECT_DOUBLE_EQ(n.link_distance, 0.28);
  EXPECT_DOUBLE_EQ(n.tilt, 0.28);
  EXPECT_DOUBLE_EQ(n.contact_radius, 0.009);
  EXPECT_TRUE(n.shackles.enabled);
  EXPECT_EQ(n.shackles.n_particles, 14);

  const Model model = build_model(c);
  const ParticleStore& p = model.particles;
  // 3 x 4 lattice: 6 rings of 100 bonded particles, 7 shackles of 14 (CountsFromRowsAndColumns).
  ASSERT_EQ(p.n_local(), 6u * 100u + 7u * 14u);
  EXPECT_EQ(model.bonds.size(), 6u * 100u);
  const int net_group = model.group_id("net"), shackle_group = model.group_id("holders");
  ASSERT_GE(net_group, 0);
  ASSERT_GE(shackle_group, 0);
  std::set<std::int32_t> bodies;
  int fixed = 0;
  double ring_mass = 0.0;
  Vec3 sum;
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    bodies.insert(p.body[k]);
    const bool is_shackle = k >= 600;  // gids: net rings first, then shackles
    EXPECT_EQ(p.group[k], is_shackle ? shackle_group : net_group) << k;
    EXPECT_EQ(p.motion[k] == Motion::kFixed, is_shackle) << k;
    EXPECT_EQ(p.material[k], is_shackle ? 1 : 0) << k;
    EXPECT_DOUBLE_EQ(p.damping_of(k), is_shackle ? 0.0 : 0.2) << k;
    fixed += is_shackle;
    if (p.body[k] == 0) ring_mass += p.mass[k];
    if (!is_shackle) sum += p.position[k];
  }
  EXPECT_EQ(bodies.size(), 13u);
  EXPECT_EQ(fixed, 98);
  EXPECT_NEAR(ring_mass, 1.2, 1e-12);  // `mass` is per ring
  // `centre` is the middle of the 3 x 4 lattice (columns 0..3, rows 0..2); the rings sit at
  // columns 1, 3, 0, 2, 1, 3 (mean 10/6) and rows 0, 0, 1, 1, 2, 2 (mean 1): their mean is
  // (10/6 - 1.5) = 1/6 pitch off `centre` in x, on it in y. A ring's particles average to its
  // centre.
  const Vec3 mean = sum / 600.0;
  EXPECT_NEAR(mean.x, 1.0 + 0.28 / std::sqrt(2.0) / 6.0, 1e-12);
  EXPECT_NEAR(mean.y, 2.0, 1e-12);
  EXPECT_NEAR(mean.z, 3.0, 1e-12);
  // Bonds only join consecutive particles of a ring: all bond ends below gid 600.
  for (std::size_t k = 0; k < model.bonds.size(); ++k) {
    EXPECT_LT(model.bonds.gid_a[k], 600);
    EXPECT_LT(model.bonds.gid_b[k], 600);
  }
}

TEST(RingNetCase, DefaultsBuildThePaperNet) {
  const auto start = std::chrono::steady_clock::now();
  const std::string text = R"(schema_version: 1
simulation: {end_time: 0.1}
materials: [{name: steel}]
bonds: [{name: ring}]
particles:
  nets: [{}]
)";
  const CaseConfig c = load_case_from_string(text, "paper_net.yaml");
  const Model model = build_model(c);
  // 180 rings x 100 particles, 36 shackles x 14; one bond per ring particle.
  EXPECT_EQ(model.particles.n_local(), 18000u + 36u * 14u);
  EXPECT_EQ(model.bonds.size(), 18000u);
  double lo_x = 1e9, hi_x = -1e9, lo_y = 1e9, hi_y = -1e9;
  for (std::size_t k = 0; k < 18000; ++k) {
    lo_x = std::min(lo_x, model.particles.position[k].x - model.particles.radius[k]);
    hi_x = std::max(hi_x, model.particles.position[k].x + model.particles.radius[k]);
    lo_y = std::min(lo_y, model.particles.position[k].y - model.particles.radius[k]);
    hi_y = std::max(hi_y, model.particles.position[k].y + model.particles.radius[k]);
  }
  // "3.9 m x 3.9 m" (paper): 18 pitches of 0.28 / sqrt(2) m plus one ring, 3.88 m and 3.87 m;
  // tolerance 5 cm.
  EXPECT_NEAR(hi_x - lo_x, 3.9, 0.05);
  EXPECT_NEAR(hi_y - lo_y, 3.9, 0.05);
  EXPECT_NEAR(lo_x + hi_x, 0.0, 1e-12);  // centred on the default centre [0, 0, 0]
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("paper net case: extent %.4f m x %.4f m, loaded and built in %.2f s\n", hi_x - lo_x,
              hi_y - lo_y, seconds);
}

/// The diagnostics of loading `text`; fails the test if it loads.
std::vector<Diagnostic> errors_of(const std::string& text,
                                  const std::vector<std::string>& overrides = {}) {
  try {
    load_case_from_string(text, "case.yaml", overrides);
  } catch (const InputError& e) {
    return e.diagnostics;
  }
  ADD_FAILURE() << "expected an InputError";
  return {};
}

std::string message_at(const std::vector<Diagnostic>& diags, const std::string& path) {
  for (const Diagnostic& d : diags)
    if (d.key_path == path) return d.message;
  return "(no diagnostic at " + path + "; got: " + InputError(diags).format() + ")";
}

TEST(RingNetCase, WidthAndLengthSetColumnsAndRows) {
  std::string text = kNetCase;
  const std::string counts = "rows: 3\n      columns: 4";
  text.replace(text.find(counts), counts.size(), "width: 2.5\n      length: 1.5");
  const CaseConfig c = load_case_from_string(text, "net.yaml");
  // As RingNetLayout.CountsFromTargetSize: 12 columns, 7 rows.
  EXPECT_EQ(c.nets[0].columns, 12);
  EXPECT_EQ(c.nets[0].rows, 7);
  // The dump keeps the targets, not the counts they set, and loads again to the same net.
  const std::string dumped = dump_case(c);
  EXPECT_EQ(dumped.find("columns:"), std::string::npos) << dumped;
  const CaseConfig again = load_case_from_string(dumped, "again.yaml");
  EXPECT_EQ(again.nets[0].columns, 12);
  EXPECT_EQ(again.nets[0].rows, 7);
  EXPECT_EQ(dump_case(again), dumped);
}

TEST(RingNetCase, GeometryErrorsAreReported) {
  const std::string p = "particles.nets[0]";
  // Both a count and its target.
  auto diags = errors_of(kNetCase, {"particles.nets.0.width=2.5"});
  EXPECT_NE(message_at(diags, p + ".columns").find("give either columns or width"),
            std::string::npos)
      << InputError(diags).format();
  // Farther apart than the centreline diameter 0.309 m: cannot interlink.
  diags = errors_of(kNetCase, {"particles.nets.0.link_distance=0.32"});
  EXPECT_NE(message_at(diags, p + ".link_distance").find("must be < internal_diameter"),
            std::string::npos);
  // Nearly flat rings cut through their neighbours.
  diags = errors_of(kNetCase, {"particles.nets.0.tilt=0.01"});
  EXPECT_NE(message_at(diags, p).find("rings touch at creation"), std::string::npos);
  // 30 shackle particles on a 38 mm circle are 7.9 mm apart, less than 2 x 8 mm: at most
  // 14 fit (2 x 0.038 sin(pi / 15) = 15.8 mm < 16 mm).
  diags = errors_of(kNetCase, {"particles.nets.0.shackles.n_particles=30"});
  EXPECT_NE(message_at(diags, p + ".shackles.n_particles").find("use at most 14 particles"),
            std::string::npos);
  // 4 shackle particles 53.7 mm apart: a net particle (contact radius 9 mm) slips between
  // them; from 7 on the spacing is below 2 (8 + 9) = 34 mm (2 x 0.038 sin(pi / 7) = 33.0 mm).
  diags = errors_of(kNetCase, {"particles.nets.0.shackles.n_particles=4"});
  EXPECT_NE(message_at(diags, p + ".shackles.n_particles").find("use at least 7 particles"),
            std::string::npos);
  // Unknown shackle material.
  diags = errors_of(kNetCase, {"particles.nets.0.shackles.material=brass"});
  EXPECT_NE(message_at(diags, p + ".shackles.material").find("'brass' is not defined"),
            std::string::npos);
  // The net's x along its normal.
  diags = errors_of(kNetCase,
                    {"particles.nets.0.normal=[0, 1, 1]", "particles.nets.0.x_axis=[0, 2, 2]"});
  EXPECT_NE(message_at(diags, p + ".x_axis").find("must not be parallel to normal"),
            std::string::npos);
}

// A net standing across a channel is the horizontal net turned about its centre: every ring
// and shackle frame is R times the horizontal one, R = (x_axis, normal x x_axis, normal) as
// columns, built here from the axes. Rotation preserves every distance, so the clearance and
// the links are the horizontal net's (to rounding).
TEST(RingNetLayout, AStandingNetIsTheHorizontalNetTurned) {
  RingNetParameters flat;
  flat.rows = 5;
  flat.columns = 6;
  flat.centre = {1.0, -2.0, 0.5};
  RingNetParameters standing = flat;
  standing.normal = normalized(Vec3{1.0, 0.3, 0.2});
  standing.x_axis = normalized(cross(Vec3{0, 0, 1}, standing.normal));  // horizontal
  const Vec3 ey = cross(standing.normal, standing.x_axis);
  const auto turn = [&](const Vec3& v) {
    return standing.x_axis * v.x + ey * v.y + standing.normal * v.z;
  };
  const RingNetLayout a = generate_ring_net(flat), b = generate_ring_net(standing);
  ASSERT_EQ(a.rings.size(), b.rings.size());
  ASSERT_EQ(a.shackles.size(), b.shackles.size());
  EXPECT_EQ(a.links, b.links);
  for (std::size_t k = 0; k < a.rings.size(); ++k) {
    EXPECT_LT(norm(b.rings[k].centre - (flat.centre + turn(a.rings[k].centre - flat.centre))),
              1e-12);
    EXPECT_LT(norm(b.rings[k].normal - turn(a.rings[k].normal)), 1e-12);
    EXPECT_LT(norm(b.rings[k].reference - turn(a.rings[k].reference)), 1e-12);
  }
  for (std::size_t k = 0; k < a.shackles.size(); ++k) {
    EXPECT_LT(norm(b.shackles[k].centre - (flat.centre + turn(a.shackles[k].centre - flat.centre))),
              1e-12);
    EXPECT_LT(norm(b.shackles[k].normal - turn(a.shackles[k].normal)), 1e-12);
  }
  const auto ca = smallest_clearance(a, 0.008, 0.008, 0.05);
  const auto cb = smallest_clearance(b, 0.008, 0.008, 0.05);
  EXPECT_NEAR(ca.gap, cb.gap, 1e-12);
  // The ring planes stand: the net's normal is nearly horizontal here, and so are the ring
  // axes up to the tilt.
  for (const auto& r : b.rings)
    EXPECT_NEAR(std::abs(dot(r.normal, standing.normal)), std::cos(flat.tilt), 1e-12);
  // Axes that are not unit and perpendicular are refused.
  RingNetParameters skew = flat;
  skew.x_axis = normalized(Vec3{1, 0, 1});
  EXPECT_THROW(generate_ring_net(skew), std::invalid_argument);
}

// The case file: `normal` alone (a barrier across a channel along x) takes the world y as the
// net's x; the built particles are the horizontal net's turned, centre kept.
TEST(RingNetCase, NormalTurnsTheNetAboutItsCentre) {
  const Model flat = build_model(load_case_from_string(kNetCase, "net.yaml"));
  const CaseConfig c =
      load_case_from_string(kNetCase, "net.yaml", {"particles.nets.0.normal=[-2, 0, 0]"});
  EXPECT_EQ(c.nets[0].normal, (Vec3{-1, 0, 0}));
  EXPECT_EQ(c.nets[0].x_axis, (Vec3{0, 1, 0}));
  const Model standing = build_model(c);
  ASSERT_EQ(flat.particles.n_local(), standing.particles.n_local());
  // R: x -> y, z -> -x, y -> normal x x_axis = (-x) x y = -z.
  const Vec3 centre{1, 2, 3};
  for (std::size_t k = 0; k < flat.particles.n_local(); ++k) {
    const Vec3 d = flat.particles.position[k] - centre;
    const Vec3 expected = centre + Vec3{-d.z, d.x, -d.y};
    ASSERT_LT(norm(standing.particles.position[k] - expected), 1e-12) << k;
  }
}

}  // namespace
}  // namespace ringdem

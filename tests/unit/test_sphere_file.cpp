// Spheres read from a CSV packing (particles.sphere_files, io/SphereFile): the model they build
// is the one the same spheres listed in the case build, bit for bit; a rank's slice reads only
// its lines; every fault of the file is reported with its file and line before a run starts.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "TestCases.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/SphereFileSource.hpp"
#include "io/CaseLoader.hpp"
#include "io/SphereFile.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

struct Sphere {
  double x, y, z, r;
};

/// 60 spheres on a jittered grid, radii 2-4 mm, printed with 17 digits (exact round trip).
std::vector<Sphere> packing() {
  std::vector<Sphere> s;
  for (int k = 0; k < 60; ++k)
    s.push_back({0.01 * (k % 5) + 1e-4 * std::sin(k), 0.01 * ((k / 5) % 4), 0.01 * (k / 20) + 0.5,
                 0.002 + 0.002 * std::fabs(std::cos(0.3 * k))});
  return s;
}

fs::path write_file(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "ringdem_sphere_file_test";
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::string csv(const std::vector<Sphere>& spheres) {
  std::string text = "# a packing\nx, y, z, radius\n\n";
  char line[160];
  for (const Sphere& s : spheres) {
    std::snprintf(line, sizeof line, "%.17g,%.17g,%.17g,%.17g\n", s.x, s.y, s.z, s.r);
    text += line;
  }
  return text;
}

TEST(SphereFile, BuildsTheModelTheListedSpheresBuild) {
  const std::vector<Sphere> spheres = packing();
  const fs::path path = write_file("packing.csv", csv(spheres));
  const Vec3 velocity{0.5, 0.0, -1.0};
  CaseConfig listed = testing::base_case();
  listed.materials.push_back(testing::soft_rock());
  for (const Sphere& s : spheres) {
    SphereConfig c;
    c.group = "grains";
    c.material = "rock";
    c.position = {s.x, s.y, s.z};
    c.radius = s.r;
    c.velocity = velocity;
    listed.spheres.push_back(c);
  }
  CaseConfig from_file = testing::base_case();
  from_file.materials.push_back(testing::soft_rock());
  SphereFileConfig f;
  f.path = path.string();
  f.group = "grains";
  f.material = "rock";
  f.velocity = velocity;
  from_file.sphere_files.push_back(f);

  const Communicator self = testing::self_comm();
  const Model a = build_model(listed, self);
  const Model b = build_model(from_file, self);
  ASSERT_EQ(a.particles.n_local(), spheres.size());
  ASSERT_EQ(b.particles.n_local(), spheres.size());
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    EXPECT_EQ(a.particles.gid[k], b.particles.gid[k]);
    EXPECT_EQ(a.particles.position[k], b.particles.position[k]) << k;
    EXPECT_EQ(a.particles.radius[k], b.particles.radius[k]) << k;
    EXPECT_EQ(a.particles.mass[k], b.particles.mass[k]) << k;
    EXPECT_EQ(a.particles.velocity[k], b.particles.velocity[k]) << k;
    EXPECT_EQ(a.particles.group[k], b.particles.group[k]) << k;
    EXPECT_EQ(a.particles.material[k], b.particles.material[k]) << k;
  }
  EXPECT_EQ(b.particles.position[7], (Vec3{spheres[7].x, spheres[7].y, spheres[7].z}));
}

TEST(SphereFile, ASliceReadsOnlyItsLinesAndTheSlicesMakeTheWhole) {
  const std::vector<Sphere> spheres = packing();
  const SphereFile file(write_file("slices.csv", csv(spheres)).string());
  ASSERT_EQ(file.count(), static_cast<std::int64_t>(spheres.size()));
  ParticleStore::NewParticle prototype;
  prototype.density = 2600;
  const SphereFileSource source(file, prototype);
  Model whole, parts;
  source.emit(0, file.count(), {100, 0, 0}, whole);
  for (int rank = 0; rank < 3; ++rank)  // the slices ModelBuilder gives 3 ranks
    source.emit(ParticleSource::slice_begin(file.count(), rank, 3),
                ParticleSource::slice_begin(file.count(), rank + 1, 3), {100, 0, 0}, parts);
  ASSERT_EQ(parts.particles.n_local(), whole.particles.n_local());
  for (std::size_t k = 0; k < spheres.size(); ++k) {
    EXPECT_EQ(whole.particles.gid[k], 100 + static_cast<std::int64_t>(k));
    EXPECT_EQ(parts.particles.gid[k], whole.particles.gid[k]);
    EXPECT_EQ(parts.particles.position[k], whole.particles.position[k]);
    EXPECT_EQ(whole.particles.radius[k], spheres[k].r);
  }
}

/// The diagnostics of loading a case whose one sphere file holds `text` (or, when `write` is
/// false, is not there).
std::string load_error(const std::string& text, bool write = true) {
  const fs::path csv_path = fs::temp_directory_path() / "ringdem_sphere_file_test" / "bad.csv";
  if (write)
    write_file("bad.csv", text);
  else
    fs::remove(csv_path);
  const fs::path case_path = write_file("case.yaml", R"(schema_version: 1
simulation: {dt: 1.0e-5, end_time: 1.0e-4}
materials:
  - {name: rock, density: 2600, youngs_modulus: 1.0e9, poisson_ratio: 0.25}
particles:
  sphere_files:
    - {path: bad.csv, material: rock}
)");
  try {
    const CaseConfig c = load_case(case_path.string());
    return "loaded " + std::to_string(c.sphere_files.at(0).count) + " spheres";
  } catch (const InputError& e) {
    return e.format();
  }
}

TEST(SphereFile, EveryFaultNamesItsFileAndLine) {
  // A file beside the case, named by a relative path, loads and is counted.
  EXPECT_EQ(load_error("x,y,z,radius\n0,0,0,0.01\n# comment\n0.1,0,0,0.01\n"), "loaded 2 spheres");
  EXPECT_NE(load_error("x,y,radius\n0,0,0.01\n")
                .find("bad.csv:1: the first line must be the "
                      "header 'x,y,z,radius'"),
            std::string::npos);
  EXPECT_NE(load_error("x,y,z,radius\n0,0,0,0.01\n\n0,0,0.01\n")
                .find("bad.csv:4: expected 4 comma-separated numbers"),
            std::string::npos);
  EXPECT_NE(load_error("x,y,z,radius\n0,0,0,0.01\n0,nan,0,0.01\n")
                .find("bad.csv:3: column 2 is not a finite number"),
            std::string::npos);
  EXPECT_NE(load_error("x,y,z,radius\n0,0,0,-0.01\n").find("bad.csv:2: the radius must be above 0"),
            std::string::npos);
  EXPECT_NE(load_error("x,y,z,radius\n0,0,0,0.01,7\n").find("bad.csv:2: expected 4"),
            std::string::npos);
  EXPECT_NE(load_error("").find("no header"), std::string::npos);
  EXPECT_NE(load_error("", false).find("bad.csv: cannot open the sphere file"), std::string::npos);
}

}  // namespace
}  // namespace ringdem

// Frame sidecar and checkpoint robustness (issue 5): the XDMF sidecar names datasets that exist
// with the dimensions it states; a truncated, corrupted or incomplete checkpoint is refused
// with a clear error, never a crash or a silent wrong restart.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "TempDir.hpp"
#include "TestCases.hpp"
#include "app/InfoCommand.hpp"
#include "engine/ModelBuilder.hpp"
#include "engine/Simulation.hpp"
#include "io/Checkpoint.hpp"
#include "io/FrameWriter.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {
namespace {

namespace fs = std::filesystem;

using testing::temp_dir;

/// One paper ring dropped onto a plane at 1 m/s: bonds, a body contact with history.
CaseConfig ring_on_floor() {
  CaseConfig c = testing::base_case();
  c.simulation.dt = 1e-6;
  c.materials[0].friction = 0.3;
  // The lowest sphere 0.2 mm into the floor; it bounces off within about 15 us.
  auto ring = testing::paper_ring({0, 0, 0.1545 + 0.0045 - 2e-4}, {0, 1, 0});
  ring.velocity = {0.2, 0, -1.0};
  c.rings.push_back(ring);
  RigidBodyConfig floor;
  floor.name = "floor";
  c.rigid_bodies.push_back(floor);
  return c;
}

std::vector<std::int64_t> parse_dims(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::int64_t> d;
  std::int64_t v;
  while (in >> v)
    d.push_back(v);
  return d;
}

TEST(FrameFile, InfoOnTheXdmfIndexDescribesItsFrameFile) {
  // Users hold the .xdmf that ParaView opens; `info` on it was "not an HDF5 file".
  const std::string dir = temp_dir("xdmf_info");
  const Communicator self = testing::self_comm();
  const CaseConfig c = ring_on_floor();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  {
    FrameWriter frames(self, dir + "/frames_0003.h5", dir + "/frames_0003.xdmf");
    for (int f = 0; f < 2; ++f) {
      sim.refresh_bond_diagnostics();
      frames.write(sim.model().particles, sim.model().bonds, sim.model().bodies, sim.time(),
                   sim.steps());
      sim.run_steps(10);
    }
  }
  std::ostringstream out;
  EXPECT_EQ(print_file_info(dir + "/frames_0003.xdmf", out), 0);
  EXPECT_NE(out.str().find(dir + "/frames_0003.xdmf: ParaView's index of the frame file " + dir +
                           "/frames_0003.h5\n" + dir + "/frames_0003.h5: ringdem frame file"),
            std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("100 particles, 100 bonds, 2 frames"), std::string::npos) << out.str();
  fs::remove(dir + "/frames_0003.h5");
  std::ostringstream missing;
  EXPECT_EQ(print_file_info(dir + "/frames_0003.xdmf", missing), 2);
  fs::remove_all(dir);
}

TEST(FrameFile, XdmfSidecarMatchesTheHdf5File) {
  const std::string dir = temp_dir("xdmf");
  const Communicator self = testing::self_comm();
  const CaseConfig c = ring_on_floor();
  Simulation sim(build_model(c, self), self, settings_from_case(c));
  FrameWriter frames(self, dir + "/frames_0000.h5", dir + "/frames_0000.xdmf");
  for (int f = 0; f < 3; ++f) {
    sim.refresh_bond_diagnostics();
    frames.write(sim.model().particles, sim.model().bonds, sim.model().bodies, sim.time(),
                 sim.steps());
    sim.run_steps(50);
  }
  std::ifstream in(dir + "/frames_0000.xdmf");
  std::stringstream text;
  text << in.rdbuf();
  const std::string xml = text.str();
  const Hdf5File h5 = Hdf5File::open_read(dir + "/frames_0000.h5");
  const std::int64_t particles = h5.attribute_int("/", "particles");
  const std::int64_t bonds = h5.attribute_int("/", "bonds");
  EXPECT_EQ(particles, 100);
  EXPECT_EQ(bonds, 100);

  // Every HDF data item: the file and path exist, with the dimensions stated.
  const std::regex hdf_item(
      R"re(<DataItem Dimensions="([0-9 ]+)"[^>]*Format="HDF">([^:<]+):([^<]+)</DataItem>)re");
  int items = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), hdf_item);
       it != std::sregex_iterator(); ++it) {
    const auto& m = *it;
    EXPECT_EQ(m[2].str(), "frames_0000.h5");
    ASSERT_TRUE(h5.exists(m[3].str())) << m[3].str();
    EXPECT_EQ(parse_dims(m[1].str()), h5.dims(m[3].str())) << m[3].str();
    ++items;
  }
  // 3 frames x (particles: geometry + their fields; bonds: connectivity, geometry, their
  // fields; the floor: its triangles, its surface points, its fields).
  const auto particle_fields = h5.list("/particles").size();
  const auto bond_fields = h5.list("/bonds").size() - 1;  // connectivity is the topology
  EXPECT_EQ(h5.list("/bodies"), (std::vector<std::string>{"active", "force", "position", "radius",
                                                          "surface", "velocity"}));
  const std::size_t body_fields = 4;  // all but active and surface
  EXPECT_EQ(items, static_cast<int>(3 * (1 + particle_fields + 2 + bond_fields + 2 + body_fields)));

  // Every data item is a hyperslab. Of a per-frame dataset, it selects one whole frame: start
  // (f, 0, ...), count (1, rows, ...), and the outer dimensions are that count without the frame
  // axis. Of a topology (fixed rows), it selects the whole [rows, nodes] block.
  const std::regex slab(
      R"re(<DataItem ItemType="HyperSlab" Dimensions="([0-9 ]+)" Type="HyperSlab">\s*<DataItem Dimensions="3 ([23])" Format="XML">([0-9 ]+)</DataItem>\s*<DataItem Dimensions="[0-9 ]+"[^>]*>[^:]+:([a-z/_]+)</DataItem>)re");
  int slabs = 0, topologies = 0;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), slab); it != std::sregex_iterator();
       ++it) {
    const auto outer = parse_dims((*it)[1].str());
    const auto v = parse_dims((*it)[3].str());
    const std::size_t rank = std::stoul((*it)[2].str());
    const std::string path = (*it)[4].str();
    ASSERT_EQ(v.size(), 3 * rank);
    const std::vector<std::int64_t> count(v.begin() + static_cast<long>(2 * rank), v.end());
    ++slabs;
    if (path == "/bonds/connectivity" || path == "/bodies/surface/triangles") {
      EXPECT_EQ(count, outer) << path;
      EXPECT_EQ(v[0], 0) << path;  // one topology block, one body
      const bool bond = path == "/bonds/connectivity";
      EXPECT_EQ(outer, (std::vector<std::int64_t>{bond ? bonds : 2, bond ? 2 : 3})) << path;
      ++topologies;
      continue;
    }
    EXPECT_EQ(count[0], 1);  // one frame
    EXPECT_TRUE(v[0] >= 0 && v[0] < 3);
    EXPECT_EQ(std::vector<std::int64_t>(count.begin() + 1, count.end()), outer);
    // 4: the floor's patch vertices; 1: the floor's fields.
    EXPECT_TRUE(outer[0] == particles || outer[0] == bonds || outer[0] == 4 || outer[0] == 1)
        << path;
  }
  EXPECT_EQ(slabs, items);
  EXPECT_EQ(topologies, 6);  // bonds and floor, 3 frames
  EXPECT_NE(xml.find(R"(<Grid Name="body_floor" GridType="Uniform">)"), std::string::npos);
  EXPECT_NE(xml.find(R"(TopologyType="Triangle" NumberOfElements="2" NodesPerElement="3")"),
            std::string::npos);
  const std::regex vertex(R"re(TopologyType="Polyvertex" NumberOfElements="([0-9]+)")re");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(xml, m, vertex));
  EXPECT_EQ(std::stoll(m[1].str()), particles);
  const auto times = h5.read_rows<double>("/frames/time");
  ASSERT_EQ(times.size(), 3u);
  EXPECT_NEAR(times[2], 100 * sim.dt(), 1e-15);  // time is summed step by step
  fs::remove_all(dir);
}

class CorruptCheckpoint : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = temp_dir("corrupt");
    const Communicator self = testing::self_comm();
    config_ = ring_on_floor();
    Simulation sim(build_model(config_, self), self, settings_from_case(config_));
    sim.run_steps(5);  // mid-contact
    DriverState d;
    d.set("next_record_time", 0.5);
    good_ =
        CheckpointStore(dir_).write(sim.comm(), sim.model(), sim.restart_state(), d, 0, config_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  /// A copy of the good checkpoint.
  std::string copy(const std::string& name) {
    const std::string path = dir_ + "/" + name;
    fs::copy_file(good_, path);
    return path;
  }
  void expect_refused(const std::string& path, const std::string& words) {
    Model model = build_model_without_particles(config_);
    DriverState d;
    try {
      read_checkpoint(testing::self_comm(), path, config_, model, d);
      ADD_FAILURE() << path << " was accepted";
    } catch (const Hdf5Error& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
  std::string dir_, good_;
  CaseConfig config_;
};

TEST_F(CorruptCheckpoint, GoodOneRestoresTheState) {
  Model model = build_model_without_particles(config_);
  DriverState d;
  CheckpointInfo info;
  const RestartState s = read_checkpoint(testing::self_comm(), good_, config_, model, d, &info);
  EXPECT_EQ(s.steps, 5);
  // The case's dt, and the time of 5 steps of it (summed step by step: a few ulp).
  EXPECT_EQ(s.dt, 1e-6);
  EXPECT_NEAR(s.time, 5 * 1e-6, 1e-20);
  EXPECT_EQ(d.get("next_record_time"), 0.5);
  // Both contact terms' stores, the floor's springs in the body-contact one.
  ASSERT_EQ(s.springs.size(), 2u);
  const auto& floor = s.springs[0].term == "body_contacts" ? s.springs[0] : s.springs[1];
  EXPECT_EQ(floor.term, "body_contacts");
  EXPECT_FALSE(floor.store.partner_is_particle());
  EXPECT_GT(floor.store.size(), 0u) << "the ring touches the floor";
  // Every registry field flagged kCheckpoint (particles, bonds, each term's springs), 10 body
  // rows (7 of state, 3 of the rebuild reference: position, orientation and the particles'
  // move bound toward the body), the outflow totals, the inflow's batches,
  // next times and totals, the momentum ledger's state, the energy ledger's state, the driver,
  // the case text.
  std::size_t fields = 0;
  const auto count = [&](const FieldInfo& i, const auto&) {
    fields += i.has(field_flag::kCheckpoint);
  };
  for (const auto& t : s.springs)
    t.store.for_each_field(count);
  // gid, partner, spring of each term, and the particle pairs' carried damping force
  EXPECT_EQ(fields, 2u * 3u + 1u);
  model.particles.for_each_field(count);
  model.bonds.for_each_field(count);
  EXPECT_EQ(verify_checkpoint(good_).size(), fields + 10u + 1u + 3u + 1u + 1u + 1u + 1u);
}

TEST_F(CorruptCheckpoint, TruncatedFileIsRefused) {
  const std::string path = copy("truncated.h5");
  fs::resize_file(path, fs::file_size(path) / 2);
  Model model = build_model_without_particles(config_);
  DriverState d;
  EXPECT_THROW(read_checkpoint(testing::self_comm(), path, config_, model, d), Hdf5Error);
}

TEST_F(CorruptCheckpoint, FlippedDataByteFailsTheChecksum) {
  const std::string path = copy("flipped.h5");
  // The byte offset of /particles/velocity's data, from HDF5 itself.
  haddr_t offset = HADDR_UNDEF;
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t d = H5Dopen2(f, "/particles/velocity", H5P_DEFAULT);
    offset = H5Dget_offset(d);
    H5Dclose(d);
    H5Fclose(f);
  }
  ASSERT_NE(offset, HADDR_UNDEF);
  std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
  io.seekg(static_cast<std::streamoff>(offset + 8 * 3 * 50 + 5));  // particle 50, x, a middle byte
  char byte = 0;
  io.read(&byte, 1);
  byte = static_cast<char>(byte ^ 0x10);
  io.seekp(static_cast<std::streamoff>(offset + 8 * 3 * 50 + 5));
  io.write(&byte, 1);
  io.close();
  expect_refused(path, "/particles/velocity fails its checksum");
}

TEST_F(CorruptCheckpoint, BrokenSignatureIsNotAnHdf5File) {
  const std::string path = copy("signature.h5");
  std::fstream io(path, std::ios::in | std::ios::out | std::ios::binary);
  io.seekp(1);
  io.write("X", 1);
  io.close();
  expect_refused(path, "not an HDF5 file");
}

TEST_F(CorruptCheckpoint, IncompleteCheckpointIsRefused) {
  const std::string path = copy("incomplete.h5");
  {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(H5Adelete(f, "complete"), 0);
    H5Fclose(f);
  }
  expect_refused(path, "incomplete checkpoint");
}

TEST_F(CorruptCheckpoint, CheckpointOfAnotherCaseIsRefused) {
  config_.rings.push_back(testing::paper_ring({1.0, 0, 0.2}));
  expect_refused(good_, "belongs to another case");
}

// The same particle, bond and body counts, another model (a material's density, which the
// saved masses came from): refused by the model identity, not by counting.
TEST_F(CorruptCheckpoint, SameCountsOfAnotherModelAreRefused) {
  config_.materials[0].density *= 2.0;
  expect_refused(good_, "belongs to another case (the model differs: materials[");
}

// A key that a restart may apply (with --allow-changes, RunControl decides): the checkpoint
// still belongs to the case.
TEST_F(CorruptCheckpoint, AppliedKeyChangeKeepsTheIdentity) {
  config_.materials[0].friction = 0.5;
  Model model = build_model_without_particles(config_);
  DriverState d;
  EXPECT_NO_THROW(read_checkpoint(testing::self_comm(), good_, config_, model, d));
}

// A run whose particle count is no longer what the case's sources create at start-up (inflow
// adds particles, outflow removes them; here one free particle is added to the built model):
// its checkpoint holds its own count and restores it, and the run goes on from it.
TEST_F(CorruptCheckpoint, ParticleCountOfTheRunNotOfTheSourcesIsRestored) {
  const Communicator self = testing::self_comm();
  Model built = build_model(config_, self);
  ParticleStore::NewParticle extra;
  extra.gid = 1000000;
  extra.position = {0.5, 0.5, 0.3};
  extra.radius = 0.0045;
  extra.density = 7850.0;
  built.particles.add(extra);
  const std::int64_t start_up = built.initial_particles;
  ASSERT_EQ(static_cast<std::int64_t>(built.particles.n_local()), start_up + 1);
  std::string path;
  {
    Simulation sim(std::move(built), self, settings_from_case(config_));
    sim.run_steps(3);
    path = CheckpointStore(dir_ + "/grown")
               .write(self, sim.model(), sim.restart_state(), DriverState{}, 0, config_);
  }
  Model model = build_model_without_particles(config_);
  DriverState d;
  CheckpointInfo info;
  const RestartState state = read_checkpoint(self, path, config_, model, d, &info);
  EXPECT_EQ(info.particles, start_up + 1);
  ASSERT_EQ(static_cast<std::int64_t>(model.particles.n_local()), start_up + 1);
  EXPECT_EQ(model.particles.gid.back(), 1000000);
  Simulation resumed(std::move(model), self, settings_from_case(config_), state);
  resumed.run_steps(2);
  EXPECT_EQ(resumed.global_particles(), start_up + 1);
}

TEST_F(CorruptCheckpoint, InfoCommandReportsAndVerifies) {
  std::ostringstream out;
  EXPECT_EQ(print_file_info(good_, out), 0);
  EXPECT_NE(out.str().find("100 particles, 100 bonds, 1 rigid bodies"), std::string::npos)
      << out.str();
  EXPECT_NE(out.str().find("datasets verified"), std::string::npos);
  const std::string path = copy("for_info.h5");
  fs::resize_file(path, 100);
  std::ostringstream bad;
  EXPECT_EQ(print_file_info(path, bad), 2);
}

TEST(Duration, ParsesTheUsualForms) {
  EXPECT_EQ(parse_duration("3600"), 3600.0);
  EXPECT_EQ(parse_duration("90m"), 5400.0);
  EXPECT_EQ(parse_duration("1h30m"), 5400.0);
  EXPECT_EQ(parse_duration("1:02:03"), 3723.0);
  EXPECT_EQ(parse_duration("45s"), 45.0);
  EXPECT_THROW(parse_duration("ten"), std::invalid_argument);
  EXPECT_THROW(parse_duration("5x"), std::invalid_argument);
  EXPECT_THROW(parse_duration(""), std::invalid_argument);
  // The message quotes the argument (never the bare "stod" of std::stod) and names the forms.
  for (const std::string bad : {"ten", "1e999", "inf", "-5", "1:xx", "h"}) {
    try {
      parse_duration(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("'" + bad + "'"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace ringdem

namespace ringdem {
namespace {

TEST_F(CorruptCheckpoint, NameWithAStepBeyond64BitsIsSkippedNotAnError) {
  // A stray file whose step does not fit 64 bits is not one of ours: --restart auto skips it
  // and takes the good checkpoint (before, std::stoll threw "stoll").
  copy("checkpoint_123456789012345678901234.h5");
  const auto all = CheckpointStore(dir_).list();
  ASSERT_EQ(all.size(), 1u);
  EXPECT_EQ(all[0], good_);
  std::vector<std::string> skipped;
  EXPECT_EQ(latest_valid_checkpoint(dir_, &skipped), good_);
}

}  // namespace
}  // namespace ringdem

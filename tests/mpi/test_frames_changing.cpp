// Frame files whose particle and bond counts change (inflow, outflow; docs/output.md): sparse
// gids from two "sources", particles added, removed and moved between ranks from frame to
// frame. Every frame is read back and checked against what was written (counts, gid order,
// values, the unwritten rows beyond the count, the topology as particle rows of the frame), the
// sidecar must select each frame's rows, and the file must hold the same bytes as a one-rank run.
#include <gtest/gtest.h>
#include <mpi.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "SharedTempDir.hpp"
#include "io/FrameWriter.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {
namespace {

struct BondDef {
  std::int64_t id, a, b;
};

/// The particles and bonds of each frame (the same on every rank count).
struct Scene {
  std::set<std::int64_t> gids;
  std::vector<BondDef> bonds;
};

std::vector<Scene> scenes() {
  std::vector<Scene> s(6);
  // Frame 0: free grains 0..5 and a chain 100..111 (bond ids 400 + g).
  for (std::int64_t g = 0; g < 6; ++g)
    s[0].gids.insert(g);
  for (std::int64_t g = 100; g < 112; ++g)
    s[0].gids.insert(g);
  for (std::int64_t g = 100; g < 111; ++g)
    s[0].bonds.push_back({400 + g, g, g + 1});
  // Frame 1, inflow: a short chain 120..122 (ids 900, 901) and grains 1006..1009.
  s[1] = s[0];
  for (std::int64_t g : {120, 121, 122, 1006, 1007, 1008, 1009})
    s[1].gids.insert(g);
  s[1].bonds.push_back({900, 120, 121});
  s[1].bonds.push_back({901, 121, 122});
  // Frame 2, outflow: grains below the bonded particles and bonded ones removed, with their
  // bonds; the rows of the survivors shift.
  s[2] = s[1];
  for (std::int64_t g : {0, 1, 2, 100, 101, 105, 120})
    s[2].gids.erase(g);
  std::erase_if(s[2].bonds,
                [&](const BondDef& b) { return !s[2].gids.count(b.a) || !s[2].gids.count(b.b); });
  // Frame 3: the same particles and bonds (new values only).
  s[3] = s[2];
  // Frame 4: more grains than ever, all above the bonded gids: the topology's rows stay.
  s[4] = s[3];
  for (std::int64_t g = 2000; g < 2010; ++g)
    s[4].gids.insert(g);
  // Frame 5: one grain below the bonded ones leaves, one above comes: the same counts, but
  // every bonded row moves down by one.
  s[5] = s[4];
  s[5].gids.erase(3);
  s[5].gids.insert(3000);
  return s;
}

/// Where each frame's topology starts in /bonds/connectivity: 11 bonds, 13, then 8 (frames
/// 2 to 4 share one block), then 8 again with other rows.
const std::vector<std::int64_t> kTopologyFirst{0, 11, 24, 24, 24, 32};
constexpr std::int64_t kTopologyRows = 40;

Vec3 position_of(std::int64_t g, int frame) {
  return {static_cast<double>(g), static_cast<double>(frame), -0.5 * static_cast<double>(g)};
}
double utilisation_of(std::int64_t id, int frame) {
  return 0.01 * static_cast<double>(id) + frame;
}
/// Which rank owns a particle: it changes from frame to frame (migration).
int owner_of(std::int64_t g, int frame, int ranks) {
  return static_cast<int>((g * 7 + frame) % ranks);
}

/// Drops the owned particles for which `keep` is false (permute, then shrink).
void keep_only(ParticleStore& p, const std::function<bool(std::int64_t)>& keep) {
  std::vector<std::size_t> order, dropped;
  for (std::size_t i = 0; i < p.n_local(); ++i)
    (keep(p.gid[i]) ? order : dropped).push_back(i);
  const std::size_t n = order.size();
  order.insert(order.end(), dropped.begin(), dropped.end());
  p.permute_local(order);
  p.resize_local(n);
  p.rebuild_index();
}

/// Brings this rank's stores to frame `frame` of the scenes: removes what left or moved away,
/// adds what came in or moved here, and sets every value of the frame.
void update(ParticleStore& p, BondStore& bonds, const Scene& scene, int frame, int rank,
            int ranks) {
  const auto mine = [&](std::int64_t g) {
    return scene.gids.count(g) && owner_of(g, frame, ranks) == rank;
  };
  keep_only(p, mine);
  for (std::int64_t g : scene.gids) {
    if (!mine(g) || p.index_of(g) >= 0) continue;
    ParticleStore::NewParticle n;
    n.gid = g;
    n.radius = 0.001 * static_cast<double>(g % 7 + 1);
    n.density = 7800;
    n.body = static_cast<std::int32_t>(g / 1000);
    p.add(n);
  }
  for (std::size_t i = 0; i < p.n_local(); ++i) {
    p.position[i] = position_of(p.gid[i], frame);
    p.velocity[i] = {static_cast<double>(frame), 0.25 * static_cast<double>(p.gid[i]), 1.0};
    p.group[i] = frame;
  }
  bonds = BondStore();
  for (const BondDef& b : scene.bonds) {
    if (!mine(b.a)) continue;  // a bond lives with its end a here (no ghosts needed)
    const std::size_t k = bonds.append(b.id, b.a, b.b, 0);
    bonds.utilisation[k] = utilisation_of(b.id, frame);
  }
}

void write_all(const Communicator& comm, const std::string& h5, const std::string& xdmf) {
  const std::vector<Scene> s = scenes();
  ParticleStore p;
  BondStore bonds;
  FrameWriter frames(comm, h5, xdmf, 1);  // compressed: filtered collective writes too
  for (int f = 0; f < static_cast<int>(s.size()); ++f) {
    update(p, bonds, s[static_cast<std::size_t>(f)], f, comm.rank(), comm.size());
    frames.write(p, bonds, {}, 0.1 * f, 10 * f);
  }
}

void expect_frames_as_written(const std::string& path) {
  const std::vector<Scene> s = scenes();
  const auto nf = static_cast<std::int64_t>(s.size());
  const Hdf5File f = Hdf5File::open_read(path);
  const auto n = f.read_rows<std::int64_t>("/frames/particles");
  const auto nb = f.read_rows<std::int64_t>("/frames/bonds");
  const auto topology = f.read_rows<std::int64_t>("/frames/connectivity");
  ASSERT_EQ(static_cast<std::int64_t>(n.size()), nf);
  // The row dimension is the largest count; topology blocks are appended when it changes only.
  EXPECT_EQ(f.attribute_int("/", "particles"), 28);
  EXPECT_EQ(f.attribute_int("/", "bonds"), 13);
  EXPECT_EQ(f.dims("/particles/position"), (std::vector<std::int64_t>{nf, 28, 3}));
  EXPECT_EQ(topology, kTopologyFirst);
  EXPECT_EQ(f.dims("/bonds/connectivity"), (std::vector<std::int64_t>{kTopologyRows, 2}));
  for (std::int64_t fr = 0; fr < nf; ++fr) {
    const Scene& scene = s[static_cast<std::size_t>(fr)];
    const std::vector<std::int64_t> expected(scene.gids.begin(), scene.gids.end());  // sorted
    ASSERT_EQ(n[static_cast<std::size_t>(fr)], static_cast<std::int64_t>(expected.size()));
    ASSERT_EQ(nb[static_cast<std::size_t>(fr)], static_cast<std::int64_t>(scene.bonds.size()));
    const auto rows = static_cast<std::int64_t>(expected.size());
    EXPECT_EQ(f.read_rows<std::int64_t>("/particles/gid", fr, 0, rows), expected) << fr;
    const auto pos = f.read_rows<Vec3>("/particles/position", fr, 0, rows);
    for (std::size_t i = 0; i < expected.size(); ++i)
      EXPECT_EQ(pos[i], position_of(expected[i], static_cast<int>(fr))) << expected[i];
    // Rows beyond the frame's count are not written; each frame is its own chunk: zeros.
    for (const auto& g : f.read_rows<std::int64_t>("/particles/gid", fr, rows, 28 - rows))
      EXPECT_EQ(g, 0) << "frame " << fr;
    for (const auto& x : f.read_rows<Vec3>("/particles/position", fr, rows, 28 - rows))
      EXPECT_EQ(x, Vec3{}) << "frame " << fr;
    std::vector<BondDef> bonds = scene.bonds;
    std::sort(bonds.begin(), bonds.end(), [](auto& x, auto& y) { return x.id < y.id; });
    const auto b_rows = static_cast<std::int64_t>(bonds.size());
    const auto ids = f.read_rows<std::int64_t>("/bonds/id", fr, 0, b_rows);
    const auto util = f.read_rows<double>("/bonds/utilisation", fr, 0, b_rows);
    for (std::size_t j = 0; j < bonds.size(); ++j) {
      EXPECT_EQ(ids[j], bonds[j].id);
      EXPECT_EQ(util[j], utilisation_of(bonds[j].id, static_cast<int>(fr)));
    }
  }
}

/// A [rows, 2] int64 dataset's rows [first, first + count) as pairs.
struct RowPair {
  std::int64_t first, second;
};

std::vector<RowPair> pairs(const Hdf5File& f, std::int64_t first, std::int64_t count) {
  std::size_t row_bytes = 0;
  const std::vector<char> all = f.read_bytes("/bonds/connectivity", row_bytes);
  std::vector<RowPair> out(static_cast<std::size_t>(count));
  if (row_bytes != sizeof(RowPair) || all.size() < (first + count) * sizeof(RowPair))
    throw std::runtime_error("/bonds/connectivity has an unexpected shape");
  std::memcpy(out.data(), all.data() + first * sizeof(RowPair), out.size() * sizeof(RowPair));
  return out;
}

void expect_topology_in_rows(const std::string& path) {
  const std::vector<Scene> s = scenes();
  const Hdf5File f = Hdf5File::open_read(path);
  const auto topology = f.read_rows<std::int64_t>("/frames/connectivity");
  for (std::size_t fr = 0; fr < s.size(); ++fr) {
    const std::vector<std::int64_t> gids(s[fr].gids.begin(), s[fr].gids.end());
    const auto row_of = [&](std::int64_t g) {
      return std::lower_bound(gids.begin(), gids.end(), g) - gids.begin();
    };
    std::vector<BondDef> bonds = s[fr].bonds;
    std::sort(bonds.begin(), bonds.end(), [](auto& x, auto& y) { return x.id < y.id; });
    const auto got = pairs(f, topology[fr], static_cast<std::int64_t>(bonds.size()));
    for (std::size_t j = 0; j < bonds.size(); ++j) {
      EXPECT_EQ(got[j].first, row_of(bonds[j].a)) << "frame " << fr << " bond " << bonds[j].id;
      EXPECT_EQ(got[j].second, row_of(bonds[j].b)) << "frame " << fr << " bond " << bonds[j].id;
    }
  }
}

std::vector<std::int64_t> numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<std::int64_t> v;
  std::int64_t x;
  while (in >> x)
    v.push_back(x);
  return v;
}

void expect_sidecar_selects_each_frame(const std::string& xdmf_path) {
  const std::vector<Scene> s = scenes();
  std::ifstream in(xdmf_path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string xml = buffer.str();
  const std::regex frame_re(R"re(<Grid Name="frame_(\d+)")re");
  std::vector<std::size_t> starts;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), frame_re);
       it != std::sregex_iterator(); ++it)
    starts.push_back(static_cast<std::size_t>(it->position()));
  ASSERT_EQ(starts.size(), s.size());
  starts.push_back(xml.size());
  for (std::size_t fr = 0; fr < s.size(); ++fr) {
    const std::string block = xml.substr(starts[fr], starts[fr + 1] - starts[fr]);
    const auto n = static_cast<std::int64_t>(s[fr].gids.size());
    const auto nb = static_cast<std::int64_t>(s[fr].bonds.size());
    std::smatch m;
    ASSERT_TRUE(
        std::regex_search(block, m, std::regex(R"re(Polyvertex" NumberOfElements="(\d+)")re")));
    EXPECT_EQ(std::stoll(m[1]), n) << "frame " << fr;
    ASSERT_TRUE(
        std::regex_search(block, m, std::regex(R"re(Polyline" NumberOfElements="(\d+)")re")));
    EXPECT_EQ(std::stoll(m[1]), nb) << "frame " << fr;
    // Every frame hyperslab: start (fr, 0 ...), count (1, rows ...) of a dataset of 6 frames x
    // the row dimension; rows = n for particles, nb for bonds.
    const std::regex slab(
        R"re(<DataItem ItemType="HyperSlab" Dimensions="([0-9 ]+)" Type="HyperSlab">\s*<DataItem Dimensions="3 ([23])" Format="XML">([0-9 ]+)</DataItem>\s*<DataItem Dimensions="([0-9 ]+)"[^>]*>[^:]+:(/[a-z]+)/([a-z_]+)</DataItem>)re");
    int particle_slabs = 0, bond_slabs = 0, topology_slabs = 0;
    for (auto it = std::sregex_iterator(block.begin(), block.end(), slab);
         it != std::sregex_iterator(); ++it) {
      const auto& sm = *it;
      const auto v = numbers(sm[3]);
      const auto full = numbers(sm[4]);
      const std::string grid = sm[5], name = sm[6];
      if (grid == "/bonds" && name == "connectivity") {
        EXPECT_EQ(v, (std::vector<std::int64_t>{kTopologyFirst[fr], 0, 1, 1, nb, 2}));
        EXPECT_EQ(full, (std::vector<std::int64_t>{kTopologyRows, 2}));
        ++topology_slabs;
        continue;
      }
      const std::size_t rank = std::stoul(sm[2]);
      const std::int64_t rows = grid == "/bonds" ? nb : n;
      EXPECT_EQ(v[0], static_cast<std::int64_t>(fr));
      EXPECT_EQ(v[2 * rank], 1);
      EXPECT_EQ(v[2 * rank + 1], rows) << grid << "/" << name << " frame " << fr;
      EXPECT_EQ(full[0], static_cast<std::int64_t>(s.size()));
      EXPECT_EQ(full[1], grid == "/bonds" ? 13 : 28);
      (grid == "/bonds" ? bond_slabs : particle_slabs)++;
    }
    EXPECT_EQ(topology_slabs, 1) << "frame " << fr;
    // Particles: geometry + 8 fields (rank included), and the bonds' geometry (the particle
    // positions); bonds: 10 fields.
    EXPECT_EQ(particle_slabs, 1 + 8 + 1) << "frame " << fr;
    EXPECT_EQ(bond_slabs, 10) << "frame " << fr;
  }
}

TEST(FrameFile, ChangingCountsAndSparseGids) {
  const testing::WorldCopy world_copy;
  const MPI_Comm world = world_copy.raw();
  {
    const Communicator comm(world);
    const std::string dir = testing::shared_temp_dir(comm, "changing");
    write_all(comm, dir + "/parallel.h5", dir + "/parallel.xdmf");
    if (comm.is_root()) write_all(Communicator::self(), dir + "/serial.h5", dir + "/serial.xdmf");
    comm.barrier();
    if (comm.is_root()) {
      expect_frames_as_written(dir + "/parallel.h5");
      expect_topology_in_rows(dir + "/parallel.h5");
      expect_sidecar_selects_each_frame(dir + "/parallel.xdmf");
      // The same bytes as one rank wrote (unwritten rows included), but for the owning ranks.
      const Hdf5File a = Hdf5File::open_read(dir + "/serial.h5");
      const Hdf5File b = Hdf5File::open_read(dir + "/parallel.h5");
      int compared = 0;
      for (const std::string g : {"/frames", "/particles", "/bonds"})
        for (const auto& name : a.list(g)) {
          if (g + "/" + name == "/particles/rank") continue;
          std::size_t ra = 0, rb = 0;
          EXPECT_EQ(a.dims(g + "/" + name), b.dims(g + "/" + name)) << g << "/" << name;
          EXPECT_TRUE(a.read_bytes(g + "/" + name, ra) == b.read_bytes(g + "/" + name, rb))
              << g << "/" << name << " differs from the one-rank file";
          ++compared;
        }
      EXPECT_GE(compared, 5 + 7 + 11);
      std::filesystem::remove_all(dir);
    }
  }
}

}  // namespace
}  // namespace ringdem

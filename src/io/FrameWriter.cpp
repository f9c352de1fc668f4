#include "io/FrameWriter.hpp"

#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <type_traits>

#include "comm/RowBlocks.hpp"
#include "core/Version.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {

namespace {

template <class T>
FrameDataset describe(const std::string& name, FrameGrid grid) {
  FrameDataset d;
  d.name = name;
  d.grid = grid;
  d.components = H5Layout<T>::components;
  using Base =
      std::conditional_t<std::is_enum_v<T>, std::underlying_type<T>, std::type_identity<T>>;
  using S = typename Base::type;
  if constexpr (std::is_same_v<S, Vec3> || std::is_same_v<S, Quat> || std::is_floating_point_v<S>) {
    d.number_type = "Float";
    d.precision = 8;
  } else if constexpr (std::is_same_v<S, std::uint8_t>) {
    d.number_type = "UChar";
    d.precision = 1;
  } else {
    d.number_type = std::is_signed_v<S> ? "Int" : "UInt";
    d.precision = static_cast<int>(sizeof(S));
  }
  return d;
}

std::string file_name(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

/// One frame of a [frame, row(, component)] dataset as an XDMF hyperslab.
std::string hyperslab(const std::string& h5_name, const FrameDataset& d, std::size_t frame,
                      std::size_t n_frames, std::int64_t rows, const std::string& indent) {
  const bool vector = d.components > 1;
  const std::string dims =
      vector ? fmt::format("{} {}", rows, d.components) : fmt::format("{}", rows);
  const std::string slab = vector ? fmt::format("{} 0 0 1 1 1 1 {} {}", frame, rows, d.components)
                                  : fmt::format("{} 0 1 1 1 {}", frame, rows);
  return fmt::format(
      "{0}<DataItem ItemType=\"HyperSlab\" Dimensions=\"{1}\" Type=\"HyperSlab\">\n"
      "{0}  <DataItem Dimensions=\"3 {2}\" Format=\"XML\">{3}</DataItem>\n"
      "{0}  <DataItem Dimensions=\"{4} {1}\" NumberType=\"{5}\" Precision=\"{6}\" "
      "Format=\"HDF\">{7}:{8}</DataItem>\n"
      "{0}</DataItem>\n",
      indent, dims, vector ? 3 : 2, slab, n_frames, d.number_type, d.precision, h5_name, d.path());
}

const char* attribute_type(int components) {
  return components == 3 ? "Vector" : components == 1 ? "Scalar" : "Matrix";
}

constexpr const char* kXdmfTrailer = "  </Grid>\n </Domain>\n</Xdmf>\n";

std::string xdmf_header() {
  return "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
         "<Xdmf Version=\"2.0\">\n <Domain>\n"
         "  <Grid Name=\"frames\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

const char* grid_name(FrameGrid g) {
  return g == FrameGrid::kParticles ? "particles" : g == FrameGrid::kBonds ? "bonds" : "bodies";
}

std::int64_t rows_of(FrameGrid g, const FrameSizes& n) {
  return g == FrameGrid::kParticles ? n.particles : g == FrameGrid::kBonds ? n.bonds : n.bodies;
}

std::string xdmf_frame(const std::string& h5_name, const FrameSizes& sizes, std::size_t frame,
                       std::size_t n_frames, double time,
                       const std::vector<FrameDataset>& datasets) {
  const FrameDataset* position[2] = {nullptr, nullptr};  // particles, bodies
  for (const auto& d : datasets)
    if (d.name == "position" && d.grid != FrameGrid::kBonds)
      position[d.grid == FrameGrid::kBodies ? 1 : 0] = &d;
  if (!position[0]) throw std::invalid_argument("xdmf_frame: no position dataset");
  std::string x = fmt::format(
      "   <Grid Name=\"frame_{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      "    <Time Value=\"{:.17g}\"/>\n",
      frame, time);
  for (const FrameGrid grid : {FrameGrid::kParticles, FrameGrid::kBonds, FrameGrid::kBodies}) {
    const std::int64_t rows = rows_of(grid, sizes);
    if (rows == 0 || (grid == FrameGrid::kBodies && !position[1])) continue;
    x += fmt::format("    <Grid Name=\"{}\" GridType=\"Uniform\">\n", grid_name(grid));
    if (grid == FrameGrid::kBonds) {
      x += fmt::format(
          "     <Topology TopologyType=\"Polyline\" NumberOfElements=\"{0}\" "
          "NodesPerElement=\"2\">\n"
          "      <DataItem Dimensions=\"{0} 2\" NumberType=\"Int\" Precision=\"8\" "
          "Format=\"HDF\">{1}:/bonds/connectivity</DataItem>\n     </Topology>\n",
          rows, h5_name);
    } else {
      x += fmt::format(
          "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
          "NodesPerElement=\"1\"/>\n",
          rows);
    }
    // Bonds join particles: their geometry is the particle positions.
    const FrameDataset& where = *position[grid == FrameGrid::kBodies ? 1 : 0];
    x += "     <Geometry GeometryType=\"XYZ\">\n";
    x += hyperslab(h5_name, where, frame, n_frames, rows_of(where.grid, sizes), "      ");
    x += "     </Geometry>\n";
    for (const auto& d : datasets) {
      if (d.grid != grid) continue;
      x += fmt::format("     <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n", d.name,
                       attribute_type(d.components), grid == FrameGrid::kBonds ? "Cell" : "Node");
      x += hyperslab(h5_name, d, frame, n_frames, rows, "      ");
      x += "     </Attribute>\n";
    }
    x += "    </Grid>\n";
  }
  x += "   </Grid>\n";
  return x;
}

}  // namespace

std::string FrameDataset::path() const {
  return std::string("/") + grid_name(grid) + "/" + name;
}

std::string frame_xdmf(const std::string& h5_name, const FrameSizes& sizes,
                       const std::vector<double>& times,
                       const std::vector<FrameDataset>& datasets) {
  std::string x = xdmf_header();
  for (std::size_t f = 0; f < times.size(); ++f)
    x += xdmf_frame(h5_name, sizes, f, times.size(), times[f], datasets);
  return x + kXdmfTrailer;
}

FrameWriter::FrameWriter(const Communicator& comm, std::string h5_path, std::string xdmf_path,
                         int compression)
    : comm_(comm),
      h5_path_(std::move(h5_path)),
      xdmf_path_(std::move(xdmf_path)),
      compression_(compression) {}

void FrameWriter::create_file(ParticleStore& p, BondStore& bonds,
                              const std::vector<RigidBody>& bodies) {
  Hdf5File f = Hdf5File::create(h5_path_, comm_);
  f.set_attribute("/", "format", std::string("ringdem-frames"));
  f.set_attribute("/", "ringdem_version", std::string(kVersion));
  f.set_attribute("/", "particles", sizes_.particles);
  f.set_attribute("/", "bonds", sizes_.bonds);
  f.set_attribute("/", "ranks", static_cast<std::int64_t>(comm_.size()));
  f.create_group("/particles");
  f.create_group("/bonds");
  f.create_group("/bodies");
  f.create_group("/frames");
  f.create_series("/frames/time", H5T_NATIVE_DOUBLE);
  f.create_series("/frames/step", H5T_NATIVE_INT64);
  datasets_.clear();
  p.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kOutput)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    datasets_.push_back(describe<T>(std::string(info.name), FrameGrid::kParticles));
    f.create_frames(datasets_.back().path(), H5Layout<T>::type(), H5Layout<T>::components,
                    sizes_.particles, compression_);
  });
  datasets_.push_back(describe<std::int32_t>("rank", FrameGrid::kParticles));
  f.create_frames("/particles/rank", H5T_NATIVE_INT32, 1, sizes_.particles, compression_);
  bonds.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kOutput)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    datasets_.push_back(describe<T>(std::string(info.name), FrameGrid::kBonds));
    f.create_frames(datasets_.back().path(), H5Layout<T>::type(), H5Layout<T>::components,
                    sizes_.bonds, compression_);
  });
  f.create_rows("/bonds/connectivity", H5T_NATIVE_INT64, 2, sizes_.bonds);
  std::string names;
  for (const auto& b : bodies)
    names += (names.empty() ? "" : "\n") + b.name;
  f.set_attribute("/bodies", "names", names);
  for (const char* name : {"position", "velocity", "force"}) {
    datasets_.push_back(describe<Vec3>(name, FrameGrid::kBodies));
    f.create_frames(datasets_.back().path(), H5T_NATIVE_DOUBLE, 3, sizes_.bodies, 0);
  }
  datasets_.push_back(describe<double>("radius", FrameGrid::kBodies));
  f.create_frames("/bodies/radius", H5T_NATIVE_DOUBLE, 1, sizes_.bodies, 0);
}

void FrameWriter::write(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies,
                        double time, std::int64_t step) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n_local = p.n_local();
  // Bonds go out once, from the rank that owns end a.
  std::vector<std::size_t> bond_local;
  std::vector<std::int64_t> bond_rows;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!bonds.counted_here(p, k)) continue;
    bond_local.push_back(k);
    bond_rows.push_back(bonds.id[k]);
  }
  FrameSizes sizes;
  sizes.particles = comm_.sum(static_cast<std::int64_t>(n_local));
  sizes.bonds = comm_.sum(static_cast<std::int64_t>(bond_local.size()));
  sizes.bodies = static_cast<std::int64_t>(bodies.size());
  const bool first = times_.empty();
  if (first) {
    sizes_ = sizes;
    create_file(p, bonds, bodies);
  } else if (sizes.particles != sizes_.particles || sizes.bonds != sizes_.bonds ||
             sizes.bodies != sizes_.bodies) {
    throw std::runtime_error(h5_path_ + ": particle, bond or body count changed between frames");
  }
  const std::int64_t frame = frames();
  const std::vector<std::int64_t> gids(p.gid.begin(),
                                       p.gid.begin() + static_cast<std::ptrdiff_t>(n_local));
  const RowBlocks particle_rows(comm_, gids);
  const RowBlocks bond_blocks(comm_, bond_rows);
  {
    Hdf5File f = Hdf5File::open_parallel(h5_path_, comm_);
    p.for_each_field([&](const FieldInfo& info, const auto& v) {
      if (!info.has(field_flag::kOutput)) return;
      f.write_rows("/particles/" + std::string(info.name), frame, particle_rows.first_row(),
                   particle_rows.to_blocks(v));
    });
    const std::vector<std::int32_t> rank(n_local, comm_.rank());
    f.write_rows("/particles/rank", frame, particle_rows.first_row(),
                 particle_rows.to_blocks(rank));
    bonds.for_each_field([&](const FieldInfo& info, const auto& v) {
      if (!info.has(field_flag::kOutput)) return;
      std::remove_cvref_t<decltype(v)> mine;
      mine.reserve(bond_local.size());
      for (std::size_t k : bond_local)
        mine.push_back(v[k]);
      f.write_rows("/bonds/" + std::string(info.name), frame, bond_blocks.first_row(),
                   bond_blocks.to_blocks(mine));
    });
    if (first) {
      // Two gids per row: moved as one 16-byte item.
      struct Pair {
        std::int64_t a, b;
      };
      std::vector<Pair> mine;
      mine.reserve(bond_local.size());
      for (std::size_t k : bond_local)
        mine.push_back({bonds.gid_a[k], bonds.gid_b[k]});
      const std::vector<Pair> block = bond_blocks.to_blocks(mine);
      f.write_rows("/bonds/connectivity", -1, bond_blocks.first_row(),
                   static_cast<std::int64_t>(block.size()), block.data(), H5T_NATIVE_INT64);
    }
    // Rigid bodies are replicated on every rank: rank 0 writes them.
    std::vector<Vec3> position, velocity, force;
    std::vector<double> radius;
    if (comm_.is_root())
      for (const auto& b : bodies) {
        position.push_back(b.position);
        velocity.push_back(b.velocity);
        force.push_back(b.force);
        radius.push_back(b.radius);
      }
    f.write_rows("/bodies/position", frame, 0, position);
    f.write_rows("/bodies/velocity", frame, 0, velocity);
    f.write_rows("/bodies/force", frame, 0, force);
    f.write_rows("/bodies/radius", frame, 0, radius);
    f.write_series("/frames/time", frame, &time, H5T_NATIVE_DOUBLE);
    f.write_series("/frames/step", frame, &step, H5T_NATIVE_INT64);
  }
  times_.push_back(time);
  steps_.push_back(step);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (comm_.is_root() && (times_.size() <= 256 || wall - last_xdmf_wall_ >= 10.0)) {
    write_xdmf();
    last_xdmf_wall_ = wall;
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

FrameWriter::~FrameWriter() {
  try {
    if (comm_.is_root() && xdmf_frames_ != times_.size()) write_xdmf();
  } catch (const std::exception&) {
    // A destructor must not throw; the sidecar then lists the frames of its last rewrite.
  }
}

void FrameWriter::write_xdmf() {
  // The hyperslab of every frame names the dataset's frame count, so a frame added changes every
  // block: rewrite the whole sidecar under a temporary name and rename it (a viewer never sees
  // half a file). The text grows with the frame count; for very long runs, use a longer
  // interval.
  const std::string tmp = xdmf_path_ + ".tmp";
  {
    std::ofstream out(tmp);
    out << frame_xdmf(file_name(h5_path_), sizes_, times_, datasets_);
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, xdmf_path_);
  xdmf_frames_ = times_.size();
}

}  // namespace ringdem

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

/// Rows [0, rows) of one frame of a [frame, row(, component)] dataset of `capacity` rows as an
/// XDMF hyperslab.
std::string hyperslab(const std::string& h5_name, const FrameDataset& d, std::size_t frame,
                      std::size_t n_frames, std::int64_t rows, std::int64_t capacity,
                      const std::string& indent) {
  const bool vector = d.components > 1;
  const std::string dims =
      vector ? fmt::format("{} {}", rows, d.components) : fmt::format("{}", rows);
  const std::string slab = vector ? fmt::format("{} 0 0 1 1 1 1 {} {}", frame, rows, d.components)
                                  : fmt::format("{} 0 1 1 1 {}", frame, rows);
  const std::string full = vector ? fmt::format("{} {} {}", n_frames, capacity, d.components)
                                  : fmt::format("{} {}", n_frames, capacity);
  return fmt::format(
      "{0}<DataItem ItemType=\"HyperSlab\" Dimensions=\"{1}\" Type=\"HyperSlab\">\n"
      "{0}  <DataItem Dimensions=\"3 {2}\" Format=\"XML\">{3}</DataItem>\n"
      "{0}  <DataItem Dimensions=\"{4}\" NumberType=\"{5}\" Precision=\"{6}\" "
      "Format=\"HDF\">{7}:{8}</DataItem>\n"
      "{0}</DataItem>\n",
      indent, dims, vector ? 3 : 2, slab, full, d.number_type, d.precision, h5_name, d.path());
}

/// The Polyline topology of a frame: its block of /bonds/connectivity, the whole dataset
/// (as ringdem always wrote it) when the topology never changed.
std::string bond_topology(const std::string& h5_name, const FrameRecord& r,
                          std::int64_t connectivity_rows) {
  std::string x = fmt::format(
      "     <Topology TopologyType=\"Polyline\" NumberOfElements=\"{}\" "
      "NodesPerElement=\"2\">\n",
      r.bonds);
  const std::string data = fmt::format(
      "DataItem Dimensions=\"{} 2\" NumberType=\"Int\" Precision=\"8\" "
      "Format=\"HDF\">{}:/bonds/connectivity</DataItem>\n",
      connectivity_rows, h5_name);
  if (r.connectivity == 0 && r.bonds == connectivity_rows) {
    x += "      <" + data;
  } else {
    x += fmt::format(
        "      <DataItem ItemType=\"HyperSlab\" Dimensions=\"{0} 2\" Type=\"HyperSlab\">\n"
        "       <DataItem Dimensions=\"3 2\" Format=\"XML\">{1} 0 1 1 {0} 2</DataItem>\n"
        "       <{2}"
        "      </DataItem>\n",
        r.bonds, r.connectivity, data);
  }
  return x + "     </Topology>\n";
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

std::string xdmf_frame(const std::string& h5_name, const FrameSizes& capacity,
                       std::int64_t connectivity_rows, const FrameRecord& record, std::size_t frame,
                       std::size_t n_frames, const std::vector<FrameDataset>& datasets) {
  const FrameDataset* position[2] = {nullptr, nullptr};  // particles, bodies
  for (const auto& d : datasets)
    if (d.name == "position" && d.grid != FrameGrid::kBonds)
      position[d.grid == FrameGrid::kBodies ? 1 : 0] = &d;
  if (!position[0]) throw std::invalid_argument("xdmf_frame: no position dataset");
  const FrameSizes rows{record.particles, record.bonds, capacity.bodies};
  std::string x = fmt::format(
      "   <Grid Name=\"frame_{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      "    <Time Value=\"{:.17g}\"/>\n",
      frame, record.time);
  for (const FrameGrid grid : {FrameGrid::kParticles, FrameGrid::kBonds, FrameGrid::kBodies}) {
    const std::int64_t n = rows_of(grid, rows);
    if (n == 0 || (grid == FrameGrid::kBodies && !position[1])) continue;
    x += fmt::format("    <Grid Name=\"{}\" GridType=\"Uniform\">\n", grid_name(grid));
    if (grid == FrameGrid::kBonds) {
      x += bond_topology(h5_name, record, connectivity_rows);
    } else {
      x += fmt::format(
          "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
          "NodesPerElement=\"1\"/>\n",
          n);
    }
    // Bonds join particles: their geometry is the particle positions of the frame.
    const FrameDataset& where = *position[grid == FrameGrid::kBodies ? 1 : 0];
    x += "     <Geometry GeometryType=\"XYZ\">\n";
    x += hyperslab(h5_name, where, frame, n_frames, rows_of(where.grid, rows),
                   rows_of(where.grid, capacity), "      ");
    x += "     </Geometry>\n";
    for (const auto& d : datasets) {
      if (d.grid != grid) continue;
      x += fmt::format("     <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n", d.name,
                       attribute_type(d.components), grid == FrameGrid::kBonds ? "Cell" : "Node");
      x += hyperslab(h5_name, d, frame, n_frames, n, rows_of(grid, capacity), "      ");
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

std::string frame_xdmf(const std::string& h5_name, const FrameSizes& capacity,
                       std::int64_t connectivity_rows, const std::vector<FrameRecord>& frames,
                       const std::vector<FrameDataset>& datasets) {
  std::string x = xdmf_header();
  for (std::size_t f = 0; f < frames.size(); ++f)
    x += xdmf_frame(h5_name, capacity, connectivity_rows, frames[f], f, frames.size(), datasets);
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
  f.set_attribute("/", "particles", capacity_.particles);
  f.set_attribute("/", "bonds", capacity_.bonds);
  f.set_attribute("/", "ranks", static_cast<std::int64_t>(comm_.size()));
  f.create_group("/particles");
  f.create_group("/bonds");
  f.create_group("/bodies");
  f.create_group("/frames");
  f.create_series("/frames/time", H5T_NATIVE_DOUBLE);
  f.create_series("/frames/step", H5T_NATIVE_INT64);
  for (const char* name : {"particles", "bonds", "connectivity"})
    f.create_series(std::string("/frames/") + name, H5T_NATIVE_INT64);
  datasets_.clear();
  p.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kOutput)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    datasets_.push_back(describe<T>(std::string(info.name), FrameGrid::kParticles));
    f.create_frames(datasets_.back().path(), H5Layout<T>::type(), H5Layout<T>::components,
                    capacity_.particles, compression_);
  });
  datasets_.push_back(describe<std::int32_t>("rank", FrameGrid::kParticles));
  f.create_frames("/particles/rank", H5T_NATIVE_INT32, 1, capacity_.particles, compression_);
  bonds.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kOutput)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    datasets_.push_back(describe<T>(std::string(info.name), FrameGrid::kBonds));
    f.create_frames(datasets_.back().path(), H5Layout<T>::type(), H5Layout<T>::components,
                    capacity_.bonds, compression_);
  });
  f.create_rows("/bonds/connectivity", H5T_NATIVE_INT64, 2, capacity_.bonds, true);
  std::string names;
  for (const auto& b : bodies)
    names += (names.empty() ? "" : "\n") + b.name;
  f.set_attribute("/bodies", "names", names);
  for (const char* name : {"position", "velocity", "force"}) {
    datasets_.push_back(describe<Vec3>(name, FrameGrid::kBodies));
    f.create_frames(datasets_.back().path(), H5T_NATIVE_DOUBLE, 3, capacity_.bodies, 0);
  }
  datasets_.push_back(describe<double>("radius", FrameGrid::kBodies));
  f.create_frames("/bodies/radius", H5T_NATIVE_DOUBLE, 1, capacity_.bodies, 0);
}

void FrameWriter::grow(Hdf5File& f, const FrameSizes& sizes) {
  for (const FrameGrid grid : {FrameGrid::kParticles, FrameGrid::kBonds}) {
    std::int64_t& capacity = grid == FrameGrid::kParticles ? capacity_.particles : capacity_.bonds;
    const std::int64_t rows = rows_of(grid, sizes);
    if (rows <= capacity) continue;
    capacity = rows;
    for (const auto& d : datasets_)
      if (d.grid == grid) f.extend_rows(d.path(), capacity);
    f.set_attribute("/", grid_name(grid), capacity);
  }
}

std::int64_t FrameWriter::write_topology(Hdf5File& f, const std::vector<RowPair>& block,
                                         std::int64_t first_row, std::int64_t n_bonds) {
  // With the same bond count every rank holds the same rows of the topology as at the last
  // frame (RowBlocks' blocks depend on the count alone), so comparing blocks is exact.
  if (!comm_.any(n_bonds != topology_bonds_ || block != topology_block_)) return topology_first_;
  topology_first_ = connectivity_rows_;
  connectivity_rows_ += n_bonds;
  f.extend_rows("/bonds/connectivity", connectivity_rows_);
  f.write_rows("/bonds/connectivity", -1, topology_first_ + first_row,
               static_cast<std::int64_t>(block.size()), block.data(), H5T_NATIVE_INT64);
  topology_block_ = block;
  topology_bonds_ = n_bonds;
  return topology_first_;
}

void FrameWriter::write(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies,
                        double time, std::int64_t step) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n_local = p.n_local();
  // Bonds go out once, from the rank that owns end a.
  std::vector<std::size_t> bond_local;
  std::vector<std::int64_t> bond_ids, ends;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!bonds.counted_here(p, k)) continue;
    bond_local.push_back(k);
    bond_ids.push_back(bonds.id[k]);
    ends.push_back(bonds.gid_a[k]);
    ends.push_back(bonds.gid_b[k]);
  }
  const std::vector<std::int64_t> gids(p.gid.begin(),
                                       p.gid.begin() + static_cast<std::ptrdiff_t>(n_local));
  const RowBlocks particle_rows(comm_, gids);
  const RowBlocks bond_blocks(comm_, bond_ids);
  const FrameSizes sizes{particle_rows.n_rows(), bond_blocks.n_rows(),
                         static_cast<std::int64_t>(bodies.size())};
  // The topology: the rows of both ends in this frame's particle rows (the far end may live on
  // another rank), in bond-id order.
  const std::vector<std::int64_t> end_rows = particle_rows.rows_of(ends);
  std::vector<RowPair> pairs(bond_local.size());
  bool dangling = false;
  for (std::size_t j = 0; j < pairs.size(); ++j) {
    pairs[j] = {end_rows[2 * j], end_rows[2 * j + 1]};
    dangling |= pairs[j].a < 0 || pairs[j].b < 0;
  }
  if (comm_.any(dangling))
    throw std::runtime_error(h5_path_ + ": a bond joins a particle that is not in the frame");
  const std::vector<RowPair> topology = bond_blocks.to_blocks(pairs);
  const bool first = records_.empty();
  if (first) {
    capacity_ = sizes;
    create_file(p, bonds, bodies);
  } else if (sizes.bodies != capacity_.bodies) {
    throw std::runtime_error(h5_path_ + ": the rigid body count changed between frames");
  }
  const std::int64_t frame = frames();
  FrameRecord record{time, sizes.particles, sizes.bonds, 0};
  {
    Hdf5File f = Hdf5File::open_parallel(h5_path_, comm_);
    grow(f, sizes);
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
    record.connectivity = write_topology(f, topology, bond_blocks.first_row(), sizes.bonds);
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
    f.write_series("/frames/particles", frame, &record.particles, H5T_NATIVE_INT64);
    f.write_series("/frames/bonds", frame, &record.bonds, H5T_NATIVE_INT64);
    f.write_series("/frames/connectivity", frame, &record.connectivity, H5T_NATIVE_INT64);
  }
  records_.push_back(record);
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
  if (comm_.is_root() && (records_.size() <= 256 || wall - last_xdmf_wall_ >= 10.0)) {
    write_xdmf();
    last_xdmf_wall_ = wall;
  }
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

FrameWriter::~FrameWriter() {
  try {
    if (comm_.is_root() && xdmf_frames_ != records_.size()) write_xdmf();
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
    out << frame_xdmf(file_name(h5_path_), capacity_, connectivity_rows_, records_, datasets_);
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, xdmf_path_);
  xdmf_frames_ = records_.size();
}

}  // namespace ringdem

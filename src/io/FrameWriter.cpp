#include "io/FrameWriter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <limits>
#include <type_traits>

#include "comm/RowBlocks.hpp"
#include "core/Version.hpp"
#include "domain/PairStore.hpp"
#include "io/BodyMesh.hpp"
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

/// Rows [first_row, first_row + rows) of a dataset as an XDMF hyperslab: of frame `frame` of a
/// [frame, row(, component)] dataset of `capacity` rows, or (frame < 0) of a fixed [row,
/// component] dataset of `capacity` rows.
std::string hyperslab(const std::string& h5_name, const FrameDataset& d, std::int64_t frame,
                      std::size_t n_frames, std::int64_t first_row, std::int64_t rows,
                      std::int64_t capacity, const std::string& indent) {
  std::vector<std::int64_t> start, count, full;
  if (frame >= 0) {
    start.push_back(frame);
    count.push_back(1);
    full.push_back(static_cast<std::int64_t>(n_frames));
  }
  start.push_back(first_row);
  count.push_back(rows);
  full.push_back(capacity);
  if (d.components > 1 || frame < 0) {
    start.push_back(0);
    count.push_back(d.components);
    full.push_back(d.components);
  }
  // The selection's shape is its count without the frame axis.
  const std::vector<std::int64_t> dims(count.begin() + (frame >= 0 ? 1 : 0), count.end());
  const std::vector<std::int64_t> stride(start.size(), 1);
  return fmt::format(
      "{0}<DataItem ItemType=\"HyperSlab\" Dimensions=\"{1}\" Type=\"HyperSlab\">\n"
      "{0}  <DataItem Dimensions=\"3 {2}\" Format=\"XML\">{3} {4} {5}</DataItem>\n"
      "{0}  <DataItem Dimensions=\"{6}\" NumberType=\"{7}\" Precision=\"{8}\" "
      "Format=\"HDF\">{9}:{10}</DataItem>\n"
      "{0}</DataItem>\n",
      indent, fmt::join(dims, " "), start.size(), fmt::join(start, " "), fmt::join(stride, " "),
      fmt::join(count, " "), fmt::join(full, " "), d.number_type, d.precision, h5_name, d.path());
}

/// A fixed (not per-frame) integer dataset of the topologies.
FrameDataset topology_dataset(const std::string& name, FrameGrid grid, int components) {
  FrameDataset d;
  d.name = name;
  d.grid = grid;
  d.components = components;
  d.number_type = "Int";
  d.precision = 8;
  return d;
}

/// A topology whose connectivity is rows [first, first + n) of a fixed dataset of `capacity`
/// rows. Always a hyperslab, even of a whole dataset: ParaView 5.11's XDMF reader takes a
/// topology whose data item holds a file name as a request to cache the grid by its topology
/// and geometry file names, and reports an error (vtkXdmfHeavyData: "Cannot find DataItem
/// element in geometry xml") when the geometry is a hyperslab, as every frame's is.
std::string topology(const std::string& h5_name, const char* type, int nodes,
                     const FrameDataset& connectivity, std::int64_t first, std::int64_t n,
                     std::int64_t capacity) {
  return fmt::format(
             "     <Topology TopologyType=\"{}\" NumberOfElements=\"{}\" "
             "NodesPerElement=\"{}\">\n",
             type, n, nodes) +
         hyperslab(h5_name, connectivity, -1, 0, first, n, capacity, "      ") +
         "     </Topology>\n";
}

const char* attribute_type(int components) {
  return components == 3 ? "Vector" : components == 1 ? "Scalar" : "Matrix";
}

std::string xml_escaped(const std::string& text) {
  std::string x;
  for (const char c : text) {
    switch (c) {
      case '&':
        x += "&amp;";
        break;
      case '<':
        x += "&lt;";
        break;
      case '>':
        x += "&gt;";
        break;
      case '"':
        x += "&quot;";
        break;
      default:
        x += c;
    }
  }
  return x;
}

constexpr const char* kXdmfTrailer = "  </Grid>\n </Domain>\n</Xdmf>\n";

std::string xdmf_header() {
  return "<?xml version=\"1.0\" ?>\n<!DOCTYPE Xdmf SYSTEM \"Xdmf.dtd\" []>\n"
         "<Xdmf Version=\"2.0\">\n <Domain>\n"
         "  <Grid Name=\"frames\" GridType=\"Collection\" CollectionType=\"Temporal\">\n";
}

const char* grid_name(FrameGrid g) {
  switch (g) {
    case FrameGrid::kParticles:
      return "particles";
    case FrameGrid::kBonds:
      return "bonds";
    case FrameGrid::kBodies:
      return "bodies";
    case FrameGrid::kRopes:
      return "ropes";
  }
  return "?";
}

std::int64_t rows_of(FrameGrid g, const FrameSizes& n) {
  return g == FrameGrid::kParticles ? n.particles : g == FrameGrid::kBonds ? n.bonds : n.bodies;
}

/// The ropes' grid of frame `frame`: their segments as a Polyline over the frame's rope points,
/// each segment with its rope's tension.
std::string xdmf_ropes(const std::string& h5_name, const FrameRopes& ropes, std::int64_t frame,
                       std::size_t n_frames) {
  FrameDataset points = topology_dataset("points", FrameGrid::kRopes, 3);
  points.number_type = "Float";
  const FrameDataset tension = describe<double>("tension", FrameGrid::kRopes);
  return "    <Grid Name=\"ropes\" GridType=\"Uniform\">\n" +
         topology(h5_name, "Polyline", 2, topology_dataset("connectivity", FrameGrid::kRopes, 2), 0,
                  ropes.segments, ropes.segments) +
         "     <Geometry GeometryType=\"XYZ\">\n" +
         hyperslab(h5_name, points, frame, n_frames, 0, ropes.points, ropes.points, "      ") +
         "     </Geometry>\n" +
         "     <Attribute Name=\"tension\" AttributeType=\"Scalar\" Center=\"Cell\">\n" +
         hyperslab(h5_name, tension, frame, n_frames, 0, ropes.segments, ropes.segments, "      ") +
         "     </Attribute>\n    </Grid>\n";
}

std::string xdmf_frame(const std::string& h5_name, const FrameSizes& capacity,
                       std::int64_t connectivity_rows, const FrameRecord& record, std::size_t frame,
                       std::size_t n_frames, const std::vector<FrameDataset>& datasets,
                       const FrameBodies& bodies, const FrameRopes& ropes) {
  const FrameDataset* position = nullptr;
  for (const auto& d : datasets)
    if (d.name == "position" && d.grid == FrameGrid::kParticles) position = &d;
  if (!position) throw std::invalid_argument("xdmf_frame: no position dataset");
  const auto f = static_cast<std::int64_t>(frame);
  const std::string geometry = "     <Geometry GeometryType=\"XYZ\">\n" +
                               hyperslab(h5_name, *position, f, n_frames, 0, record.particles,
                                         capacity.particles, "      ") +
                               "     </Geometry>\n";
  std::string x = fmt::format(
      "   <Grid Name=\"frame_{}\" GridType=\"Collection\" CollectionType=\"Spatial\">\n"
      "    <Time Value=\"{:.17g}\"/>\n",
      frame, record.time);
  const FrameSizes rows{record.particles, record.bonds, capacity.bodies};
  for (const FrameGrid grid : {FrameGrid::kParticles, FrameGrid::kBonds}) {
    const std::int64_t n = rows_of(grid, rows);
    if (n == 0) continue;
    x += fmt::format("    <Grid Name=\"{}\" GridType=\"Uniform\">\n", grid_name(grid));
    if (grid == FrameGrid::kBonds) {
      x += topology(h5_name, "Polyline", 2, topology_dataset("connectivity", grid, 2),
                    record.connectivity, n, connectivity_rows);
    } else {
      x += fmt::format(
          "     <Topology TopologyType=\"Polyvertex\" NumberOfElements=\"{}\" "
          "NodesPerElement=\"1\"/>\n",
          n);
    }
    // Bonds join particles: their geometry is the particle positions of the frame.
    x += geometry;
    for (const auto& d : datasets) {
      if (d.grid != grid) continue;
      x += fmt::format("     <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"{}\">\n", d.name,
                       attribute_type(d.components), grid == FrameGrid::kBonds ? "Cell" : "Node");
      x += hyperslab(h5_name, d, f, n_frames, 0, n, rows_of(grid, capacity), "      ");
      x += "     </Attribute>\n";
    }
    x += "    </Grid>\n";
  }
  // Each rigid body in play: its surface, its fields as attributes of the whole grid (field
  // data in ParaView).
  const FrameDataset triangles = topology_dataset("surface/triangles", FrameGrid::kBodies, 3);
  FrameDataset points = triangles;
  points.name = "surface/points";
  points.number_type = "Float";
  for (std::size_t b = 0; b < bodies.names.size(); ++b) {
    if (b < record.active.size() && !record.active[b]) continue;
    const std::int64_t v0 = bodies.vertex_first[b], t0 = bodies.triangle_first[b];
    x += fmt::format("    <Grid Name=\"body_{}\" GridType=\"Uniform\">\n",
                     xml_escaped(bodies.names[b]));
    x += topology(h5_name, "Triangle", 3, triangles, t0, bodies.triangle_first[b + 1] - t0,
                  bodies.triangles());
    x += "     <Geometry GeometryType=\"XYZ\">\n";
    x += hyperslab(h5_name, points, f, n_frames, v0, bodies.vertex_first[b + 1] - v0,
                   bodies.vertices(), "      ");
    x += "     </Geometry>\n";
    for (const auto& d : datasets) {
      if (d.grid != FrameGrid::kBodies) continue;
      x += fmt::format("     <Attribute Name=\"{}\" AttributeType=\"{}\" Center=\"Grid\">\n",
                       d.name, attribute_type(d.components));
      x += hyperslab(h5_name, d, f, n_frames, static_cast<std::int64_t>(b), 1, capacity.bodies,
                     "      ");
      x += "     </Attribute>\n";
    }
    x += "    </Grid>\n";
  }
  if (ropes.points > 0) x += xdmf_ropes(h5_name, ropes, f, n_frames);
  x += "   </Grid>\n";
  return x;
}

}  // namespace

std::string FrameDataset::path() const {
  return std::string("/") + grid_name(grid) + "/" + name;
}

std::string frame_xdmf(const std::string& h5_name, const FrameSizes& capacity,
                       std::int64_t connectivity_rows, const std::vector<FrameRecord>& frames,
                       const std::vector<FrameDataset>& datasets, const FrameBodies& bodies,
                       const FrameRopes& ropes) {
  std::string x = xdmf_header();
  for (std::size_t f = 0; f < frames.size(); ++f)
    x += xdmf_frame(h5_name, capacity, connectivity_rows, frames[f], f, frames.size(), datasets,
                    bodies, ropes);
  return x + kXdmfTrailer;
}

FrameWriter::FrameWriter(const Communicator& comm, std::string h5_path, std::string xdmf_path,
                         int compression)
    : comm_(comm),
      h5_path_(std::move(h5_path)),
      xdmf_path_(std::move(xdmf_path)),
      compression_(compression) {}

void FrameWriter::create_file(ParticleStore& p, BondStore& bonds,
                              const std::vector<RigidBody>& bodies, const RopeStore& ropes) {
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
  f.create_frames("/bodies/active", H5T_NATIVE_UINT8, 1, capacity_.bodies, 0);
  create_body_surfaces(f, p, bodies);
  create_ropes(f, ropes);
}

void FrameWriter::create_ropes(Hdf5File& f, const RopeStore& ropes) {
  ropes_ = FrameRopes{};
  if (ropes.empty()) return;
  // Rope r's path has n_r + 2 points and n_r + 1 segments, each joining a point to the next.
  std::vector<std::array<std::int64_t, 2>> segments;
  std::int64_t first = 0;
  for (std::size_t r = 0; r < ropes.size(); ++r) {
    const auto n = static_cast<std::int64_t>(ropes.bodies_of(r).size()) + 2;
    for (std::int64_t i = 0; i + 1 < n; ++i)
      segments.push_back({first + i, first + i + 1});
    first += n;
  }
  ropes_ = {first, static_cast<std::int64_t>(segments.size())};
  f.create_group("/ropes");
  f.create_frames("/ropes/points", H5T_NATIVE_DOUBLE, 3, ropes_.points, 0);
  f.create_frames("/ropes/tension", H5T_NATIVE_DOUBLE, 1, ropes_.segments, 0);
  f.create_rows("/ropes/connectivity", H5T_NATIVE_INT64, 2, ropes_.segments);
  // Ropes are the same on every rank: rank 0 writes them.
  if (!comm_.is_root()) segments.clear();
  f.write_rows("/ropes/connectivity", -1, 0, static_cast<std::int64_t>(segments.size()),
               segments.data(), H5T_NATIVE_INT64);
}

void FrameWriter::create_body_surfaces(Hdf5File& f, const ParticleStore& p,
                                       const std::vector<RigidBody>& bodies) {
  // A plane has no extent: its patch lies under the particles of the first frame, centred at
  // the projection of their bounding box's centre and as wide as its diagonal.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::array<double, 6> box{-kInf, -kInf, -kInf, -kInf, -kInf, -kInf};  // hi, -lo
  for (std::size_t i = 0; i < p.n_local(); ++i)
    for (int c = 0; c < 3; ++c) {
      box[c] = std::max(box[c], p.position[i][c]);
      box[3 + c] = std::max(box[3 + c], -p.position[i][c]);
    }
  box = comm_.max(box);
  const Vec3 hi{box[0], box[1], box[2]}, lo{-box[3], -box[4], -box[5]};
  const bool particles = box[0] >= lo.x;
  constexpr double kSmallestPatch = 0.5;  // m, half width
  const double half_width = particles ? std::max(0.5 * norm(hi - lo), kSmallestPatch) : 1.0;
  body_meshes_ = FrameBodies{};
  local_vertices_.clear();
  std::vector<std::array<std::int64_t, 3>> triangles;
  for (const auto& b : bodies) {
    const BodyMesh m = BodyMesh::of(b, half_width, particles ? 0.5 * (lo + hi) : b.position);
    local_vertices_.insert(local_vertices_.end(), m.vertices.begin(), m.vertices.end());
    triangles.insert(triangles.end(), m.triangles.begin(), m.triangles.end());
    body_meshes_.names.push_back(b.name);
    body_meshes_.vertex_first.push_back(static_cast<std::int64_t>(local_vertices_.size()));
    body_meshes_.triangle_first.push_back(static_cast<std::int64_t>(triangles.size()));
  }
  f.create_group("/bodies/surface");
  f.create_frames("/bodies/surface/points", H5T_NATIVE_DOUBLE, 3, body_meshes_.vertices(), 0);
  f.create_rows("/bodies/surface/triangles", H5T_NATIVE_INT64, 3, body_meshes_.triangles());
  const auto n_bodies = static_cast<std::int64_t>(bodies.size());
  f.create_rows("/bodies/surface/vertex_first", H5T_NATIVE_INT64, 1, n_bodies + 1);
  f.create_rows("/bodies/surface/triangle_first", H5T_NATIVE_INT64, 1, n_bodies + 1);
  // Bodies are the same on every rank: rank 0 writes them.
  if (!comm_.is_root()) triangles.clear();
  const auto root_rows = [&](const std::vector<std::int64_t>& v) {
    return comm_.is_root() ? v : std::vector<std::int64_t>{};
  };
  f.write_rows("/bodies/surface/triangles", -1, 0, static_cast<std::int64_t>(triangles.size()),
               triangles.data(), H5T_NATIVE_INT64);
  f.write_rows("/bodies/surface/vertex_first", -1, 0, root_rows(body_meshes_.vertex_first));
  f.write_rows("/bodies/surface/triangle_first", -1, 0, root_rows(body_meshes_.triangle_first));
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
                        double time, std::int64_t step, const RopeStore& ropes) {
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n_local = p.n_local();
  // Bonds go out once, from the rank that owns end a.
  std::vector<std::size_t> bond_local;
  std::vector<std::int64_t> bond_ids, ends;
  for (std::size_t k = 0; k < bonds.size(); ++k) {
    if (!counted_here(p, bonds, k)) continue;
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
    create_file(p, bonds, bodies, ropes);
  } else if (sizes.bodies != capacity_.bodies) {
    throw std::runtime_error(h5_path_ + ": the rigid body count changed between frames");
  } else if (static_cast<std::int64_t>(ropes.path_points()) != ropes_.points) {
    throw std::runtime_error(h5_path_ + ": the support ropes changed between frames");
  }
  const std::int64_t frame = frames();
  FrameRecord record{time, sizes.particles, sizes.bonds, 0, {}};
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
    // Rigid bodies are replicated on every rank: rank 0 writes them. A body out of play is
    // written where it is (parked), flagged inactive, and left out of the sidecar's frame.
    std::vector<Vec3> position, velocity, force, points;
    std::vector<double> radius;
    std::vector<std::uint8_t> active;
    for (std::size_t b = 0; b < bodies.size(); ++b) {
      record.active.push_back(bodies[b].active ? 1 : 0);
      if (!comm_.is_root()) continue;
      position.push_back(bodies[b].position);
      velocity.push_back(bodies[b].velocity);
      force.push_back(bodies[b].force);
      radius.push_back(bodies[b].radius);
      active.push_back(record.active.back());
      for (auto v = body_meshes_.vertex_first[b]; v < body_meshes_.vertex_first[b + 1]; ++v)
        points.push_back(body_to_world(bodies[b], local_vertices_[static_cast<std::size_t>(v)]));
    }
    f.write_rows("/bodies/position", frame, 0, position);
    f.write_rows("/bodies/velocity", frame, 0, velocity);
    f.write_rows("/bodies/force", frame, 0, force);
    f.write_rows("/bodies/radius", frame, 0, radius);
    f.write_rows("/bodies/active", frame, 0, active);
    f.write_rows("/bodies/surface/points", frame, 0, points);
    if (ropes_.points > 0) {
      std::vector<Vec3> rope_points;
      std::vector<double> segment_tension;  // the ropes' segments in order, as the connectivity
      for (std::size_t r = 0; comm_.is_root() && r < ropes.size(); ++r) {
        const std::vector<Vec3> path = ropes.path_of(r, bodies);
        rope_points.insert(rope_points.end(), path.begin(), path.end());
      }
      if (comm_.is_root()) segment_tension = ropes.segment_tension;
      f.write_rows("/ropes/points", frame, 0, rope_points);
      f.write_rows("/ropes/tension", frame, 0, segment_tension);
    }
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
    out << frame_xdmf(file_name(h5_path_), capacity_, connectivity_rows_, records_, datasets_,
                      body_meshes_, ropes_);
    if (!out) throw std::runtime_error("cannot write " + tmp);
  }
  std::filesystem::rename(tmp, xdmf_path_);
  xdmf_frames_ = records_.size();
}

}  // namespace ringdem

#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/BondStore.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"
#include "domain/RopeStore.hpp"

namespace ringdem {

class Hdf5File;

/// What a frame dataset belongs to: particles (Polyvertex), bonds (Polyline between particles),
/// rigid bodies (one row per body; each body in play is a Triangle grid of its surface, these
/// rows its field data), support ropes (one Polyline grid of their paths).
enum class FrameGrid { kParticles, kBonds, kBodies, kRopes };

/// One per-frame dataset of a frame file, as the XDMF sidecar describes it.
struct FrameDataset {
  std::string name;  ///< field name; the dataset is /<grid>/<name>
  FrameGrid grid = FrameGrid::kParticles;
  int components = 1;
  std::string number_type;  ///< XDMF NumberType: Float, Int, UInt, UChar
  int precision = 8;        ///< bytes
  std::string path() const;
};

/// Row counts of the three grids.
struct FrameSizes {
  std::int64_t particles = 0, bonds = 0, bodies = 0;
};

/// What the sidecar needs of one frame: its time, its particle and bond rows, and where its
/// bond topology starts in /bonds/connectivity.
struct FrameRecord {
  double time = 0.0;
  std::int64_t particles = 0, bonds = 0;
  std::int64_t connectivity = 0;     ///< first row of the frame's topology
  std::vector<std::uint8_t> active;  ///< per rigid body: in play (RigidBody::active)
};

/// The support ropes as the frame file holds them: /ropes/points [frame, point, 3] the points of
/// every rope's path (anchor, the centres of the bodies on it, anchor; rope after rope),
/// /ropes/connectivity the `segments` pairs of points that each segment joins, /ropes/tension
/// [frame, segment] each segment's tension. Empty without ropes.
struct FrameRopes {
  std::int64_t points = 0, segments = 0;
};

/// The rigid bodies' surface meshes as the frame file holds them: body b's vertices are rows
/// [vertex_first[b], vertex_first[b + 1]) of /bodies/surface/points, its triangles rows
/// [triangle_first[b], triangle_first[b + 1]) of /bodies/surface/triangles, whose vertex
/// numbers count from the body's first vertex.
struct FrameBodies {
  std::vector<std::string> names;
  std::vector<std::int64_t> vertex_first{0}, triangle_first{0};
  std::int64_t vertices() const { return vertex_first.back(); }
  std::int64_t triangles() const { return triangle_first.back(); }
};

/// Frame output (DESIGN §5, docs/output.md): one HDF5 file per run segment, written
/// collectively, rows in gid (particles) and bond-id (bonds) order so that the file does not
/// depend on the rank count. Gids and bond ids may be sparse, and the particle and bond counts
/// may change from frame to frame (inflow, outflow, bonds removed).
///
/// Every field flagged kOutput in the particle and bond registries is a chunked dataset
/// [frame, row(, component)] extendible in both, plus the owning rank of each particle. Frame f
/// holds its n_f rows at [0, n_f) (/frames/particles, /frames/bonds); the row dimension is the
/// largest count so far (root attributes `particles`, `bonds`); rows beyond n_f are not
/// written (each frame is its own chunk, so they read as zeros). /bonds/connectivity holds the bond
/// topology as pairs of particle ROWS of the frame: a new block of rows is appended only when the
/// topology changes, and /frames/connectivity gives the first row of each frame's block. A run
/// whose counts never change thus has one topology block and the layout it always had. /bodies/
/// holds the rigid bodies (position, velocity, contact force, radius, whether in play, names in
/// an attribute) and their triangulated surfaces (BodyMesh) in /bodies/surface; /frames/time and
/// /frames/step the frame times. After each frame rank 0 rewrites an XDMF 2 sidecar (Polyvertex
/// particles, Polyline bonds, one Triangle grid per body in play; hyperslabs select each frame's
/// rows) under a temporary name and renames it, and the HDF5 file is closed between frames, so
/// ParaView can open a run that is still going. Beyond 256 frames the sidecar, whose size
/// grows with the frame count, is rewritten at most every 10 s of wall time, and once more at
/// the end.
class FrameWriter {
 public:
  FrameWriter(const Communicator& comm, std::string h5_path, std::string xdmf_path,
              int compression = 0);
  /// Writes the sidecar a last time if the newest frames are not in it yet.
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  /// Collective. Bond diagnostics (axial force, moment, utilisation) must be current. `ropes`
  /// run through `bodies`; their count must not change between frames.
  void write(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies, double time,
             std::int64_t step, const RopeStore& ropes = RopeStore{});

  std::int64_t frames() const { return static_cast<std::int64_t>(records_.size()); }
  const std::string& h5_path() const { return h5_path_; }
  const std::string& xdmf_path() const { return xdmf_path_; }

  /// Seconds spent writing (this rank), for the output-cost figure.
  double seconds() const { return seconds_; }

 private:
  /// Two particle rows per bond: the topology of a frame.
  struct RowPair {
    std::int64_t a, b;
    bool operator==(const RowPair&) const = default;
  };

  void create_file(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies,
                   const RopeStore& ropes);
  /// The ropes' datasets (/ropes) and their fixed segments: collective, at file creation.
  void create_ropes(Hdf5File& f, const RopeStore& ropes);
  /// The bodies' surface meshes (/bodies/surface): collective, at file creation.
  void create_body_surfaces(Hdf5File& f, const ParticleStore& p,
                            const std::vector<RigidBody>& bodies);
  void grow(Hdf5File& f, const FrameSizes& sizes);
  std::int64_t write_topology(Hdf5File& f, const std::vector<RowPair>& block,
                              std::int64_t first_row, std::int64_t n_bonds);
  void write_xdmf();

  const Communicator& comm_;
  std::string h5_path_, xdmf_path_;
  int compression_ = 0;
  FrameSizes capacity_;  ///< row dimensions of the datasets: the largest counts so far
  std::vector<FrameDataset> datasets_;
  std::vector<FrameRecord> records_;
  FrameBodies body_meshes_;              ///< the layout of /bodies/surface
  FrameRopes ropes_;                     ///< the layout of /ropes
  std::vector<Vec3> local_vertices_;     ///< every body's mesh vertices, in its body frame
  std::int64_t connectivity_rows_ = 0;   ///< rows of /bonds/connectivity
  std::int64_t topology_first_ = 0;      ///< first row of the newest topology block
  std::int64_t topology_bonds_ = -1;     ///< its bond count (-1: none yet)
  std::vector<RowPair> topology_block_;  ///< this rank's block of it
  double seconds_ = 0.0;
  std::size_t xdmf_frames_ = 0;  ///< frames the sidecar on disk lists
  double last_xdmf_wall_ = 0.0;
};

/// XDMF 2 text of a frame file: a Temporal collection whose members are Spatial collections of
/// the particle, bond, rigid-body and rope grids of one frame, each attribute a hyperslab (one
/// frame, its rows) of its dataset. `capacity`: the datasets' row dimensions;
/// `connectivity_rows`: the rows of /bonds/connectivity.
std::string frame_xdmf(const std::string& h5_name, const FrameSizes& capacity,
                       std::int64_t connectivity_rows, const std::vector<FrameRecord>& frames,
                       const std::vector<FrameDataset>& datasets, const FrameBodies& bodies,
                       const FrameRopes& ropes);

}  // namespace ringdem

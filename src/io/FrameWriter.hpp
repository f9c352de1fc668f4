#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "comm/Communicator.hpp"
#include "domain/BondStore.hpp"
#include "domain/ParticleStore.hpp"
#include "domain/RigidBody.hpp"

namespace ringdem {

/// The three grids of a frame: particles (Polyvertex), bonds (Polyline between particles),
/// rigid bodies (Polyvertex at their reference points).
enum class FrameGrid { kParticles, kBonds, kBodies };

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

/// Frame output (DESIGN §5): one HDF5 file per run segment, written collectively, rows in gid
/// (particles) and bond-id (bonds) order so that the file does not depend on the rank count.
/// Every field flagged kOutput in the particle and bond registries is a chunked extendible
/// dataset [frame, row(, component)], plus the owning rank of each particle; /bonds/connectivity
/// holds the gid pairs; /bodies/ the rigid bodies (position, velocity, contact force, radius,
/// names in an attribute); /frames/time and /frames/step the frame times. After each frame
/// rank 0 rewrites an XDMF 2 sidecar (Polyvertex particles and bodies, Polyline bonds) under a
/// temporary name and
/// renames it, and the HDF5 file is closed between frames, so ParaView can open a run that is
/// still going. Beyond 256 frames the sidecar, whose size grows with the frame count, is
/// rewritten at most every 10 s of wall time, and once more at the end.
class FrameWriter {
 public:
  FrameWriter(const Communicator& comm, std::string h5_path, std::string xdmf_path,
              int compression = 0);
  /// Writes the sidecar a last time if the newest frames are not in it yet.
  ~FrameWriter();
  FrameWriter(const FrameWriter&) = delete;
  FrameWriter& operator=(const FrameWriter&) = delete;

  /// Collective. Bond diagnostics (axial force, moment, utilisation) must be current.
  void write(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies, double time,
             std::int64_t step);

  std::int64_t frames() const { return static_cast<std::int64_t>(times_.size()); }
  const std::string& h5_path() const { return h5_path_; }
  const std::string& xdmf_path() const { return xdmf_path_; }

  /// Seconds spent writing (this rank), for the output-cost figure.
  double seconds() const { return seconds_; }

 private:
  void create_file(ParticleStore& p, BondStore& bonds, const std::vector<RigidBody>& bodies);
  void write_xdmf();

  const Communicator& comm_;
  std::string h5_path_, xdmf_path_;
  int compression_ = 0;
  FrameSizes sizes_;
  std::vector<FrameDataset> datasets_;
  std::vector<double> times_;
  std::vector<std::int64_t> steps_;
  double seconds_ = 0.0;
  std::size_t xdmf_frames_ = 0;  ///< frames the sidecar on disk lists
  double last_xdmf_wall_ = 0.0;
};

/// XDMF 2 text of a frame file: a Temporal collection whose members are Spatial collections of
/// the particle, bond and rigid-body grids of one frame, each attribute a hyperslab (one frame)
/// of its dataset.
std::string frame_xdmf(const std::string& h5_name, const FrameSizes& sizes,
                       const std::vector<double>& times, const std::vector<FrameDataset>& datasets);

}  // namespace ringdem

#include "io/SizeEstimate.hpp"

#include <fmt/format.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "io/GrainsInput.hpp"

namespace ringdem {

namespace {

/// Sites k in [0, length) of a row or column starting at a with a + k odd (the net's ring
/// sites are those with column + row odd, domain/RingNet.hpp).
std::int64_t odd_sites(std::int64_t a, std::int64_t length) {
  return a % 2 == 0 ? length / 2 : (length + 1) / 2;
}

}  // namespace

double SizeEstimate::bytes_per_rank(int ranks) const {
  const double share = 1.0 / ranks;
  const double ghosts = ranks > 1 ? kGhostFactor : 1.0;
  return kBaseBytes + (writes_frames ? kFrameFileBytes : 0.0) +
         ghosts * share *
             (static_cast<double>(particles) * kBytesPerParticle +
              static_cast<double>(bonds) * kBytesPerBond);
}

SizeEstimate estimate_size(const CaseConfig& c) {
  SizeEstimate e;
  for (const RingConfig& r : c.rings) {
    e.particles += r.n_particles;
    e.bonds += r.n_particles;
  }
  for (const RingNetConfig& n : c.nets) {
    const std::int64_t rows = n.rows, columns = n.columns;
    const std::int64_t rings = rows * columns / 2;
    e.particles += rings * n.n_particles;
    e.bonds += rings * n.n_particles;
    if (n.shackles.enabled && !n.shackles.rigid_tori()) {  // tori are rigid bodies
      const std::int64_t shackles = odd_sites(0, rows) + odd_sites(columns - 1, rows) +
                                    odd_sites(0, columns) + odd_sites(rows - 1, columns);
      e.particles += shackles * n.shackles.n_particles;
    }
  }
  for (const LatticeConfig& l : c.lattices)
    e.particles += std::int64_t{l.count[0]} * l.count[1] * l.count[2];
  for (const GrainsConfig& g : c.grains)
    e.particles += static_cast<std::int64_t>(std::llround(expected_grain_count(g)));
  e.particles += static_cast<std::int64_t>(c.spheres.size());
  for (const SphereFileConfig& f : c.sphere_files)
    e.particles += f.count;
  e.writes_frames = c.output.frame_interval > 0.0 || c.output.frame_interval_steps > 0;
  return e;
}

namespace {

/// The value of `key` (a "Key:  N kB" line) in a /proc file, in bytes; 0 when absent.
double proc_kib_entry(const char* file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string name;
    double kib = 0.0;
    if (s >> name >> kib && name == key) return kib * 1024.0;
  }
  return 0.0;
}

}  // namespace

double available_memory_bytes() {
  return proc_kib_entry("/proc/meminfo", "MemAvailable:");
}

double peak_resident_bytes() {
  return proc_kib_entry("/proc/self/status", "VmHWM:");
}

double shared_resident_bytes() {
  return proc_kib_entry("/proc/self/status", "RssShmem:");
}

std::string describe(const SizeEstimate& e, int ranks) {
  return fmt::format("{} particles, {} bonds: about {:.0f} MiB per rank on {} rank{}", e.particles,
                     e.bonds, e.bytes_per_rank(ranks) / (1024.0 * 1024.0), ranks,
                     ranks == 1 ? "" : "s");
}

}  // namespace ringdem

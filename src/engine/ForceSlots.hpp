#pragma once

#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"

namespace ringdem {

/// Which interactions a force evaluation computes. A single-rate step computes all of them;
/// multi-rate stepping (simulation.substeps, docs/physics.md "Two time scales") computes the
/// fast ones (bonds, and every interaction with a net particle at one end) at every sub-step
/// and the slow ones (grain–grain and grain–body contacts) once per grain step.
enum class ForceRate { kAll, kFast, kSlow };

/// A contiguous range of force slots (or of a term's own items).
struct SlotRange {
  std::uint32_t begin = 0;
  std::uint32_t count = 0;
  std::uint32_t end() const { return begin + count; }
};

/// Per-interaction force and torque contributions, one slot per interaction end, structure
/// of arrays so the kernels store contiguously. Each force term writes only the slots of its
/// own ranges; GatherMap then sums each owned particle's slots in a fixed order (DESIGN §3).
struct ForceSlots {
  std::vector<double> fx, fy, fz, tx, ty, tz;

  std::size_t size() const { return fx.size(); }
  void assign(std::size_t n) {
    for (auto* v : {&fx, &fy, &fz, &tx, &ty, &tz})
      v->assign(n, 0.0);
  }
  void set(std::size_t i, const Vec3& f, const Vec3& t) {
    fx[i] = f.x;
    fy[i] = f.y;
    fz[i] = f.z;
    tx[i] = t.x;
    ty[i] = t.y;
    tz[i] = t.z;
  }
  Vec3 force(std::size_t i) const { return {fx[i], fy[i], fz[i]}; }
  Vec3 torque(std::size_t i) const { return {tx[i], ty[i], tz[i]}; }
};

/// The owned particles' force and torque, for a term that sums its loads per particle itself
/// instead of writing slots (PairContactTerm). Such a term must add to particle k in ascending
/// order of the partner's sort key (ParticleStore::sorts_before, a property of the particle as
/// the gid is; DESIGN §4): the sum is then the same on any rank count. It runs
/// after the loads are initialised (gravity in the drift pass, point loads: GatherMap)
/// and before the slots are gathered, which is the gather order when its partners sort before
/// every other term's (particle pairs: bonded pairs get no contact).
struct ParticleLoads {
  Vec3* force = nullptr;
  Vec3* torque = nullptr;
  std::size_t n_owned = 0;
  bool owned(std::size_t k) const { return k < n_owned; }
};

/// Hands out slot ranges to the force terms at a rebuild, in term order; the total sizes the
/// ForceSlots once.
class SlotAllocator {
 public:
  void reset() { next_ = 0; }
  SlotRange take(std::size_t n) {
    const SlotRange r{next_, static_cast<std::uint32_t>(n)};
    next_ += static_cast<std::uint32_t>(n);
    return r;
  }
  std::size_t size() const { return next_; }

 private:
  std::uint32_t next_ = 0;
};

}  // namespace ringdem

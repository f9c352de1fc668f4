#include "engine/SubstepParticles.hpp"

#include <stdexcept>

namespace ringdem {

namespace {
/// Runs of movers closer than this many others are joined, the others between them moved at
/// every sub-step as movers (zero loads: the same bits). A pass's runs of fewer than four
/// particles go through padded lanes (Integrator), and a net's rings lie among the grains.
/// 64 rather than 16: in the pile at a meshed net (the 10^5-grain channel, 0.35-0.38 s, 2
/// ranks) fewer, longer runs took 45.5 s against 47.6 s (3 pairs, ratio 1.05); 4: ratio 0.84.
constexpr std::size_t kJoinGap = 64;
}  // namespace

void SubstepParticles::classify(const ParticleStore& p, const GatherMap& gather,
                                const std::vector<std::unique_ptr<ForceTerm>>& terms,
                                const std::vector<PointLoad>& point_loads) {
  if (pending_ != 0)
    throw std::logic_error("SubstepParticles::classify(): drifts are pending (catch_up() first)");
  const std::size_t n = p.n_local();
  flag_.assign(n, move_all_ ? 1 : 0);
  if (!move_all_) {
    for (std::size_t k = 0; k < n; ++k) {
      const Vec3& f = p.force[k];
      const Vec3& t = p.torque[k];
      const bool loaded =
          f.x != 0.0 || f.y != 0.0 || f.z != 0.0 || t.x != 0.0 || t.y != 0.0 || t.z != 0.0;
      flag_[k] = is_fast_particle(p, k) || loaded ? 1 : 0;
    }
    for (const std::uint32_t k : gather.particles_with_slots(ForceRate::kFast))
      flag_[k] = 1;
    for (const auto& term : terms)
      term->mark_fast_particles(p, flag_);
    for (const PointLoad& load : point_loads) {
      const std::int64_t k = p.index_of(load.gid);
      if (k >= 0 && static_cast<std::size_t>(k) < n) flag_[static_cast<std::size_t>(k)] = 1;
    }
  }
  // The movers' runs, joined over short gaps; the others are the rest.
  movers_.clear();
  others_.clear();
  n_movers_ = 0;
  for (std::size_t k = 0; k < n;) {
    if (flag_[k] == 0) {
      ++k;
      continue;
    }
    std::size_t end = k + 1;
    for (;;) {
      while (end < n && flag_[end] != 0)
        ++end;
      std::size_t next = end;
      while (next < n && next - end < kJoinGap && flag_[next] == 0)
        ++next;
      if (next < n && flag_[next] != 0 && next - end < kJoinGap)
        end = next;
      else
        break;
    }
    movers_.push_back({k, end});
    n_movers_ += end - k;
    k = end;
  }
  std::size_t begin = 0;
  for (const Integrator::Run& run : movers_) {
    if (run.begin > begin) others_.push_back({begin, run.begin});
    begin = run.end;
  }
  if (begin < n) others_.push_back({begin, n});
  measure_others(p);
  current_ = true;
}

void SubstepParticles::catch_up(ParticleStore& p, double h) {
  if (pending_ == 0) return;
  Integrator::drift_unloaded(p, h, others_, pending_);
  pending_ = 0;
}

}  // namespace ringdem

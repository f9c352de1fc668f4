#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "engine/Model.hpp"

namespace ringdem {

/// The numbers a source's output is keyed by: its first gid, first bond id and first ring
/// (body) id. ModelBuilder gives each source the totals of the sources before it, so every
/// id depends on the case alone, never on the rank count.
struct SourceBases {
  std::int64_t gid = 0;
  std::int64_t bond_id = 0;
  std::int32_t body = 0;
};

/// A generator of particles (and the bonds between them) as a sequence of items: item i is
/// particle gid = bases.gid + i. A rank asks for the items [first, last) of every source (its
/// slice; ModelBuilder takes an equal share per rank), so no rank ever generates or holds the
/// whole model; the first distribution then moves each particle to the owner of its block.
/// Each bond comes with exactly one item (one of its ends); the first distribution finds the
/// owners of both ends through a gid directory and sends the bond to them.
///
/// Adding a source (an inflow, say) is one class deriving from this and one line in
/// ModelBuilder (docs/architecture.md, "Adding a particle source").
class ParticleSource {
 public:
  virtual ~ParticleSource() = default;
  virtual std::string describe() const = 0;
  /// Particles this source creates at start-up.
  virtual std::int64_t count() const = 0;
  /// Items (gids) it reserves: its gids are bases.gid + item for items in [0, gid_range()),
  /// and the ranks slice this range. A source whose items are not all particles (sparse gids,
  /// as GrainSource's packing cells) reserves more than it creates.
  virtual std::int64_t gid_range() const { return count(); }
  /// Bonds it creates (ids bases.bond_id ...).
  virtual std::int64_t bond_count() const { return 0; }
  /// Ring (body) ids it uses (bases.body ...).
  virtual std::int32_t body_count() const { return 0; }
  /// Appends the particles of items [first, last) of [0, gid_range()) to `model` and the bonds
  /// that come with them.
  virtual void emit(std::int64_t first, std::int64_t last, const SourceBases& bases,
                    Model& model) const = 0;

  /// The slice [first, last) of `n` items that rank `rank` of `ranks` emits.
  static std::int64_t slice_begin(std::int64_t n, int rank, int ranks) { return n * rank / ranks; }
};

}  // namespace ringdem

#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/Vec3.hpp"
#include "domain/ContactLedgerState.hpp"
#include "domain/ParticleStore.hpp"

namespace ringdem {

/// The tangential springs of one contact term (physics.md §3), structure of arrays, one row per
/// contact keyed by (gid, partner). What `partner` names is a property of the store, not of a
/// row: another particle's gid (particle pairs, gid < partner) or a rigid body's number
/// (particle–rigid-body contacts). for_each_field() is the store's field registry, with the
/// particle registry's flags: migration, checkpoints and their checksums loop over it.
///
/// Between two neighbour-list rebuilds the rows are the term's contact candidates, in its
/// order, and its kernel updates `spring` in place. At a rebuild the store first keeps only the
/// touching contacts (drop_released()), migration moves those rows to the owners of their
/// particles, and the term's rebuild() reads them back by key for its new candidates.
class ContactSpringStore {
 public:
  enum class Partner : std::uint8_t { kParticle, kRigidBody };

  explicit ContactSpringStore(Partner kind = Partner::kParticle) : partner_(kind) {}

  std::vector<std::int64_t> gid;      ///< the particle
  std::vector<std::int64_t> partner;  ///< the other particle's gid, or the rigid body's number
  std::vector<Vec3> spring;           ///< tangential spring (physics.md §3), zero when released
  /// Particle pairs only, where carries_ledger() (a field of their registry then; otherwise
  /// empty): what the energy ledger carries to the next step where it books each pair's work
  /// in the pair loop (ContactLedgerState: the viscous force on the particle `gid` and the
  /// overlap); zero where it does not.
  std::vector<ContactLedgerState> ledger;

  /// The field registry: calls f(FieldInfo, std::vector<T>&) for every field.
  template <class F>
  void for_each_field(F&& f) {
    fields(*this, f);
  }
  template <class F>
  void for_each_field(F&& f) const {
    fields(*this, f);
  }

  Partner partner_kind() const { return partner_; }
  /// Whether the rows have the `ledger` field. A rebuild at the middle of a step books what the
  /// contacts carried (PairContactTerm::book_carried_work()), and its rows go without: at 10^6
  /// grains in contact that field (then 28 bytes a contact) took the run's peak from 400 to 473 MB.
  /// Every rank must agree (migration packs the fields of the registry). Setting false drops it.
  bool carries_ledger() const { return partner_is_particle() && carries_ledger_; }
  void set_carries_ledger(bool carries) {
    carries_ledger_ = carries;
    if (carries)
      ledger.resize(gid.size());
    else
      std::vector<ContactLedgerState>().swap(ledger);
  }
  bool partner_is_particle() const { return partner_ == Partner::kParticle; }
  std::size_t size() const { return gid.size(); }
  void resize(std::size_t n) {
    for_each_field([n](const FieldInfo&, auto& v) { v.resize(n); });
  }
  void reserve(std::size_t n) {
    for_each_field([n](const FieldInfo&, auto& v) { v.reserve(n); });
  }
  /// Whether row k holds anything to carry: a spring, or ledger state (where rows have it).
  bool carries_state(std::size_t k) const {
    return norm2(spring[k]) > 0.0 || (!ledger.empty() && !ledger[k].is_empty());
  }
  void append(std::int64_t gid_value, std::int64_t partner_value, const Vec3& spring_value,
              const ContactLedgerState& ledger_value = {}) {
    gid.push_back(gid_value);
    partner.push_back(partner_value);
    spring.push_back(spring_value);
    if (carries_ledger()) ledger.push_back(ledger_value);
  }
  /// The particle gids row k joins (the pair-store protocol, domain/PairStore.hpp): a rigid
  /// body is no particle (-1).
  std::array<std::int64_t, 2> ends(std::size_t k) const {
    return {gid[k], partner_is_particle() ? partner[k] : std::int64_t{-1}};
  }
  /// Contact springs cost nothing a block weight should count.
  static constexpr int kBlockWeight = 0;
  /// After migration appended rows: a row that came from both old owners is the same spring
  /// twice, and the terms look rows up by key, so neither duplicates nor order matter here.
  void settle_arrivals(std::size_t /*first*/) {}
  /// Keeps the rows k with keep[k] != 0, in order.
  void keep_rows(const std::vector<char>& keep);
  /// Keeps the rows whose spring or ledger state is not zero (touching contacts; a head-on
  /// contact has no spring), in order: what a rebuild carries.
  void drop_released();
  /// Takes the rows of `other` (a store of the same partner kind read from a checkpoint).
  void assign_rows(ContactSpringStore&& other);

 private:
  template <class Self, class F>
  static void fields(Self& s, F& f) {
    using namespace field_flag;
    constexpr unsigned kState = kMigrate | kCheckpoint;
    f(FieldInfo{"gid", kState}, s.gid);
    f(FieldInfo{"partner", kState}, s.partner);
    f(FieldInfo{"spring", kState}, s.spring);
    // A checkpoint of format 17 or older has none (16 and 17 have a "ledger" of six floats, the
    // folded normal too, which is not read): its contacts carry nothing to the ledger.
    if (s.carries_ledger()) f(FieldInfo{"ledger_load", kState | kZeroIfAbsent}, s.ledger);
  }

  Partner partner_;
  bool carries_ledger_ = true;
};

}  // namespace ringdem

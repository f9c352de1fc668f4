#include "comm/DomainDecomposition.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <stdexcept>
#include <tuple>
#include <unordered_set>

#include "comm/CellGraph.hpp"
#include "comm/FieldRecords.hpp"
#include "core/CellKeys.hpp"

namespace ringdem {

namespace {

using cell_keys::floor_div;
using cell_keys::for_each_cell_around_block;
using cell_keys::for_each_neighbour;
using cell_keys::pack;
using cell_keys::unpack;
using field_records::pack_fields;
using field_records::record_size;
using field_records::unpack_fields;

constexpr unsigned kGhostFields = field_flag::kGhostOnce | field_flag::kGhostStep;

}  // namespace

DomainDecomposition::DomainDecomposition(const Communicator& comm, double block_size,
                                         double imbalance_threshold, int cell_blocks)
    : comm_(comm),
      block_size_(block_size),
      imbalance_threshold_(imbalance_threshold),
      fixed_cell_blocks_(cell_blocks),
      cell_blocks_(cell_blocks > 0 ? cell_blocks : 1) {
  if (!(block_size_ > 0.0)) throw std::invalid_argument("block size must be positive");
  if (cell_blocks < 0) throw std::invalid_argument("blocks per cell must not be negative");
}

std::uint64_t DomainDecomposition::cell_of_block(std::uint64_t block) const {
  if (cell_blocks_ == 1) return block;
  std::int64_t i, j, k;
  unpack(block, i, j, k);
  const std::int64_t n = cell_blocks_;
  return pack(floor_div(i, n), floor_div(j, n), floor_div(k, n));
}

std::uint64_t DomainDecomposition::block_of(const Vec3& x) const {
  const double inv = 1.0 / block_size_;
  return pack(static_cast<std::int64_t>(std::floor(x.x * inv)),
              static_cast<std::int64_t>(std::floor(x.y * inv)),
              static_cast<std::int64_t>(std::floor(x.z * inv)));
}

int DomainDecomposition::owner_of(const Vec3& x) const {
  if (comm_.size() == 1) return 0;  // no map of cells: every one is this rank's
  const auto it = owner_.find(cell_of(x));
  if (it == owner_.end()) throw std::logic_error("particle in a cell without owner");
  return it->second;
}

std::vector<CellLoad> DomainDecomposition::global_cells(
    const ParticleStore& p, const std::vector<PairStore>& stores) const {
  // Counted by sorting cell keys, not in a hash map: with one-block cells a cell holds about
  // one grain, and a map node per cell cost six times the keys' memory.
  std::vector<std::uint64_t> keys(p.n_local());
  for (std::size_t k = 0; k < p.n_local(); ++k)
    keys[k] = cell_of(p.position[k]);
  std::sort(keys.begin(), keys.end());
  std::vector<CellLoad> mine;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    if (mine.empty() || mine.back().key != keys[k]) mine.push_back({keys[k], 0, 0, comm_.rank()});
    ++mine.back().particles;
  }
  std::vector<std::uint64_t>().swap(keys);
  const auto cell_here = [&](std::size_t k) {
    const std::uint64_t key = cell_of(p.position[k]);
    return std::lower_bound(mine.begin(), mine.end(), key,
                            [](const CellLoad& b, std::uint64_t c) { return b.key < c; });
  };
  // Multi-rate stepping: a grain in contact with the net has every contact evaluated at every
  // sub-step, as a bond is, and weighs as a bond does (Simulation::note_net_contacts).
  if (!p.net_contact.empty() && row_weight_scale_ > 1)
    for (std::size_t k = 0; k < p.n_local(); ++k)
      if (p.net_contact[k] != 0) cell_here(k)->rows += row_weight_scale_;
  // A row of a weighing store (a bond) counts its store's weight (times the scale) in the cell
  // of its first end, on the rank that counts it (an owned particle here: its cell is in
  // `mine`).
  for (const PairStore& handle : stores)
    visit_store(handle, [&](const auto& s) {
      constexpr int weight = std::remove_cvref_t<decltype(s)>::kBlockWeight;
      if constexpr (weight > 0) {
        for (std::size_t r = 0; r < s.size(); ++r) {
          if (!counted_here(p, s, r)) continue;
          const auto a = static_cast<std::size_t>(p.index_of(s.ends(r)[0]));
          const auto it = cell_here(a);
          if (it == mine.end() || it->key != cell_of(p.position[a]))
            throw std::logic_error("a counted bond whose first end is in no occupied cell here");
          it->rows += weight * row_weight_scale_;
        }
      }
    });
  std::vector<CellLoad> all = comm_.size() > 1 ? comm_.allgather(mine) : std::move(mine);
  std::sort(all.begin(), all.end(), [](const CellLoad& a, const CellLoad& b) {
    return a.key < b.key || (a.key == b.key && a.rank < b.rank);
  });
  // Merged in place: one entry per key, with the smallest rank that has particles there.
  std::size_t merged = 0;
  for (std::size_t i = 0; i < all.size(); ++i) {
    if (merged > 0 && all[merged - 1].key == all[i].key) {
      all[merged - 1].particles += all[i].particles;
      all[merged - 1].rows += all[i].rows;
    } else {
      all[merged++] = all[i];
    }
  }
  all.resize(merged);
  return all;
}

void DomainDecomposition::partition(const ParticleStore& p, const std::vector<PairStore>& stores) {
  if (fixed_cell_blocks_ == 0) {
    // About max(4096, 256 per rank) cells if a block holds one particle: enough for METIS to
    // balance, few enough that every rank's map of them stays small at any model size.
    const auto n = static_cast<double>(comm_.sum(static_cast<std::int64_t>(p.n_local())));
    const double target = std::max(4096.0, 256.0 * comm_.size());
    cell_blocks_ = std::max(1, static_cast<int>(std::floor(std::cbrt(n / target))));
  }
  const std::vector<CellLoad> blocks = global_cells(p, stores);
  owner_.clear();
  forget_halo_ranks();
  cells_held_ = static_cast<std::int64_t>(blocks.size());
  if (comm_.size() == 1) {
    // One rank owns every cell: a map of them would only say so.
    ++repartitions_;
    return;
  }
  // The graph is partitioned on the root alone (METIS is serial) and its parts broadcast.
  std::vector<std::int32_t> part(blocks.size(), 0);
  if (comm_.is_root()) part = CellGraph::partition(blocks, comm_.size());
  comm_.broadcast(part, 0);
  for (std::size_t v = 0; v < blocks.size(); ++v)
    owner_[blocks[v].key] = part[v];
  ++repartitions_;
}

void DomainDecomposition::assign_new_cells(const std::vector<CellLoad>& cells) {
  // A cell that became occupied goes to the smallest rank that has particles in it, which
  // every rank can tell from the merged list; a cell that every particle left is forgotten,
  // so that no rank keeps receiving ghosts around a cell it no longer has particles in.
  cells_held_ = static_cast<std::int64_t>(cells.size());
  if (comm_.size() == 1) return;
  // A changed cell changes the halo ranks of the blocks around it only (the cache exists with
  // cells of one block, where a cell is a block).
  const auto forget_around = [&](std::uint64_t cell) {
    if (!halo_ranks_.empty())
      for_each_neighbour(cell, [&](std::uint64_t block) { halo_ranks_.erase(block); });
  };
  for (auto it = owner_.begin(); it != owner_.end();) {
    const std::uint64_t key = it->first;
    const auto at = std::lower_bound(cells.begin(), cells.end(), key,
                                     [](const CellLoad& c, std::uint64_t k) { return c.key < k; });
    if (at != cells.end() && at->key == key) {
      ++it;
      continue;
    }
    it = owner_.erase(it);
    forget_around(key);
  }
  for (const auto& c : cells)
    if (owner_.try_emplace(c.key, c.rank).second) forget_around(c.key);
}

void DomainDecomposition::collect_halo_ranks(std::uint64_t block, std::vector<int>& ranks) const {
  // The owners of the cells of the 27 blocks around this one (at most 8 cells when a cell is
  // two blocks wide or more; one inside a cell).
  const int me = comm_.rank();
  const auto begin = static_cast<std::ptrdiff_t>(ranks.size());
  for_each_cell_around_block(block, cell_blocks_, [&](std::uint64_t cell) {
    const auto owner = owner_.find(cell);
    if (owner != owner_.end() && owner->second != me) ranks.push_back(owner->second);
  });
  std::sort(ranks.begin() + begin, ranks.end());
  ranks.erase(std::unique(ranks.begin() + begin, ranks.end()), ranks.end());
}

std::pair<const int*, const int*> DomainDecomposition::cached_halo_ranks(std::uint64_t block) {
  auto it = halo_ranks_.find(block);
  if (it == halo_ranks_.end()) {
    // Entries erased for new cells leave their ranks in the pool: start afresh when most of
    // it is such garbage.
    if (halo_rank_pool_.size() > 1024 + 4 * halo_ranks_.size()) forget_halo_ranks();
    const auto begin = static_cast<std::uint32_t>(halo_rank_pool_.size());
    collect_halo_ranks(block, halo_rank_pool_);
    const auto count = static_cast<std::uint32_t>(halo_rank_pool_.size()) - begin;
    it = halo_ranks_.emplace(block, std::make_pair(begin, count)).first;
  }
  const int* const first = halo_rank_pool_.data() + it->second.first;
  return {first, first + it->second.second};
}

std::vector<int> DomainDecomposition::owners_of_gids(const ParticleStore& p,
                                                     const std::vector<int>& owner,
                                                     const std::vector<std::int64_t>& gids) const {
  // A rendezvous directory: the entry of gid g lives on rank g mod P. Every rank files its
  // particles' owners there, asks for the gids it lacks, and gets the answers back: three
  // all-to-alls of small records, O(held items) memory on every rank.
  const int n_ranks = comm_.size();
  const auto home = [n_ranks](std::int64_t g) {
    return static_cast<std::size_t>(((g % n_ranks) + n_ranks) % n_ranks);
  };
  struct Entry {
    std::int64_t gid;
    std::int64_t owner;
  };
  std::vector<std::vector<char>> filed(static_cast<std::size_t>(n_ranks));
  for (std::size_t k = 0; k < p.n_local(); ++k) {
    const Entry e{p.gid[k], owner[k]};
    const char* src = reinterpret_cast<const char*>(&e);
    filed[home(e.gid)].insert(filed[home(e.gid)].end(), src, src + sizeof(e));
  }
  std::vector<int> counts;
  // Buffers handed over (moved), so that each goes as soon as it is packed: at a restart every
  // spring row asks for its two ends, and the copies made the start-up's peak.
  std::vector<char> entries = comm_.alltoall_bytes(std::move(filed), counts);
  // The directory as entries sorted by gid: 16 B an entry, where a hash map's nodes took 55 B
  // and made the peak of a 10^6-grain start-up (docs/performance.md, seventh round).
  std::vector<Entry> directory(entries.size() / sizeof(Entry));
  if (!directory.empty()) std::memcpy(directory.data(), entries.data(), entries.size());
  std::vector<char>().swap(entries);
  std::sort(directory.begin(), directory.end(),
            [](const Entry& a, const Entry& b) { return a.gid < b.gid; });
  const bool duplicate =
      std::adjacent_find(directory.begin(), directory.end(), [](const Entry& a, const Entry& b) {
        return a.gid == b.gid;
      }) != directory.end();
  // Each particle must be held by one rank (a model built whole on every rank is not).
  if (comm_.any(duplicate))
    throw std::logic_error("first distribution: a particle gid is held by more than one rank");
  // The gids this rank does not own, each asked once, sorted: at a restart every spring row
  // names its two ends, so a grain in contact is named about six times, and a question and
  // its place per mention were 16 B a row of the start-up's peak (docs/performance.md,
  // fifty-eighth round).
  // The index of gid g among the particles this rank owns, or -1.
  const auto owned_index = [&](std::int64_t g) -> std::int64_t {
    const std::int64_t k = p.index_of(g);
    return k >= 0 && static_cast<std::size_t>(k) < p.n_local() ? k : -1;
  };
  std::vector<std::int64_t> wanted;
  for (const std::int64_t g : gids)
    if (owned_index(g) < 0) wanted.push_back(g);
  std::sort(wanted.begin(), wanted.end());
  wanted.erase(std::unique(wanted.begin(), wanted.end()), wanted.end());
  wanted.shrink_to_fit();
  // Questions to each home rank in gid order; the answers come back in the order asked.
  std::vector<std::vector<char>> asked(static_cast<std::size_t>(n_ranks));
  for (const std::int64_t g : wanted) {
    const char* src = reinterpret_cast<const char*>(&g);
    asked[home(g)].insert(asked[home(g)].end(), src, src + sizeof(g));
  }
  std::vector<char> questions = comm_.alltoall_bytes(std::move(asked), counts);
  std::vector<std::vector<char>> answers(static_cast<std::size_t>(n_ranks));
  std::size_t offset = 0;
  for (std::size_t r = 0; r < answers.size(); ++r) {
    const std::size_t n = static_cast<std::size_t>(counts[r]) / sizeof(std::int64_t);
    answers[r].reserve(n * sizeof(std::int64_t));
    for (std::size_t q = 0; q < n; ++q, offset += sizeof(std::int64_t)) {
      std::int64_t g;
      std::memcpy(&g, questions.data() + offset, sizeof(g));
      const auto it = std::lower_bound(directory.begin(), directory.end(), g,
                                       [](const Entry& e, std::int64_t x) { return e.gid < x; });
      const std::int64_t a = it != directory.end() && it->gid == g ? it->owner : -1;
      const char* src = reinterpret_cast<const char*>(&a);
      answers[r].insert(answers[r].end(), src, src + sizeof(a));
    }
  }
  std::vector<char>().swap(questions);
  std::vector<Entry>().swap(directory);
  const std::vector<char> replies = comm_.alltoall_bytes(std::move(answers), counts);
  // Each home rank's replies follow its questions, which went in gid order: walking `wanted`
  // in that order again, a cursor per rank finds each gid's answer.
  std::vector<std::size_t> cursor(static_cast<std::size_t>(n_ranks), 0);
  for (std::size_t r = 1; r < cursor.size(); ++r)
    cursor[r] = cursor[r - 1] + static_cast<std::size_t>(counts[r - 1]);
  std::vector<int> wanted_owner(wanted.size());
  for (std::size_t w = 0; w < wanted.size(); ++w) {
    std::int64_t a;
    std::memcpy(&a, replies.data() + cursor[home(wanted[w])], sizeof(a));
    cursor[home(wanted[w])] += sizeof(a);
    wanted_owner[w] = static_cast<int>(a);
  }
  std::vector<int> out(gids.size(), -1);
  std::int64_t missing = -1;
  for (std::size_t i = 0; i < gids.size(); ++i) {
    const std::int64_t k = owned_index(gids[i]);
    if (k >= 0) {
      out[i] = owner[static_cast<std::size_t>(k)];
      continue;
    }
    const auto w = static_cast<std::size_t>(
        std::lower_bound(wanted.begin(), wanted.end(), gids[i]) - wanted.begin());
    out[i] = wanted_owner[w];
    if (out[i] < 0) missing = gids[i];
  }
  // Every rank throws, not only the one that asked (the others would wait in the migration).
  if (comm_.any(missing >= 0))
    throw std::runtime_error(
        missing >= 0 ? "particle " + std::to_string(missing) +
                           " is named by a bond or a contact but held by no rank"
                     : std::string("a bond or a contact names a particle that no rank holds"));
  return out;
}

void DomainDecomposition::distribute_initial(ParticleStore& p,
                                             const std::vector<PairStore>& stores) {
  p.resize_ghosts(0);
  p.rebuild_index();
  partition(p, stores);
  std::vector<int> owner(p.n_local());
  for (std::size_t k = 0; k < p.n_local(); ++k)
    owner[k] = owner_of(p.position[k]);
  // The owners of every particle a held row names, from wherever it is (a partner that is no
  // particle goes where the first end goes).
  std::size_t n_named = 0;
  for (const PairStore& handle : stores)
    n_named += 2 * visit_store(handle, [](const auto& s) { return s.size(); });
  std::vector<std::int64_t> named;
  named.reserve(n_named);
  for (const PairStore& handle : stores)
    visit_store(handle, [&](const auto& s) {
      for (std::size_t r = 0; r < s.size(); ++r) {
        const auto ends = s.ends(r);
        named.push_back(ends[0]);
        named.push_back(ends[1] >= 0 ? ends[1] : ends[0]);
      }
    });
  const std::vector<int> named_owner = owners_of_gids(p, owner, named);
  std::vector<std::int64_t>().swap(named);
  Destinations to;
  to.particle = std::move(owner);
  std::vector<std::size_t> first_named(stores.size() + 1, 0);  // each store's rows in `named`
  for (std::size_t s = 0; s < stores.size(); ++s)
    first_named[s + 1] =
        first_named[s] + 2 * visit_store(stores[s], [](const auto& st) { return st.size(); });
  to.row = [&](std::size_t s, std::size_t h) {
    const std::size_t at = first_named[s] + 2 * h;
    return std::array<int, 2>{named_owner[at], named_owner[at + 1]};
  };
  migrate(p, stores, to);
}

void DomainDecomposition::redistribute(ParticleStore& p, const std::vector<PairStore>& stores) {
  p.rebuild_index();
  // One rank owns every cell: there is nothing to assign, and counting the occupied cells (for
  // the rank report alone) sorted every particle's cell key at each rebuild, 2-3 % of a
  // 10^6-grain packing's loop. The count stays that of the last partition.
  if (comm_.size() > 1) {
    // The cells as they stand (new ones assigned), weighed as the partition weighs them: a
    // partition that gives the rank holding a net fewer grains is balanced, and testing its
    // particle counts repartitioned at every rebuild (the debris demo's 40 % at the start).
    const std::vector<CellLoad> cells = global_cells(p, stores);
    assign_new_cells(cells);
    if (cell_imbalance(cells) > imbalance_threshold_) partition(p, stores);
  }
  // New owner of every particle this rank holds (owned and ghost): an intact bond or a
  // contact has both its particles here, owned or as ghosts.
  // A ghost in a cell no rank owns any more is the copy of a particle its owner took out since
  // (an outflow): it has no owner, like a particle this rank does not hold.
  std::vector<int> owner(p.n_total());
  for (std::size_t k = 0; k < p.n_local(); ++k)
    owner[k] = owner_of(p.position[k]);
  for (std::size_t k = p.n_local(); k < p.n_total(); ++k) {
    const auto it = owner_.find(cell_of(p.position[k]));
    owner[k] = it == owner_.end() ? -1 : it->second;
  }
  // -1 for a particle this rank does not hold (only the far end of a broken bond).
  auto owner_of_gid = [&](std::int64_t gid) {
    const std::int64_t k = p.index_of(gid);
    return k < 0 ? -1 : owner[static_cast<std::size_t>(k)];
  };
  Destinations to;
  to.particle.assign(owner.begin(), owner.begin() + static_cast<std::ptrdiff_t>(p.n_local()));
  to.row = [&](std::size_t s, std::size_t r) {
    const auto ends = visit_store(stores[s], [r](const auto& st) { return st.ends(r); });
    const int oa = owner_of_gid(ends[0]);
    return std::array<int, 2>{oa, ends[1] >= 0 ? owner_of_gid(ends[1]) : oa};
  };
  migrate(p, stores, to);
}

void DomainDecomposition::build_ghosts(ParticleStore& p) {
  const auto n_ranks = static_cast<std::size_t>(comm_.size());
  ghost_send_.assign(n_ranks, {});
  ghost_subset_.clear();
  std::vector<std::vector<char>> send(n_ranks);
  // With one rank every block is this rank's: nobody to send a ghost to.
  const std::size_t n_senders = n_ranks > 1 ? p.n_local() : 0;
  std::vector<int> targets, far_targets;
  if (n_ranks > 1)  // collective: every rank, those that own nothing too
    for (FarGhosts& far : far_)
      far.index(comm_, p, [this](const Vec3& x) { return block_of(x); });
  for (std::size_t k = 0; k < n_senders; ++k) {
    const std::uint64_t block = block_of(p.position[k]);
    const int* first = nullptr;
    const int* last = nullptr;
    if (cell_blocks_ == 1) {
      std::tie(first, last) = cached_halo_ranks(block);
    } else {
      targets.clear();
      collect_halo_ranks(block, targets);
      first = targets.data();
      last = first + targets.size();
    }
    if (!far_.empty()) {
      far_targets.clear();
      for (const FarGhosts& far : far_)
        far.append_targets(p, k, block, far_targets);
      if (!far_targets.empty()) {  // with the layer's, each rank once, in rank order
        far_targets.insert(far_targets.end(), first, last);
        std::sort(far_targets.begin(), far_targets.end());
        far_targets.erase(std::unique(far_targets.begin(), far_targets.end()), far_targets.end());
        first = far_targets.data();
        last = first + far_targets.size();
      }
    }
    for (const int* r = first; r != last; ++r) {
      ghost_send_[static_cast<std::size_t>(*r)].push_back(static_cast<std::uint32_t>(k));
      pack_fields(p, k, kGhostFields, send[static_cast<std::size_t>(*r)]);
    }
  }
  std::vector<int> counts;
  const std::vector<char> recv = comm_.alltoall_bytes(std::move(send), counts);
  const std::size_t size = record_size(p, kGhostFields);
  ghost_recv_count_.assign(n_ranks, 0);
  for (std::size_t r = 0; r < n_ranks; ++r)
    ghost_recv_count_[r] = static_cast<int>(static_cast<std::size_t>(counts[r]) / size);
  const std::size_t n_ghost = recv.size() / size;
  const std::size_t first = p.n_local();
  p.resize_ghosts(n_ghost);
  const char* data = recv.data();
  for (std::size_t k = 0; k < n_ghost; ++k)
    data = unpack_fields(p, first + k, kGhostFields, data);
  p.rebuild_index();
}

void DomainDecomposition::update_ghosts(ParticleStore& p, unsigned fields) {
  const auto n_ranks = static_cast<std::size_t>(comm_.size());
  if (n_ranks == 1) return;
  const unsigned flags = fields;
  const std::size_t size = record_size(p, flags);
  // Column by column within each rank's block: a column's values for all the ghosts a rank
  // gets, in a row, copied in a tight loop on the way out and in one piece on the way in (the
  // ghosts from one rank are stored together, in the order sent). A record per particle went
  // through the registry once per particle and field, a tenth of the debris demo's loop on 2
  // ranks (docs/performance.md, twenty-sixth round). Buffers are members: resized, not freed,
  // so the step loop does not allocate.
  ghost_send_buffers_.resize(n_ranks);
  for (std::size_t r = 0; r < n_ranks; ++r) {
    const std::vector<std::uint32_t>& send = ghost_send_[r];
    std::vector<char>& buffer = ghost_send_buffers_[r];
    buffer.resize(send.size() * size);
    char* out = buffer.data();
    p.for_each_field([&](const FieldInfo& f, auto& v) {
      if (!(f.flags & flags)) return;
      constexpr std::size_t kBytes = sizeof(v[0]);
      for (const std::uint32_t k : send) {
        std::memcpy(out, static_cast<const void*>(&v[k]), kBytes);
        out += kBytes;
      }
    });
  }
  ghost_recv_bytes_.resize(n_ranks);
  for (std::size_t r = 0; r < n_ranks; ++r)
    ghost_recv_bytes_[r] = static_cast<int>(static_cast<std::size_t>(ghost_recv_count_[r]) * size);
  comm_.exchange_bytes(ghost_send_buffers_, ghost_recv_bytes_, ghost_recv_buffer_);
  if (ghost_recv_buffer_.size() != p.n_ghost() * size)
    throw std::logic_error("ghost update: count changed");
  const char* data = ghost_recv_buffer_.data();
  std::size_t ghost = p.n_local();
  for (std::size_t r = 0; r < n_ranks; ++r) {
    const auto n = static_cast<std::size_t>(ghost_recv_count_[r]);
    p.for_each_field([&](const FieldInfo& f, auto& v) {
      if (!(f.flags & flags)) return;
      const std::size_t bytes = n * sizeof(v[0]);
      if (bytes > 0) std::memcpy(static_cast<void*>(&v[ghost]), data, bytes);
      data += bytes;
    });
    ghost += n;
  }
}

double DomainDecomposition::cell_imbalance(const std::vector<CellLoad>& cells) const {
  // Every rank holds every occupied cell and its owner: the same sums on every rank.
  std::vector<std::int64_t> load(static_cast<std::size_t>(comm_.size()), 0);
  std::int64_t total = 0;
  for (const CellLoad& c : cells) {
    const auto it = owner_.find(c.key);
    const int rank = it != owner_.end() ? it->second : c.rank;
    load[static_cast<std::size_t>(rank)] += CellGraph::vertex_weight(c);
    total += CellGraph::vertex_weight(c);
  }
  const double mean = static_cast<double>(total) / comm_.size();
  const auto most = static_cast<double>(*std::max_element(load.begin(), load.end()));
  return mean > 0.0 ? most / mean - 1.0 : 0.0;
}

double DomainDecomposition::imbalance(const ParticleStore& p) const {
  const auto n = static_cast<std::int64_t>(p.n_local());
  const double mean = static_cast<double>(comm_.sum(n)) / comm_.size();
  const double most = static_cast<double>(comm_.max(n));
  return mean > 0.0 ? most / mean - 1.0 : 0.0;
}

std::vector<DomainDecomposition::RankReport> DomainDecomposition::report(
    const ParticleStore& p, const BondStore& bonds) const {
  RankReport mine;
  mine.particles = static_cast<std::int64_t>(p.n_local());
  mine.ghosts = static_cast<std::int64_t>(p.n_ghost());
  mine.bonds = static_cast<std::int64_t>(bonds.size());
  for (std::size_t b = 0; b < bonds.size(); ++b) {
    const std::int64_t ia = p.index_of(bonds.gid_a[b]);
    const std::int64_t ib = p.index_of(bonds.gid_b[b]);
    const bool a_here = ia >= 0 && static_cast<std::size_t>(ia) < p.n_local();
    const bool b_here = ib >= 0 && static_cast<std::size_t>(ib) < p.n_local();
    mine.cut_bonds += a_here != b_here;
  }
  for (const auto& [key, rank] : owner_)
    mine.cells += rank == comm_.rank();
  if (comm_.size() == 1) mine.cells = cells_held_;
  return comm_.allgather(std::vector<RankReport>{mine});
}

}  // namespace ringdem

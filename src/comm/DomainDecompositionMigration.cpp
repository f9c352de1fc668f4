// DomainDecomposition's migration: owned particles and pair-store rows to their new ranks, in
// rounds, so that a migration in which most items leave (a start, a restart) never holds a
// store and all of what leaves and arrives at once.
#include <algorithm>
#include <cstring>
#include <numeric>
#include <stdexcept>

#include "comm/DomainDecomposition.hpp"
#include "comm/FieldRecords.hpp"

namespace ringdem {

using field_records::pack_fields_at;
using field_records::record_size;
using field_records::unpack_fields;

namespace {

// A round moves at most an eighth of a rank's store (and at least round_min_bytes_); at most
// 1 GiB, as MPI counts bytes in an int.
constexpr std::size_t kRoundsPerStore = 8;
constexpr std::size_t kMaxRoundBytes = std::size_t{1} << 30;

}  // namespace

void DomainDecomposition::migrate_particles(ParticleStore& p, const std::vector<int>& owner) {
  const int me = comm_.rank();
  const unsigned migrate = field_flag::kMigrate;
  const std::size_t p_size = record_size(p, migrate);
  p.resize_ghosts(0);
  // In rounds of at most an eighth of the store (and at least round_min_bytes_): each round
  // packs its share of what leaves into one buffer, exactly sized, exchanges it, drops it from
  // the store and appends what arrived into the room it left. At the start-up distribution
  // most of a rank's particles leave it; in one round the store, what leaves and what arrives
  // were all held at once, more than twice the store. Every rank takes part in every round.
  // At most 1 GiB a round: MPI counts bytes in an int.
  std::vector<int> dest(owner.begin(), owner.end());
  const std::size_t n_leaving = static_cast<std::size_t>(
      std::count_if(dest.begin(), dest.end(), [me](int r) { return r != me; }));
  const std::size_t per_round =
      std::min(std::max({std::size_t{1}, round_min_bytes_ / p_size, p.n_local() / kRoundsPerStore}),
               kMaxRoundBytes / p_size);
  const std::int64_t rounds = comm_.max(
      static_cast<std::int64_t>(std::max<std::size_t>(1, (n_leaving + per_round - 1) / per_round)));
  last_rounds_ = rounds;
  std::vector<int> send_counts(static_cast<std::size_t>(comm_.size()));
  std::vector<std::size_t> send_at(send_counts.size());
  std::vector<char> keep;
  for (std::int64_t round = 0; round < rounds; ++round) {
    // This round's share: the first per_round particles (in store order) that leave.
    const std::size_t n = p.n_local();
    keep.assign(n, 1);
    std::fill(send_counts.begin(), send_counts.end(), 0);
    for (std::size_t k = 0, taken = 0; k < n && taken < per_round; ++k)
      if (dest[k] != me) {
        keep[k] = 0;
        ++taken;
        send_counts[static_cast<std::size_t>(dest[k])] += static_cast<int>(p_size);
      }
    send_at[0] = 0;
    for (std::size_t r = 1; r < send_at.size(); ++r)
      send_at[r] = send_at[r - 1] + static_cast<std::size_t>(send_counts[r - 1]);
    std::vector<char> send(send_at.back() + static_cast<std::size_t>(send_counts.back()));
    for (std::size_t k = 0; k < n; ++k)
      if (!keep[k]) {
        std::size_t& at = send_at[static_cast<std::size_t>(dest[k])];
        pack_fields_at(p, k, migrate, send.data() + at);
        at += p_size;
      }
    std::vector<int> recv_counts;
    const std::vector<char> arrived =
        comm_.alltoall_bytes(std::move(send), send_counts, recv_counts);
    const std::size_t n_kept = compact_rows(p, keep);
    p.resize_local(n_kept);
    std::size_t d = 0;
    for (std::size_t k = 0; k < n; ++k)
      if (keep[k]) dest[d++] = dest[k];
    dest.resize(d);
    const std::size_t n_in = arrived.size() / p_size;
    p.resize_local(n_kept + n_in);
    const char* data = arrived.data();
    for (std::size_t k = 0; k < n_in; ++k)
      data = unpack_fields(p, n_kept + k, migrate, data);
    dest.resize(n_kept + n_in, me);
  }
}

std::vector<std::size_t> DomainDecomposition::migrate_rows(const std::vector<PairStore>& stores,
                                                           const Destinations& to) {
  const int me = comm_.rank();
  const auto n_ranks = static_cast<std::size_t>(comm_.size());
  const unsigned migrate = field_flag::kMigrate;
  const std::size_t n_stores = stores.size();
  // The ranks other than this one that a row goes to (none, one or two).
  const auto others = [me](const std::array<int, 2>& d, int out[2]) {
    int n = 0;
    if (d[0] >= 0 && d[0] != me) out[n++] = d[0];
    if (d[1] >= 0 && d[1] != d[0] && d[1] != me) out[n++] = d[1];
    return n;
  };
  // Rows of all pair stores in rounds, each round one exchange: per rank, each store's row
  // count, then its rows. A row goes to each owner of its ends (once when both are the same
  // rank) and stays where it has an end. At a restart nearly every spring row leaves its rank:
  // in one exchange the store, all that left and all that arrived were held at once, twice
  // the steps' memory (docs/performance.md, fifty-seventh round). A round takes rows from the
  // end of each store's rows not yet looked at, so the rows before them keep the indices that
  // `to.row` knows them by; the store then drops what left it and appends what arrived.
  // Each row's fate in a byte (bit 0: it stays; above: the ranks it goes to), asked of `to`
  // once; a column of destinations was 8 bytes a contact at a rebuild's peak.
  std::vector<std::vector<std::uint8_t>> fate(n_stores);
  std::vector<std::size_t> row_size(n_stores), unvisited(n_stores);
  std::size_t store_bytes = 0, leaving_bytes = 0;
  for (std::size_t s = 0; s < n_stores; ++s)
    visit_store(stores[s], [&](auto& store) {
      row_size[s] = record_size(store, migrate);
      unvisited[s] = store.size();
      store_bytes += store.size() * row_size[s];
      fate[s].resize(store.size());
      int ranks[2];
      for (std::size_t h = 0; h < store.size(); ++h) {
        const std::array<int, 2> d = to.row(s, h);
        const int n = others(d, ranks);
        fate[s][h] = static_cast<std::uint8_t>((d[0] == me || d[1] == me ? 1 : 0) | (n << 1));
        leaving_bytes += static_cast<std::size_t>(n) * row_size[s];
      }
    });
  const auto stays = [&](std::size_t s, std::size_t h) { return (fate[s][h] & 1) != 0; };
  const auto n_others = [&](std::size_t s, std::size_t h) {
    return static_cast<std::size_t>(fate[s][h] >> 1);
  };
  const std::size_t round_bytes =
      std::min(std::max(round_min_bytes_, store_bytes / kRoundsPerStore), kMaxRoundBytes);
  const std::int64_t rounds = comm_.max(static_cast<std::int64_t>(
      std::max<std::size_t>(1, (leaving_bytes + round_bytes - 1) / round_bytes)));
  last_row_rounds_ = rounds;
  const std::size_t header = n_stores * sizeof(std::uint64_t);
  std::vector<int> send_counts(n_ranks);
  std::vector<std::size_t> at(n_ranks), first(n_stores), arrived_rows(n_stores, 0);
  std::vector<std::uint64_t> counts(n_ranks * n_stores);
  std::vector<char> keep;
  for (std::int64_t round = 0; round < rounds; ++round) {
    // This round's rows: [first[s], unvisited[s]) of each store, taken from the end until the
    // round's bytes are used up (the last round takes every row left).
    const bool last = round + 1 == rounds;
    std::size_t taken = 0;
    for (std::size_t s = 0; s < n_stores; ++s) {
      std::size_t h = unvisited[s];
      if (last) h = 0;
      while (h > 0) {
        const std::size_t bytes = n_others(s, h - 1) * row_size[s];
        if (taken > 0 && taken + bytes > round_bytes) break;
        taken += bytes;
        --h;
      }
      first[s] = h;
    }
    // Pack: each destination's header (its rows in every store), then its rows.
    std::fill(send_counts.begin(), send_counts.end(), static_cast<int>(header));
    std::fill(counts.begin(), counts.end(), 0);
    for (std::size_t s = 0; s < n_stores; ++s)
      for (std::size_t k = first[s]; k < unvisited[s]; ++k) {
        if (n_others(s, k) == 0) continue;
        int ranks[2];
        for (int i = 0, n = others(to.row(s, k), ranks); i < n; ++i) {
          const auto r = static_cast<std::size_t>(ranks[i]);
          send_counts[r] += static_cast<int>(row_size[s]);
          ++counts[r * n_stores + s];
        }
      }
    std::size_t total = 0;
    for (std::size_t r = 0; r < n_ranks; ++r) {
      at[r] = total;
      total += static_cast<std::size_t>(send_counts[r]);
    }
    std::vector<char> send(total);
    for (std::size_t r = 0; r < n_ranks && n_stores > 0; ++r) {  // (no stores: no bytes)
      std::memcpy(send.data() + at[r], counts.data() + r * n_stores, header);
      at[r] += header;
    }
    for (std::size_t s = 0; s < n_stores; ++s)
      visit_store(stores[s], [&](auto& store) {
        for (std::size_t k = first[s]; k < unvisited[s]; ++k) {
          if (n_others(s, k) == 0) continue;
          int ranks[2];
          for (int i = 0, n = others(to.row(s, k), ranks); i < n; ++i) {
            std::size_t& cursor = at[static_cast<std::size_t>(ranks[i])];
            pack_fields_at(store, k, migrate, send.data() + cursor);
            cursor += row_size[s];
          }
        }
      });
    std::vector<int> recv_bytes;
    const std::vector<char> arrived =
        comm_.alltoall_bytes(std::move(send), send_counts, recv_bytes);
    // What left goes (the rows before the round's do not move); what arrived is appended, by
    // source rank, each store's rows in turn.
    std::vector<std::size_t> next(n_stores);
    for (std::size_t s = 0; s < n_stores; ++s)
      visit_store(stores[s], [&](auto& store) {
        bool drops = false;
        for (std::size_t k = first[s]; k < unvisited[s] && !drops; ++k)
          drops = !stays(s, k);
        if (drops) {
          keep.assign(store.size(), 1);
          for (std::size_t k = first[s]; k < unvisited[s]; ++k)
            keep[k] = stays(s, k) ? 1 : 0;
          store.keep_rows(keep);
        }
        unvisited[s] = first[s];
        std::size_t arrivals = 0;
        const char* data = arrived.data();
        for (std::size_t r = 0; r < n_ranks; ++r) {
          std::uint64_t n_rows = 0;
          std::memcpy(&n_rows, data + s * sizeof(std::uint64_t), sizeof(n_rows));
          arrivals += n_rows;
          data += static_cast<std::size_t>(recv_bytes[r]);
        }
        next[s] = store.size();
        store.resize(next[s] + arrivals);
        arrived_rows[s] += arrivals;
      });
    const char* data = arrived.data();
    for (std::size_t r = 0; r < n_ranks && n_stores > 0; ++r) {
      std::vector<std::uint64_t> n_rows(n_stores);
      std::memcpy(static_cast<void*>(n_rows.data()), data, header);
      const char* rows = data + header;
      std::size_t bytes = header;
      for (std::size_t s = 0; s < n_stores; ++s) {
        bytes += n_rows[s] * row_size[s];
        visit_store(stores[s], [&](auto& store) {
          for (std::uint64_t k = 0; k < n_rows[s]; ++k)
            rows = unpack_fields(store, next[s]++, migrate, rows);
        });
      }
      if (bytes != static_cast<std::size_t>(recv_bytes[r]))
        throw std::logic_error("row migration: message size mismatch");
      data += bytes;
    }
  }
  // The rows this rank kept come first, then every round's arrivals: the stores settle from
  // the first arrival.
  std::vector<std::size_t> first_arrival(n_stores);
  for (std::size_t s = 0; s < n_stores; ++s)
    first_arrival[s] =
        visit_store(stores[s], [](const auto& st) { return st.size(); }) - arrived_rows[s];
  return first_arrival;
}

void DomainDecomposition::migrate(ParticleStore& p, const std::vector<PairStore>& stores,
                                  const Destinations& to) {
  // The rows first: `to` knows them by their indices and the particles by theirs as they are.
  const std::vector<std::size_t> first_arrival = migrate_rows(stores, to);
  migrate_particles(p, to.particle);
  // A bond store drops duplicates (a row from both old owners) and restores its canonical order.
  for (std::size_t s = 0; s < stores.size(); ++s)
    visit_store(stores[s], [&](auto& store) { store.settle_arrivals(first_arrival[s]); });

  // Owned particles in the order of their sort keys (bin of the last re-sort, gid), so the
  // local layout is the same for any history of moves. Most rebuilds move no particle between
  // ranks and come between re-sorts: the order then still holds.
  bool sorted = true;
  for (std::size_t k = 1; k < p.n_local() && sorted; ++k)
    sorted = !p.sorts_before(k, k - 1);
  if (!sorted) {
    std::vector<std::size_t> order(p.n_local());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&p](std::size_t x, std::size_t y) { return p.sorts_before(x, y); });
    p.permute_local(order);
  }
  build_ghosts(p);
}

}  // namespace ringdem

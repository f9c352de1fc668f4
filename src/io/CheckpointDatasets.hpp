#pragma once

// The datasets of a checkpoint (io/Checkpoint.cpp): rows written in blocks or concatenated over
// the ranks, each with an order-independent checksum, and read back checked against it; pair
// stores and replicated stores through their field registries. Kept apart so that the writer
// and the reader of the format stay readable; nothing outside the checkpoint uses them.

#include <algorithm>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "comm/Communicator.hpp"
#include "comm/RowBlocks.hpp"
#include "domain/PairStore.hpp"
#include "domain/ParticleStore.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem::checkpoint_datasets {

/// Order-independent checksum of a block of rows: the sum of each row's hash seeded with its
/// global row index, so partial sums of blocks written by any number of ranks add up to the
/// checksum of the whole dataset read by one.
template <class T>
std::uint64_t rows_checksum(const std::vector<T>& rows, std::int64_t first_row) {
  std::uint64_t sum = 0;
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto row = static_cast<std::uint64_t>(first_row) + k;
    sum += fnv1a64(&rows[k], sizeof(T), fnv1a64(&row, sizeof(row)));
  }
  return sum;
}

inline std::uint64_t total(const Communicator& comm, std::uint64_t partial) {
  std::uint64_t sum = 0;
  for (std::uint64_t v : comm.allgather(std::vector<std::uint64_t>{partial}))
    sum += v;
  return sum;
}

inline void set_checksum(Hdf5File& f, const std::string& name, std::uint64_t sum) {
  f.set_attribute(name, "checksum", static_cast<std::int64_t>(sum));
}

inline std::uint64_t bytes_checksum(const std::vector<char>& bytes, std::size_t row_bytes) {
  std::uint64_t sum = 0;
  if (row_bytes == 0) return 0;
  for (std::size_t k = 0; k * row_bytes < bytes.size(); ++k) {
    const std::uint64_t row = k;
    sum += fnv1a64(bytes.data() + k * row_bytes, row_bytes, fnv1a64(&row, sizeof(row)));
  }
  return sum;
}

/// Writes one registry field in row blocks, with its checksum.
template <class T>
void write_field(Hdf5File& f, const Communicator& comm, const RowBlocks& blocks,
                 const std::string& name, const std::vector<T>& values) {
  const std::vector<T> block = blocks.to_blocks(values);
  f.create_rows(name, H5Layout<T>::type(), H5Layout<T>::components, blocks.n_rows());
  f.write_rows(name, -1, blocks.first_row(), block);
  set_checksum(f, name, total(comm, rows_checksum(block, blocks.first_row())));
}

/// Writes rows each rank holds (no global order), concatenated in rank order.
template <class T>
void write_concatenated(Hdf5File& f, const Communicator& comm, const std::string& name,
                        const std::vector<T>& local) {
  const auto counts =
      comm.allgather(std::vector<std::int64_t>{static_cast<std::int64_t>(local.size())});
  std::int64_t first = 0, n = 0;
  for (int r = 0; r < comm.size(); ++r) {
    if (r < comm.rank()) first += counts[static_cast<std::size_t>(r)];
    n += counts[static_cast<std::size_t>(r)];
  }
  f.create_rows(name, H5Layout<T>::type(), H5Layout<T>::components, n);
  f.write_rows(name, -1, first, local);
  set_checksum(f, name, total(comm, rows_checksum(local, first)));
}

/// How the ranks read a table: each its own block of rows, or every rank all of them.
enum class ReadBy { kBlocks, kEveryRank };

/// Whether a pair store's rows carry a global id (bonds do): its rows are then written in id
/// order, else concatenated over the ranks (contact springs, which a term looks up by key).
template <class Store>
constexpr bool kRowsById = requires(Store& s) {
  s.id;
};

/// Writes the checkpoint fields of a pair store (domain/PairStore.hpp) as <prefix><field>: each
/// row once, by the rank that counts it, through the store's registry.
template <class Store>
void write_pair_rows(Hdf5File& f, const Communicator& comm, const ParticleStore& p,
                     const Store& store, const std::string& prefix) {
  std::vector<std::size_t> local;
  for (std::size_t k = 0; k < store.size(); ++k)
    if (counted_here(p, store, k)) local.push_back(k);
  // Rows by id are ranked over the ranks (a collective sample sort): only stores that have ids.
  std::optional<RowBlocks> blocks;
  if constexpr (kRowsById<Store>) {
    std::vector<std::int64_t> ids;
    for (std::size_t k : local)
      ids.push_back(store.id[k]);
    blocks.emplace(comm, ids);
  }
  // Springs come counted already (ForceTerm::touching_springs): their columns are written as
  // they are, without a copy of each (at 2.5 x 10^5 grains in contact a rank, 26 MiB of the
  // checkpoint's peak: docs/performance.md, fifty-seventh round).
  const bool every_row = local.size() == store.size();
  if (!kRowsById<Store> && every_row) std::vector<std::size_t>().swap(local);
  store.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kCheckpoint)) return;
    if constexpr (!kRowsById<Store>) {
      if (every_row) {
        write_concatenated(f, comm, prefix + std::string(info.name), v);
        return;
      }
    }
    std::remove_cvref_t<decltype(v)> mine;
    mine.reserve(local.size());
    for (std::size_t k : local)
      mine.push_back(v[k]);
    const std::string name = prefix + std::string(info.name);
    if constexpr (kRowsById<Store>)
      write_field(f, comm, *blocks, name, mine);
    else
      write_concatenated(f, comm, name, mine);
  });
}

/// Rows a rank builds in parts (`part(k, parts)`, a store like `kind` each: a pair store whose
/// rows come counted, as contact springs do), written as <prefix><field> through the store's
/// registry, concatenated over the ranks in rank order as write_pair_rows() writes a whole
/// store: the same datasets and checksums. Each part is built twice, once to count the rows
/// and once to write them at its offset, so that no rank holds more than one part at once.
/// `parts` must be the same on every rank (each part's writes are collective).
template <class Store, class MakePart>
void write_rows_in_parts(Hdf5File& f, const Communicator& comm, const std::string& prefix,
                         const Store& kind, std::size_t parts, MakePart&& part) {
  std::int64_t local = 0;
  for (std::size_t k = 0; k < parts; ++k)
    local += static_cast<std::int64_t>(part(k, parts).size());
  const auto counts = comm.allgather(std::vector<std::int64_t>{local});
  std::int64_t first = 0, n = 0;
  for (int r = 0; r < comm.size(); ++r) {
    if (r < comm.rank()) first += counts[static_cast<std::size_t>(r)];
    n += counts[static_cast<std::size_t>(r)];
  }
  std::vector<std::uint64_t> sums;
  kind.for_each_field([&](const FieldInfo& info, const auto& v) {
    if (!info.has(field_flag::kCheckpoint)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    f.create_rows(prefix + std::string(info.name), H5Layout<T>::type(), H5Layout<T>::components, n);
    sums.push_back(0);
  });
  std::int64_t at = first;
  for (std::size_t k = 0; k < parts; ++k) {
    const Store rows = part(k, parts);
    std::size_t field = 0;
    rows.for_each_field([&](const FieldInfo& info, const auto& v) {
      if (!info.has(field_flag::kCheckpoint)) return;
      f.write_rows(prefix + std::string(info.name), -1, at, v);
      sums.at(field++) += rows_checksum(v, at);
    });
    at += static_cast<std::int64_t>(rows.size());
  }
  if (at != first + local)
    throw std::logic_error("checkpoint: the parts of " + prefix + " changed between the passes");
  std::size_t field = 0;
  kind.for_each_field([&](const FieldInfo& info, const auto&) {
    if (info.has(field_flag::kCheckpoint))
      set_checksum(f, prefix + std::string(info.name), total(comm, sums[field++]));
  });
}

/// Rows [first, end) of a dataset of `rows` rows, read collectively, checked against the
/// dataset's checksum: the blocks' partial checksums add up to it.
template <class T>
std::vector<T> read_verified_block(const Hdf5File& f, const Communicator& comm,
                                   const std::string& name, std::int64_t rows, std::int64_t first,
                                   std::int64_t end, ReadBy read_by = ReadBy::kBlocks) {
  const auto d = f.dims(name);
  if ((d.empty() ? 0 : d[0]) != rows)
    throw Hdf5Error(f.path() + ": dataset " + name + " has " +
                    std::to_string(d.empty() ? 0 : d[0]) + " rows, expected " +
                    std::to_string(rows));
  std::vector<T> block = f.read_row_block<T>(name, first, end - first);
  const auto stored = static_cast<std::uint64_t>(f.attribute_int(name, "checksum"));
  const std::uint64_t partial = rows_checksum(block, first);
  if (stored != (read_by == ReadBy::kBlocks ? total(comm, partial) : partial))
    throw Hdf5Error(f.path() + ": dataset " + name +
                    " fails its checksum: the checkpoint is corrupted");
  return block;
}

/// Reads this rank's block of the `rows` checkpoint rows of a pair store (<prefix><field>,
/// through its registry); the first distribution then moves them to their particles' owners.
template <class Store>
void read_pair_rows(const Hdf5File& f, const Communicator& comm, Store& store,
                    const std::string& prefix, std::int64_t rows) {
  const std::int64_t first = RowBlocks::block_begin(rows, comm.rank(), comm.size());
  const std::int64_t end = RowBlocks::block_begin(rows, comm.rank() + 1, comm.size());
  const auto n = static_cast<std::size_t>(end - first);
  // Room for what the first distribution brings beyond what leaves, as the particles get
  // (ParticleStore::reserve_share): grown there, a store of springs was copied whole.
  if constexpr (requires { store.reserve(n); })
    store.reserve(comm.size() > 1 ? static_cast<std::size_t>(static_cast<double>(n) *
                                                             ParticleStore::kDistributedHeadroom)
                                  : n);
  store.resize(n);
  store.for_each_field([&](const FieldInfo& field, auto& v) {
    if (!field.has(field_flag::kCheckpoint)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    const std::string name = prefix + std::string(field.name);
    if (field.has(field_flag::kZeroIfAbsent) && !f.exists(name)) {
      std::fill(v.begin(), v.end(), T{});  // written before the field was kept
      return;
    }
    const auto block = read_verified_block<T>(f, comm, name, rows, first, end);
    std::copy(block.begin(), block.end(), v.begin());
  });
}

/// A replicated store's state (brake elements, support ropes: the same on every rank), through
/// its registry as `<group>/<field>`; rank 0's rows land in the file. Only a model that has
/// some writes the group.
template <class Store>
void write_replicated_state(Hdf5File& f, const Communicator& comm, const std::string& group,
                            const Store& store) {
  if (store.empty()) return;
  f.create_group(group);
  store.for_each_field([&](const FieldInfo& field, const auto& rows) {
    if (!field.has(field_flag::kCheckpoint)) return;
    auto mine = rows;
    if (!comm.is_root()) mine.clear();
    write_concatenated(f, comm, group + "/" + std::string(field.name), mine);
  });
}

/// Reads what write_replicated_state() wrote, on every rank, into a store the case built;
/// `what` names the store's rows for the error when the checkpoint lacks them.
template <class Store>
void read_replicated_state(const Hdf5File& f, const Communicator& comm, const std::string& path,
                           const std::string& group, const std::string& what, Store& store) {
  if (store.empty()) return;
  if (!f.exists(group))
    throw Hdf5Error(path + ": the case has " + what + ", the checkpoint has no state for them " +
                    "(written by a case without them)");
  store.for_each_field([&](const FieldInfo& field, auto& v) {
    if (!field.has(field_flag::kCheckpoint)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    // As many rows as the case built (a row per element, or per rope segment).
    const auto n = static_cast<std::int64_t>(v.size());
    v = read_verified_block<T>(f, comm, group + "/" + std::string(field.name), n, 0, n,
                               ReadBy::kEveryRank);
  });
}

}  // namespace ringdem::checkpoint_datasets

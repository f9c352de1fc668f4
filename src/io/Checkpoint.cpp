#include "io/Checkpoint.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <regex>

#include "comm/RowBlocks.hpp"
#include "core/Version.hpp"
#include "domain/PairStore.hpp"
#include "io/CaseText.hpp"
#include "io/CheckpointDatasets.hpp"
#include "io/Hdf5File.hpp"
#include "io/RestartChanges.hpp"

namespace ringdem {

namespace fs = std::filesystem;
using namespace checkpoint_datasets;

namespace {

constexpr const char* kFormat = "ringdem-checkpoint";
// 2: bond columns of unread section values dropped; 3: the case it was written by (/case/text,
// model_fingerprint) and the time-step origin (dt_origin_step, dt_origin_time); 4: what the
// neighbour-list rebuild criterion reads (particles/position_at_rebuild, the bodies' position
// and orientation at the last rebuild, rebuild_forced, bonds_broke); 5: one set of spring
// datasets per contact term (/history/<term>.<field>, its store's registry) instead of one
// table with a partner-kind column; 6: outflow and inflow (outflow_pending, /outflow/totals,
// /inflow/batches, /inflow/next_due, /inflow/totals: the exact totals of what crossed); 7: plastic
// bond hinges in the end frames; 8: the particles' move bound since the last rebuild
// (move_bound) instead of a column of their positions then; 9: the momentum ledger
// (/momentum/state: the exact totals of the impulses and the booked half kick); 10: the energy
// ledger's contact tallies as the exact totals of the ranks' sums (/ledger/state) instead of
// six particle columns (dissipated_damping, dissipated_friction, boundary_work and their last
// powers); 11: the energy the contacts hold as the ranks' exact sums in /ledger/state (held and
// held by leaving grains) instead of two particle columns (tangential_energy, contact_energy);
// 12: the particles' sort bins (/particles/sort_bin, the spatial order of the last re-sort);
// 13: the support ropes' state per segment (/ropes/segment_rest, segment_tension,
// friction_work; work is brake_work); 14: multi-rate stepping, only in a sub-stepped run's file:
// the root attribute substeps, the fast ledgers (/substeps/momentum, /substeps/ledger) and the
// particles' slow_force and slow_torque; 15: a sub-stepped run's grains in contact with the net
// (/particles/net_contact: their interactions are fast; a file of 14 restarts with none, and the
// next check finds them); 16: each particle pair's damping force of its last evaluation
// (/history/<term>.damping: the energy ledger books it again at the next step; a file of 15 or
// older restarts with none, which the ledger of that one step notices, the motion not at all);
// 17: the particles' move bounds relative to a common translation (relative_move_bound) and
// toward each rigid body (/bodies/surface_move_bound; engine/MoveBounds): a file of 16 or older
// restarts with its move_bound for both, which rebuilds no later than needed; 18: each particle
// pair's ledger state without the folded normal (/history/<term>.ledger_load: the damping force
// and the overlap, the normal rebuilt one drift back): a file of 16 or 17 restarts with none, as
// one of 15 does.
// This version, 17, 16, 15, 14, 13, 12 and 11 are read: a file of 11
// restarts every particle at bin 0, the gid order that format's writer kept, and so goes on as its
// run did until the next re-sort; one of 11 or 12 with support ropes is refused (read_checkpoint).
// Older files lack what this one needs to go on bit for bit.
constexpr std::int64_t kFormatVersion = 18;
constexpr std::int64_t kOldestReadFormatVersion = 11;

constexpr const char* kParticlePartner = "particle";
constexpr const char* kBodyPartner = "rigid_body";

/// The dataset of field `field` of a contact term's spring store.
std::string spring_dataset(const std::string& term, std::string_view field) {
  return "/history/" + term + "." + std::string(field);
}

/// The contact terms whose springs a checkpoint holds (the names of its /history/<term>.gid).
std::vector<std::string> spring_terms(const Hdf5File& f) {
  std::vector<std::string> terms;
  if (!f.exists("/history")) return terms;
  for (const std::string& name : f.list("/history"))
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".gid") == 0)
      terms.push_back(name.substr(0, name.size() - 4));
  return terms;
}

std::string join(const std::vector<std::string>& names) {
  std::string s;
  for (const auto& n : names)
    s += (s.empty() ? "" : "\n") + n;
  return s;
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> out;
  std::size_t start = 0;
  while (!s.empty()) {
    const std::size_t end = s.find('\n', start);
    out.push_back(s.substr(start, end - start));
    if (end == std::string::npos) break;
    start = end + 1;
  }
  return out;
}

/// The dynamic state of the rigid bodies, one row per body.
struct BodyRows {
  std::vector<Vec3> position, velocity, omega, force, torque, position_at_rebuild;
  std::vector<Quat> orientation, orientation_at_rebuild;
  std::vector<Motion> motion;  ///< drivers change it (a boulder released)
  /// f(name, rows) for each column.
  template <class F>
  void for_each(F&& f) {
    f("motion", motion);
    f("position", position);
    f("orientation", orientation);
    f("velocity", velocity);
    f("omega", omega);
    f("force", force);
    f("torque", torque);
    f("position_at_rebuild", position_at_rebuild);
    f("orientation_at_rebuild", orientation_at_rebuild);
  }
};

/// The step in a checkpoint's file name, or -1 for a name that is not one of ours (also a
/// number too long for 64 bits: such a file is skipped, never an error).
std::int64_t step_of(const fs::path& p) {
  static const std::regex re(R"(checkpoint_(\d+)\.h5)");
  std::smatch m;
  const std::string name = p.filename().string();
  if (!std::regex_match(name, m, re)) return -1;
  const std::string digits = m[1];
  std::int64_t step = -1;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), step);
  return error == std::errc() && end == digits.data() + digits.size() ? step : -1;
}

}  // namespace

void DriverState::set(const std::string& name, double v) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    names.push_back(name);
    values.push_back(v);
  } else {
    values[static_cast<std::size_t>(it - names.begin())] = v;
  }
}

double DriverState::get(const std::string& name, double fallback) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? fallback : values[static_cast<std::size_t>(it - names.begin())];
}

CheckpointStore::CheckpointStore(std::string dir, int keep) : dir_(std::move(dir)), keep_(keep) {}

std::vector<std::string> CheckpointStore::list() const {
  std::vector<std::pair<std::int64_t, std::string>> found;
  if (fs::is_directory(dir_))
    for (const auto& e : fs::directory_iterator(dir_))
      if (const std::int64_t s = step_of(e.path()); s >= 0)
        found.emplace_back(s, e.path().string());
  std::sort(found.begin(), found.end());
  std::vector<std::string> out;
  for (auto& f : found)
    out.push_back(std::move(f.second));
  return out;
}

std::string CheckpointStore::write(const Communicator& comm, Model& model,
                                   const RestartState& state, const DriverState& driver,
                                   std::int64_t segment, const CaseConfig& config) const {
  const std::string final_path = fmt::format("{}/checkpoint_{:012d}.h5", dir_, state.steps);
  const std::string tmp_path = final_path + ".tmp";
  if (comm.is_root()) fs::create_directories(dir_);
  comm.barrier();
  ParticleStore& p = model.particles;
  const BondStore& bonds = model.bonds;
  std::int64_t my_bonds = 0;
  for (std::size_t k = 0; k < bonds.size(); ++k)
    my_bonds += counted_here(p, bonds, k);
  const std::int64_t n_particles = comm.sum(static_cast<std::int64_t>(p.n_local()));
  const std::int64_t n_bonds = comm.sum(my_bonds);
  {
    Hdf5File f = Hdf5File::create(tmp_path, comm);
    f.set_attribute("/", "format", std::string(kFormat));
    f.set_attribute("/", "format_version", kFormatVersion);
    f.set_attribute("/", "ringdem_version", std::string(kVersion));
    const std::string case_text = canonical_case_text(config);
    f.set_attribute("/", "case", config.name);
    f.set_attribute("/", "model_fingerprint", model_fingerprint(case_text));
    f.set_attribute("/", "time", state.time);
    f.set_attribute("/", "dt", state.dt);
    f.set_attribute("/", "step", state.steps);
    f.set_attribute("/", "rebuilds", state.rebuilds);
    f.set_attribute("/", "dt_origin_step", state.dt_origin_step);
    f.set_attribute("/", "dt_origin_time", state.dt_origin_time);
    f.set_attribute("/", "rebuild_forced", std::int64_t{state.rebuild_forced});
    f.set_attribute("/", "bonds_broke", std::int64_t{state.bonds_broke});
    f.set_attribute("/", "move_bound", state.move_bound);
    f.set_attribute("/", "relative_move_bound", state.relative_move_bound);
    f.set_attribute("/", "segment", segment);
    f.set_attribute("/", "ranks", static_cast<std::int64_t>(comm.size()));
    f.set_attribute("/", "particles", n_particles);
    f.set_attribute("/", "bonds", n_bonds);
    f.set_attribute("/", "bodies", static_cast<std::int64_t>(model.bodies.size()));
    if (state.substepped)
      f.set_attribute("/", "substeps", static_cast<std::int64_t>(config.simulation.substeps));

    f.create_group("/particles");
    const std::vector<std::int64_t> gids(p.gid.begin(),
                                         p.gid.begin() + static_cast<std::ptrdiff_t>(p.n_local()));
    const RowBlocks particle_rows(comm, gids);
    p.for_each_field([&](const FieldInfo& info, const auto& v) {
      if (info.has(field_flag::kCheckpoint))
        write_field(f, comm, particle_rows, "/particles/" + std::string(info.name), v);
    });

    // Term stores (domain/PairStore.hpp), each through its registry: the bonds in bond-id
    // order, each contact term's springs as /history/<term>.<field> with what `partner` names.
    f.create_group("/bonds");
    write_pair_rows(f, comm, p, model.bonds, "/bonds/");
    f.create_group("/history");
    for (const RestartState::TermSprings& t : state.springs) {
      if (t.part) {
        // Every rank the same number of parts (each a collective write), none larger than
        // rows_per_part of the sources it looks through.
        const auto local_parts =
            static_cast<std::int64_t>((t.sources + t.rows_per_part - 1) / t.rows_per_part);
        const auto parts =
            static_cast<std::size_t>(std::max<std::int64_t>(1, comm.max(local_parts)));
        write_rows_in_parts(f, comm, spring_dataset(t.term, ""), t.store, parts, t.part);
      } else {
        write_pair_rows(f, comm, p, t.store, spring_dataset(t.term, ""));
      }
      f.set_attribute(spring_dataset(t.term, "partner"), "names",
                      std::string(t.store.partner_is_particle() ? kParticlePartner : kBodyPartner));
    }

    // Bodies and driver state: the same on every rank; rank 0's rows land in the file.
    f.create_group("/bodies");
    BodyRows body_rows;
    std::vector<std::string> body_names;
    if (state.body_position_at_rebuild.size() != model.bodies.size() ||
        state.body_orientation_at_rebuild.size() != model.bodies.size())
      throw std::logic_error("checkpoint: no rebuild reference for every rigid body");
    body_rows.position_at_rebuild = state.body_position_at_rebuild;
    body_rows.orientation_at_rebuild = state.body_orientation_at_rebuild;
    for (const auto& b : model.bodies) {
      body_names.push_back(b.name);
      body_rows.position.push_back(b.position);
      body_rows.orientation.push_back(b.orientation);
      body_rows.velocity.push_back(b.velocity);
      body_rows.omega.push_back(b.omega);
      body_rows.force.push_back(b.force);
      body_rows.torque.push_back(b.torque);
      body_rows.motion.push_back(b.motion);
    }
    f.set_attribute("/bodies", "names", join(body_names));
    body_rows.for_each([&](const char* name, const auto& rows) {
      auto mine = rows;
      if (!comm.is_root()) mine.clear();
      write_concatenated(f, comm, std::string("/bodies/") + name, mine);
    });
    if (state.surface_move_bound.size() != model.bodies.size())
      throw std::logic_error("checkpoint: no move bound toward every rigid body");
    std::vector<double> surface_move_bound = state.surface_move_bound;
    if (!comm.is_root()) surface_move_bound.clear();
    write_concatenated(f, comm, "/bodies/surface_move_bound", surface_move_bound);
    // Brake elements and support ropes: replicated like the bodies they hold.
    write_replicated_state(f, comm, "/brakes", model.brakes);
    write_replicated_state(f, comm, "/ropes", model.ropes);
    f.set_attribute("/", "outflow_pending", std::int64_t{state.outflow_pending});
    f.create_group("/outflow");
    std::vector<std::int64_t> outflow = state.outflow_totals;  // the same on every rank
    if (!comm.is_root()) outflow.clear();
    write_concatenated(f, comm, "/outflow/totals", outflow);
    f.create_group("/inflow");
    std::vector<std::int64_t> inflow_batches = state.inflow_batches,
                              inflow_totals = state.inflow_totals;
    std::vector<double> inflow_next_due = state.inflow_next_due;
    if (!comm.is_root()) {
      inflow_batches.clear();
      inflow_totals.clear();
      inflow_next_due.clear();
    }
    write_concatenated(f, comm, "/inflow/batches", inflow_batches);
    write_concatenated(f, comm, "/inflow/next_due", inflow_next_due);
    write_concatenated(f, comm, "/inflow/totals", inflow_totals);
    f.create_group("/momentum");
    std::vector<std::int64_t> momentum = state.momentum;  // the same on every rank
    if (!comm.is_root()) momentum.clear();
    write_concatenated(f, comm, "/momentum/state", momentum);
    f.create_group("/ledger");
    std::vector<std::int64_t> ledger = state.energy_ledger;  // the same on every rank
    if (!comm.is_root()) ledger.clear();
    write_concatenated(f, comm, "/ledger/state", ledger);
    if (state.substepped) {
      f.create_group("/substeps");
      std::vector<std::int64_t> fast_momentum = state.fast_momentum;  // the same on every rank
      std::vector<std::int64_t> fast_ledger = state.fast_energy_ledger;
      if (!comm.is_root()) {
        fast_momentum.clear();
        fast_ledger.clear();
      }
      write_concatenated(f, comm, "/substeps/momentum", fast_momentum);
      write_concatenated(f, comm, "/substeps/ledger", fast_ledger);
    }
    f.create_group("/driver");
    f.set_attribute("/driver", "names", join(driver.names));
    std::vector<double> values = driver.values;
    if (!comm.is_root()) values.clear();
    write_concatenated(f, comm, "/driver/values", values);
    f.create_group("/case");
    std::vector<std::uint8_t> text_bytes(case_text.begin(), case_text.end());
    if (!comm.is_root()) text_bytes.clear();
    write_concatenated(f, comm, "/case/text", text_bytes);
    // Written last: a file without it was cut short.
    f.set_attribute("/", "complete", std::int64_t{1});
  }
  comm.barrier();
  if (comm.is_root()) {
    fs::rename(tmp_path, final_path);
    const auto all = list();
    for (std::size_t k = 0; k + static_cast<std::size_t>(keep_) < all.size(); ++k)
      fs::remove(all[k]);
  }
  comm.barrier();
  return final_path;
}

CheckpointInfo read_checkpoint_info(const std::string& path) {
  if (!fs::exists(path)) throw Hdf5Error(path + ": no such checkpoint");
  const Hdf5File f = Hdf5File::open_read(path);
  if (!f.has_attribute("/", "format") || f.attribute_string("/", "format") != kFormat)
    throw Hdf5Error(path + ": not a ringdem checkpoint");
  const std::int64_t version = f.attribute_int("/", "format_version");
  if (version < kOldestReadFormatVersion || version > kFormatVersion)
    throw Hdf5Error(fmt::format(
        "{}: checkpoint format version {} is not one this ringdem reads ({} to {}){}", path,
        version, kOldestReadFormatVersion, kFormatVersion,
        version < kFormatVersion
            ? ": it was written by an older ringdem, whose checkpoints lack what this one needs "
              "to go on bit for bit; continue it with that version or start afresh"
            : ": it was written by a newer ringdem"));
  if (!f.has_attribute("/", "complete"))
    throw Hdf5Error(path + ": incomplete checkpoint (the run stopped while writing it)");
  CheckpointInfo info;
  info.path = path;
  info.format_version = version;
  info.version = f.attribute_string("/", "ringdem_version");
  info.case_name = f.attribute_string("/", "case");
  info.time = f.attribute_double("/", "time");
  info.dt = f.attribute_double("/", "dt");
  info.step = f.attribute_int("/", "step");
  info.rebuilds = f.attribute_int("/", "rebuilds");
  info.segment = f.attribute_int("/", "segment");
  info.ranks = f.attribute_int("/", "ranks");
  info.particles = f.attribute_int("/", "particles");
  info.bonds = f.attribute_int("/", "bonds");
  info.bodies = f.attribute_int("/", "bodies");
  if (f.has_attribute("/", "substeps")) info.substeps = f.attribute_int("/", "substeps");
  for (const std::string& term : spring_terms(f)) {
    const auto d = f.dims(spring_dataset(term, "gid"));
    info.history_entries += d.empty() ? 0 : d[0];
  }
  info.dt_origin_step = f.attribute_int("/", "dt_origin_step");
  info.dt_origin_time = f.attribute_double("/", "dt_origin_time");
  info.model_fingerprint = f.attribute_string("/", "model_fingerprint");
  const auto text = f.read_rows<std::uint8_t>("/case/text");
  if (static_cast<std::uint64_t>(f.attribute_int("/case/text", "checksum")) !=
      rows_checksum(text, 0))
    throw Hdf5Error(path + ": dataset /case/text fails its checksum: the checkpoint is corrupted");
  info.case_text.assign(text.begin(), text.end());
  return info;
}

RestartState read_checkpoint(const Communicator& comm, const std::string& path,
                             const CaseConfig& config, Model& model, DriverState& driver,
                             CheckpointInfo* info_out) {
  const CheckpointInfo info = read_checkpoint_info(path);
  ParticleStore& p = model.particles;
  BondStore& bonds = model.bonds;
  if (p.n_total() != 0 || bonds.size() != 0)
    throw std::logic_error("read_checkpoint: the model must be built without particles");
  // Whose state it is: the fingerprint belongs to the case text it holds, and that case defines
  // the same model as `config`. Not the particle or bond count the case's sources create at
  // start-up: particles come and go during a run (inflow, outflow), so the checkpoint's own
  // counts are the truth, and every dataset is checked against them as it is read.
  if (model_fingerprint(info.case_text) != info.model_fingerprint)
    throw Hdf5Error(path +
                    ": its model fingerprint does not match the case it holds: the checkpoint is "
                    "corrupted");
  const std::string given = canonical_case_text(config);
  if (model_identity(info.case_text) != model_identity(given)) {
    std::string keys;
    for (const CaseChange& c : case_changes(info.case_text, given))
      if (c.rule->kind == RestartKeyKind::kFixed)
        keys += (keys.empty() ? "" : "; ") + describe_change(c);
    throw Hdf5Error(
        fmt::format("{}: it belongs to another case (the model differs: {})", path, keys));
  }
  if (info.bodies != static_cast<std::int64_t>(model.bodies.size()))
    throw Hdf5Error(fmt::format("{}: the checkpoint holds {} rigid bodies, the case builds {}",
                                path, info.bodies, model.bodies.size()));
  const Hdf5File f = Hdf5File::open_parallel_read(path, comm);
  // Each rank reads one block of every table's rows; the first distribution then moves the
  // rows to their owners.
  const auto block_of = [&](std::int64_t n) {
    return std::pair{RowBlocks::block_begin(n, comm.rank(), comm.size()),
                     RowBlocks::block_begin(n, comm.rank() + 1, comm.size())};
  };
  const auto [p_first, p_end] = block_of(info.particles);
  // Damping set while the run went on (Simulation::set_group_damping) is in the file although
  // the case damps nothing: its coefficients and tallies come back (the same on every rank).
  if (f.exists("/particles/damping")) p.set_tracks_damping(true);
  // A sub-stepped run's slow loads of its last grain step.
  if (info.substeps > 1) p.set_tracks_slow_loads(true);
  p.reserve_share(static_cast<std::size_t>(p_end - p_first), comm.size());
  p.resize_local(static_cast<std::size_t>(p_end - p_first));
  p.for_each_field([&](const FieldInfo& field, auto& v) {
    if (!field.has(field_flag::kCheckpoint)) return;
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    const std::string name = "/particles/" + std::string(field.name);
    if (field.has(field_flag::kZeroIfAbsent) && !f.exists(name)) {
      std::fill(v.begin(), v.end(), T{});  // written by a run that did not keep the field
      return;
    }
    auto rows = read_verified_block<T>(f, comm, name, info.particles, p_first, p_end);
    std::copy(rows.begin(), rows.end(), v.begin());
  });
  // Rows in strictly increasing gid order, across the blocks too.
  bool ordered = std::is_sorted(p.gid.begin(), p.gid.end()) &&
                 std::adjacent_find(p.gid.begin(), p.gid.end()) == p.gid.end();
  const std::int64_t my_last = p.gid.empty() ? -1 : p.gid.back();
  const auto lasts = comm.allgather(std::vector<std::int64_t>{my_last});
  for (int r = comm.rank() - 1; r >= 0 && !p.gid.empty(); --r)
    if (lasts[static_cast<std::size_t>(r)] >= 0) {
      ordered = ordered && lasts[static_cast<std::size_t>(r)] < p.gid.front();
      break;
    }
  if (comm.any(!ordered)) throw Hdf5Error(path + ": particle rows are not in gid order");
  p.rebuild_index();

  read_pair_rows(f, comm, bonds, "/bonds/", info.bonds);

  RestartState state;
  state.time = info.time;
  state.dt = info.dt;
  state.steps = info.step;
  state.rebuilds = info.rebuilds;
  state.dt_origin_step = info.dt_origin_step;
  state.dt_origin_time = info.dt_origin_time;
  state.rebuild_forced = f.attribute_int("/", "rebuild_forced") != 0;
  state.bonds_broke = f.attribute_int("/", "bonds_broke") != 0;
  state.move_bound = f.attribute_double("/", "move_bound");
  state.outflow_pending = f.attribute_int("/", "outflow_pending") != 0;
  // Small datasets that every rank reads whole.
  const auto read_whole = [&](const std::string& name, auto* out) {
    using T = typename std::remove_pointer_t<decltype(out)>::value_type;
    const auto d = f.dims(name);
    const std::int64_t n = d.empty() ? 0 : d[0];
    *out = read_verified_block<T>(f, comm, name, n, 0, n, ReadBy::kEveryRank);
  };
  read_whole("/outflow/totals", &state.outflow_totals);
  read_whole("/inflow/batches", &state.inflow_batches);
  read_whole("/inflow/next_due", &state.inflow_next_due);
  read_whole("/inflow/totals", &state.inflow_totals);
  read_whole("/momentum/state", &state.momentum);
  read_whole("/ledger/state", &state.energy_ledger);
  state.substepped = info.substeps > 1;
  if (state.substepped) {
    read_whole("/substeps/momentum", &state.fast_momentum);
    read_whole("/substeps/ledger", &state.fast_energy_ledger);
  }
  for (const std::string& term : spring_terms(f)) {
    const std::string partner = f.attribute_string(spring_dataset(term, "partner"), "names");
    if (partner != kParticlePartner && partner != kBodyPartner)
      throw Hdf5Error(path + ": springs of '" + term + "' name an unknown partner '" + partner +
                      "'");
    RestartState::TermSprings& t = state.springs.emplace_back(RestartState::TermSprings{
        term,
        ContactSpringStore(partner == kParticlePartner ? ContactSpringStore::Partner::kParticle
                                                       : ContactSpringStore::Partner::kRigidBody)});
    const auto d = f.dims(spring_dataset(term, "gid"));
    read_pair_rows(f, comm, t.store, spring_dataset(term, ""), d.empty() ? 0 : d[0]);
  }

  const auto names = split(f.attribute_string("/bodies", "names"));
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (b >= names.size() || names[b] != model.bodies[b].name)
      throw Hdf5Error(path + ": rigid body " + std::to_string(b) + " is '" +
                      (b < names.size() ? names[b] : std::string("?")) + "' in the checkpoint, '" +
                      model.bodies[b].name + "' in the case");
  BodyRows rows;
  const auto n_bodies = static_cast<std::int64_t>(model.bodies.size());
  rows.for_each([&](const char* name, auto& v) {
    using T = typename std::remove_cvref_t<decltype(v)>::value_type;
    v = read_verified_block<T>(f, comm, std::string("/bodies/") + name, n_bodies, 0, n_bodies,
                               ReadBy::kEveryRank);
  });
  state.body_position_at_rebuild = rows.position_at_rebuild;
  state.body_orientation_at_rebuild = rows.orientation_at_rebuild;
  // Format 16 and older bounded the moves by move_bound alone, which bounds the others too.
  if (info.format_version >= 17) {
    state.relative_move_bound = f.attribute_double("/", "relative_move_bound");
    state.surface_move_bound = read_verified_block<double>(
        f, comm, "/bodies/surface_move_bound", n_bodies, 0, n_bodies, ReadBy::kEveryRank);
  } else {
    state.relative_move_bound = state.move_bound;
    state.surface_move_bound.assign(model.bodies.size(), state.move_bound);
  }
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    RigidBody& body = model.bodies[b];
    body.position = rows.position[b];
    body.orientation = rows.orientation[b];
    body.velocity = rows.velocity[b];
    body.omega = rows.omega[b];
    body.force = rows.force[b];
    body.torque = rows.torque[b];
    if (static_cast<int>(rows.motion[b]) > static_cast<int>(Motion::kPrescribed))
      throw Hdf5Error(path + ": invalid rigid-body motion");
    body.motion = rows.motion[b];
  }
  read_replicated_state(f, comm, path, "/brakes", "brake elements on its shackles", model.brakes);
  if (!model.ropes.empty() && info.format_version < 13)
    throw Hdf5Error(fmt::format(
        "{}: checkpoint format version {} holds each support rope's state as one tension, this "
        "ringdem's ropes have one per segment (format 13); continue it with the ringdem that "
        "wrote it or start afresh",
        path, info.format_version));
  read_replicated_state(f, comm, path, "/ropes", "support ropes on its nets", model.ropes);
  driver.names = split(f.attribute_string("/driver", "names"));
  const auto n_values = static_cast<std::int64_t>(driver.names.size());
  driver.values = read_verified_block<double>(f, comm, "/driver/values", n_values, 0, n_values,
                                              ReadBy::kEveryRank);
  if (info_out) *info_out = info;
  return state;
}

std::vector<std::string> verify_checkpoint(const std::string& path) {
  read_checkpoint_info(path);
  const Hdf5File f = Hdf5File::open_read(path);
  std::vector<std::string> checked;
  for (const char* group :
       {"/particles", "/bonds", "/history", "/bodies", "/brakes", "/ropes", "/outflow", "/inflow",
        "/momentum", "/ledger", "/substeps", "/driver", "/case"}) {
    for (const std::string& name : f.list(group)) {
      const std::string full = std::string(group) + "/" + name;
      std::size_t row_bytes = 0;
      const std::vector<char> bytes = f.read_bytes(full, row_bytes);
      const auto stored = static_cast<std::uint64_t>(f.attribute_int(full, "checksum"));
      if (stored != bytes_checksum(bytes, row_bytes))
        throw Hdf5Error(path + ": dataset " + full +
                        " fails its checksum: the checkpoint is corrupted");
      checked.push_back(full);
    }
  }
  return checked;
}

std::string latest_valid_checkpoint(const std::string& dir, std::vector<std::string>* skipped) {
  const auto all = CheckpointStore(dir).list();
  for (auto it = all.rbegin(); it != all.rend(); ++it) {
    try {
      read_checkpoint_info(*it);
      return *it;
    } catch (const Hdf5Error& e) {
      if (skipped) skipped->push_back(e.what());
    }
  }
  return "";
}

}  // namespace ringdem

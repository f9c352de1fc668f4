#include "app/InfoCommand.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "io/CaseText.hpp"
#include "io/Checkpoint.hpp"
#include "io/Hdf5File.hpp"

namespace ringdem {

namespace {

constexpr const char* kDurationForms =
    "give seconds (3600), H:MM:SS (1:00:00) or numbers with units h, m, s (1h30m)";

/// The non-negative number at the start of `s` (from_chars: no sign, no spaces); sets `used`.
/// Throws std::invalid_argument naming the whole `text` when there is none or it is not finite.
double leading_number(std::string_view s, const std::string& text, std::size_t* used) {
  double v = 0.0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec == std::errc::result_out_of_range)
    throw std::invalid_argument("'" + text + "': number out of range");
  if (ec != std::errc() || end == s.data() || !std::isfinite(v) || v < 0.0)
    throw std::invalid_argument("'" + text + "' is not a duration: " + kDurationForms);
  *used = static_cast<std::size_t>(end - s.data());
  return v;
}

}  // namespace

double parse_duration(const std::string& text) {
  if (text.empty()) throw std::invalid_argument(std::string("empty duration: ") + kDurationForms);
  if (text.find(':') != std::string::npos) {
    double total = 0.0;
    std::size_t start = 0;
    int parts = 0;
    while (true) {
      const std::size_t end = text.find(':', start);
      const std::string part = text.substr(start, end - start);
      if (part.empty() || part.find_first_not_of("0123456789.") != std::string::npos)
        throw std::invalid_argument("'" + text + "' is not H:MM:SS");
      std::size_t used = 0;
      total = total * 60.0 + leading_number(part, text, &used);
      if (used != part.size()) throw std::invalid_argument("'" + text + "' is not H:MM:SS");
      ++parts;
      if (end == std::string::npos) break;
      start = end + 1;
    }
    if (parts > 3) throw std::invalid_argument("'" + text + "' is not H:MM:SS");
    return total;
  }
  double total = 0.0;
  std::size_t k = 0;
  while (k < text.size()) {
    std::size_t used = 0;
    const double v = leading_number(std::string_view(text).substr(k), text, &used);
    k += used;
    double unit = 1.0;
    if (k < text.size()) {
      const char c = static_cast<char>(std::tolower(static_cast<unsigned char>(text[k])));
      if (c == 'h')
        unit = 3600.0;
      else if (c == 'm')
        unit = 60.0;
      else if (c == 's')
        unit = 1.0;
      else
        throw std::invalid_argument("'" + text + "': unknown unit '" + text[k] + "' (h, m or s)");
      ++k;
    }
    total += v * unit;
  }
  if (!(total > 0.0) || !std::isfinite(total))
    throw std::invalid_argument("'" + text + "' is not a positive duration");
  return total;
}

namespace {

void print_datasets(const Hdf5File& f, const std::string& group, std::ostream& out) {
  for (const std::string& name : f.list(group)) {
    const std::string full = group + "/" + name;
    std::string shape;
    for (auto d : f.dims(full))
      shape += (shape.empty() ? "" : " x ") + std::to_string(d);
    out << fmt::format("  {:<32} {}\n", full, shape);
  }
}

}  // namespace

int print_file_info(const std::string& path, std::ostream& out) {
  // The .xdmf that ParaView opens is the index of the frame file beside it (the same name with
  // .h5, io/FrameWriter): describe that file rather than call the index "not an HDF5 file".
  const std::filesystem::path as_given(path);
  if (as_given.extension() == ".xdmf") {
    const std::string data = std::filesystem::path(as_given).replace_extension(".h5").string();
    if (!std::filesystem::is_regular_file(data)) {
      std::fprintf(stderr,
                   "ringdem info: %s is ParaView's index of the frame file %s, which is missing\n",
                   path.c_str(), data.c_str());
      return 2;
    }
    out << fmt::format("{}: ParaView's index of the frame file {}\n", path, data);
    return print_file_info(data, out);
  }
  try {
    const Hdf5File f = Hdf5File::open_read(path);
    const std::string format =
        f.has_attribute("/", "format") ? f.attribute_string("/", "format") : std::string("?");
    if (format == "ringdem-checkpoint") {
      const CheckpointInfo info = read_checkpoint_info(path);
      out << fmt::format(
          "{}: ringdem checkpoint (written by ringdem {} on {} rank{})\n"
          "  case {}, t = {:.9g} s, step {}, dt = {:.6g} s{}, {} neighbour rebuilds, frame "
          "segment {}\n"
          "  {} particles, {} bonds, {} rigid bodies, {} contact springs\n"
          "  model fingerprint {} ({} case keys in /case/text)\n",
          path, info.version, info.ranks, info.ranks == 1 ? "" : "s", info.case_name, info.time,
          info.step, info.dt,
          info.substeps > 1 ? fmt::format(" (a grain step of {} sub-steps)", info.substeps) : "",
          info.rebuilds, info.segment, info.particles, info.bonds, info.bodies,
          info.history_entries, info.model_fingerprint, case_text_keys(info.case_text).size());
      const auto checked = verify_checkpoint(path);
      out << fmt::format("  checksums: {} datasets verified\n", checked.size());
      for (const char* g :
           {"/particles", "/bonds", "/history", "/bodies", "/substeps", "/driver", "/case"})
        print_datasets(f, g, out);
      return 0;
    }
    if (format == "ringdem-frames") {
      const auto times = f.read_rows<double>("/frames/time");
      out << fmt::format("{}: ringdem frame file (written by ringdem {} on {} rank{})\n", path,
                         f.attribute_string("/", "ringdem_version"), f.attribute_int("/", "ranks"),
                         f.attribute_int("/", "ranks") == 1 ? "" : "s");
      // Counts that change between frames (inflow, outflow) are given as their range.
      const auto count = [&](const char* name) {
        const std::string full = std::string("/frames/") + name;
        const std::vector<std::int64_t> per_frame =
            f.exists(full) ? f.read_rows<std::int64_t>(full) : std::vector<std::int64_t>{};
        const auto [lo, hi] = std::minmax_element(per_frame.begin(), per_frame.end());
        return per_frame.empty() || *lo == *hi ? fmt::format("{}", f.attribute_int("/", name))
                                               : fmt::format("{}..{}", *lo, *hi);
      };
      out << fmt::format("  {} particles, {} bonds, {} frames", count("particles"), count("bonds"),
                         times.size());
      if (!times.empty())
        out << fmt::format(" from t = {:.6g} s to {:.6g} s", times.front(), times.back());
      out << "\n";
      for (const char* g : {"/frames", "/particles", "/bonds"})
        print_datasets(f, g, out);
      return 0;
    }
    out << path << ": an HDF5 file, but not one ringdem wrote\n";
    return 2;
  } catch (const std::exception& e) {
    out.flush();
    std::fprintf(stderr, "ringdem info: %s\n", e.what());
    return 2;
  }
}

}  // namespace ringdem

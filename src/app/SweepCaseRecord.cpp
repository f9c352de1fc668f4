#include "app/SweepCaseRecord.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "io/ResultsWriter.hpp"

namespace ringdem {

namespace {

const char* const kCaseFile = "/sweep_case.txt";
const char* const kRowFile = "/sweep_row.csv";
const char* const kCaseTextFile = "/sweep_case_resolved.txt";

}  // namespace

int SweepCaseRecord::exit_code() const {
  const std::vector<std::string> names = split_csv_line(header);
  const std::vector<std::string> cells = split_csv_line(values);
  for (std::size_t c = 0; c < names.size(); ++c)
    if (names[c] == "exit_code") {
      try {
        return c < cells.size() ? std::stoi(cells[c]) : kExitCaseNotStarted;
      } catch (const std::exception&) {
        return kExitCaseNotStarted;  // a damaged row is run again
      }
    }
  return 0;
}

SweepCaseRecord read_case_record(const std::string& dir) {
  SweepCaseRecord record;
  if (std::ifstream in(dir + kCaseFile); in) {
    record.overrides.emplace();
    for (std::string line; std::getline(in, line);)
      record.overrides->push_back(line);
  }
  if (std::ifstream in(dir + kCaseTextFile); in) {
    std::ostringstream text;
    text << in.rdbuf();
    record.case_text = text.str();
  }
  if (std::ifstream in(dir + kRowFile); in) {
    std::getline(in, record.header);
    std::getline(in, record.values);
  }
  return record;
}

void write_case_start(const std::string& dir, const std::vector<std::string>& overrides,
                      const std::string& case_text) {
  std::filesystem::create_directories(dir);
  std::ofstream out(dir + kCaseFile);
  for (const std::string& o : overrides)
    out << o << "\n";
  std::ofstream(dir + kCaseTextFile) << case_text;
}

void write_case_row(const std::string& dir, const std::string& header, const std::string& values) {
  std::filesystem::create_directories(dir);
  std::ofstream(dir + kRowFile) << header << "\n" << values << "\n";
}

}  // namespace ringdem

#include "app/CaseClaims.hpp"

#include <sys/stat.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>

namespace ringdem {

CaseClaims::CaseClaims(const std::string& output_dir, std::size_t case_count,
                       const Communicator& world, std::size_t first_case)
    : folder_(output_dir + "/" + kFolderName), case_count_(case_count), own_first_(first_case) {
  std::string error;
  if (world.is_root()) {
    std::error_code ec;
    std::filesystem::remove_all(folder_, ec);  // an earlier study's, killed before its end
    std::filesystem::create_directories(folder_, ec);
    if (ec) error = "cannot create " + folder_ + ": " + ec.message();
  }
  // Every rank throws, so that none waits in a collective the others never reach.
  if (world.any(!error.empty()))
    throw std::runtime_error(error.empty() ? "the root rank could not create " + folder_ : error);
}

bool CaseClaims::claim(std::size_t k) {
  const std::string path = folder_ + "/" + std::to_string(k);
  if (::mkdir(path.c_str(), 0755) == 0) return true;
  if (errno == EEXIST) return false;
  throw std::runtime_error("cannot claim a case in " + folder_ + ": " + std::strerror(errno));
}

std::optional<std::size_t> CaseClaims::next() {
  if (!asked_own_) {
    asked_own_ = true;
    if (own_first_ < case_count_ && claim(own_first_)) return own_first_;
  }
  while (next_lowest_ < case_count_) {
    const std::size_t k = next_lowest_++;
    if (claim(k)) return k;
  }
  return std::nullopt;
}

void CaseClaims::close(const Communicator& world) {
  world.barrier();  // every rank has had its last answer from next()
  if (world.is_root()) {
    std::error_code ec;
    std::filesystem::remove_all(folder_, ec);  // a leftover is cleared by the next study
  }
}

}  // namespace ringdem

#pragma once

/// Which rank runs which case of a parameter study: the next case goes to the first rank that
/// comes free, so that a study whose cases differ in length keeps every rank busy to its end
/// (a fixed deal, case i on rank i mod N, left ranks idle behind one long case).
///
/// A claim is a folder made with mkdir(2), which succeeds for one caller only, on local file
/// systems and on the shared ones of clusters (NFS, Lustre, GPFS) alike. The study's output folder
/// is shared by its ranks already (rank 0 joins the rows the others write), so no rank has to
/// serve the others and no MPI call waits on a busy one.

#include <cstddef>
#include <optional>
#include <string>

#include "comm/Communicator.hpp"

namespace ringdem {

class CaseClaims {
 public:
  /// The folder under a study's output folder that holds the claims.
  static constexpr const char* kFolderName = ".sweep_claims";

  /// A fresh set of claims on `case_count` cases in `output_dir`/kFolderName: the root rank
  /// removes what an earlier study left there (a killed one) and every rank waits for it, so
  /// collective over `world`. The caller holds the folder's output lock, so no other study
  /// claims there at the same time. `first_case`: the case this rank asks for first (its own
  /// number, or its group's), so that the first round needs no contest.
  CaseClaims(const std::string& output_dir, std::size_t case_count, const Communicator& world,
             std::size_t first_case);

  /// The next case this rank runs, or nothing when every case is taken: first_case, then the
  /// lowest case not yet taken.
  std::optional<std::size_t> next();

  /// Collective: when every rank has asked for its last case, the root rank removes the claims.
  void close(const Communicator& world);

 private:
  /// Whether case k was claimed by this rank now: true for one caller only (throws
  /// std::runtime_error when the folder cannot be written).
  bool claim(std::size_t k);

  std::string folder_;
  std::size_t case_count_ = 0;
  std::size_t own_first_ = 0;  ///< the case of this rank's number, asked for first
  bool asked_own_ = false;
  std::size_t next_lowest_ = 0;  ///< every case below it is taken
};

}  // namespace ringdem

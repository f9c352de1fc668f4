// The process's operator new advises large blocks as transparent huge pages
// (core/HugePageAdvice.cpp). The kernel's own record is the oracle: /proc/self/smaps lists the
// mapping that holds a block with the flag "hg" (VM_HUGEPAGE) where madvise(MADV_HUGEPAGE) was
// applied to it.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "core/HugePageAdvice.hpp"

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ringdem {
namespace {

/// The VmFlags of the mapping of /proc/self/smaps that holds `address`, or "" where none does.
std::string vm_flags_at(const void* address) {
  const auto a = reinterpret_cast<std::uintptr_t>(address);
  std::ifstream smaps("/proc/self/smaps");
  std::string line;
  bool inside = false;
  while (std::getline(smaps, line)) {
    unsigned long long begin = 0, end = 0;
    if (std::sscanf(line.c_str(), "%llx-%llx ", &begin, &end) == 2 && line.find('-') < 17) {
      inside = a >= begin && a < end;
      continue;
    }
    if (inside && line.rfind("VmFlags:", 0) == 0) return line.substr(8);
  }
  return "";
}

bool has_flag(const std::string& flags, const std::string& flag) {
  std::istringstream words(flags);
  std::string w;
  while (words >> w)
    if (w == flag) return true;
  return false;
}

bool kernel_has_huge_pages() {
  return static_cast<bool>(std::ifstream("/sys/kernel/mm/transparent_hugepage/enabled"));
}

/// Whether this process was started with the advice turned off (the ctest entry
/// HugePageAdvice.OffInTheEnvironment sets RINGDEM_HUGE_PAGES=off), read here from the
/// environment itself, not from the code under test.
bool started_with_advice_off() {
  const char* value = std::getenv("RINGDEM_HUGE_PAGES");
  return value != nullptr && std::string(value) == "off";
}

TEST(HugePageAdvice, ALargeVectorsPagesAreAdvisedAsHugePages) {
  if (!huge_page_advice_built()) GTEST_SKIP() << "this build keeps the default operator new";
  if (started_with_advice_off()) GTEST_SKIP() << "the advice is off in this process";
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  // 16 MiB, well above kAdviseFrom: at least six whole 2 MiB pages lie inside it.
  std::vector<double> column(std::size_t{2} << 20, 1.0);
  const void* middle = column.data() + column.size() / 2;
  const std::string flags = vm_flags_at(middle);
  ASSERT_FALSE(flags.empty()) << "no mapping in /proc/self/smaps holds the vector";
  EXPECT_TRUE(has_flag(flags, "hg")) << "VmFlags:" << flags;
}

TEST(HugePageAdvice, AnAlignedLargeBlockIsAdvisedToo) {
  if (!huge_page_advice_built()) GTEST_SKIP() << "this build keeps the default operator new";
  if (started_with_advice_off()) GTEST_SKIP() << "the advice is off in this process";
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  struct alignas(64) Line {
    double v[8];
  };
  // The aligned operator new (a cache-line type, as the ledger's entries are).
  const auto lines = std::make_unique<Line[]>(std::size_t{1} << 18);  // 16 MiB
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(lines.get()) % 64, 0u);
  EXPECT_TRUE(has_flag(vm_flags_at(lines.get() + (std::size_t{1} << 17)), "hg"));
}

// Columns from kAlignFrom bytes on start on a cache line, whatever malloc would have given
// (16 bytes past a page for the mmap'd ones), so that the passes' vector loads do not span two
// lines; with the advice on or off. Sizes about the threshold and well above it (mmap'd).
TEST(HugePageAdvice, ALargeBlockStartsOnACacheLine) {
  if (!huge_page_advice_built()) GTEST_SKIP() << "this build keeps the default operator new";
  for (const std::size_t bytes :
       {kAlignFrom, kAlignFrom + 8, std::size_t{100} << 10, std::size_t{3} << 20}) {
    // Several at once, so that they do not all take the same freed block.
    std::vector<std::vector<double>> columns;
    for (int copy = 0; copy < 4; ++copy) {
      columns.emplace_back(bytes / sizeof(double), 1.0);
      EXPECT_EQ(reinterpret_cast<std::uintptr_t>(columns.back().data()) % kCacheLine, 0u)
          << bytes << " bytes, copy " << copy;
    }
  }
  // A type that asks for more than a cache line still gets its own alignment.
  struct alignas(256) Wide {
    double v[32];
  };
  const auto wide = std::make_unique<Wide[]>(64);
  EXPECT_EQ(reinterpret_cast<std::uintptr_t>(wide.get()) % 256, 0u);
}

TEST(HugePageAdvice, ABlockBelowTheThresholdIsLeftAlone) {
  // Advised by hand, a block under kAdviseFrom changes nothing; the whole mapping is advised.
#if defined(__linux__)
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  if (started_with_advice_off()) GTEST_SKIP() << "the advice is off in this process";
  // A block just under the threshold, in a fresh mapping (so that nothing else advised it)
  // of twice the threshold: its first whole 2 MiB page lies inside the small block too.
  const std::size_t mapped = 2 * kAdviseFrom;
  void* block = mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  ASSERT_NE(block, MAP_FAILED);
  const auto first_page =
      (reinterpret_cast<std::uintptr_t>(block) + kHugePage - 1) & ~(kHugePage - 1);
  const void* first_huge = reinterpret_cast<const void*>(first_page);
  ASSERT_LE(first_page + kHugePage, reinterpret_cast<std::uintptr_t>(block) + kAdviseFrom - 4096);
  advise_huge_pages(block, kAdviseFrom - 4096);
  EXPECT_FALSE(has_flag(vm_flags_at(first_huge), "hg"));
  advise_huge_pages(block, mapped);
  EXPECT_TRUE(has_flag(vm_flags_at(first_huge), "hg"));
  munmap(block, mapped);
#else
  GTEST_SKIP() << "Linux only";
#endif
}

// Run by its own ctest entry with RINGDEM_HUGE_PAGES=off (tests/CMakeLists.txt); skipped
// elsewhere. A large vector and a large aligned block must not be advised, and the process says
// so.
TEST(HugePageAdvice, OffInTheEnvironmentLeavesLargeBlocksAlone) {
  if (!started_with_advice_off()) GTEST_SKIP() << "run with RINGDEM_HUGE_PAGES=off";
  if (!huge_page_advice_built()) GTEST_SKIP() << "this build keeps the default operator new";
  if (!kernel_has_huge_pages()) GTEST_SKIP() << "no transparent huge pages in this kernel";
  EXPECT_FALSE(huge_page_advice_on());
  std::vector<double> column(std::size_t{2} << 20, 1.0);  // 16 MiB
  const std::string flags = vm_flags_at(column.data() + column.size() / 2);
  ASSERT_FALSE(flags.empty()) << "no mapping in /proc/self/smaps holds the vector";
  EXPECT_FALSE(has_flag(flags, "hg")) << "VmFlags:" << flags;
  struct alignas(64) Line {
    double v[8];
  };
  const auto lines = std::make_unique<Line[]>(std::size_t{1} << 18);  // 16 MiB
  EXPECT_FALSE(has_flag(vm_flags_at(lines.get() + (std::size_t{1} << 17)), "hg"));
}

}  // namespace
}  // namespace ringdem

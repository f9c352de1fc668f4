#pragma once

#include <cstddef>

namespace ringdem {

/// The size of a transparent huge page on x86-64 and most Linux targets.
inline constexpr std::size_t kHugePage = std::size_t{2} << 20;
/// Blocks of at least this many bytes are advised as huge pages by the process's operator new
/// (core/HugePageAdvice.cpp): the columns and lists of large models, not the many small
/// objects.
inline constexpr std::size_t kAdviseFrom = std::size_t{4} << 20;

/// Blocks of at least this many bytes start on a cache line (kCacheLine), from the process's
/// operator new: malloc starts a large block 16 bytes past a page, so that every 64-byte load
/// of the passes' eight lanes, and a third of their 32-byte ones, spanned two cache lines.
inline constexpr std::size_t kCacheLine = 64;
inline constexpr std::size_t kAlignFrom = std::size_t{4} << 10;
/// The environment variable that turns the advice off for a process: "off" or "0". A node
/// whose memory is fragmented may compact it synchronously when an advised block first
/// faults in (the kernel's defrag setting "madvise"); there a user trades the rebuilds' gain
/// for steady steps.
inline constexpr const char* kHugePagesVariable = "RINGDEM_HUGE_PAGES";

/// Advises the kernel to back the 2 MiB-aligned pages wholly inside [block, block + bytes) with
/// transparent huge pages, where `bytes` >= kAdviseFrom (smaller blocks are left alone) and
/// huge_page_advice_on(). Changes no value; a kernel without transparent huge pages ignores it.
void advise_huge_pages(void* block, std::size_t bytes);

/// Whether this build's operator new advises large blocks (Linux, and not under
/// AddressSanitizer, whose own operators stay).
bool huge_page_advice_built();

/// Whether this process advises: not turned off by kHugePagesVariable, read once at the first
/// call (the first large allocation).
bool huge_page_advice_on();

}  // namespace ringdem

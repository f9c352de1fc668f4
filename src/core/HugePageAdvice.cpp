// The process's operator new and delete: large blocks are advised to the kernel as transparent
// huge pages (madvise MADV_HUGEPAGE) and start on a cache line, everything else is plain
// malloc and free.
//
// Why: at 10^6 grains a rank's columns and lists are tens of MB each, and the neighbour rebuild
// gives its scratch back and takes it again (docs/performance.md, fifteenth round: that keeps a
// packing under 400 bytes a grain). On 4 KiB pages each rebuild faulted every page in afresh
// (the kernel's page faults were a third of a 10^6-grain flow's rebuild time), and the pair
// loop's far ends missed the TLB across a 24 MB position column. Where the kernel's
// transparent huge pages are "madvise" (the Debian default) nothing else would use them; with
// "always" the advice changes nothing, with "never" it is ignored. The advice changes no value:
// the same bits with it or without (docs/performance.md, twenty-ninth round).
//
// RINGDEM_HUGE_PAGES=off (or 0) in the environment turns the advice off for the process
// (core/HugePageAdvice.hpp, docs/parallel.md).
//
// Only blocks of kAdviseFrom bytes or more are advised, and only the 2 MiB-aligned pages that
// lie wholly inside the block, so that no huge page reaches beyond memory the caller asked for.
// Under AddressSanitizer its own operators stay (it checks that new pairs with delete).
#include "core/HugePageAdvice.hpp"

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace ringdem {

bool huge_page_advice_built() {
#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)
  return true;
#else
  return false;
#endif
}

bool huge_page_advice_on() {
  // getenv allocates nothing, so operator new may ask it; the guarded static neither.
  static const bool on = [] {
    const char* value = std::getenv(kHugePagesVariable);
    return value == nullptr || (std::strcmp(value, "off") != 0 && std::strcmp(value, "0") != 0);
  }();
  return on;
}

void advise_huge_pages(void* block, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  if (block == nullptr || bytes < kAdviseFrom || !huge_page_advice_on()) return;
  const auto begin = reinterpret_cast<std::uintptr_t>(block);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  // A refusal (no transparent huge pages in this kernel) leaves the block as it is.
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)block;
  (void)bytes;
#endif
}

}  // namespace ringdem

#if defined(__linux__) && !defined(__SANITIZE_ADDRESS__)

namespace {

// The allocation loop of [new.delete.single]: call the new-handler until it gives memory or
// there is none.
void* allocate(std::size_t bytes, std::size_t alignment) {
  if (bytes == 0) bytes = 1;
  for (;;) {
    void* block = nullptr;
    // A large block on a cache line (core/HugePageAdvice.hpp, kAlignFrom): the columns the
    // vector passes read.
    if (alignment <= alignof(std::max_align_t) && bytes >= ringdem::kAlignFrom)
      alignment = ringdem::kCacheLine;
    if (alignment <= alignof(std::max_align_t)) {
      block = std::malloc(bytes);
    } else {
      // aligned_alloc wants a multiple of the alignment.
      block = std::aligned_alloc(alignment, (bytes + alignment - 1) / alignment * alignment);
    }
    if (block != nullptr) {
      ringdem::advise_huge_pages(block, bytes);
      return block;
    }
    const std::new_handler handler = std::get_new_handler();
    if (handler == nullptr) throw std::bad_alloc();
    handler();
  }
}

void* allocate_nothrow(std::size_t bytes, std::size_t alignment) noexcept {
  try {
    return allocate(bytes, alignment);
  } catch (...) {
    return nullptr;
  }
}

std::size_t alignment_of(std::align_val_t alignment) {
  return static_cast<std::size_t>(alignment);
}

}  // namespace

void* operator new(std::size_t bytes) {
  return allocate(bytes, 0);
}
void* operator new[](std::size_t bytes) {
  return allocate(bytes, 0);
}
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept {
  return allocate_nothrow(bytes, 0);
}
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept {
  return allocate_nothrow(bytes, 0);
}
void* operator new(std::size_t bytes, std::align_val_t alignment) {
  return allocate(bytes, alignment_of(alignment));
}
void* operator new[](std::size_t bytes, std::align_val_t alignment) {
  return allocate(bytes, alignment_of(alignment));
}
void* operator new(std::size_t bytes, std::align_val_t alignment, const std::nothrow_t&) noexcept {
  return allocate_nothrow(bytes, alignment_of(alignment));
}
void* operator new[](std::size_t bytes, std::align_val_t alignment,
                     const std::nothrow_t&) noexcept {
  return allocate_nothrow(bytes, alignment_of(alignment));
}

// Every block above came from malloc or aligned_alloc: free gives each back.
void operator delete(void* block) noexcept {
  std::free(block);
}
void operator delete[](void* block) noexcept {
  std::free(block);
}
void operator delete(void* block, std::size_t) noexcept {
  std::free(block);
}
void operator delete[](void* block, std::size_t) noexcept {
  std::free(block);
}
void operator delete(void* block, const std::nothrow_t&) noexcept {
  std::free(block);
}
void operator delete[](void* block, const std::nothrow_t&) noexcept {
  std::free(block);
}
void operator delete(void* block, std::align_val_t) noexcept {
  std::free(block);
}
void operator delete[](void* block, std::align_val_t) noexcept {
  std::free(block);
}
void operator delete(void* block, std::size_t, std::align_val_t) noexcept {
  std::free(block);
}
void operator delete[](void* block, std::size_t, std::align_val_t) noexcept {
  std::free(block);
}
void operator delete(void* block, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(block);
}
void operator delete[](void* block, std::align_val_t, const std::nothrow_t&) noexcept {
  std::free(block);
}

#endif

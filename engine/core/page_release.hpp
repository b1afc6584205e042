#pragma once
// Hands the memory pages of an array back to the operating system while the
// array stays allocated, so that two large arrays that hold the same data in
// turn (one is copied into the other, piece by piece) need not both be
// resident at the peak. Only whole pages inside the range are released; what
// they held reads as zero afterwards (Linux), or is kept where the system
// offers no such call, so a caller must treat the range as garbage until it
// writes it again.

#include <cstddef>
#include <cstdint>
#include <vector>

#if __has_include(<sys/mman.h>) && __has_include(<unistd.h>)
#include <sys/mman.h>
#include <unistd.h>
#define GRANFLOW_HAS_MADVISE 1
#endif
#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace granflow {

inline void release_pages(const void* begin, std::size_t bytes) {
#if defined(GRANFLOW_HAS_MADVISE) && defined(MADV_DONTNEED)
  static const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  if (page == 0 || bytes < page) return;
  const auto first = (reinterpret_cast<std::uintptr_t>(begin) + page - 1) / page * page;
  const auto last = (reinterpret_cast<std::uintptr_t>(begin) + bytes) / page * page;
  // A refusal only leaves the pages resident: nothing to report.
  if (last > first) (void)madvise(reinterpret_cast<void*>(first), last - first, MADV_DONTNEED);
#else
  (void)begin;
  (void)bytes;
#endif
}

template <class T>
void release_pages(const std::vector<T>& values) {
  release_pages(values.data(), values.size() * sizeof(T));
}

// Returns the pages of freed heap memory to the system. Large temporaries
// (a sort's keys, a permutation's copy of a column) are freed into the heap
// rather than unmapped once glibc has raised its mmap threshold, and would
// otherwise stay resident after the step that needed them.
inline void return_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

}  // namespace granflow

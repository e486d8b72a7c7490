// An allocator for the OT solver's largest arrays (the grid LU's factors and fronts, hundreds of MB at
// n = 1024). Two things the default allocator does that cost there:
// - std::vector value-initialises what it grows into, so the kernel zeroes each fresh page and then the
//   library zeroes it again; BigBufferAllocator default-initialises (no zeroing) instead;
// - every fresh 4 KiB page is a separate fault, and faults are expensive in a VM (at n = 1024 a solve took
//   hundreds of thousands of them, and their system time was a sizeable share of its wall time;
//   docs/ot_solver.md, "What the figures say"). Blocks of 2 MiB and more are therefore 2 MiB-aligned
//   and advised as transparent huge pages (madvise(MADV_HUGEPAGE); Debian's default THP mode honours it).
//   Where the kernel has no huge page to give, the advice is ignored and nothing else changes.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>
#include <utility>
#include <sys/mman.h>
#include <vector>

namespace iblx {

template <typename T>
struct BigBufferAllocator {
  using value_type = T;

  BigBufferAllocator() = default;
  template <typename U>
  BigBufferAllocator(const BigBufferAllocator<U>&) noexcept {}

  T* allocate(std::size_t count) {
    constexpr std::size_t kHugePage = std::size_t(2) << 20;
    const std::size_t bytes = count * sizeof(T);
    if (bytes < kHugePage) {
      if (void* p = std::malloc(bytes > 0 ? bytes : 1)) return static_cast<T*>(p);
      throw std::bad_alloc();
    }
    const std::size_t rounded = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // advice only: failure leaves ordinary pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }

  // Default-initialisation: growing a vector of numbers leaves the new entries unwritten.
  template <typename U>
  void construct(U* p) noexcept {
    ::new (static_cast<void*>(p)) U;
  }
  template <typename U, typename... Args>
  void construct(U* p, Args&&... args) {
    ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }

  template <typename U>
  bool operator==(const BigBufferAllocator<U>&) const noexcept {
    return true;
  }
};

// A vector whose growth does not zero its new entries (resize(n) leaves them indeterminate: write before
// reading), on huge pages when large.
template <typename T>
using BigBuffer = std::vector<T, BigBufferAllocator<T>>;

}  // namespace iblx

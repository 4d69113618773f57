#pragma once
// An allocator for large tables read at random (environment-map sampling tables, the visible-
// normal tables of tabulated NDFs): blocks of 1 MB and more are placed on 2 MB boundaries and the
// kernel is asked for transparent huge pages there (madvise; the advice may be ignored). With
// 4 KB pages nearly every random read of a table of tens of megabytes also misses the TLB.

#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace microbrdf::detail {

/// Asks the kernel for transparent huge pages on [p, p + bytes) (advice only: where it is not
/// offered, the memory keeps ordinary pages).
inline void advise_huge_pages(void* p, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  (void)madvise(p, bytes, MADV_HUGEPAGE);
#else
  (void)p;
  (void)bytes;
#endif
}

/// Blocks under 1 MB: plain operator new.
template <class T>
struct HugePageAllocator {
  using value_type = T;
  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}
  static constexpr std::size_t kHuge = std::size_t(2) << 20;
  T* allocate(std::size_t n) {
    const std::size_t bytes = n * sizeof(T);
    if (bytes < (std::size_t(1) << 20)) return static_cast<T*>(::operator new(bytes));
    const std::size_t rounded = (bytes + kHuge - 1) / kHuge * kHuge;
    void* p = std::aligned_alloc(kHuge, rounded);
    if (!p) throw std::bad_alloc();
    advise_huge_pages(p, rounded);
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < (std::size_t(1) << 20))
      ::operator delete(p);
    else
      std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
};

}  // namespace microbrdf::detail

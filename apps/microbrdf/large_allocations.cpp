// Large blocks on transparent huge pages, for the whole command-line program.
//
// A run touches a few large arrays once each (the scan's heights, the 1025^2 tables, the FFT
// buffers), and with 4 KB pages most of its system time goes to page faults on them: on a
// 1280 x 960 scan about 17 000 faults, a third of a naive NDF run. The replaceable global
// operator new below places blocks of 4 MB and more on 2 MB boundaries and asks the kernel for
// huge pages there (madvise; advice only, the kernel may keep small pages), so the same memory
// takes about 512 times fewer faults. Smaller blocks, and every block of the library used from
// Python or another program, keep the ordinary allocator. Blocks are released with free(),
// which takes both kinds.
#include <sys/mman.h>

#include <cstddef>
#include <cstdlib>
#include <new>

namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kLarge = std::size_t{4} << 20;

void* allocate(std::size_t bytes) {
  if (bytes >= kLarge) {
    // Huge pages for the whole 2 MB pages of the block only: a huge page over the last partial
    // one would count up to 2 MB that nothing uses in the resident set (4.3 MB over the four
    // large arrays of a 640 x 480 D_K table); the tail keeps 4 KB pages.
    void* p = nullptr;
    if (posix_memalign(&p, kHugePage, bytes) == 0) {
#ifdef MADV_HUGEPAGE
      if (const std::size_t whole = bytes / kHugePage * kHugePage; whole > 0)
        (void)madvise(p, whole, MADV_HUGEPAGE);
#endif
      return p;
    }
  } else if (void* p = std::malloc(bytes == 0 ? 1 : bytes)) {
    return p;
  }
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t bytes) { return allocate(bytes); }
void* operator new[](std::size_t bytes) { return allocate(bytes); }
void* operator new(std::size_t bytes, const std::nothrow_t&) noexcept {
  try {
    return allocate(bytes);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t bytes, const std::nothrow_t&) noexcept {
  try {
    return allocate(bytes);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }

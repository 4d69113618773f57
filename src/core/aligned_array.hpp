#pragma once
// A 64-byte aligned array of trivially copyable T without a page-touching constructor, reused
// as scratch across calls (SIMD loads, FFTW plans made on one buffer and run on another of the
// same alignment: FFTW's estimated plans depend on the alignment they were made for).

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>

#include "core/huge_page_allocator.hpp"

namespace microbrdf::detail {

/// 64-byte aligned, uninitialised array of trivially copyable T (no page-touching constructor);
/// arrays of 4 MiB and more are aligned to 2 MiB and advised to use huge pages.
template <class T>
class AlignedArray {
 public:
  AlignedArray() = default;
  explicit AlignedArray(std::size_t n) { resize(n); }
  /// Capacity at least n; the contents are kept only when no reallocation is needed.
  void resize(std::size_t n) {
    if (n <= cap_) {
      n_ = n;
      return;
    }
    constexpr std::size_t kHuge = std::size_t{2} << 20;
    const bool huge = n * sizeof(T) >= 2 * kHuge;
    const std::size_t align = huge ? kHuge : 64;
    const std::size_t bytes =
        std::max<std::size_t>((n * sizeof(T) + align - 1) / align * align, 64);
    p_.reset(static_cast<T*>(std::aligned_alloc(align, bytes)));
    if (!p_) throw std::bad_alloc();
    if (huge) advise_huge_pages(p_.get(), bytes);
    cap_ = n_ = n;
  }
  /// Grow-only scratch use: capacity at least n, then the data (contents not kept on growth).
  T* get(std::size_t n) {
    resize(n);
    return data();
  }
  T* data() { return p_.get(); }
  const T* data() const { return p_.get(); }
  T& operator[](std::size_t i) { return p_[i]; }
  const T& operator[](std::size_t i) const { return p_[i]; }
  std::size_t size() const { return n_; }

 private:
  struct Free {
    void operator()(T* p) const { std::free(p); }
  };
  std::unique_ptr<T[], Free> p_;
  std::size_t n_ = 0, cap_ = 0;
};

}  // namespace microbrdf::detail

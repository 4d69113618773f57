#pragma once
// Internal to the fast Kirchhoff table (kirchhoff_fast.cpp): one axis of its separable transform
//   X_v[k] = sum_{j<n} x_v[j] exp(-i (w0 + k dw) j),  k < m,
// for V vectors at a time (vector v's inputs at in[v * in_stride() + position(j)]), by a type-2
// NUFFT (inputs times a factor, one FFT of length L >= 2n, K-tap kernel-weighted sums of the
// bins) or by a chirp-z transform (inputs times the pre-chirp, FFT of length L >= n + m - 1,
// product with the chirp's spectrum, inverse FFT). Both are the sums above up to a factor per
// output k of modulus 1 (NUFFT: exp(-i w_k c), the shift to the centre sample; chirp-z: the
// post-chirp), common to every vector and every input array that reaches an output, so that
// D_K = |I|^2 never needs it: it is dropped.
//
// The setup (factors, bin positions, kernel weights, FFTW plans made with FFTW_ESTIMATE, one
// thread, so that results depend on nothing but the inputs) is made once per parameter set and
// shared: axis() returns a cached, read-only object that any number of threads may execute
// concurrently, each with its own Scratch (FFTW's new-array execute).
#include <algorithm>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <new>
#include <vector>

#include "core/aligned_array.hpp"

namespace microbrdf::detail {

using cd = std::complex<double>;

/// Gauss-Legendre nodes and weights on [0, 1].
void gauss_legendre01(std::size_t n, std::vector<double>& x, std::vector<double>& w);

class KirchhoffAxis {
 public:
  enum class Kind { Nufft, ChirpZ };
  /// The cached setup for these parameters (made on first use; thread-safe). `taps` is used by
  /// the NUFFT only.
  static std::shared_ptr<const KirchhoffAxis> get(Kind kind, std::size_t n, std::size_t m,
                                                  double w0, double dw, int taps,
                                                  std::size_t vectors);
  /// NUFFT taps K for a relative tolerance eps (about 10^(1-K) <= eps), clamped to [4, 16].
  static int taps_for(double eps);
  ~KirchhoffAxis();
  KirchhoffAxis(const KirchhoffAxis&) = delete;
  KirchhoffAxis& operator=(const KirchhoffAxis&) = delete;

  /// A thread's buffers for this axis: `in` (V vectors of in_stride(), zero except where inputs
  /// go: fill those n x V entries every time) and `out` (the bins after run(), V vectors of
  /// out_stride()).
  struct Scratch {
    AlignedArray<cd> in, out;
    std::uint64_t ready_for = 0;  // id() of the axis the buffers are laid out for
  };
  /// Lays `s` out for this axis if it is not already (zeroes `in`).
  void prepare(Scratch& s) const;
  /// in -> out: the FFT(s) of all V vectors; afterwards output k of vector v is
  /// sum_{t<K} weight(k)[t] out[v out_stride() + start(k) + t] (K = taps(), even: the last
  /// weight may be 0).
  void run(Scratch& s) const;

  Kind kind() const { return kind_; }
  std::size_t n() const { return n_; }
  std::size_t m() const { return m_; }
  std::size_t vectors() const { return v_; }
  std::size_t taps() const { return k_; }
  std::size_t in_stride() const { return ldi_; }
  std::size_t out_stride() const { return ldo_; }
  /// Factor by which input j is multiplied before it is stored at position(j).
  cd factor(std::size_t j) const { return factor_[j]; }
  std::size_t position(std::size_t j) const { return pos_[j]; }
  std::size_t start(std::size_t k) const { return start_[k]; }
  const double* weight(std::size_t k) const { return &weight_[k * k_]; }
  const std::size_t* positions() const { return pos_.data(); }
  const std::size_t* starts() const { return start_.data(); }
  const double* weights() const { return weight_.data(); }  ///< m x K
  std::uint64_t id() const { return id_; }

 private:
  KirchhoffAxis() = default;
  Kind kind_ = Kind::Nufft;
  std::size_t n_ = 0, m_ = 0, l_ = 0, k_ = 1, v_ = 1, ldi_ = 0, ldo_ = 0;
  double w0_ = 0, dw_ = 0;
  int taps_ = 0;  // as asked (the key); k_ is it rounded up to even
  std::vector<cd> factor_;
  std::vector<std::size_t> pos_, start_;
  std::vector<double> weight_;
  std::vector<cd> kernel_;  // chirp-z: spectrum of the chirp, per bin
  void* fwd_ = nullptr;     // fftw_plan, out-of-place in -> out
  void* inv_ = nullptr;     // chirp-z: in place on out
  std::uint64_t id_ = 0;
};

}  // namespace microbrdf::detail

#pragma once
// Thin RAII layer over FFTW for the 2-D real transforms microbrdf needs (ACF, PSD, generators).
// Threads: FFTW's own (fftw_plan_with_nthreads), initialised once. Planning uses FFTW_ESTIMATE
// so results are deterministic and planning costs nothing.

#include <complex>
#include <cstddef>
#include <mutex>
#include <vector>

namespace microbrdf::detail {

/// FFTW's planner is not thread-safe: code outside fft.cpp that makes or destroys FFTW plans does
/// so while holding this lock (taking it also initialises FFTW's threads, once).
std::unique_lock<std::mutex> fftw_planner_lock();

/// Forward 2-D real-to-complex FFT of an ny x nx row-major array. Output has ny x (nx/2+1)
/// complex values (FFTW's half-spectrum layout). Unnormalised.
std::vector<std::complex<double>> fft2_r2c(std::size_t nx, std::size_t ny,
                                           const std::vector<double>& in);

/// Inverse of fft2_r2c: ny x (nx/2+1) half spectrum -> ny x nx real. Unnormalised (the result is
/// nx*ny times the input of the forward transform).
std::vector<double> fft2_c2r(std::size_t nx, std::size_t ny, std::vector<std::complex<double>> in);

/// Angular frequency (rad per sample) of FFT bin i of n: 2*pi*i/n folded to [-pi, pi).
double fft_freq(std::size_t i, std::size_t n);

/// A size >= n that FFTW transforms fast (product of 2, 3, 5, 7).
std::size_t fft_good_size(std::size_t n);
/// A size >= n that is a product of 2, 3 and 5 only (FFTW's fastest codelets).
std::size_t fft_good_size_235(std::size_t n);

/// In-place forward complex 2-D FFT of an ny x nx row-major array with the plan made once
/// (FFTW_ESTIMATE, threads as for the other transforms): the reference cost in the benchmarks.
class Fft2c {
 public:
  Fft2c(std::size_t nx, std::size_t ny);
  ~Fft2c();
  Fft2c(const Fft2c&) = delete;
  Fft2c& operator=(const Fft2c&) = delete;
  std::vector<std::complex<double>>& data() { return data_; }
  void execute();

 private:
  std::vector<std::complex<double>> data_;
  void* plan_ = nullptr;
};

/// Batched 1-D chirp-z (zoom) transform with plans made once and reused (Bluestein):
///   X_b[k] = sum_{j<n} x_b[j] exp(-i (w0 + k dw) j),   k = 0..m-1,  b = 0..batch-1,
/// i.e. the DTFT of each input vector at m equispaced angular frequencies (rad per sample) of
/// any spacing -- exactly, not interpolated. Cost: two complex FFTs of length L >= n + m - 1 per
/// vector (the chirp's spectrum is computed once). Not thread-safe per object (one work buffer).
/// `measure`: plan with FFTW_MEASURE (faster transforms; planning takes a moment the first time a
/// size is seen in the process, FFTW's wisdom makes later plans of that size cheap).
class ChirpZ {
 public:
  ChirpZ(std::size_t n, std::size_t m, double w0, double dw, std::size_t batch,
         bool measure = false);
  ~ChirpZ();
  ChirpZ(const ChirpZ&) = delete;
  ChirpZ& operator=(const ChirpZ&) = delete;

  /// Input element (b, j) is read from in[b * b_stride + j * j_stride]; output (b, k) is written
  /// to out[b * ob + k * ok] (ob = 0 means m).
  void execute(const std::complex<double>* in, std::size_t b_stride, std::size_t j_stride,
               std::complex<double>* out, std::size_t ob = 0, std::size_t ok = 1);
  std::size_t fft_length() const { return l_; }
  std::size_t batch() const { return batch_; }

 private:
  std::size_t n_, m_, batch_, l_;
  std::vector<std::complex<double>> pre_;     // exp(-i (w0 j + dw j^2 / 2)), j < n
  std::vector<std::complex<double>> post_;    // exp(-i dw k^2 / 2) / L, k < m
  std::vector<std::complex<double>> kernel_;  // FFT of exp(+i dw r^2 / 2), r = -(n-1)..m-1
  std::vector<std::complex<double>> work_;    // batch x L
  void* fwd_ = nullptr;                       // fftw_plan
  void* inv_ = nullptr;
};

/// The same sums as ChirpZ, X_b[k] = sum_{j<n} x_b[j] exp(-i (w0 + k dw) j), to a tolerance,
/// by a non-uniform FFT (type 2 in the usual naming: uniform samples, arbitrary frequencies):
/// the inputs are divided by the kernel's Fourier transform, zero-padded to M = good(2n), one
/// FFT of length M per vector, and each output is the K-tap kernel-weighted sum of the M bins
/// around its frequency. Kernel: exp(beta (sqrt(1 - (2u/K)^2) - 1)), |u| <= K/2 bins, beta =
/// 2.30 K ("exponential of semicircle", Barnett, Magland & af Klinteberg 2019); the relative
/// error (to sum |x|) is about 10^(1-K). One FFT of length ~2n instead of two of length n + m.
class ZoomNufft {
 public:
  /// `taps` K in [2, 16].
  ZoomNufft(std::size_t n, std::size_t m, double w0, double dw, std::size_t batch, int taps,
            bool measure = false);
  ~ZoomNufft();
  ZoomNufft(const ZoomNufft&) = delete;
  ZoomNufft& operator=(const ZoomNufft&) = delete;
  /// Same input conventions as ChirpZ::execute; output (b, k) goes to out[b * ob + k * ok]
  /// (ob = m, ok = 1 by default; ob = 1, ok = batch writes the transpose).
  void execute(const std::complex<double>* in, std::size_t b_stride, std::size_t j_stride,
               std::complex<double>* out, std::size_t ob = 0, std::size_t ok = 1);
  std::size_t fft_length() const { return l_; }
  /// Taps for a relative tolerance eps (about 10^(1-K) <= eps), clamped to [4, 16].
  static int taps_for(double eps);

 private:
  std::size_t n_, m_, batch_, l_;
  int taps_;
  std::ptrdiff_t centre_;
  std::vector<double> deconv_;               // 1 / Phi(2 pi (j - c) / M), j < n
  std::vector<std::ptrdiff_t> start_;        // first bin of output k (may be negative)
  std::vector<double> weight_;               // m x K kernel weights
  std::vector<std::complex<double>> phase_;  // exp(-i w_k c)
  std::size_t ld_;                           // row distance in work_ (M + 4: no 4 KiB aliasing)
  std::vector<std::complex<double>> work_;   // batch x ld_
  void* fwd_ = nullptr;
};

}  // namespace microbrdf::detail

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

/// Circular autocorrelation sums in place (Wiener-Khinchin): `buf` holds a real ny x nx array
/// in rows of stride 2 (nx/2 + 1) (FFTW's in-place padding); on return it holds
/// sum_p a(p) a(p + l) at lag l (indices modulo nx, ny), same layout. One buffer, two transforms.
void autocorrelation_sums_inplace(std::size_t nx, std::size_t ny, std::vector<double>& buf);

/// Inverse of fft2_r2c: ny x (nx/2+1) half spectrum -> ny x nx real. Unnormalised (the result is
/// nx*ny times the input of the forward transform).
std::vector<double> fft2_c2r(std::size_t nx, std::size_t ny, std::vector<std::complex<double>> in);

/// Angular frequency (rad per sample) of FFT bin i of n: 2*pi*i/n folded to [-pi, pi).
double fft_freq(std::size_t i, std::size_t n);

/// A size >= n that FFTW transforms fast (product of 2, 3, 5, 7).
std::size_t fft_good_size(std::size_t n);

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

}  // namespace microbrdf::detail

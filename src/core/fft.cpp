#include "core/fft.hpp"

#include <fftw3.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <stdexcept>

namespace microbrdf::detail {
namespace {

// FFTW's planner is not thread-safe; plans are made under this lock.
std::mutex g_plan_mutex;

void init_threads_once() {
  static bool done = [] {
    fftw_init_threads();
    return true;
  }();
  (void)done;
}

struct Plan {
  fftw_plan p = nullptr;
  ~Plan() {
    if (p) {
      std::lock_guard<std::mutex> lock(g_plan_mutex);
      fftw_destroy_plan(p);
    }
  }
};

}  // namespace

std::unique_lock<std::mutex> fftw_planner_lock() {
  std::unique_lock<std::mutex> lock(g_plan_mutex);
  init_threads_once();
  return lock;
}

std::vector<std::complex<double>> fft2_r2c(std::size_t nx, std::size_t ny,
                                           const std::vector<double>& in) {
  if (in.size() != nx * ny) throw std::invalid_argument("fft2_r2c: size mismatch");
  std::vector<double> work(in);  // FFTW_ESTIMATE does not overwrite, but r2c may use the input
  std::vector<std::complex<double>> out(ny * (nx / 2 + 1));
  Plan plan;
  {
    std::lock_guard<std::mutex> lock(g_plan_mutex);
    init_threads_once();
    fftw_plan_with_nthreads(omp_get_max_threads());
    plan.p = fftw_plan_dft_r2c_2d(static_cast<int>(ny), static_cast<int>(nx), work.data(),
                                  reinterpret_cast<fftw_complex*>(out.data()), FFTW_ESTIMATE);
  }
  if (!plan.p) throw std::runtime_error("FFTW could not plan a transform");
  fftw_execute(plan.p);
  return out;
}

void autocorrelation_sums_inplace(std::size_t nx, std::size_t ny, std::vector<double>& buf) {
  const std::size_t hx = nx / 2 + 1;
  if (buf.size() != ny * 2 * hx) throw std::invalid_argument("autocorrelation_sums: size mismatch");
  auto* spec = reinterpret_cast<fftw_complex*>(buf.data());
  Plan fwd, inv;
  {
    std::lock_guard<std::mutex> lock(g_plan_mutex);
    init_threads_once();
    fftw_plan_with_nthreads(omp_get_max_threads());
    fwd.p = fftw_plan_dft_r2c_2d(static_cast<int>(ny), static_cast<int>(nx), buf.data(), spec,
                                 FFTW_ESTIMATE);
    inv.p = fftw_plan_dft_c2r_2d(static_cast<int>(ny), static_cast<int>(nx), spec, buf.data(),
                                 FFTW_ESTIMATE);
  }
  if (!fwd.p || !inv.p) throw std::runtime_error("FFTW could not plan a transform");
  fftw_execute(fwd.p);
  // |A|^2 / (nx ny): the unnormalised inverse then gives the sums themselves.
  const double scale = 1.0 / static_cast<double>(nx * ny);
  for (std::size_t i = 0; i < ny * hx; ++i) {
    spec[i][0] = (spec[i][0] * spec[i][0] + spec[i][1] * spec[i][1]) * scale;
    spec[i][1] = 0;
  }
  fftw_execute(inv.p);
}

std::vector<double> fft2_c2r(std::size_t nx, std::size_t ny, std::vector<std::complex<double>> in) {
  if (in.size() != ny * (nx / 2 + 1)) throw std::invalid_argument("fft2_c2r: size mismatch");
  std::vector<double> out(nx * ny);
  Plan plan;
  {
    std::lock_guard<std::mutex> lock(g_plan_mutex);
    init_threads_once();
    fftw_plan_with_nthreads(omp_get_max_threads());
    plan.p =
        fftw_plan_dft_c2r_2d(static_cast<int>(ny), static_cast<int>(nx),
                             reinterpret_cast<fftw_complex*>(in.data()), out.data(), FFTW_ESTIMATE);
  }
  if (!plan.p) throw std::runtime_error("FFTW could not plan a transform");
  fftw_execute(plan.p);
  return out;
}

double fft_freq(std::size_t i, std::size_t n) {
  double k =
      (i <= n / 2) ? static_cast<double>(i) : static_cast<double>(i) - static_cast<double>(n);
  if (n % 2 == 0 && i == n / 2) k = -static_cast<double>(n) / 2;
  return 2.0 * M_PI * k / static_cast<double>(n);
}

std::size_t fft_good_size(std::size_t n) {
  for (std::size_t m = std::max<std::size_t>(n, 1);; ++m) {
    std::size_t r = m;
    for (std::size_t p : {2, 3, 5, 7})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

Fft2c::Fft2c(std::size_t nx, std::size_t ny) : data_(nx * ny) {
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  init_threads_once();
  fftw_plan_with_nthreads(omp_get_max_threads());
  auto* d = reinterpret_cast<fftw_complex*>(data_.data());
  plan_ = fftw_plan_dft_2d(static_cast<int>(ny), static_cast<int>(nx), d, d, FFTW_FORWARD,
                           FFTW_ESTIMATE);
  if (!plan_) throw std::runtime_error("FFTW could not plan a transform");
}

Fft2c::~Fft2c() {
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  if (plan_) fftw_destroy_plan(static_cast<fftw_plan>(plan_));
}

void Fft2c::execute() { fftw_execute(static_cast<fftw_plan>(plan_)); }

}  // namespace microbrdf::detail

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

namespace {

// exp(-i phase) for phase = a * j^2 / 2 with j^2 reduced exactly before the multiplication, so
// the argument stays accurate for long transforms.
std::complex<double> chirp(double a, std::size_t j) {
  double ph = a * 0.5 * static_cast<double>(j) * static_cast<double>(j);
  return std::polar(1.0, -ph);
}

}  // namespace

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

std::size_t fft_good_size_235(std::size_t n) {
  for (std::size_t m = std::max<std::size_t>(n, 1);; ++m) {
    std::size_t r = m;
    for (std::size_t p : {2, 3, 5})
      while (r % p == 0) r /= p;
    if (r == 1) return m;
  }
}

ChirpZ::ChirpZ(std::size_t n, std::size_t m, double w0, double dw, std::size_t batch, bool measure)
    : n_(n), m_(m), batch_(batch), l_(fft_good_size_235(n + m - 1)) {
  if (n == 0 || m == 0 || batch == 0) throw std::invalid_argument("ChirpZ: empty transform");
  pre_.resize(n);
  for (std::size_t j = 0; j < n; ++j)
    pre_[j] = std::polar(1.0, -w0 * static_cast<double>(j)) * chirp(dw, j);
  post_.resize(m);
  for (std::size_t k = 0; k < m; ++k) post_[k] = chirp(dw, k) / static_cast<double>(l_);
  // Kernel b[r] = exp(+i dw r^2 / 2) for r = -(n-1)..(m-1), stored circularly (r < 0 at L + r).
  kernel_.assign(l_, {0.0, 0.0});
  for (std::size_t r = 0; r < m; ++r) kernel_[r] = std::conj(chirp(dw, r));
  for (std::size_t r = 1; r < n; ++r) kernel_[l_ - r] = std::conj(chirp(dw, r));
  work_.assign(batch * l_, {0.0, 0.0});
  const int len = static_cast<int>(l_);
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  init_threads_once();
  fftw_plan_with_nthreads(batch * l_ > (1u << 18) ? omp_get_max_threads() : 1);
  fftw_plan kp = fftw_plan_dft_1d(len, reinterpret_cast<fftw_complex*>(kernel_.data()),
                                  reinterpret_cast<fftw_complex*>(kernel_.data()), FFTW_FORWARD,
                                  FFTW_ESTIMATE);
  if (!kp) throw std::runtime_error("FFTW could not plan a transform");
  fftw_execute(kp);
  fftw_destroy_plan(kp);
  auto* w = reinterpret_cast<fftw_complex*>(work_.data());
  const unsigned flags = measure ? FFTW_MEASURE : FFTW_ESTIMATE;
  fwd_ = fftw_plan_many_dft(1, &len, static_cast<int>(batch), w, nullptr, 1, len, w, nullptr, 1,
                            len, FFTW_FORWARD, flags);
  inv_ = fftw_plan_many_dft(1, &len, static_cast<int>(batch), w, nullptr, 1, len, w, nullptr, 1,
                            len, FFTW_BACKWARD, flags);
  if (!fwd_ || !inv_) throw std::runtime_error("FFTW could not plan a transform");
}

ChirpZ::~ChirpZ() {
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  if (fwd_) fftw_destroy_plan(static_cast<fftw_plan>(fwd_));
  if (inv_) fftw_destroy_plan(static_cast<fftw_plan>(inv_));
}

void ChirpZ::execute(const std::complex<double>* in, std::size_t b_stride, std::size_t j_stride,
                     std::complex<double>* out, std::size_t ob, std::size_t ok) {
  const std::size_t n = n_, m = m_, l = l_;
  if (ob == 0) ob = m;
  const bool big = batch_ * l > (1u << 18);  // threads only pay off on large batches
  // Complex products written out (std::complex's operator* checks for NaN/Inf per product).
  auto mul = [](std::complex<double> a, std::complex<double> b) {
    return std::complex<double>(a.real() * b.real() - a.imag() * b.imag(),
                                a.real() * b.imag() + a.imag() * b.real());
  };
  // Gather with pre-chirp; blocks of 8 vectors so strided (column) reads share cache lines.
  constexpr std::size_t kBlock = 8;
  const std::size_t nblocks = (batch_ + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) if (big)
  for (std::size_t blk = 0; blk < nblocks; ++blk) {
    const std::size_t b0 = blk * kBlock, b1 = std::min(batch_, b0 + kBlock);
    for (std::size_t j = 0; j < n; ++j) {
      const std::complex<double> c = pre_[j];
      for (std::size_t b = b0; b < b1; ++b)
        work_[b * l + j] = mul(in[b * b_stride + j * j_stride], c);
    }
    for (std::size_t b = b0; b < b1; ++b)
      std::fill(work_.begin() + static_cast<std::ptrdiff_t>(b * l + n),
                work_.begin() + static_cast<std::ptrdiff_t>((b + 1) * l),
                std::complex<double>(0.0, 0.0));
  }
  fftw_execute(static_cast<fftw_plan>(fwd_));
#pragma omp parallel for schedule(static) if (big)
  for (std::size_t b = 0; b < batch_; ++b) {
    std::complex<double>* w = work_.data() + b * l;
    for (std::size_t r = 0; r < l; ++r) w[r] = mul(w[r], kernel_[r]);
  }
  fftw_execute(static_cast<fftw_plan>(inv_));
#pragma omp parallel for schedule(static) if (big)
  for (std::size_t b = 0; b < batch_; ++b) {
    const std::complex<double>* w = work_.data() + b * l;
    std::complex<double>* y = out + b * ob;
    for (std::size_t k = 0; k < m; ++k) y[k * ok] = mul(w[k], post_[k]);
  }
}

int ZoomNufft::taps_for(double eps) {
  if (!(eps > 0)) return 16;
  int k = static_cast<int>(std::ceil(-std::log10(eps))) + 1;
  return std::clamp(k, 4, 16);
}

ZoomNufft::ZoomNufft(std::size_t n, std::size_t m, double w0, double dw, std::size_t batch,
                     int taps, bool measure)
    : n_(n), m_(m), batch_(batch), l_(fft_good_size_235(2 * n)), taps_(taps) {
  if (n == 0 || m == 0 || batch == 0) throw std::invalid_argument("ZoomNufft: empty transform");
  if (taps < 2 || taps > 16) throw std::invalid_argument("ZoomNufft: taps must be in [2, 16]");
  const double K = taps, beta = 2.30 * K, M = static_cast<double>(l_);
  auto kernel = [&](double u) {  // u in bins
    double x = 2 * u / K;
    return std::fabs(x) >= 1 ? 0.0 : std::exp(beta * (std::sqrt(1 - x * x) - 1));
  };
  centre_ = static_cast<std::ptrdiff_t>(n / 2);
  // Phi(s) = integral kernel(u) exp(i u s) du = 2 int_0^{K/2} kernel(u) cos(u s) du, by
  // Gauss-Legendre on [0, K/2] (the kernel is smooth inside; 200 nodes are ample).
  const int nq = 200;
  std::vector<double> gx(nq), gw(nq);
  for (int i = 0; i < (nq + 1) / 2; ++i) {  // Legendre nodes by Newton
    double z = std::cos(M_PI * (i + 0.75) / (nq + 0.5)), pp = 0;
    for (int it = 0; it < 100; ++it) {
      double p1 = 1, p2 = 0;
      for (int j = 1; j <= nq; ++j) {
        double p3 = p2;
        p2 = p1;
        p1 = ((2.0 * j - 1) * z * p2 - (j - 1.0) * p3) / j;
      }
      pp = nq * (z * p1 - p2) / (z * z - 1);
      double dz = p1 / pp;
      z -= dz;
      if (std::fabs(dz) < 1e-15) break;
    }
    gx[i] = -z;
    gx[nq - 1 - i] = z;
    gw[i] = gw[nq - 1 - i] = 2 / ((1 - z * z) * pp * pp);
  }
  deconv_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    double s = 2 * M_PI * static_cast<double>(static_cast<std::ptrdiff_t>(j) - centre_) / M;
    double phi = 0;
    for (int q = 0; q < nq; ++q) {
      double u = 0.25 * K * (gx[q] + 1);  // [0, K/2]
      phi += gw[q] * 0.25 * K * kernel(u) * std::cos(u * s);
    }
    deconv_[j] = 1 / (2 * phi);
  }
  start_.resize(m);
  weight_.resize(m * static_cast<std::size_t>(taps));
  phase_.resize(m);
  for (std::size_t k = 0; k < m; ++k) {
    double w = w0 + dw * static_cast<double>(k);
    double u = w * M / (2 * M_PI);  // position in bins
    auto l0 = static_cast<std::ptrdiff_t>(std::ceil(u - K / 2));
    start_[k] = l0;
    for (int t = 0; t < taps; ++t)
      weight_[k * static_cast<std::size_t>(taps) + static_cast<std::size_t>(t)] =
          kernel(u - static_cast<double>(l0 + t));
    phase_[k] = std::polar(1.0, -w * static_cast<double>(centre_));
  }
  ld_ = l_ + 4;
  work_.assign(batch * ld_, {0.0, 0.0});
  const int len = static_cast<int>(l_), dist = static_cast<int>(ld_);
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  init_threads_once();
  fftw_plan_with_nthreads(batch * l_ > (1u << 18) ? omp_get_max_threads() : 1);
  auto* wp = reinterpret_cast<fftw_complex*>(work_.data());
  fwd_ = fftw_plan_many_dft(1, &len, static_cast<int>(batch), wp, nullptr, 1, dist, wp, nullptr, 1,
                            dist, FFTW_FORWARD, measure ? FFTW_MEASURE : FFTW_ESTIMATE);
  if (!fwd_) throw std::runtime_error("FFTW could not plan a transform");
}

ZoomNufft::~ZoomNufft() {
  std::lock_guard<std::mutex> lock(g_plan_mutex);
  if (fwd_) fftw_destroy_plan(static_cast<fftw_plan>(fwd_));
}

void ZoomNufft::execute(const std::complex<double>* in, std::size_t b_stride, std::size_t j_stride,
                        std::complex<double>* out, std::size_t ob, std::size_t ok) {
  const std::size_t n = n_, m = m_, l = ld_, K = static_cast<std::size_t>(taps_);
  if (ob == 0) ob = m;
  const std::ptrdiff_t L = static_cast<std::ptrdiff_t>(l_), c = centre_;
  const bool big = batch_ * l > (1u << 18);  // threads only pay off on large batches
  // Blocks of 8 vectors: strided reads and transposed writes then share cache lines.
  constexpr std::size_t kBlock = 8;
  const std::size_t nblocks = (batch_ + kBlock - 1) / kBlock;
#pragma omp parallel for schedule(static) if (big)
  for (std::size_t blk = 0; blk < nblocks; ++blk) {
    const std::size_t b0 = blk * kBlock, b1 = std::min(batch_, b0 + kBlock);
    // Samples j sit at offset j - c, stored circularly: [0, n - c) and [L - c, L); zero between.
    for (std::size_t b = b0; b < b1; ++b)
      std::fill(
          work_.begin() + static_cast<std::ptrdiff_t>(b * l) + (static_cast<std::ptrdiff_t>(n) - c),
          work_.begin() + static_cast<std::ptrdiff_t>(b * l) + (L - c),
          std::complex<double>(0.0, 0.0));
    for (std::size_t j = 0; j < n; ++j) {
      std::ptrdiff_t pos = static_cast<std::ptrdiff_t>(j) - c;
      if (pos < 0) pos += L;
      const double d = deconv_[j];
      const std::complex<double>* src = in + j * j_stride;
      std::complex<double>* dst = work_.data() + static_cast<std::size_t>(pos);
      for (std::size_t b = b0; b < b1; ++b) dst[b * l] = src[b * b_stride] * d;
    }
  }
  fftw_execute(static_cast<fftw_plan>(fwd_));
#pragma omp parallel for schedule(static) if (big)
  for (std::size_t blk = 0; blk < nblocks; ++blk) {
    const std::size_t b0 = blk * kBlock, b1 = std::min(batch_, b0 + kBlock);
    for (std::size_t k = 0; k < m; ++k) {
      const double* wk = &weight_[k * K];
      std::ptrdiff_t l0 = start_[k] % L;
      if (l0 < 0) l0 += L;
      const bool wraps = l0 + static_cast<std::ptrdiff_t>(K) > L;
      const std::complex<double> p = phase_[k];
      for (std::size_t b = b0; b < b1; ++b) {
        const std::complex<double>* g = work_.data() + b * l;
        double re = 0, im = 0;
        if (!wraps) {
          const std::complex<double>* gg = g + l0;
          for (std::size_t t = 0; t < K; ++t) {
            re += wk[t] * gg[t].real();
            im += wk[t] * gg[t].imag();
          }
        } else {
          for (std::size_t t = 0; t < K; ++t) {
            std::ptrdiff_t idx = (l0 + static_cast<std::ptrdiff_t>(t)) % L;
            re += wk[t] * g[idx].real();
            im += wk[t] * g[idx].imag();
          }
        }
        out[b * ob + k * ok] = {re * p.real() - im * p.imag(), re * p.imag() + im * p.real()};
      }
    }
  }
}

}  // namespace microbrdf::detail

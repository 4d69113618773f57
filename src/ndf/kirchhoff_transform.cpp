#include "ndf/kirchhoff_transform.hpp"

#include <fftw3.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <mutex>
#include <stdexcept>
#include <utility>

#include "core/fft.hpp"

namespace microbrdf::detail {

void gauss_legendre01(std::size_t n, std::vector<double>& x, std::vector<double>& w) {
  x.assign(n, 0.0);
  w.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double t = std::cos(M_PI * (static_cast<double>(i) + 0.75) / (static_cast<double>(n) + 0.5));
    double dp = 1;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = t;  // P_0, P_1
      for (std::size_t k = 2; k <= n; ++k) {
        const double p2 =
            ((2.0 * static_cast<double>(k) - 1) * t * p1 - (static_cast<double>(k) - 1) * p0) /
            static_cast<double>(k);
        p0 = p1;
        p1 = p2;
      }
      dp = static_cast<double>(n) * (t * p1 - p0) / (t * t - 1);
      const double dt = p1 / dp;
      t -= dt;
      if (std::fabs(dt) < 1e-16) break;
    }
    x[i] = 0.5 * (1 - t);
    w[i] = 1.0 / ((1 - t * t) * dp * dp);  // 2 / ((1 - t^2) P_n'^2), halved for [0, 1]
  }
}

namespace {

struct Cache {
  std::mutex m;
  std::vector<std::shared_ptr<const KirchhoffAxis>> axes;  // most recent last
};

// Never destroyed: the FFTW plans it holds outlive every static whose destructor could use them.
Cache& cache() {
  static auto* c = new Cache;
  return *c;
}

std::atomic<std::uint64_t> g_next_id{1};

// FFT length for at least n points: the cheapest of the smallest 2^a, 5 2^a and 3 2^a, weighted
// by their cost per point under FFTW_ESTIMATE plans (measured: 1.40, 1.47 and 1.99 ns at
// lengths 1024, 1280 and 1536; other 2,3,5-smooth lengths such as 972 or 1152 cost 3.2-3.5 ns).
std::size_t fft_length(std::size_t n) {
  std::size_t best = 0;
  double best_cost = 0;
  const std::pair<std::size_t, double> forms[] = {{1, 1.0}, {5, 1.05}, {3, 1.4}};
  for (const auto& [f, w] : forms) {
    std::size_t l = f;
    while (l < n) l *= 2;
    const double cost = w * static_cast<double>(l);
    if (best == 0 || cost < best_cost) {
      best = l;
      best_cost = cost;
    }
  }
  return best;
}

// exp(-i a j^2 / 2) with j^2 formed exactly before the multiplication.
cd chirp(double a, std::size_t j) {
  return std::polar(1.0, -a * 0.5 * static_cast<double>(j) * static_cast<double>(j));
}

}  // namespace

std::shared_ptr<const KirchhoffAxis> KirchhoffAxis::get(Kind kind, std::size_t n, std::size_t m,
                                                        double w0, double dw, int taps,
                                                        std::size_t vectors) {
  if (n == 0 || m == 0 || vectors == 0) throw std::invalid_argument("KirchhoffAxis: empty");
  if (kind == Kind::Nufft && (taps < 2 || taps > 16))
    throw std::invalid_argument("KirchhoffAxis: taps must be in [2, 16]");
  struct Key {
    Kind kind;
    std::size_t n, m, v;
    double w0, dw;
    int taps;
  };
  const Key key{kind, n, m, vectors, w0, dw, kind == Kind::Nufft ? taps : 1};
  Cache& c = cache();
  std::lock_guard<std::mutex> lock(c.m);
  for (std::size_t i = 0; i < c.axes.size(); ++i) {
    const auto& a = *c.axes[i];
    if (a.kind_ == key.kind && a.n_ == key.n && a.m_ == key.m && a.v_ == key.v && a.w0_ == key.w0 &&
        a.dw_ == key.dw && a.taps_ == key.taps) {
      auto hit = c.axes[i];
      c.axes.erase(c.axes.begin() + static_cast<std::ptrdiff_t>(i));
      c.axes.push_back(hit);
      return hit;
    }
  }

  std::shared_ptr<KirchhoffAxis> a(new KirchhoffAxis);
  a->kind_ = kind;
  a->n_ = n;
  a->m_ = m;
  a->v_ = vectors;
  a->w0_ = w0;
  a->dw_ = dw;
  a->taps_ = key.taps;
  a->id_ = g_next_id.fetch_add(1);
  a->factor_.resize(n);
  a->pos_.resize(n);
  a->start_.resize(m);
  if (kind == Kind::Nufft) {
    a->l_ = fft_length(2 * n);
    a->k_ = static_cast<std::size_t>(taps + (taps & 1));  // even: pairs of taps in the sums
    const double K = taps, beta = 2.30 * K, M = static_cast<double>(a->l_);
    auto kernel = [&](double u) {  // u in bins
      const double x = 2 * u / K;
      return std::fabs(x) >= 1 ? 0.0 : std::exp(beta * (std::sqrt(1 - x * x) - 1));
    };
    // Phi(s) = 2 int_0^{K/2} kernel(u) cos(u s) du by Gauss-Legendre (200 nodes are ample).
    std::vector<double> gx, gw;
    gauss_legendre01(200, gx, gw);
    const auto centre = static_cast<std::ptrdiff_t>(n / 2);
    const auto L = static_cast<std::ptrdiff_t>(a->l_);
    for (std::size_t j = 0; j < n; ++j) {
      const std::ptrdiff_t off = static_cast<std::ptrdiff_t>(j) - centre;
      const double s = 2 * M_PI * static_cast<double>(off) / M;
      double phi = 0;
      for (std::size_t q = 0; q < gx.size(); ++q) {
        const double u = 0.5 * K * gx[q];
        phi += gw[q] * 0.5 * K * kernel(u) * std::cos(u * s);
      }
      a->factor_[j] = 1 / (2 * phi);
      a->pos_[j] = static_cast<std::size_t>(off < 0 ? off + L : off);
    }
    a->weight_.resize(m * a->k_);
    for (std::size_t k = 0; k < m; ++k) {
      const double u = (w0 + dw * static_cast<double>(k)) * M / (2 * M_PI);  // in bins
      const auto l0 = static_cast<std::ptrdiff_t>(std::ceil(u - K / 2));
      for (std::size_t t = 0; t < a->k_; ++t)
        a->weight_[k * a->k_ + t] = t < static_cast<std::size_t>(taps)
                                        ? kernel(u - static_cast<double>(l0 + static_cast<long>(t)))
                                        : 0.0;
      std::ptrdiff_t st = l0 % L;
      if (st < 0) st += L;
      a->start_[k] = static_cast<std::size_t>(st);
    }
  } else {
    a->l_ = fft_length(n + m - 1);
    a->k_ = 2;  // the output itself and a zero weight (pairs of taps in the sums)
    for (std::size_t j = 0; j < n; ++j) {
      a->factor_[j] = std::polar(1.0, -w0 * static_cast<double>(j)) * chirp(dw, j);
      a->pos_[j] = j;
    }
    for (std::size_t k = 0; k < m; ++k) a->start_[k] = k;
    a->weight_.assign(2 * m, 0.0);
    for (std::size_t k = 0; k < m; ++k) a->weight_[2 * k] = 1.0;
    a->kernel_.assign(a->l_, cd(0, 0));
    for (std::size_t r = 0; r < m; ++r) a->kernel_[r] = std::conj(chirp(dw, r));
    for (std::size_t r = 1; r < n; ++r) a->kernel_[a->l_ - r] = std::conj(chirp(dw, r));
  }

  // Vector strides: a multiple of four (64-byte aligned vectors) beyond L (+ the K bins copied
  // from the start for the NUFFT's sums).
  a->ldi_ = (a->l_ + 3) / 4 * 4 + 4;
  a->ldo_ = (a->l_ + a->k_ + 3) / 4 * 4 + 4;
  const int len = static_cast<int>(a->l_), v = static_cast<int>(vectors);
  const int di = static_cast<int>(a->ldi_), dout = static_cast<int>(a->ldo_);
  AlignedArray<cd> in(a->ldi_ * vectors), out(a->ldo_ * vectors);
  {
    auto plock = fftw_planner_lock();
    fftw_plan_with_nthreads(1);
    if (kind == Kind::ChirpZ) {
      auto* kp = reinterpret_cast<fftw_complex*>(a->kernel_.data());
      fftw_plan p = fftw_plan_dft_1d(len, kp, kp, FFTW_FORWARD, FFTW_ESTIMATE);
      if (!p) throw std::runtime_error("FFTW could not plan a transform");
      fftw_execute(p);
      fftw_destroy_plan(p);
      for (auto& z : a->kernel_) z /= static_cast<double>(a->l_);
    }
    auto* ip = reinterpret_cast<fftw_complex*>(in.data());
    auto* op = reinterpret_cast<fftw_complex*>(out.data());
    a->fwd_ = fftw_plan_many_dft(1, &len, v, ip, nullptr, 1, di, op, nullptr, 1, dout, FFTW_FORWARD,
                                 FFTW_ESTIMATE);
    if (kind == Kind::ChirpZ)
      a->inv_ = fftw_plan_many_dft(1, &len, v, op, nullptr, 1, dout, op, nullptr, 1, dout,
                                   FFTW_BACKWARD, FFTW_ESTIMATE);
    if (!a->fwd_ || (kind == Kind::ChirpZ && !a->inv_))
      throw std::runtime_error("FFTW could not plan a transform");
  }
  c.axes.push_back(a);
  if (c.axes.size() > 16) c.axes.erase(c.axes.begin());
  return a;
}

int KirchhoffAxis::taps_for(double eps) {
  if (!(eps > 0)) return 16;
  const int k = static_cast<int>(std::ceil(-std::log10(eps))) + 1;
  return std::clamp(k, 4, 16);
}

KirchhoffAxis::~KirchhoffAxis() {
  auto plock = fftw_planner_lock();
  if (fwd_) fftw_destroy_plan(static_cast<fftw_plan>(fwd_));
  if (inv_) fftw_destroy_plan(static_cast<fftw_plan>(inv_));
}

void KirchhoffAxis::prepare(Scratch& s) const {
  if (s.ready_for == id_) return;
  s.in.resize(ldi_ * v_);
  s.out.resize(ldo_ * v_);
  std::memset(static_cast<void*>(s.in.data()), 0, ldi_ * v_ * sizeof(cd));
  std::memset(static_cast<void*>(s.out.data()), 0, ldo_ * v_ * sizeof(cd));
  s.ready_for = id_;
}

void KirchhoffAxis::run(Scratch& s) const {
  auto* ip = reinterpret_cast<fftw_complex*>(s.in.data());
  auto* op = reinterpret_cast<fftw_complex*>(s.out.data());
  fftw_execute_dft(static_cast<fftw_plan>(fwd_), ip, op);
  if (kind_ == Kind::Nufft) {  // the first K bins again after the last: no wrap in the sums
    for (std::size_t v = 0; v < v_; ++v) {
      cd* o = s.out.data() + v * ldo_;
      std::memcpy(static_cast<void*>(o + l_), o, k_ * sizeof(cd));
    }
    return;
  }
  for (std::size_t v = 0; v < v_; ++v) {
    cd* o = s.out.data() + v * ldo_;
    for (std::size_t r = 0; r < l_; ++r) {
      const cd k = kernel_[r], z = o[r];
      o[r] =
          cd(z.real() * k.real() - z.imag() * k.imag(), z.real() * k.imag() + z.imag() * k.real());
    }
  }
  fftw_execute_dft(static_cast<fftw_plan>(inv_), op, op);
}

}  // namespace microbrdf::detail

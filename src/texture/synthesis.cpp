// Separable Fourier synthesis of parameter textures (Dong 2015 section 9): per parameter, the
// 1-D amplitude spectra of the exemplars along x and y, their outer product as the 2-D spectrum,
// resampled to the output size and pitch, random phases, inverse FFT, then the exemplars' mean
// and variance, and the valid range. See docs/texture.md.
#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <cstring>
#include <numbers>

#include "core/fft.hpp"
#include "core/splitmix64.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/texture.hpp"
#include "texture/synthesis_detail.hpp"

namespace microbrdf {
namespace detail {
namespace {

// Uniform in [0, 1) from (seed, stream, index): counter-based, so the texture does not depend
// on the thread count or on the order of evaluation.
double uniform(std::uint64_t seed, std::uint64_t stream, std::uint64_t index) {
  const std::uint64_t h =
      splitmix64(seed ^ splitmix64(stream * 0x632be59bd9b4e019ULL ^ splitmix64(index)));
  return static_cast<double>(h >> 11) * 0x1.0p-53;
}

// Half-spectrum with modulus amp and random phase; Hermitian on the self-conjugate columns
// (kx = 0 and, for even nx, kx = nx/2): X[ny - ky] = conj X[ky], real at ky = 0 (and ny/2).
std::vector<std::complex<double>> random_phase_spectrum(const std::vector<double>& amp,
                                                        std::size_t nx, std::size_t ny,
                                                        std::uint64_t seed, std::uint64_t stream) {
  const std::size_t h = nx / 2 + 1;
  std::vector<std::complex<double>> s(h * ny);
#pragma omp parallel for schedule(static) if (h * ny > 65536)
  for (long y = 0; y < static_cast<long>(ny); ++y) {
    const auto ky = static_cast<std::size_t>(y);
    for (std::size_t kx = 0; kx < h; ++kx) {
      const bool self_conjugate = kx == 0 || 2 * kx == nx;
      // On the self-conjugate columns both partners take the modulus of the lower one.
      const double a =
          self_conjugate ? amp[std::min(ky, (ny - ky) % ny) * h + kx] : amp[ky * h + kx];
      if (!self_conjugate) {
        const double ph = 2 * std::numbers::pi * uniform(seed, stream, ky * h + kx);
        s[ky * h + kx] = std::polar(a, ph);
        continue;
      }
      const std::size_t partner = (ny - ky) % ny;
      if (partner == ky) {  // real entry: a random sign
        s[ky * h + kx] = uniform(seed, stream, ky * h + kx) < 0.5 ? a : -a;
      } else {
        const std::size_t lo = std::min(ky, partner);
        const double ph = 2 * std::numbers::pi * uniform(seed, stream, lo * h + kx);
        s[ky * h + kx] = std::polar(a, ky == lo ? ph : -ph);
      }
    }
  }
  return s;
}

}  // namespace

std::size_t exemplar_band(std::size_t k, std::size_t n, double pitch, std::size_t m,
                          double pitch_out) {
  // Output bin k sits at k / (m pitch_out) = x exemplar spacings, x = k n pitch / (m pitch_out);
  // band j holds [j - 1/2, j + 1/2). Integer arithmetic when the pitches agree, so that bins on a
  // band edge are assigned the same way everywhere.
  if (pitch == pitch_out) return (2 * k * n + m) / (2 * m);
  const double x = static_cast<double>(k) * static_cast<double>(n) * pitch /
                   (static_cast<double>(m) * pitch_out);
  return static_cast<std::size_t>(std::floor(x + 0.5));
}

std::vector<double> resample_line_spectrum(const std::vector<double>& p, std::size_t n,
                                           double pitch, std::size_t m, double pitch_out) {
  if (n < 4 || p.size() != n / 2 + 1) throw InputError("exemplar line spectrum too short");
  if (m < 2 || !(pitch > 0) || !(pitch_out > 0)) throw InputError("bad output grid");
  const std::size_t top = n / 2, half = m / 2;
  // Which band every output bin falls in; a bin beyond the exemplar's Nyquist frequency (or in
  // its upper half band for even n) gets nothing.
  std::vector<std::size_t> band(half + 1, 0), count(top + 1, 0);
  for (std::size_t k = 1; k <= half; ++k) {
    const std::size_t j = exemplar_band(k, n, pitch, m, pitch_out);
    // x > n/2  <=>  2 k pitch > m pitch_out (never when the pitches agree: k <= m/2).
    const bool beyond = j > top || (pitch != pitch_out && 2 * static_cast<double>(k) * pitch >
                                                              static_cast<double>(m) * pitch_out);
    band[k] = beyond ? 0 : j;
    if (band[k] > 0) ++count[band[k]];
  }
  std::vector<double> out(half + 1, 0.0);
  for (std::size_t k = 1; k <= half; ++k)
    if (band[k] > 0) out[k] = p[band[k]] / static_cast<double>(count[band[k]]);
  // Bands no output bin falls in (output coarser in frequency than the exemplar): their power
  // goes to the bin nearest to their centre, so the total is kept.
  const double r = static_cast<double>(m) * pitch_out / (static_cast<double>(n) * pitch);
  for (std::size_t j = 1; j <= top; ++j)
    if (count[j] == 0) {
      const auto k = static_cast<std::size_t>(std::llround(static_cast<double>(j) * r));
      if (k >= 1 && k <= half) out[k] += p[j];
    }
  return out;
}

std::vector<double> random_phase_field(const std::vector<double>& amp, std::size_t nx,
                                       std::size_t ny, std::uint64_t seed, std::uint64_t stream,
                                       bool direct) {
  const std::size_t h = nx / 2 + 1;
  if (amp.size() != h * ny) throw InputError("amplitude array has the wrong size");
  auto spec = random_phase_spectrum(amp, nx, ny, seed, stream);
  if (!direct) return fft2_c2r(nx, ny, std::move(spec));
  // Brute force: f(x, y) = sum over the full spectrum of X(kx, ky) exp(+2 pi i (kx x/nx +
  // ky y/ny)), the missing half from Hermitian symmetry; one double sum per texel.
  std::vector<std::complex<double>> full(nx * ny);
  for (std::size_t ky = 0; ky < ny; ++ky)
    for (std::size_t kx = 0; kx < nx; ++kx)
      full[ky * nx + kx] =
          kx < h ? spec[ky * h + kx] : std::conj(spec[((ny - ky) % ny) * h + (nx - kx)]);
  std::vector<double> f(nx * ny);
#pragma omp parallel for schedule(static)
  for (long yy = 0; yy < static_cast<long>(ny); ++yy)
    for (std::size_t x = 0; x < nx; ++x) {
      const auto y = static_cast<std::size_t>(yy);
      std::complex<double> acc = 0;
      for (std::size_t ky = 0; ky < ny; ++ky)
        for (std::size_t kx = 0; kx < nx; ++kx) {
          const double ph = 2 * std::numbers::pi *
                            (static_cast<double>((kx * x) % nx) / static_cast<double>(nx) +
                             static_cast<double>((ky * y) % ny) / static_cast<double>(ny));
          acc += full[ky * nx + kx] * std::complex<double>(std::cos(ph), std::sin(ph));
        }
      f[y * nx + x] = acc.real();
    }
  return f;
}

std::vector<double> lognormal_amplitudes(const std::vector<double>& amp, std::size_t nx,
                                         std::size_t ny, double mean, double variance) {
  // A log-normal field L = exp(G), G Gaussian with variance s^2, has the normalised correlation
  // rho_L = (exp(s^2 rho_G) - 1) / (exp(s^2) - 1). For L to have the designed spectrum amp^2
  // (correlation rho_L), G needs rho_G = ln(1 + rho_L (e^{s^2} - 1)) / s^2: correlation from the
  // spectrum (inverse FFT), transformed, back to a spectrum (FFT), negative rounding clipped.
  const std::size_t h = nx / 2 + 1;
  const double s2 = std::log(1 + variance / (mean * mean));
  if (!(s2 > 1e-12)) return amp;
  std::vector<std::complex<double>> p(h * ny);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = amp[i] * amp[i];
  std::vector<double> acf = fft2_c2r(nx, ny, std::move(p));
  const double r0 = acf[0];
  if (!(r0 > 0)) return amp;
  const double e = std::expm1(s2);
  for (double& v : acf) v = std::log(std::max(1e-12, 1 + (v / r0) * e)) / s2;
  const auto g = fft2_r2c(nx, ny, acf);
  std::vector<double> out(h * ny);
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = std::sqrt(std::max(0.0, g[i].real()));
  out[0] = 0;  // the mean is set separately
  return out;
}

void to_lognormal(std::vector<double>& f, double mean, double variance) {
  const double s2 = std::log(1 + variance / (mean * mean));
  double m = 0, v = 0;
  for (double x : f) m += x;
  m /= static_cast<double>(f.size());
  for (double x : f) v += (x - m) * (x - m);
  const double sd = std::sqrt(v / static_cast<double>(f.size()));
  const double mu = std::log(mean) - s2 / 2, s = std::sqrt(s2);
  for (double& x : f) x = std::exp(mu + s * (sd > 0 ? (x - m) / sd : 0.0));
}

std::vector<double> radial_power_spectrum(const std::vector<std::complex<double>>& spec,
                                          std::size_t n) {
  const std::size_t h = n / 2 + 1;
  if (n < 2 || spec.size() != h * n) throw InputError("radial spectrum: not an n x n spectrum");
  std::vector<double> sum(h, 0.0), count(h, 0.0);
  const double norm = 1.0 / (static_cast<double>(n) * static_cast<double>(n));
  for (std::size_t ky = 0; ky < n; ++ky) {
    const double fy = static_cast<double>(std::min(ky, n - ky));
    for (std::size_t kx = 0; kx < h; ++kx) {
      const auto r =
          static_cast<std::size_t>(std::llround(std::sqrt(static_cast<double>(kx * kx) + fy * fy)));
      if (r == 0 || r >= h) continue;  // the mean, and the corners beyond the Nyquist circle
      // Half spectrum: every entry but the self-conjugate columns stands for two.
      const double w = (kx == 0 || 2 * kx == n) ? 1.0 : 2.0;
      sum[r] += w * std::norm(spec[ky * h + kx]) * norm * norm;
      count[r] += w;
    }
  }
  for (std::size_t r = 1; r < h; ++r) sum[r] = count[r] > 0 ? sum[r] / count[r] : 0.0;
  return sum;
}

std::vector<double> radial_power_spectrum(const std::vector<double>& v, std::size_t n) {
  if (n < 2 || v.size() != n * n) throw InputError("radial spectrum: not an n x n field");
  double mean = 0;
  for (double x : v) mean += x;
  mean /= static_cast<double>(v.size());
  std::vector<double> c(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) c[i] = v[i] - mean;
  return radial_power_spectrum(fft2_r2c(n, n, c), n);
}

double spectrum_distance(const std::vector<double>& a, const std::vector<double>& b) {
  double sa = 0, sb = 0;
  for (std::size_t r = 1; r < a.size() && r < b.size(); ++r) sa += a[r], sb += b[r];
  if (!(sa > 0) || !(sb > 0)) return 0.0;
  double num = 0, den = 0;
  for (std::size_t r = 1; r < a.size() && r < b.size(); ++r) {
    const double x = a[r] / sa, y = b[r] / sb;
    num += (x - y) * (x - y);
    den += y * y;
  }
  return std::sqrt(num / den);
}

std::vector<float> quantile_table(std::vector<float> values, std::size_t n) {
  if (values.empty()) throw InputError("histogram matching: no exemplar values");
  std::sort(values.begin(), values.end());
  const std::size_t m = values.size();
  std::vector<float> q(n);
  for (std::size_t r = 0; r < n; ++r) {
    // Output rank r sits at the probability (r + 1/2)/n; exemplar order statistic i at
    // (i + 1/2)/m; linear between neighbours, the extremes held at the exemplar's min and max.
    const double pos =
        (static_cast<double>(r) + 0.5) * static_cast<double>(m) / static_cast<double>(n) - 0.5;
    if (pos <= 0) {
      q[r] = values.front();
    } else if (pos >= static_cast<double>(m - 1)) {
      q[r] = values.back();
    } else {
      const auto i = static_cast<std::size_t>(pos);
      const double t = pos - static_cast<double>(i);
      const double v = (1 - t) * values[i] + t * values[i + 1];
      // Rounding to float stays between the two neighbours (both floats).
      q[r] = std::clamp(static_cast<float>(v), values[i], values[i + 1]);
    }
  }
  return q;
}

void rank_remap(const std::vector<double>& f, const std::vector<float>& q,
                std::vector<float>& out) {
  const std::size_t n = f.size();
  if (q.size() != n) throw InputError("histogram matching: quantile table of the wrong size");
  if (n >= (std::size_t{1} << 32)) throw InputError("histogram matching: field too large");
  // Stable LSD radix sort (two 16-bit passes) of the values as order-preserving 32-bit keys
  // (float precision), carrying the texel index: equal keys keep index order, so the ranking is
  // deterministic. Linear in n: a 2048^2 channel ranks in tens of ms.
  std::vector<std::uint32_t> key(n), key2(n), idx(n), idx2(n);
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t b;
    const float x = static_cast<float>(f[i]);
    std::memcpy(&b, &x, sizeof b);
    key[i] = (b & 0x80000000u) ? ~b : (b | 0x80000000u);
    idx[i] = static_cast<std::uint32_t>(i);
  }
  for (int shift : {0, 16}) {
    std::vector<std::size_t> start(65537, 0);
    for (std::size_t i = 0; i < n; ++i) ++start[((key[i] >> shift) & 0xffffu) + 1];
    for (std::size_t d = 1; d <= 65536; ++d) start[d] += start[d - 1];
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t j = start[(key[i] >> shift) & 0xffffu]++;
      key2[j] = key[i];
      idx2[j] = idx[i];
    }
    key.swap(key2);
    idx.swap(idx2);
  }
  out.resize(n);
  for (std::size_t r = 0; r < n; ++r) out[idx[r]] = q[r];
}

}  // namespace detail

namespace {

ChannelStats pooled(const ChannelStats& a, const ChannelStats& b) {
  ChannelStats s;
  s.count = a.count + b.count;
  if (s.count == 0) return s;
  const double na = static_cast<double>(a.count), nb = static_cast<double>(b.count);
  s.mean = (na * a.mean + nb * b.mean) / (na + nb);
  s.variance = (na * (a.variance + (a.mean - s.mean) * (a.mean - s.mean)) +
                nb * (b.variance + (b.mean - s.mean) * (b.mean - s.mean))) /
               (na + nb);
  s.min = std::min(a.count ? a.min : b.min, b.count ? b.min : a.min);
  s.max = std::max(a.count ? a.max : b.max, b.count ? b.max : a.max);
  return s;
}

void clamp_range(int c, double& v) {
  constexpr double half_pi = std::numbers::pi / 2;
  if (c < 2)
    v = std::clamp(v, ParamRange::alpha_min, ParamRange::alpha_max);
  else if (c < 4)
    v = std::clamp(v, -ParamRange::tilt_max, ParamRange::tilt_max);
  else
    v = std::clamp(v, -half_pi, half_pi);
}

// Shift and scale f to the target mean and variance, clamp to the valid range; clamping a tail
// moves the mean and variance (alphas are skewed: a Gaussian field reaches alpha_min where the
// exemplar does not), so offset and gain are re-solved until the clamped values have them (to
// 1e-4). Returns the number of clamped values.
std::size_t match_clamp(const std::vector<double>& f, int c, const ChannelStats& target,
                        std::vector<float>& ch) {
  double mean = 0, var = 0;
  for (double v : f) mean += v;
  mean /= static_cast<double>(f.size());
  for (double v : f) var += (v - mean) * (v - mean);
  var /= static_cast<double>(f.size());
  const double sd = std::sqrt(var), want_sd = std::sqrt(target.variance);
  double offset = target.mean, gain = sd > 0 ? want_sd / sd : 0.0;
  ch.assign(f.size(), 0.0f);
  std::size_t clipped = 0;
  for (int pass = 0; pass < 8; ++pass) {
    clipped = 0;
    double m = 0, m2 = 0;
#pragma omp parallel for reduction(+ : clipped, m) schedule(static)
    for (long i = 0; i < static_cast<long>(f.size()); ++i) {
      double v = offset + (f[static_cast<std::size_t>(i)] - mean) * gain;
      const double before = v;
      clamp_range(c, v);
      clipped += v != before;
      ch[static_cast<std::size_t>(i)] = static_cast<float>(v);
      m += v;
    }
    m /= static_cast<double>(f.size());
#pragma omp parallel for reduction(+ : m2) schedule(static)
    for (long i = 0; i < static_cast<long>(f.size()); ++i) {
      const double d = ch[static_cast<std::size_t>(i)] - m;
      m2 += d * d;
    }
    const double got_sd = std::sqrt(m2 / static_cast<double>(f.size()));
    if (clipped == 0 || !(got_sd > 0) ||
        (std::fabs(m - target.mean) <= 1e-4 * want_sd && std::fabs(got_sd / want_sd - 1) < 1e-4))
      break;
    offset += target.mean - m;
    gain *= want_sd / got_sd;
  }
  return clipped;
}

struct Candidate {
  std::vector<float> values;
  std::size_t clipped = 0;
  bool lognormal = false;
  double spectrum_error = 0;
  std::vector<double> before;  // radially averaged power spectrum of the field before matching
  int rounds = 0;              // histogram-matching rounds
  double modulus_error = 0;    // relative L2 of the moduli against the design before the last round
};

// Exemplar grids of the two axes (bands the spectra are compared in).
struct Grids {
  std::size_t nx_e, ny_e;
  double px_e, py_e, pitch;
};

// Relative L2 distance between the output's line amplitude spectra along x and y and the design
// (sx, sy: one-sided power per output bin), gathered into the exemplar's bands (what acceptance
// measures), each normalised to unit power.
std::array<double, 2> design_errors(const std::vector<float>& v, std::size_t n,
                                    const std::vector<double>& sx, const std::vector<double>& sy,
                                    const Grids& g) {
  double mean = 0;
  for (float x : v) mean += x;
  mean /= static_cast<double>(v.size());
  std::array<double, 2> err{};
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double> a(v.size());
    for (std::size_t iy = 0; iy < n; ++iy)
      for (std::size_t ix = 0; ix < n; ++ix)
        a[axis == 0 ? ix + n * iy : iy + n * ix] = v[ix + n * iy] - mean;
    const auto spec = detail::fft2_r2c(n, n, a);
    const std::size_t h = n / 2 + 1;
    const auto& design = axis == 0 ? sx : sy;
    std::vector<double> p(h, 0.0);
    for (std::size_t l = 0; l < n; ++l)
      for (std::size_t k = 1; k < h; ++k) p[k] += std::norm(spec[l * h + k]);
    const std::size_t ne = axis == 0 ? g.nx_e : g.ny_e;
    const double pe = axis == 0 ? g.px_e : g.py_e;
    std::vector<double> bp(ne / 2 + 1, 0.0), bd(ne / 2 + 1, 0.0);
    double sp = 0, sd = 0;
    for (std::size_t k = 1; k < h; ++k) {
      p[k] *= (2 * k == n) ? 1.0 : 2.0;
      const std::size_t j = detail::exemplar_band(k, ne, pe, n, g.pitch);
      if (j >= 1 && j < bp.size()) {
        bp[j] += p[k];
        bd[j] += design[k];
        sp += p[k];
        sd += design[k];
      }
    }
    if (!(sp > 0) || !(sd > 0)) continue;
    double num = 0, den = 0;
    for (std::size_t j = 1; j < bp.size(); ++j) {
      const double x = std::sqrt(bp[j] / sp), y = std::sqrt(bd[j] / sd);
      num += (x - y) * (x - y);
      den += y * y;
    }
    err[static_cast<std::size_t>(axis)] = std::sqrt(num / den);
  }
  return err;
}

double design_error(const std::vector<float>& v, std::size_t n, const std::vector<double>& sx,
                    const std::vector<double>& sy, const Grids& g) {
  const auto e = design_errors(v, n, sx, sy, g);
  return e[0] + e[1];
}

// Histogram matching after the spectrum step (iterative amplitude-adjusted Fourier transform,
// Schreiber & Schmitz 1996): the field's values are replaced rank for rank by the exemplar's
// quantiles (q); then, in rounds, the designed moduli are put back under the field's own phases
// and the result replaced rank for rank again, until the spectrum's moduli are within `tolerance`
// (relative L2) of the design (or after max_rounds). It ends on a rank
// step, so the values are exactly the exemplar's quantiles (its range, its histogram); the
// spectrum is what the rounds left (meta.histogram.*.spectrum_change).
void match_histogram(const std::vector<double>& f, const std::vector<double>& amp, std::size_t n,
                     const std::vector<float>& q, int max_rounds, double tolerance,
                     Candidate& out) {
  detail::rank_remap(f, q, out.values);
  out.rounds = 0;
  for (int round = 0; round < max_rounds; ++round) {
    std::vector<double> v(out.values.begin(), out.values.end());
    auto spec = detail::fft2_r2c(n, n, v);
    // Distance of the moduli from the design, both normalised (the mean left out): the quantity
    // the rounds reduce, stricter than the radial average.
    double sm = 0, sa = 0, num = 0;
    for (std::size_t i = 1; i < spec.size(); ++i) sm += std::norm(spec[i]), sa += amp[i] * amp[i];
    const double km = sm > 0 ? 1 / std::sqrt(sm) : 0.0, ka = sa > 0 ? 1 / std::sqrt(sa) : 0.0;
    for (std::size_t i = 1; i < spec.size(); ++i) {
      const double d = std::abs(spec[i]) * km - amp[i] * ka;
      num += d * d;
    }
    out.modulus_error = std::sqrt(num);
    if (out.modulus_error <= tolerance) break;
    for (std::size_t i = 0; i < spec.size(); ++i) {
      const double m = std::abs(spec[i]);
      spec[i] = m > 0 ? spec[i] * (amp[i] / m) : std::complex<double>(amp[i], 0.0);
    }
    ++out.rounds;
    detail::rank_remap(detail::fft2_c2r(n, n, std::move(spec)), q, out.values);
  }
  out.clipped = 0;
}

Candidate make_candidate(const std::vector<double>& amp, std::size_t n, int c,
                         const ChannelStats& target, std::uint64_t seed, bool lognormal,
                         const std::vector<double>& sx, const std::vector<double>& sy,
                         const Grids& g, bool compare, const std::vector<float>* quantiles,
                         const SynthesisOptions& o) {
  Candidate out;
  out.lognormal = lognormal;
  std::vector<double> f = detail::random_phase_field(
      lognormal ? detail::lognormal_amplitudes(amp, n, n, target.mean, target.variance) : amp, n, n,
      seed, static_cast<std::uint64_t>(c));
  if (lognormal) detail::to_lognormal(f, target.mean, target.variance);
  out.before = detail::radial_power_spectrum(f, n);
  if (quantiles) {
    match_histogram(f, amp, n, *quantiles, o.histogram_rounds, o.histogram_tolerance, out);
    out.spectrum_error = compare ? design_error(out.values, n, sx, sy, g) : 0.0;
    return out;
  }
  out.clipped = match_clamp(f, c, target, out.values);
  // A clamped tail changes the spectrum too (clipping whitens it). Iterative amplitude adjustment
  // (Schreiber & Schmitz 1996): put the designed moduli back under the field's own phases, invert,
  // match and clamp again; a few rounds bring spectrum, mean, variance and range together.
  for (int round = 0; round < 6 && out.clipped > 0; ++round) {
    std::vector<double> v(out.values.begin(), out.values.end());
    auto spec = detail::fft2_r2c(n, n, v);
    for (std::size_t i = 0; i < spec.size(); ++i) {
      const double m = std::abs(spec[i]);
      spec[i] = m > 0 ? spec[i] * (amp[i] / m) : std::complex<double>(amp[i], 0.0);
    }
    out.clipped = match_clamp(detail::fft2_c2r(n, n, std::move(spec)), c, target, out.values);
  }
  // Only when there are two candidates to choose from (two FFTs).
  out.spectrum_error = compare ? design_error(out.values, n, sx, sy, g) : 0.0;
  return out;
}

}  // namespace

ParamTexture synthesize_texture(const ParamTexture& along, const ParamTexture& across,
                                const SynthesisOptions& options) {
  const std::size_t n = options.size;
  if (n < 2 || n > (std::size_t{1} << 15)) throw InputError("texture size must lie in 2..32768");
  if (along.nx < 4)
    throw InputError("the exemplar along the brushing needs at least 4 texels along x (has " +
                     std::to_string(along.nx) + ")");
  if (across.ny < 4)
    throw InputError("the exemplar across the brushing needs at least 4 texels along y (has " +
                     std::to_string(across.ny) + ")");
  if (!(along.texel_m > 0) || !(across.texel_m > 0))
    throw InputError("exemplars need a texel size");
  if (along.valid_count() == 0 || across.valid_count() == 0)
    throw InputError("an exemplar has no valid texel");
  const double pitch = options.texel_m > 0 ? options.texel_m : along.texel_m;
  ParamTexture out = ParamTexture::empty(n, n, pitch, "");
  std::fill(out.valid.begin(), out.valid.end(), 1);
  const std::size_t h = n / 2 + 1;
  nlohmann::json stats = nlohmann::json::object(), clamped = nlohmann::json::object(),
                 field = nlohmann::json::object(), histogram = nlohmann::json::object(),
                 spectra = nlohmann::json::object();
  const Grids grids{along.nx, across.ny, along.texel_m, across.texel_m, pitch};
  for (int c = 0; c < 5; ++c) {
    const ChannelStats target = &along == &across
                                    ? channel_stats(along, c)
                                    : pooled(channel_stats(along, c), channel_stats(across, c));
    const auto sx = detail::resample_line_spectrum(line_power_spectrum(along, c, 0), along.nx,
                                                   along.texel_m, n, pitch);
    const auto sy = detail::resample_line_spectrum(line_power_spectrum(across, c, 1), across.ny,
                                                   across.texel_m, n, pitch);
    // Separable spectrum: |X(kx, ky)|^2 = w_x(kx) w_y(ky), w the two-sided power per bin (half
    // the one-sided power, except at 0 and the Nyquist bin, which are single); the overall
    // constant does not matter, the variance is matched below.
    auto two_sided = [n](const std::vector<double>& s, std::size_t k) {
      const std::size_t f = std::min(k, n - k);
      return (f == 0 || 2 * f == n) ? s[f] : 0.5 * s[f];
    };
    std::vector<double> amp(h * n);
    for (std::size_t ky = 0; ky < n; ++ky) {
      const double wy = two_sided(sy, ky);
      for (std::size_t kx = 0; kx < h; ++kx) amp[ky * h + kx] = std::sqrt(two_sided(sx, kx) * wy);
    }
    // D15's Gaussian field; for alphas optionally also a log-normal field, keeping the one whose
    // line spectra are nearer the design (docs/texture.md).
    const bool both = options.lognormal_alpha && c < 2 && target.mean > 0;
    // The exemplar's values (valid texels of both strips, pooled) as n^2 quantiles.
    std::vector<float> q;
    if (options.match_histogram) {
      std::vector<float> values;
      const std::vector<const ParamTexture*> exemplars =
          &along == &across ? std::vector<const ParamTexture*>{&along}
                            : std::vector<const ParamTexture*>{&along, &across};
      for (const ParamTexture* e : exemplars) {
        const auto& ch = e->channel[static_cast<std::size_t>(c)];
        for (std::size_t i = 0; i < e->size(); ++i)
          if (e->valid[i]) {
            double v = ch[i];
            clamp_range(c, v);  // fitted texels are in range already; a hand-made file may not be
            values.push_back(static_cast<float>(v));
          }
      }
      q = detail::quantile_table(std::move(values), n * n);
    }
    const std::vector<float>* qp = options.match_histogram ? &q : nullptr;
    Candidate best =
        make_candidate(amp, n, c, target, options.seed, false, sx, sy, grids, both, qp, options);
    if (both) {
      Candidate ln =
          make_candidate(amp, n, c, target, options.seed, true, sx, sy, grids, true, qp, options);
      if (ln.spectrum_error < best.spectrum_error) best = std::move(ln);
    }
    {
      const auto line = design_errors(best.values, n, sx, sy, grids);
      spectra[ParamTexture::channel_names[c]] = {{"x", line[0]}, {"y", line[1]}};
      std::vector<double> v(best.values.begin(), best.values.end());
      const auto after = detail::radial_power_spectrum(v, n);
      const double change = detail::spectrum_distance(after, best.before);
      const auto range = std::minmax_element(best.values.begin(), best.values.end());
      histogram[ParamTexture::channel_names[c]] = {
          {"exemplar_min", target.min}, {"exemplar_max", target.max}, {"min", *range.first},
          {"max", *range.second},       {"rounds", best.rounds},      {"spectrum_change", change}};
    }
    out.channel[static_cast<std::size_t>(c)] = std::move(best.values);
    const std::size_t clipped = best.clipped;
    field[ParamTexture::channel_names[c]] = best.lognormal ? "log-normal" : "gaussian";
    stats[ParamTexture::channel_names[c]] = {
        {"mean", target.mean}, {"variance", target.variance}, {"texels", target.count}};
    clamped[ParamTexture::channel_names[c]] = clipped;
  }
  nlohmann::json sources = {{"along", along.meta.value("sources", nlohmann::json::array())},
                            {"across", across.meta.value("sources", nlohmann::json::array())}};
  out.meta = {
      {"kind", "synthesised"},
      {"method",
       options.match_histogram
           ? "separable Fourier synthesis (Dong 2015 sec. 9): 1-D amplitude spectra along x "
             "(along exemplar) and y (across exemplar), outer product, random phase, inverse "
             "FFT, then each channel matched to the exemplars' histogram (iterative "
             "amplitude-adjusted Fourier transform): values within the exemplars' range"
           : "separable Fourier synthesis (Dong 2015 sec. 9): 1-D amplitude spectra along x "
             "(along exemplar) and y (across exemplar), outer product, random phase, inverse "
             "FFT, matched mean and variance, clamped to the valid range"},
      {"histogram_matched", options.match_histogram},
      {"seed", options.seed},
      {"size", n},
      {"texel_m", pitch},
      {"exemplar_texel_m", {{"along", along.texel_m}, {"across", across.texel_m}}},
      {"exemplar_size", {{"along", {along.nx, along.ny}}, {"across", {across.nx, across.ny}}}},
      {"exemplar_stats", stats},
      {"clamped_texels", clamped},
      {"histogram", histogram},
      {"line_spectrum_error", spectra},
      {"field", field},
      {"sources", sources}};
  return out;
}

ParamTexture synthesize_texture(const ParamTexture& exemplar, const SynthesisOptions& options) {
  if (exemplar.nx < 4 || exemplar.ny < 4)
    throw InputError("a 2-D exemplar needs at least 4 x 4 texels (has " +
                     std::to_string(exemplar.nx) + " x " + std::to_string(exemplar.ny) +
                     "); for strips give one along and one across");
  ParamTexture t = synthesize_texture(exemplar, exemplar, options);
  t.meta["sources"] = exemplar.meta.value("sources", nlohmann::json::array());
  return t;
}

}  // namespace microbrdf

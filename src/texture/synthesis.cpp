// Separable Fourier synthesis of parameter textures (Dong 2015 section 9): per parameter, the
// 1-D amplitude spectra of the exemplars along x and y, their outer product as the 2-D spectrum,
// resampled to the output size and pitch, random phases, inverse FFT, then the exemplars' mean
// and variance, and the valid range. See docs/texture.md.
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>

#include "core/fft.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/texture.hpp"
#include "texture/synthesis_detail.hpp"

namespace microbrdf {
namespace detail {
namespace {

std::uint64_t splitmix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

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
  nlohmann::json stats = nlohmann::json::object(), clamped = nlohmann::json::object();
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
    std::vector<double> f =
        detail::random_phase_field(amp, n, n, options.seed, static_cast<std::uint64_t>(c));
    double mean = 0, var = 0;
    for (double v : f) mean += v;
    mean /= static_cast<double>(f.size());
    for (double v : f) var += (v - mean) * (v - mean);
    var /= static_cast<double>(f.size());
    // Mean and variance of the exemplar, then the valid range. Clamping a tail moves the mean and
    // variance (alphas are skewed: a Gaussian field reaches alpha_min where the exemplar does
    // not), so offset and gain are re-solved a few times until the clamped texture has them.
    const double sd = std::sqrt(var);
    double offset = target.mean, gain = sd > 0 ? std::sqrt(target.variance) / sd : 0.0;
    std::size_t clipped = 0;
    auto& ch = out.channel[static_cast<std::size_t>(c)];
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
      const double want_sd = std::sqrt(target.variance);
      if (clipped == 0 || !(got_sd > 0) ||
          (std::fabs(m - target.mean) <= 1e-4 * want_sd && std::fabs(got_sd / want_sd - 1) < 1e-4))
        break;
      offset += target.mean - m;
      gain *= want_sd / got_sd;
    }
    stats[ParamTexture::channel_names[c]] = {
        {"mean", target.mean}, {"variance", target.variance}, {"texels", target.count}};
    clamped[ParamTexture::channel_names[c]] = clipped;
  }
  nlohmann::json sources = {{"along", along.meta.value("sources", nlohmann::json::array())},
                            {"across", across.meta.value("sources", nlohmann::json::array())}};
  out.meta = {
      {"kind", "synthesised"},
      {"method",
       "separable Fourier synthesis (Dong 2015 sec. 9): 1-D amplitude spectra along x "
       "(along exemplar) and y (across exemplar), outer product, random phase, inverse "
       "FFT, matched mean and variance, clamped to the valid range"},
      {"seed", options.seed},
      {"size", n},
      {"texel_m", pitch},
      {"exemplar_texel_m", {{"along", along.texel_m}, {"across", across.texel_m}}},
      {"exemplar_size", {{"along", {along.nx, along.ny}}, {"across", {across.nx, across.ny}}}},
      {"exemplar_stats", stats},
      {"clamped_texels", clamped},
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

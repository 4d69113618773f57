// Synthetic surfaces. Lengths in metres, angles in radians (see generate.hpp).
#include "microbrdf/generate.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>

#include "core/fft.hpp"
#include "core/splitmix64.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

void require(bool ok, const std::string& what) {
  if (!ok) throw InputError(what);
}

void check_grid(std::size_t nx, std::size_t ny, double dx, double dy) {
  require(nx >= 1 && ny >= 1, "grid must have at least 1 x 1 samples");
  require(nx * ny <= (std::size_t{1} << 28), "grid too large (more than 2^28 samples)");
  require(dx > 0 && dy > 0 && std::isfinite(dx) && std::isfinite(dy), "spacing must be positive");
  // The range a scan's spacing must lie in when it is read (surface/io.cpp).
  require(dx >= 1e-12 && dy >= 1e-12 && dx <= 1 && dy <= 1, "spacing must lie in 1 pm .. 1 m");
}

// White Gaussian noise, reproducible from the seed.
std::vector<double> white_noise(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::vector<double> w(n);
  for (auto& v : w) v = normal(rng);
  return w;
}

void normalise(Surface& s, double sigma) {
  double mean = 0;
  for (double v : s.z) mean += v;
  mean /= static_cast<double>(s.size());
  double var = 0;
  for (double& v : s.z) {
    v -= mean;
    var += v * v;
  }
  double rms = std::sqrt(var / static_cast<double>(s.size()));
  if (rms > 0)
    for (double& v : s.z) v *= sigma / rms;
}

// Range of v = -x sin(angle) + y cos(angle) (the coordinate across a direction at `angle`)
// over the grid's extent.
std::pair<double, double> across_range(std::size_t nx, std::size_t ny, double dx, double dy,
                                       double angle) {
  const double c = std::cos(angle), sn = std::sin(angle);
  const double W = static_cast<double>(nx) * dx, H = static_cast<double>(ny) * dy;
  return {std::min({0.0, -W * sn, H * c, -W * sn + H * c}),
          std::max({0.0, -W * sn, H * c, -W * sn + H * c})};
}

void base_metadata(Surface& s, const std::string& kind) {
  s.meta.format = std::string("generated");
  s.meta.instrument = "microbrdf generate " + kind;
  s.meta.z_unit_in_file = std::string(1, 'm');
}

}  // namespace

Surface generate_gaussian(const GaussianSurfaceParams& p) {
  check_grid(p.nx, p.ny, p.dx, p.dy);
  // A micro-surface: an rms height or a correlation length beyond 1 m is a unit mistake (and
  // 1e300 m makes every height non-finite).
  require(p.sigma >= 0 && p.sigma <= 1, "sigma must lie in 0 .. 1 m");
  require(p.tau_x > 0 && p.tau_y > 0 && p.tau_x <= 1 && p.tau_y <= 1,
          "correlation lengths must lie in (0, 1 m]");
  Surface s(p.nx, p.ny, p.dx, p.dy);
  auto spec = detail::fft2_r2c(p.nx, p.ny, white_noise(p.nx * p.ny, p.seed));
  // Filter with sqrt(PSD): PSD ~ exp(-(ku^2 tau_x^2 + kv^2 tau_y^2)/4), so the filter is
  // exp(-(...)/8) and the ACF of the result is exp(-(u/tau_x)^2 - (v/tau_y)^2).
  const std::size_t hx = p.nx / 2 + 1;
  const double c = std::cos(p.angle), sn = std::sin(p.angle);
  for (std::size_t iy = 0; iy < p.ny; ++iy) {
    double ky = detail::fft_freq(iy, p.ny) / p.dy;
    for (std::size_t ix = 0; ix < hx; ++ix) {
      double kx = detail::fft_freq(ix, p.nx) / p.dx;
      double ku = kx * c + ky * sn, kv = -kx * sn + ky * c;
      auto& w = spec[iy * hx + ix];
      // Unit modulus keeps the phase (and the Hermitian symmetry of a real input's spectrum).
      if (p.exact_spectrum) w = std::abs(w) > 0 ? w / std::abs(w) : std::complex<double>(1.0, 0.0);
      w *= std::exp(-(ku * ku * p.tau_x * p.tau_x + kv * kv * p.tau_y * p.tau_y) / 8.0);
    }
  }
  s.z = detail::fft2_c2r(p.nx, p.ny, std::move(spec));
  normalise(s, p.sigma);
  base_metadata(s, "gaussian");
  s.meta.set("sigma_m", std::to_string(p.sigma));
  s.meta.set("tau_x_m", std::to_string(p.tau_x));
  s.meta.set("tau_y_m", std::to_string(p.tau_y));
  s.meta.set("angle_rad", std::to_string(p.angle));
  s.meta.set("seed", std::to_string(p.seed));
  s.meta.set("noise", p.exact_spectrum ? "exact-spectrum (random phase)" : "gaussian process");
  return s;
}

Surface generate_profiles(const ProfileParams& p) {
  check_grid(p.n, p.rows, p.dx, p.dx);
  require(p.tau > 0 && p.sigma >= 0, "tau must be positive and sigma >= 0");
  const auto half = static_cast<std::size_t>(std::ceil(3.0 * p.tau / p.dx));
  require(half < (std::size_t{1} << 24), "tau is too many samples long");
  std::vector<double> w(2 * half + 1);
  double norm2 = 0;
  for (std::size_t j = 0; j < w.size(); ++j) {
    double x = (static_cast<double>(j) - static_cast<double>(half)) * p.dx;
    w[j] = std::exp(-2.0 * x * x / (p.tau * p.tau));
    norm2 += w[j] * w[j];
  }
  const double scale = p.sigma / std::sqrt(norm2);
  Surface s(p.n, p.rows, p.dx, p.dx);
#pragma omp parallel for schedule(dynamic)
  for (long r = 0; r < static_cast<long>(p.rows); ++r) {
    auto eps =
        white_noise(p.n + 2 * half, detail::chunk_seed(p.seed, static_cast<std::uint64_t>(r)));
    for (std::size_t i = 0; i < p.n; ++i) {
      double acc = 0;
      for (std::size_t j = 0; j < w.size(); ++j) acc += w[j] * eps[i + j];
      s.z[static_cast<std::size_t>(r) * p.n + i] = acc * scale;
    }
  }
  base_metadata(s, "profile");
  s.meta.set("sigma_m", std::to_string(p.sigma));
  s.meta.set("tau_m", std::to_string(p.tau));
  s.meta.set("seed", std::to_string(p.seed));
  return s;
}

double predicted_filtered_alpha(double sigma, double tau_u, double tau_v, double s) {
  double au = s * s + tau_u * tau_u / 4, av = s * s + tau_v * tau_v / 4;
  double b2 = tau_u * tau_v * sigma * sigma / (8 * std::pow(au, 1.5) * std::sqrt(av));
  return std::sqrt(2 * b2);
}

void solve_brushed_base(BrushedParams& p, double alpha_along, double alpha_across, double s) {
  require(alpha_along > 0 && alpha_across >= alpha_along,
          "brushed widths need 0 < alpha_along <= alpha_across");
  require(p.tau_across > 0 && s >= 0, "tau_across must be positive");
  // alpha_u^2 ~ 1 / (a_u^{3/2} a_v^{1/2})  =>  a_along / a_across = (alpha_across/alpha_along)^2.
  double a_across = s * s + p.tau_across * p.tau_across / 4;
  double ratio = alpha_across / alpha_along;
  double a_along = a_across * ratio * ratio;
  p.tau_along = 2 * std::sqrt(a_along - s * s);
  p.sigma = std::sqrt(4 * alpha_across * alpha_across * std::pow(a_across, 1.5) *
                      std::sqrt(a_along) / (p.tau_across * p.tau_along));
}

std::vector<std::string> brushed_preset_names() { return {"stainless4", "aluminium4"}; }

std::pair<double, double> brushed_modulation_calibration(const BrushedParams& p) {
  if (p.modulation <= 0) return {1.0, 1.0};
  return {1.6, 1.8};
}

BrushedParams brushed_preset(const std::string& name) {
  // Depth modulation (log-amplitude rms 0.6; 50 um along, 8 um across): the brushing depth varies
  // over the surface, so the NDF is a scale mixture of Gaussian lobes with heavier tails than
  // Beckmann, as Dong's measured metals (the ellipsoid fits them better, Fig. 12), and 53 um
  // texels differ in roughness (Fig. 11). The mixture's peak is narrower than its rms width, so
  // the base is solved for rms widths kAlong / kAcross times the Fig. 12 ellipsoid widths; the
  // factors are calibrated so the ellipsoid fit of the filtered NDF (1 um, 2048 x 1024, seeds
  // 1-3) lands on them within ~7% (docs/fitting.md; tests fit.BrushedPresetsFig12).
  BrushedParams p;
  p.tau_across = 2e-6;
  p.modulation = 0.6;
  p.modulation_along = 50e-6;
  p.modulation_across = 8e-6;
  const auto [kAlong, kAcross] = brushed_modulation_calibration(p);
  if (name == "stainless4") {
    solve_brushed_base(p, 0.007 * kAlong, 0.14 * kAcross, 1e-6);
    p.scratch_density = 2e4;  // 2 per 100 um
    p.scratch_depth = 0.1e-6;
    p.scratch_width = 0.3e-6;
  } else if (name == "aluminium4" || name == "aluminum4") {
    solve_brushed_base(p, 0.02 * kAlong, 0.47 * kAcross, 1e-6);
    p.scratch_density = 4e4;
    p.scratch_depth = 0.3e-6;
    p.scratch_width = 0.4e-6;
  } else {
    throw InputError("unknown brushed preset '" + name + "' (known: stainless4, aluminium4)");
  }
  return p;
}

Surface generate_brushed(const BrushedParams& p) {
  GaussianSurfaceParams g;
  g.nx = p.nx;
  g.ny = p.ny;
  g.dx = p.dx;
  g.dy = p.dy;
  g.sigma = p.sigma;
  g.tau_x = p.tau_along;
  g.tau_y = p.tau_across;
  g.angle = p.angle;
  g.seed = p.seed;
  g.exact_spectrum = p.exact_spectrum;
  Surface s = generate_gaussian(g);
  require(p.scratch_density >= 0 && p.scratch_depth >= 0 && p.scratch_width >= 0,
          "scratch parameters must be >= 0");
  if (p.scratch_density > 0 && p.scratch_depth > 0 && p.scratch_width > 0) {
    // v = coordinate across the brushing; scratches are uniform over the v range the grid covers.
    const double c = std::cos(p.angle), sn = std::sin(p.angle);
    auto [vmin, vmax] = across_range(p.nx, p.ny, p.dx, p.dy, p.angle);
    std::mt19937_64 rng(p.seed ^ 0x5eed5c7a7c4e5ULL);
    std::uniform_real_distribution<double> uni(0.0, 1.0);
    std::exponential_distribution<double> depth(1.0 / p.scratch_depth);
    auto count = static_cast<std::size_t>(std::llround(p.scratch_density * (vmax - vmin)));
    for (std::size_t k = 0; k < count; ++k) {
      double v0 = vmin + uni(rng) * (vmax - vmin);
      double d = depth(rng);
      double w = p.scratch_width * (0.5 + uni(rng));
#pragma omp parallel for
      for (long iy = 0; iy < static_cast<long>(p.ny); ++iy) {
        double y = static_cast<double>(iy) * p.dy;
        for (std::size_t ix = 0; ix < p.nx; ++ix) {
          double x = static_cast<double>(ix) * p.dx;
          double dv = (-x * sn + y * c) - v0;
          if (std::fabs(dv) > 5 * w) continue;
          s.z[static_cast<std::size_t>(iy) * p.nx + ix] -= d * std::exp(-dv * dv / (2 * w * w));
        }
      }
    }
    s.meta.set("scratches", std::to_string(count));
  }
  require(p.modulation >= 0, "modulation must be >= 0");
  if (p.modulation > 0) {
    require(p.modulation_along > 0 && p.modulation_across > 0,
            "modulation needs positive correlation lengths along and across");
    // Log-normal depth modulation: a = exp(m h) / sqrt(mean exp(2 m h)), mean a^2 = 1 exactly.
    GaussianSurfaceParams gm = g;
    gm.sigma = 1;
    gm.tau_x = p.modulation_along;
    gm.tau_y = p.modulation_across;
    gm.seed = p.seed * 0x9e3779b97f4a7c15ULL + 0x6d6f64ULL;
    const Surface h = generate_gaussian(gm);
    double mean_a2 = 0;
    for (double v : h.z) mean_a2 += std::exp(2 * p.modulation * v);
    mean_a2 /= static_cast<double>(h.size());
    const double norm = 1 / std::sqrt(mean_a2);
    for (std::size_t i = 0; i < s.size(); ++i) s.z[i] *= norm * std::exp(p.modulation * h.z[i]);
    s.meta.set("modulation", std::to_string(p.modulation));
    s.meta.set("modulation_along_m", std::to_string(p.modulation_along));
    s.meta.set("modulation_across_m", std::to_string(p.modulation_across));
  }
  s.meta.instrument = "microbrdf generate brushed";
  s.meta.set("brushing_angle_rad", std::to_string(p.angle));
  s.meta.set("tau_along_m", std::to_string(p.tau_along));
  s.meta.set("tau_across_m", std::to_string(p.tau_across));
  return s;
}

Surface generate_cylinders(const CylindersParams& p) {
  check_grid(p.nx, p.ny, p.dx, p.dy);
  require(p.radius > 0 && p.pitch > 0, "radius and pitch must be positive");
  require(p.jitter >= 0 && p.jitter <= 0.5, "jitter must be in [0, 0.5] (fraction of the pitch)");
  Surface s(p.nx, p.ny, p.dx, p.dy);
  const double c = std::cos(p.angle), sn = std::sin(p.angle);
  auto [vmin, vmax] = across_range(p.nx, p.ny, p.dx, p.dy, p.angle);
  long kmin = static_cast<long>(std::floor(vmin / p.pitch)) - 2;
  long kmax = static_cast<long>(std::ceil(vmax / p.pitch)) + 2;
  std::vector<double> shift(static_cast<std::size_t>(kmax - kmin + 1), 0.0);
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> uni(-p.jitter, p.jitter);
  for (auto& v : shift) v = uni(rng) * p.pitch;
  const long reach = static_cast<long>(std::ceil(p.radius / p.pitch)) + 1;
  for (std::size_t iy = 0; iy < p.ny; ++iy)
    for (std::size_t ix = 0; ix < p.nx; ++ix) {
      double v = -static_cast<double>(ix) * p.dx * sn + static_cast<double>(iy) * p.dy * c;
      long k0 = static_cast<long>(std::lround(v / p.pitch));
      double h = 0;
      for (long k = std::max(kmin, k0 - reach); k <= std::min(kmax, k0 + reach); ++k) {
        double d =
            v - (static_cast<double>(k) * p.pitch + shift[static_cast<std::size_t>(k - kmin)]);
        if (std::fabs(d) < p.radius) h = std::max(h, std::sqrt(p.radius * p.radius - d * d));
      }
      s.z[iy * p.nx + ix] = p.grooves ? -h : h;
    }
  base_metadata(s, p.grooves ? "grooves" : "cylinders");
  s.meta.set("radius_m", std::to_string(p.radius));
  s.meta.set("pitch_m", std::to_string(p.pitch));
  return s;
}

Surface generate_grating(const GratingParams& p) {
  check_grid(p.nx, p.ny, p.dx, p.dy);
  require(p.period > 0, "period must be positive");
  Surface s(p.nx, p.ny, p.dx, p.dy);
  const double c = std::cos(p.angle), sn = std::sin(p.angle);
  for (std::size_t iy = 0; iy < p.ny; ++iy)
    for (std::size_t ix = 0; ix < p.nx; ++ix) {
      double u = static_cast<double>(ix) * p.dx * c + static_cast<double>(iy) * p.dy * sn;
      s.z[iy * p.nx + ix] = p.amplitude * std::sin(2 * M_PI * u / p.period);
    }
  base_metadata(s, "grating");
  s.meta.set("amplitude_m", std::to_string(p.amplitude));
  s.meta.set("period_m", std::to_string(p.period));
  return s;
}

}  // namespace microbrdf

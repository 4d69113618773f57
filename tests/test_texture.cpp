// Spatially varying ellipsoid textures (issue 7, acceptance 3 and 4): per-texel fits, the skew of
// small-area NDFs, separable Fourier synthesis against its brute-force reference and its
// exemplars' statistics, EXR round trip, the SVBRDF against the uniform microfacet BRDF.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/texture.hpp"
#include "texture/synthesis_detail.hpp"
#include "texture_test_util.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir(const std::string& name) {
  auto d = fs::temp_directory_path() / ("microbrdf_texture_" + name + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

// A ParamTexture whose channels are smooth random fields with realistic brushed-metal values
// (Gaussian ACF, correlation `cx` texels along x and `cy` along y), all valid.
ParamTexture random_exemplar(std::size_t nx, std::size_t ny, double cx, double cy,
                             std::uint64_t seed) {
  ParamTexture t = test_util::gaussian_param_texture(
      nx, ny, cx, cy, {0.0015, 0.03, 0.01, 0.002, 0.005}, seed * 10, false);
  t.meta = {{"sources", {"random"}}};
  return t;
}

// Relative L2 distance of the band amplitude spectra: the synthesised power gathered into the
// exemplar's bands (detail::exemplar_band, the synthesis' own assignment of output bins to
// bands), both normalised to unit total, then square-rooted.
double band_spectrum_error(const std::vector<double>& pe, std::size_t ne, double pitch_e,
                           const std::vector<double>& ps, std::size_t ns, double pitch_s) {
  std::vector<double> band(pe.size(), 0.0);
  for (std::size_t k = 1; k < ps.size(); ++k) {
    const std::size_t j = detail::exemplar_band(k, ne, pitch_e, ns, pitch_s);
    if (j >= 1 && j < band.size()) band[j] += ps[k];
  }
  double se = 0, ss = 0;
  for (std::size_t j = 1; j < pe.size(); ++j) se += pe[j], ss += band[j];
  double num = 0, den = 0;
  for (std::size_t j = 1; j < pe.size(); ++j) {
    const double a = std::sqrt(pe[j] / se), b = std::sqrt(band[j] / ss);
    num += (a - b) * (a - b);
    den += a * a;
  }
  return std::sqrt(num / den);
}

bool in_range(const ParamTexture& t) {
  for (std::size_t i = 0; i < t.size(); ++i) {
    for (int c = 0; c < 2; ++c) {
      const float a = t.channel[static_cast<std::size_t>(c)][i];
      // alpha_min as stored (float)
      if (!(a >= static_cast<float>(ParamRange::alpha_min) && a <= ParamRange::alpha_max))
        return false;
    }
    for (int c = 2; c < 4; ++c)
      if (!(std::fabs(t.channel[static_cast<std::size_t>(c)][i]) <= ParamRange::tilt_max))
        return false;
    if (!(std::fabs(t.channel[4][i]) <= std::numbers::pi / 2 + 1e-6)) return false;
  }
  return true;
}

}  // namespace

TEST(texture, RandomPhaseFieldFftMatchesDirectDft) {
  for (auto [nx, ny] : {std::pair<std::size_t, std::size_t>{12, 10}, {9, 7}, {8, 5}}) {
    const std::size_t h = nx / 2 + 1;
    std::vector<double> amp(h * ny);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.1, 1.0);
    for (auto& a : amp) a = u(rng);
    // A real field's spectrum: equal moduli at ky and ny - ky on the self-conjugate columns.
    for (std::size_t kx : {std::size_t{0}, nx / 2})
      if (kx == 0 || 2 * kx == nx)
        for (std::size_t ky = 1; ky < ny; ++ky) amp[ky * h + kx] = amp[(ny - ky) * h + kx];
    const auto fast = detail::random_phase_field(amp, nx, ny, 42, 1);
    const auto slow = detail::random_phase_field(amp, nx, ny, 42, 1, true);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < fast.size(); ++i) {
      num += (fast[i] - slow[i]) * (fast[i] - slow[i]);
      den += slow[i] * slow[i];
    }
    EXPECT_LT(std::sqrt(num / den), 1e-12) << nx << " x " << ny;
    // Parseval: the field's mean square is the sum of |X|^2 over the full spectrum.
    double ms = 0, power = 0;
    for (double v : fast) ms += v * v;
    ms /= static_cast<double>(fast.size());
    for (std::size_t ky = 0; ky < ny; ++ky)
      for (std::size_t kx = 0; kx < h; ++kx) {
        const bool self = kx == 0 || 2 * kx == nx;
        power += (self ? 1.0 : 2.0) * amp[ky * h + kx] * amp[ky * h + kx];
      }
    EXPECT_NEAR(ms / power, 1.0, 1e-9);
  }
}

TEST(texture, LinePowerSpectrumIsParseval) {
  const ParamTexture t = random_exemplar(40, 30, 4, 2, 1);
  for (int c = 0; c < 5; ++c)
    for (int axis = 0; axis < 2; ++axis) {
      const auto p = line_power_spectrum(t, c, axis);
      // Mean over lines of the variance about the channel mean = sum of all bins.
      double s = 0;
      for (double v : p) s += v;
      const ChannelStats st = channel_stats(t, c);
      EXPECT_NEAR(s / st.variance, 1.0, 1e-9) << c << " " << axis;
    }
}

// Acceptance 3: mean, variance and 1-D amplitude spectra of the exemplar within 5 % (over
// seeds), every parameter inside its range; reproducible from the seed.
TEST(texture, SynthesisFromTwoDimensionalExemplarKeepsStatistics) {
  const ParamTexture ex = random_exemplar(64, 48, 5, 2, 7);
  SynthesisOptions o;
  o.size = 256;
  double err[5][2] = {};
  const int seeds = 3;
  for (int seed = 1; seed <= seeds; ++seed) {
    o.seed = static_cast<std::uint64_t>(seed);
    const ParamTexture t = synthesize_texture(ex, o);
    ASSERT_EQ(t.nx, 256u);
    EXPECT_DOUBLE_EQ(t.texel_m, ex.texel_m);
    EXPECT_TRUE(in_range(t));
    EXPECT_EQ(t.valid_count(), t.size());
    for (int c = 0; c < 5; ++c) {
      const ChannelStats a = channel_stats(ex, c), b = channel_stats(t, c);
      EXPECT_NEAR(b.mean, a.mean, 0.05 * std::sqrt(a.variance) + 1e-12) << c;
      EXPECT_NEAR(b.variance / a.variance, 1.0, 0.05) << c;
      err[c][0] += band_spectrum_error(line_power_spectrum(ex, c, 0), ex.nx, ex.texel_m,
                                       line_power_spectrum(t, c, 0), t.nx, t.texel_m) /
                   seeds;
      err[c][1] += band_spectrum_error(line_power_spectrum(ex, c, 1), ex.ny, ex.texel_m,
                                       line_power_spectrum(t, c, 1), t.ny, t.texel_m) /
                   seeds;
    }
  }
  for (int c = 0; c < 5; ++c) {
    std::printf("%s: band amplitude spectrum error x %.2e y %.2e\n", ParamTexture::channel_names[c],
                err[c][0], err[c][1]);
    EXPECT_LT(err[c][0], 0.05) << c;
    EXPECT_LT(err[c][1], 0.05) << c;
  }
  o.seed = 5;
  const ParamTexture a = synthesize_texture(ex, o), b = synthesize_texture(ex, o);
  EXPECT_EQ(a.channel[1], b.channel[1]);
  o.seed = 6;
  EXPECT_NE(synthesize_texture(ex, o).channel[1], a.channel[1]);
  EXPECT_EQ(a.meta.at("seed"), 5);
}

// A skewed exemplar: alpha_x log-normal around 0.003 (a factor e^0.6 rms), as narrow brushed
// texels are; alpha_y log-normal around 0.14 (factor e^0.3).
ParamTexture skewed_exemplar(std::size_t nx, std::size_t ny, std::uint64_t seed) {
  ParamTexture ex = random_exemplar(nx, ny, 4, 3, seed);
  for (auto& v : ex.channel[0])
    v = static_cast<float>(std::exp(std::log(0.003) + (v - 0.007) / 0.0015 * 0.6));
  for (auto& v : ex.channel[1])
    v = static_cast<float>(std::exp(std::log(0.14) + (v - 0.14) / 0.03 * 0.3));
  return ex;
}

// Without histogram matching (mean and variance only): alphas crowding the lower bound are
// clamped at alpha_min, which must not cost the mean, the variance or the spectra their 5 %.
TEST(texture, SynthesisNearTheRangeLimitKeepsStatistics) {
  ParamTexture ex = random_exemplar(48, 48, 4, 3, 11);
  for (auto& v : ex.channel[0])
    v = static_cast<float>(std::exp(std::log(0.0008) + (v - 0.007) / 0.0015 * 0.8));
  SynthesisOptions o;
  o.size = 192;
  o.match_histogram = false;
  double dm = 0, dv = 0, ds = 0;
  for (int seed = 1; seed <= 3; ++seed) {
    o.seed = static_cast<std::uint64_t>(seed);
    const ParamTexture t = synthesize_texture(ex, o);
    EXPECT_TRUE(in_range(t));
    const ChannelStats a = channel_stats(ex, 0), b = channel_stats(t, 0);
    dm += std::fabs(b.mean / a.mean - 1) / 3;
    dv += std::fabs(b.variance / a.variance - 1) / 3;
    ds += band_spectrum_error(line_power_spectrum(ex, 0, 0), ex.nx, ex.texel_m,
                              line_power_spectrum(t, 0, 0), t.nx, t.texel_m) /
          3;
    EXPECT_GT(t.meta.at("clamped_texels").at("alpha_x").get<std::size_t>(), 0u);
  }
  std::printf(
      "alpha_x near alpha_min (moments only): mean %.2e, variance %.2e, spectrum %.2e off\n", dm,
      dv, ds);
  EXPECT_LT(dm, 0.05);
  EXPECT_LT(dv, 0.05);
  EXPECT_LT(ds, 0.05);
  // The log-normal option: whichever field is kept, the same guarantees.
  o.lognormal_alpha = true;
  o.seed = 1;
  const ParamTexture t = synthesize_texture(ex, o);
  const std::string kind = t.meta.at("field").at("alpha_x");
  EXPECT_TRUE(kind == "log-normal" || kind == "gaussian") << kind;
  const ChannelStats a = channel_stats(ex, 0), b = channel_stats(t, 0);
  EXPECT_NEAR(b.mean / a.mean, 1.0, 0.05);
  EXPECT_NEAR(b.variance / a.variance, 1.0, 0.05);
  EXPECT_LT(band_spectrum_error(line_power_spectrum(ex, 0, 0), ex.nx, ex.texel_m,
                                line_power_spectrum(t, 0, 0), t.nx, t.texel_m),
            0.05);
  EXPECT_TRUE(in_range(t));
  std::printf("log-normal option kept the %s field for alpha_x\n", kind.c_str());
}

// Acceptance: every synthesised channel lies within [min, max] of the exemplar (histogram
// matching after the spectrum step), and the spectra stay as before: the radially averaged power
// spectrum within 2 % (relative L2, shapes) of the field before matching (the same seed with
// mean-and-variance matching only, which leaves the range), the line spectra within 5 % of the
// exemplar's, mean and variance within 5 %.
TEST(texture, SynthesisStaysInTheExemplarsRangeWithItsSpectrum) {
  const ParamTexture ex = skewed_exemplar(64, 48, 12);
  SynthesisOptions o;
  o.size = 192;
  SynthesisOptions before = o;
  before.match_histogram = false;
  double worst_radial = 0, worst_line = 0;
  std::size_t outside_before = 0;
  for (int seed = 1; seed <= 3; ++seed) {
    o.seed = before.seed = static_cast<std::uint64_t>(seed);
    const ParamTexture t = synthesize_texture(ex, o), b = synthesize_texture(ex, before);
    EXPECT_TRUE(t.meta.at("histogram_matched").get<bool>());
    for (int c = 0; c < 5; ++c) {
      const auto ch = static_cast<std::size_t>(c);
      const ChannelStats e = channel_stats(ex, c), s = channel_stats(t, c);
      const auto range = std::minmax_element(t.channel[ch].begin(), t.channel[ch].end());
      EXPECT_GE(*range.first, static_cast<float>(e.min)) << c;
      EXPECT_LE(*range.second, static_cast<float>(e.max)) << c;
      for (float v : b.channel[ch]) outside_before += v < e.min || v > e.max;
      EXPECT_NEAR(s.mean, e.mean, 0.05 * std::sqrt(e.variance)) << c;
      EXPECT_NEAR(s.variance / e.variance, 1.0, 0.05) << c;
      const std::vector<double> vt(t.channel[ch].begin(), t.channel[ch].end()),
          vb(b.channel[ch].begin(), b.channel[ch].end());
      const double radial = detail::spectrum_distance(detail::radial_power_spectrum(vt, t.nx),
                                                      detail::radial_power_spectrum(vb, b.nx));
      worst_radial = std::max(worst_radial, radial);
      EXPECT_LT(radial, 0.02) << c;
      EXPECT_NEAR(t.meta.at("histogram").at(ParamTexture::channel_names[c]).at("spectrum_change"),
                  radial, 0.01);
      for (int axis = 0; axis < 2; ++axis) {
        const double line =
            band_spectrum_error(line_power_spectrum(ex, c, axis), axis ? ex.ny : ex.nx, ex.texel_m,
                                line_power_spectrum(t, c, axis), axis ? t.ny : t.nx, t.texel_m);
        worst_line = std::max(worst_line, line);
        EXPECT_LT(line, 0.05) << c << " " << axis;
      }
    }
  }
  std::printf(
      "histogram matched: radial spectrum change <= %.2e, line spectra vs exemplar <= "
      "%.2e; %zu texel values outside the exemplar's range without matching\n",
      worst_radial, worst_line, outside_before);
  EXPECT_GT(outside_before, 0u);  // the problem is real on this exemplar
  // Strips: the range is the pooled range of both.
  const ParamTexture along = skewed_exemplar(100, 2, 3), across = skewed_exemplar(2, 100, 4);
  o.size = 256;
  const ParamTexture t = synthesize_texture(along, across, o);
  for (int c = 0; c < 5; ++c) {
    const ChannelStats a = channel_stats(along, c), b = channel_stats(across, c);
    const auto& ch = t.channel[static_cast<std::size_t>(c)];
    const auto range = std::minmax_element(ch.begin(), ch.end());
    EXPECT_GE(*range.first, static_cast<float>(std::min(a.min, b.min))) << c;
    EXPECT_LE(*range.second, static_cast<float>(std::max(a.max, b.max))) << c;
  }
}

TEST(texture, HistogramMatchingPieces) {
  // Quantiles: within [min, max], ends at min and max, monotone; rank remap puts them in the
  // field's order, deterministically (ties by index).
  const std::vector<float> values = {0.3f, 0.1f, 0.2f, 0.5f};
  const auto q = detail::quantile_table(values, 9);
  EXPECT_EQ(q.front(), 0.1f);
  EXPECT_EQ(q.back(), 0.5f);
  EXPECT_TRUE(std::is_sorted(q.begin(), q.end()));
  const std::vector<double> f = {3, -1, 2, 2, 0, 7, -4, 1, 5};
  std::vector<float> out;
  detail::rank_remap(f, q, out);
  std::vector<std::size_t> idx(f.size());
  for (std::size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::stable_sort(idx.begin(), idx.end(), [&](auto a, auto b) { return f[a] < f[b]; });
  for (std::size_t r = 0; r < idx.size(); ++r) EXPECT_EQ(out[idx[r]], q[r]) << r;
  EXPECT_LT(out[2], out[3] + 1e-9f);  // the tie: index 2 ranks first
  // Radial spectrum of a single cosine: all its power in one annulus.
  const std::size_t n = 32;
  std::vector<double> c(n * n);
  for (std::size_t y = 0; y < n; ++y)
    for (std::size_t x = 0; x < n; ++x)
      c[y * n + x] = std::cos(2 * std::numbers::pi * (3.0 * x + 4.0 * y) / n);
  const auto r = detail::radial_power_spectrum(c, n);
  double total = 0;
  for (double v : r) total += v;
  EXPECT_NEAR(r[5] / total, 1.0, 1e-12);
}

// Widths below a table node from the texel's own normals: on normals drawn from an ellipsoid NDF
// with alpha_x a thirtieth of a node of the 129^2 table, the median rule recovers both widths.
TEST(texture, WidthsFromNormalsRecoverANarrowEllipsoid) {
  for (const EllipsoidParams p :
       {EllipsoidParams{5e-4, 0.12, 0.02, -0.01, 0.1}, EllipsoidParams{3e-5, 0.2, -0.05, 0.0, 0.0},
        EllipsoidParams{0.004, 0.03, 0.0, 0.03, -0.3}}) {
    const EllipsoidDistribution d(p);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> normals;
    for (int i = 0; i < 200000; ++i) {
      // GGX slopes in the ellipsoid's frame (radial CDF r^2/(1 + r^2)), turned back by R^T.
      const double u1 = u(rng), r = std::sqrt(u1 / (1 - u1)), phi = 2 * std::numbers::pi * u(rng);
      const Vec3 mp =
          Vec3(-p.alpha_x * r * std::cos(phi), -p.alpha_y * r * std::sin(phi), 1).normalized();
      normals.push_back(d.R().transpose() * mp);
    }
    const auto w = ellipsoid_widths_from_normals(normals, p);
    std::printf("alpha (%.3g, %.3g): from normals (%.4g, %.4g)\n", p.alpha_x, p.alpha_y, w[0],
                w[1]);
    EXPECT_NEAR(w[0] / p.alpha_x, 1.0, 0.02);
    EXPECT_NEAR(w[1] / p.alpha_y, 1.0, 0.02);
  }
  EXPECT_THROW(ellipsoid_widths_from_normals({Vec3(0, 0, 1)}, EllipsoidParams{}), InputError);
}

TEST(texture, SynthesisFromStripsUsesEachAxis) {
  // Dong's exemplars: a 100 x 1 strip along the brushing, a 1 x 100 strip across; different
  // correlation lengths along x and y, so each axis' spectrum must come from its own strip.
  const ParamTexture along = random_exemplar(100, 1, 8, 1, 3);
  const ParamTexture across = random_exemplar(1, 100, 1, 2, 4);
  SynthesisOptions o;
  o.size = 400;
  o.seed = 2;
  const ParamTexture t = synthesize_texture(along, across, o);
  EXPECT_TRUE(in_range(t));
  for (int c = 0; c < 5; ++c) {
    const double ex = band_spectrum_error(line_power_spectrum(along, c, 0), 100, along.texel_m,
                                          line_power_spectrum(t, c, 0), t.nx, t.texel_m);
    const double ey = band_spectrum_error(line_power_spectrum(across, c, 1), 100, across.texel_m,
                                          line_power_spectrum(t, c, 1), t.ny, t.texel_m);
    EXPECT_LT(ex, 0.05) << c;
    EXPECT_LT(ey, 0.05) << c;
    // ... and not from the other strip.
    EXPECT_GT(band_spectrum_error(line_power_spectrum(across, c, 1), 100, across.texel_m,
                                  line_power_spectrum(t, c, 0), t.nx, t.texel_m),
              0.2)
        << c;
  }
  EXPECT_THROW(synthesize_texture(across, along, o), InputError);  // strips the wrong way round
}

TEST(texture, SynthesisAtAnotherPitchKeepsPhysicalFrequencies) {
  // Output texels twice as large: the spectrum in cycles per metre is kept up to the new Nyquist
  // frequency (half the exemplar's); band j of the output holds exemplar bands 2j-1.. folded in.
  const ParamTexture ex = random_exemplar(64, 64, 6, 6, 9);
  SynthesisOptions o;
  o.size = 128;
  o.texel_m = 2 * ex.texel_m;
  const ParamTexture t = synthesize_texture(ex, o);
  EXPECT_DOUBLE_EQ(t.texel_m, 2 * ex.texel_m);
  // Physical length covered: output 128 * 2 p = 4x the exemplar; the output's correlation length
  // in texels is half the exemplar's: compare lag-1 autocorrelations along x via the spectra.
  auto lag1 = [](const std::vector<double>& p, std::size_t n) {
    double s = 0, c = 0;
    for (std::size_t k = 1; k < p.size(); ++k) {
      s += p[k];
      c += p[k] * std::cos(2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(n));
    }
    return c / s;
  };
  const double r_ex2 = [&] {  // exemplar autocorrelation at lag 2 texels = 1 output texel
    const auto p = line_power_spectrum(ex, 1, 0);
    double s = 0, c = 0;
    for (std::size_t k = 1; k < p.size(); ++k) {
      s += p[k];
      c += p[k] * std::cos(4 * std::numbers::pi * static_cast<double>(k) / 64.0);
    }
    return c / s;
  }();
  EXPECT_NEAR(lag1(line_power_spectrum(t, 1, 0), t.nx), r_ex2, 0.05);
}

TEST(texture, ParamTextureExrRoundTrip) {
  const auto dir = temp_dir("exr");
  ParamTexture t = random_exemplar(17, 9, 3, 2, 5);
  t.valid[4] = 0;
  t.why_invalid[4] = "fit did not converge: test";
  t.channel[2][4] = std::numeric_limits<float>::quiet_NaN();
  t.meta["seed"] = 12;
  const std::string path = (dir / "t.exr").string();
  write_param_texture(t, path);
  EXPECT_TRUE(is_param_texture_file(path));
  const ParamTexture r = read_param_texture(path);
  ASSERT_EQ(r.nx, 17u);
  ASSERT_EQ(r.ny, 9u);
  EXPECT_DOUBLE_EQ(r.texel_m, t.texel_m);
  for (int c = 0; c < 5; ++c)
    for (std::size_t i = 0; i < t.size(); ++i)
      if (i != 4) {
        EXPECT_EQ(r.channel[static_cast<std::size_t>(c)][i],
                  t.channel[static_cast<std::size_t>(c)][i]);
      }
  EXPECT_EQ(r.valid, t.valid);
  EXPECT_EQ(r.why_invalid[4], "fit did not converge: test");
  EXPECT_EQ(r.meta.at("seed"), 12);
  write_param_preview(t, (dir / "t.png").string());
  EXPECT_TRUE(fs::file_size(dir / "t.png") > 100);
  // Not a parameter texture: a height map, a missing file.
  Surface s(8, 8, 1e-6, 1e-6);
  write_surface(s, (dir / "h.npy").string());
  EXPECT_FALSE(is_param_texture_file((dir / "h.npy").string()));
  EXPECT_FALSE(is_param_texture_file((dir / "missing.exr").string()));
  EXPECT_THROW(read_param_texture((dir / "missing.exr").string()), FileError);
  EXPECT_THROW(read_param_texture((dir / "h.npy").string()), FileError);
  fs::remove_all(dir);
}

// Acceptance 4 (Dong Fig. 11): small-area NDFs of a brushed surface are skewed: their peaks lean
// away from n by the texel's mean tilt, which the ellipsoid's theta_x / theta_y capture, while
// the whole area's NDF is centred.
TEST(texture, BrushedTexelsAreSkewedLikeTheirMeanNormal) {
  BrushedParams bp = brushed_preset("stainless4");
  bp.nx = 768;
  bp.ny = 384;
  bp.seed = 3;
  const Surface s = generate_brushed(bp);
  TexelFitOptions o;
  o.texel_m = 14e-6;  // 127 samples: 6 x 3 texels
  const ParamTexture t = fit_texels(s, o);
  ASSERT_EQ(t.nx, 6u);
  ASSERT_EQ(t.ny, 3u);
  EXPECT_EQ(t.valid_count(), t.size()) << t.why_invalid[0];
  // The texels' own mean normals (filtered normals of the levelled surface, as fit_texels uses).
  Surface lv = s;
  level_surface(lv, LevelingSpec{});
  const NormalField nf = filtered_normals(lv, o.filter_sigma_m);
  const double per = o.texel_m / s.dx;
  double tilt2 = 0, miss2 = 0, alpha_y = 0;
  std::vector<double> py, my;
  for (std::size_t ty = 0; ty < t.ny; ++ty)
    for (std::size_t tx = 0; tx < t.nx; ++tx) {
      Vec3 m(0, 0, 0);
      for (auto y = static_cast<std::size_t>(std::llround(ty * per));
           y < static_cast<std::size_t>(std::llround((ty + 1) * per)); ++y)
        for (auto x = static_cast<std::size_t>(std::llround(tx * per));
             x < static_cast<std::size_t>(std::llround((tx + 1) * per)); ++x) {
          const std::size_t j = y * s.nx + x;
          if (nf.mz[j] > 0) m += Vec3(nf.mx[j], nf.my[j], nf.mz[j]);
        }
      m.normalize();
      const EllipsoidParams p = t.at(tx, ty);
      const Vec3 peak = EllipsoidDistribution(p).peak();
      // Peak tilt across the brushing (y) against the texel's mean normal.
      miss2 += (peak.y() - m.y()) * (peak.y() - m.y());
      py.push_back(peak.y());
      my.push_back(m.y());
      tilt2 += p.theta_x * p.theta_x;
      alpha_y += p.alpha_y / static_cast<double>(t.size());
    }
  const double tilt_rms = std::sqrt(tilt2 / static_cast<double>(t.size()));
  const double miss_rms = std::sqrt(miss2 / static_cast<double>(t.size()));
  // Whole area: the same NDF fitted over the whole surface is centred.
  NdfEstimateOptions eo;
  eo.resolution = 257;
  const FitResult whole = fit_ndf(estimate_ndf(lv, eo), FitOptions{});
  std::printf(
      "texel theta_x rms %.4f rad (peak vs mean normal rms %.4f), whole-area theta_x %.4f, "
      "mean texel alpha_y %.3f\n",
      tilt_rms, miss_rms, whole.params.at("theta_x"), alpha_y);
  // The peak leans the way the texel leans (correlation of peak and mean-normal tilts), by more
  // than the whole area's peak does.
  double sa = 0, sb = 0, sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < py.size(); ++i) {
    sa += py[i], sb += my[i], sab += py[i] * my[i], saa += py[i] * py[i], sbb += my[i] * my[i];
  }
  const double nn = static_cast<double>(py.size());
  const double corr = (sab - sa * sb / nn) / std::sqrt((saa - sa * sa / nn) * (sbb - sb * sb / nn));
  std::printf("correlation of peak and mean-normal tilt across the brushing: %.3f\n", corr);
  EXPECT_GT(tilt_rms, 0.01);
  EXPECT_GT(tilt_rms, 3 * std::fabs(whole.params.at("theta_x")));
  EXPECT_GT(corr, 0.8);
}

TEST(texture, TexelLayoutValidityAndScanSets) {
  const auto dir = temp_dir("scans");
  GaussianSurfaceParams g;
  g.nx = 200;
  g.ny = 110;
  g.sigma = 0.05e-6;
  g.tau_x = g.tau_y = 2e-6;
  std::vector<std::string> paths;
  for (int k = 0; k < 2; ++k) {
    g.seed = static_cast<std::uint64_t>(k + 1);
    Surface s = generate_gaussian(g);
    if (k == 1)  // a hole over the first texel of the second scan
      for (std::size_t y = 0; y < 50; ++y)
        for (std::size_t x = 0; x < 50; ++x) s.invalidate(y * s.nx + x);
    paths.push_back((dir / ("s" + std::to_string(k) + ".x3p")).string());
    write_surface(s, paths.back());
  }
  TexelFitOptions o;
  o.texel_m = 5.5e-6;  // 50 samples: 4 x 2 texels per scan, 10 columns dropped
  o.ndf_resolution = 65;
  const ParamTexture t = fit_texels(paths, ReadOptions{}, o);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (!t.valid[i]) std::printf("texel %zu: %s\n", i, t.why_invalid[i].c_str());
  EXPECT_EQ(t.nx, 8u);
  EXPECT_EQ(t.ny, 2u);
  EXPECT_EQ(t.valid[4], 0);
  EXPECT_NE(t.why_invalid[4].find("too few filtered normals"), std::string::npos);
  EXPECT_EQ(t.valid_count(), 15u);
  EXPECT_EQ(t.meta.at("scans").size(), 2u);
  EXPECT_EQ(t.meta.at("scans")[1].at("offset"), 4);
  EXPECT_EQ(t.meta.at("failed"), 1);
  // Isotropic Gaussian: the texels' alphas agree on average, and lie below the whole area's
  // filtered Beckmann width (a small area holds only part of the slope variance, and the
  // GGX-tailed ellipsoid is narrower than Beckmann at equal variance).
  const double expect = predicted_filtered_alpha(g.sigma, g.tau_x, g.tau_y, o.filter_sigma_m);
  const double ax = channel_stats(t, 0).mean, ay = channel_stats(t, 1).mean;
  std::printf("texel alphas %.4f %.4f, whole-area filtered Beckmann width %.4f\n", ax, ay, expect);
  EXPECT_NEAR(ax / ay, 1.0, 0.2);
  EXPECT_GT(ax, 0.3 * expect);
  EXPECT_LT(ax, 1.0 * expect);
  o.stack_along_y = true;
  const ParamTexture ty = fit_texels(paths, ReadOptions{}, o);
  EXPECT_EQ(ty.nx, 4u);
  EXPECT_EQ(ty.ny, 4u);
  EXPECT_EQ(ty.valid[0 + 4 * 2], 0);
  o.texel_m = 30e-6;  // larger than the scan
  EXPECT_THROW(fit_texels(paths, ReadOptions{}, o), InputError);
  fs::remove_all(dir);
}

TEST(texture, SvbrdfMatchesUniformMicrofacetBrdf) {
  ParamTexture t = ParamTexture::empty(4, 3, 53e-6, "");
  const EllipsoidParams p0{0.1, 0.3, 0.05, -0.03, 0.2}, p1{0.2, 0.15, -0.04, 0.02, -0.1};
  for (std::size_t i = 0; i < t.size(); ++i) {
    const EllipsoidParams& p = (i % 2) ? p1 : p0;
    const double v[5] = {p.alpha_x, p.alpha_y, p.theta_x, p.theta_y, p.theta_z};
    for (int c = 0; c < 5; ++c)
      t.channel[static_cast<std::size_t>(c)][i] = static_cast<float>(v[c]);
    t.valid[i] = 1;
  }
  t.valid[2] = 0;  // invalid: drawn with the mean
  auto tex = std::make_shared<const ParamTexture>(t);
  auto fres = std::make_shared<const ConductorFresnel>(metal("Al"));
  const EllipsoidTextureSvbrdf sv(tex, fres);
  auto params_of = [&](std::size_t i) {
    const auto q = tex->at(i % 4, i / 4);
    return EllipsoidParams{q.alpha_x, q.alpha_y, q.theta_x, q.theta_y, q.theta_z};
  };
  const Vec3 wi = Vec3(0.3, -0.2, 0.9).normalized(), wo = Vec3(-0.25, 0.3, 0.8).normalized();
  // Texel 1 = (1, 0): u in [0.25, 0.5), v in [0, 1/3); also one repeat over.
  const MicrofacetBrdf ref(std::make_shared<EllipsoidDistribution>(params_of(1)), fres, true);
  for (double du : {0.0, 1.0, -2.0}) {
    EXPECT_NEAR(sv.eval(0.3 + du, 0.1, wi, wo, 550e-9), ref.eval(wi, wo, 550e-9),
                1e-12 * ref.eval(wi, wo, 550e-9));
    EXPECT_NEAR(sv.pdf(0.3 + du, 0.1, wi, wo), ref.pdf(wi, wo), 1e-12 * ref.pdf(wi, wo));
  }
  const auto a = sv.sample(0.3, 0.1, wi, 0.3, 0.7, 550e-9);
  const auto b = ref.sample(wi, 0.3, 0.7, 550e-9);
  ASSERT_TRUE(a && b);
  EXPECT_NEAR((a->wo - b->wo).norm(), 0, 1e-12);
  EXPECT_NEAR(a->weight, b->weight, 1e-12);
  // Weight = f cos / pdf.
  EXPECT_NEAR(a->weight, sv.eval(0.3, 0.1, wi, a->wo, 550e-9) * a->wo.z() / a->pdf, 1e-9);
  // Reciprocity (F(wi.h) = F(wo.h), separable G symmetric) on every texel.
  for (double u : {0.05, 0.3, 0.55, 0.8})
    for (double v : {0.1, 0.5, 0.9}) {
      const double f1 = sv.eval(u, v, wi, wo, 550e-9), f2 = sv.eval(u, v, wo, wi, 550e-9);
      EXPECT_NEAR(f1, f2, 1e-12 * f1) << u << " " << v;
    }
  // Neighbouring texels differ; the invalid texel uses the mean of the valid ones.
  EXPECT_NE(sv.eval(0.05, 0.1, wi, wo, 550e-9), sv.eval(0.3, 0.1, wi, wo, 550e-9));
  const EllipsoidParams m = sv.params_at(0.6, 0.1);  // texel (2, 0) = index 2
  EXPECT_NEAR(m.alpha_x, tex->mean_valid().alpha_x, 1e-12);
  EXPECT_NE(sv.describe().find("ellipsoid-NDF texture 4 x 3"), std::string::npos);
  // Energy: the albedo of each texel's lobe is at most 1 (F <= 1, G <= 1).
  const double alb = directional_albedo_sampled(ref, wi, 550e-9, 64);
  EXPECT_LE(alb, 1.0 + 1e-6);
  EXPECT_GT(alb, 0.5);
}

// Zoomed refits. (1) On normals drawn from an ellipsoid with alpha_x a thirtieth of a node of the
// 129^2 table, the zoomed table recovers alpha_x. (2) On stainless4 texels the zoom is neutral
// where the plain table resolves the lobe: alpha_y (~0.1, 6+ nodes) refitted with a 3-fold zoom
// agrees with the plain fit.
TEST(texture, ZoomedRefitRecoversNarrowLobes) {
  TexelFitOptions o;
  for (const EllipsoidParams p : {EllipsoidParams{5e-4, 0.12, 0.02, -0.001, 0.0},
                                  EllipsoidParams{3e-5, 0.2, -0.05, 0.0, 0.0}}) {
    const EllipsoidDistribution d(p);
    std::mt19937_64 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::vector<Vec3> normals;
    for (int i = 0; i < 100000; ++i) {
      const double u1 = u(rng), r = std::sqrt(u1 / (1 - u1)), phi = 2 * std::numbers::pi * u(rng);
      const Vec3 mp =
          Vec3(-p.alpha_x * r * std::cos(phi), -p.alpha_y * r * std::sin(phi), 1).normalized();
      normals.push_back(d.R().transpose() * mp);
    }
    EllipsoidParams first = p;
    first.alpha_x = 0.004;  // what the plain table gives: "below a node"
    const EllipsoidParams z = refit_narrow_lobe(normals, first, o);
    std::printf("alpha_x %.3g: zoomed refit %.4g (theta_y %.3g)\n", p.alpha_x, z.alpha_x,
                z.theta_y);
    EXPECT_NEAR(z.alpha_x / p.alpha_x, 1.0, 0.05);
    EXPECT_EQ(z.alpha_y, first.alpha_y);
  }
}

TEST(texture, ZoomedRefitAgreesWithResolvedFits) {
  BrushedParams bp = brushed_preset("stainless4");
  bp.nx = 768;
  bp.ny = 384;
  bp.seed = 3;
  const Surface s = generate_brushed(bp);
  TexelFitOptions o;
  o.texel_m = 14e-6;
  const ParamTexture fit = fit_texels(s, o);
  EXPECT_EQ(fit.meta.at("alpha_zoomed").get<std::size_t>(), fit.valid_count());
  EXPECT_EQ(fit.meta.at("alpha_lifted_to_min").get<std::size_t>(), 0u);
  // The zoom on alpha_y: refit each texel with "below" raised above its alpha_y, zoom 3x.
  Surface lv = s;
  level_surface(lv, LevelingSpec{});
  const NormalField nf = filtered_normals(lv, o.filter_sigma_m);
  const double per = o.texel_m / s.dx;
  std::vector<double> ratio;
  for (std::size_t ty = 0; ty < fit.ny; ++ty)
    for (std::size_t tx = 0; tx < fit.nx; ++tx) {
      const std::size_t i = tx + fit.nx * ty;
      if (!fit.valid[i]) continue;
      std::vector<Vec3> normals;
      for (auto y = static_cast<std::size_t>(std::llround(ty * per));
           y < static_cast<std::size_t>(std::llround((ty + 1) * per)); ++y)
        for (auto x = static_cast<std::size_t>(std::llround(tx * per));
             x < static_cast<std::size_t>(std::llround((tx + 1) * per)); ++x) {
          const std::size_t j = y * s.nx + x;
          if (nf.mz[j] > 0) normals.emplace_back(nf.mx[j], nf.my[j], nf.mz[j]);
        }
      const EllipsoidParams p = fit.at(tx, ty);
      TexelFitOptions zo = o;
      zo.zoom_below_nodes = p.alpha_y / (2.0 / 128) * 1.01;  // just above: alpha_y gets zoomed
      const double median_rule = ellipsoid_widths_from_normals(normals, p)[1];
      zo.zoom_nodes = 3 * p.alpha_y / (2.0 / 128) * median_rule / p.alpha_y;  // k = 3
      EllipsoidParams q = p;
      q.alpha_x = 1;  // only alpha_y is below "below"
      const EllipsoidParams z = refit_narrow_lobe(normals, q, zo);
      ratio.push_back(z.alpha_y / p.alpha_y);
    }
  ASSERT_GT(ratio.size(), 10u);
  std::sort(ratio.begin(), ratio.end());
  std::printf(
      "alpha_y zoomed 3x / plain fit: median %.3f, range %.3f-%.3f over %zu texels; "
      "zoomed alpha_x mean %.2e (a node is %.4f)\n",
      ratio[ratio.size() / 2], ratio.front(), ratio.back(), ratio.size(),
      channel_stats(fit, 0).mean, 2.0 / 128);
  EXPECT_NEAR(ratio[ratio.size() / 2], 1.0, 0.05);
}

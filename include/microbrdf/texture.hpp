#pragma once
// Spatially varying ellipsoid-NDF textures (Dong 2015 section 9): per-texel filtered NDFs and
// ellipsoid fits, separable Fourier synthesis of large parameter textures from small exemplars,
// and the SVBRDF that draws them.
//
// Units: texel sizes and pitches in metres; angles in radians; alphas dimensionless.
// Channel order everywhere: alpha_x, alpha_y, theta_x, theta_y, theta_z (EllipsoidParams).

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/surface.hpp"
#include "microbrdf/svbrdf.hpp"

namespace microbrdf {

/// A 5-channel ellipsoid parameter image, row-major, iy = 0 first, (ix, iy) -> ix + nx * iy.
struct ParamTexture {
  std::size_t nx = 0, ny = 0;
  double texel_m = 0;                         ///< texel pitch (both axes)
  std::array<std::vector<float>, 5> channel;  ///< alpha_x, alpha_y, theta_x, theta_y, theta_z
  std::vector<std::uint8_t> valid;            ///< 1 = fitted / synthesised; 0 = failed
  std::vector<std::string> why_invalid;       ///< per texel, empty where valid
  nlohmann::json meta;                        ///< sources, seed, texel size, fit settings
  EllipsoidParams at(std::size_t ix, std::size_t iy) const;

  // Added by the texture implementation (docs/texture.md).
  static constexpr const char* channel_names[5] = {"alpha_x", "alpha_y", "theta_x", "theta_y",
                                                   "theta_z"};
  std::size_t size() const { return nx * ny; }
  std::size_t valid_count() const;
  /// Mean of each channel over the valid texels (EllipsoidParams{} defaults if none is valid).
  EllipsoidParams mean_valid() const;
  /// An nx x ny texture, every texel invalid with NaN parameters and reason `why`.
  static ParamTexture empty(std::size_t nx, std::size_t ny, double texel_m, const std::string& why);
};

/// Valid ranges the fits and the synthesis keep parameters in.
struct ParamRange {
  static constexpr double alpha_min = 1e-5, alpha_max = 2.0;
  static constexpr double tilt_max = 0.5;  ///< |theta_x|, |theta_y|, rad
};

struct TexelFitOptions {
  double texel_m = 53e-6;        ///< texel size (square), m
  double filter_sigma_m = 1e-6;  ///< filtered NDF kernel (Dong section 5.1)
  std::size_t ndf_resolution = 129;
  int threads = 0;
  std::function<void(double)> progress;

  // Added by the texture implementation.
  LevelingSpec leveling;       ///< applied to each scan before its texels are cut (default plane)
  bool stack_along_y = false;  ///< lay successive scans' texels along y (a 1 x N "across" strip)
  double min_valid_fraction = 0.5;  ///< a texel needs filtered normals at this fraction of samples
  double min_area_fraction = 0.98;  ///< a border texel this much inside the scan still counts
  /// How the model meets the texel table (fit.hpp). Node (default): D at the nodes with a fitted
  /// amplitude, 10-80 ms per texel. Tent: the exact histogram operator, ~100x slower, because a
  /// brushed texel's lobe along the scratches is narrower than a node at any affordable
  /// resolution (docs/texture.md) and tent mode then refines its quadrature to the limit.
  FitSampling sampling = FitSampling::Node;
  int max_iterations = 200;  ///< Levenberg-Marquardt iterations per texel
  /// A fitted width below this many table nodes (2/(N-1) each) is refitted on a table zoomed
  /// along that axis so that the lobe spans about zoom_nodes nodes (refit_narrow_lobe; counted
  /// in meta.alpha_zoomed): the N^2 table cannot show a lobe narrower than a node. 0 = never.
  double zoom_below_nodes = 1.0;
  double zoom_nodes = 10.0;
};

/// Refits a texel's ellipsoid whose width along x and/or y is below zoom_below_nodes nodes of the
/// N^2 table on a table zoomed along that axis: the slopes (m_x/m_z, m_y/m_z) of the texel's
/// normals are stretched k-fold along it (k = zoom_nodes nodes / the width the median rule of
/// ellipsoid_widths_from_normals gives, 1..1e5) before they are splatted, the ellipsoid fitted as
/// usual, and its width and tilt along that axis divided by k. The other parameters are kept from
/// `first`. Returns `first` when nothing is below a node or the zoomed fit does not converge.
EllipsoidParams refit_narrow_lobe(const std::vector<Vec3>& normals, const EllipsoidParams& first,
                                  const TexelFitOptions& options);

/// Widths (alpha_x, alpha_y) of the ellipsoid NDF with the tilts of `p` from unit normals
/// (projected-area weighted, as a texel's filtered normals are) directly, without a table: each
/// normal is turned into the ellipsoid's frame (m' = R m, EllipsoidDistribution::R), its slopes
/// s = (m'x/m'z, m'y/m'z) taken, and alpha = sqrt(3) median |s - median s| per axis. In that
/// frame the ellipsoid NDF is GGX, whose slope marginal 1/(2a) (1 + s^2/a^2)^(-3/2) has
/// median |s| = a/sqrt(3) (its variance is infinite, so the median, not the second moment). Exact
/// for untilted lobes; the tilt's change of the area weighting (m.n against m'.z) is of order
/// tilt x width. Needs >= 2 normals with m'z > 0; throws InputError otherwise.
std::array<double, 2> ellipsoid_widths_from_normals(const std::vector<Vec3>& normals,
                                                    const EllipsoidParams& p);

/// Cuts every scan of the set into whole texels (partial texels at the borders are dropped, the
/// count is in meta) and fits an ellipsoid NDF to each texel's filtered NDF. One scan in memory at
/// a time; the texels of successive scans are laid side by side along x. Under mpirun the scans
/// are spread over the ranks (distribute.hpp) and assembled on rank 0 in scan order (the same
/// texture for any number of ranks and threads); other ranks get an empty texture. `stats`
/// (rank 0): scans and seconds per rank.
ParamTexture fit_texels(const std::vector<std::string>& scans, const ReadOptions& read,
                        const TexelFitOptions& options, WorkStats* stats = nullptr);
/// The same for one surface already in memory.
ParamTexture fit_texels(const Surface& s, const TexelFitOptions& options);

struct SynthesisOptions {
  std::size_t size = 2048;  ///< output is size x size texels
  double texel_m = 0;       ///< output pitch; 0 = the exemplars' pitch
  std::uint64_t seed = 1;
  /// Added: synthesise alpha_x, alpha_y as log-normal fields (exp of a Gaussian field whose
  /// correlation is pre-distorted so that the alphas get the exemplar's spectrum, mean and
  /// variance): positive and right-skewed like the fitted alphas, so far fewer texels are clamped
  /// at alpha_min than with a Gaussian field (docs/texture.md). false = D15's Gaussian field.
  bool lognormal_alpha = false;
  /// Histogram matching after the spectrum step: every channel's values are the exemplars'
  /// quantiles (so within their range); rounds of the iterative amplitude-adjusted Fourier
  /// transform restore the spectrum until its moduli are within histogram_tolerance (relative
  /// L2) of the design, at most histogram_rounds (docs/texture.md).
  /// false = the exemplars' mean and variance, clamped to ParamRange.
  bool match_histogram = true;
  int histogram_rounds = 20;
  double histogram_tolerance = 0.01;
};
/// Separable synthesis from an exemplar strip along the brushing direction (its 1D spectra along
/// x) and one across (along y): per-parameter amplitude spectra, outer product, resampling to the
/// target size and pitch, random phase, inverse FFT, matched mean and variance, clamped to range.
ParamTexture synthesize_texture(const ParamTexture& along, const ParamTexture& across,
                                const SynthesisOptions& options);
/// The same from any 2D exemplar (its 1D spectra along both axes).
ParamTexture synthesize_texture(const ParamTexture& exemplar, const SynthesisOptions& options);

/// Per-parameter statistics and 1-D spectra (what synthesis keeps; docs/texture.md).
struct ChannelStats {
  double mean = 0, variance = 0, min = 0, max = 0;
  std::size_t count = 0;  ///< valid texels
};
ChannelStats channel_stats(const ParamTexture& t, int channel);
/// One-sided power spectrum of a channel along x (axis 0, rows) or y (axis 1, columns), averaged
/// over the lines: invalid texels take the channel mean, the channel mean is subtracted, and
/// P[k] = c_k |X_k|^2 / n^2 (c_k = 2 for 0 < k < n/2, else 1) for k = 0..n/2, so sum_{k>0} P[k]
/// is the variance along a line. Bin k is the spatial frequency k / (n texel_m) (1/m).
std::vector<double> line_power_spectrum(const ParamTexture& t, int channel, int axis);

/// 5-channel float EXR (+ a 6th "valid" channel) with meta in a header attribute; atomic.
void write_param_texture(const ParamTexture& t, const std::string& path);
ParamTexture read_param_texture(const std::string& path);
/// True if `path` is an EXR holding a parameter texture (an "alpha_x" channel); false for other
/// files (height-map EXRs, other formats). Never throws.
bool is_param_texture_file(const std::string& path);
/// One PNG with a panel per channel (false colour between the channel's 1st and 99th
/// percentile, range printed under it) and the validity mask (failed texels red); long side at
/// most max_panel pixels per panel. Atomic; throws FileError.
void write_param_preview(const ParamTexture& t, const std::string& path,
                         std::size_t max_panel = 512);

/// Ellipsoid microfacet BRDF (Dong eq. 1 with eq. 14 shadowing) with each texel's parameters
/// (nearest texel; (u, v) in texture repeats) and a Fresnel term; invalid texels use the mean.
class EllipsoidTextureSvbrdf final : public Svbrdf {
 public:
  EllipsoidTextureSvbrdf(std::shared_ptr<const ParamTexture> tex, std::shared_ptr<const Fresnel> f);
  double eval(double u, double v, const Vec3& wi, const Vec3& wo,
              double wavelength_m) const override;
  std::optional<BrdfSample> sample(double u, double v, const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(double u, double v, const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;
  /// The parameters used at (u, v): the nearest texel's, or the mean where it is invalid.
  EllipsoidParams params_at(double u, double v) const;
  const ParamTexture& texture() const { return *tex_; }

 private:
  std::shared_ptr<const ParamTexture> tex_;
  std::shared_ptr<const Fresnel> f_;
  EllipsoidParams mean_;
};

/// The Svbrdf a BRDF spec describes: for the texture kind the texture read from spec.texture as
/// an EllipsoidTextureSvbrdf with the material's Fresnel term, for every other kind
/// UniformSvbrdf(make_brdf(spec, material)). Throws FileError / InputError as make_brdf does.
std::shared_ptr<const Svbrdf> make_svbrdf(const BrdfSpec& spec, const MaterialSpec& material);

}  // namespace microbrdf

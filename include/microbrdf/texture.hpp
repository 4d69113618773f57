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

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/surface.hpp"
#include "microbrdf/svbrdf.hpp"

namespace microbrdf {

/// A 5-channel ellipsoid parameter image, row-major, iy = 0 first, (ix, iy) -> ix + nx * iy.
struct ParamTexture {
  std::size_t nx = 0, ny = 0;
  double texel_m = 0;  ///< texel pitch (both axes)
  std::array<std::vector<float>, 5> channel;  ///< alpha_x, alpha_y, theta_x, theta_y, theta_z
  std::vector<std::uint8_t> valid;             ///< 1 = fitted / synthesised; 0 = failed
  std::vector<std::string> why_invalid;        ///< per texel, empty where valid
  nlohmann::json meta;                         ///< sources, seed, texel size, fit settings
  EllipsoidParams at(std::size_t ix, std::size_t iy) const;
};

/// Valid ranges the fits and the synthesis keep parameters in.
struct ParamRange {
  static constexpr double alpha_min = 1e-3, alpha_max = 2.0;
  static constexpr double tilt_max = 0.5;  ///< |theta_x|, |theta_y|, rad
};

struct TexelFitOptions {
  double texel_m = 53e-6;          ///< texel size (square), m
  double filter_sigma_m = 1e-6;    ///< filtered NDF kernel (Dong section 5.1)
  std::size_t ndf_resolution = 129;
  int threads = 0;
  std::function<void(double)> progress;
};

/// Cuts every scan of the set into whole texels (partial texels at the borders are dropped, the
/// count is in meta) and fits an ellipsoid NDF to each texel's filtered NDF. One scan in memory at
/// a time; the texels of successive scans are laid side by side along x.
ParamTexture fit_texels(const std::vector<std::string>& scans, const ReadOptions& read,
                        const TexelFitOptions& options);
/// The same for one surface already in memory.
ParamTexture fit_texels(const Surface& s, const TexelFitOptions& options);

struct SynthesisOptions {
  std::size_t size = 2048;  ///< output is size x size texels
  double texel_m = 0;       ///< output pitch; 0 = the exemplars' pitch
  std::uint64_t seed = 1;
};
/// Separable synthesis from an exemplar strip along the brushing direction (its 1D spectra along
/// x) and one across (along y): per-parameter amplitude spectra, outer product, resampling to the
/// target size and pitch, random phase, inverse FFT, matched mean and variance, clamped to range.
ParamTexture synthesize_texture(const ParamTexture& along, const ParamTexture& across,
                                const SynthesisOptions& options);
/// The same from any 2D exemplar (its 1D spectra along both axes).
ParamTexture synthesize_texture(const ParamTexture& exemplar, const SynthesisOptions& options);

/// 5-channel float EXR (+ a 6th "valid" channel) with meta in a header attribute; atomic.
void write_param_texture(const ParamTexture& t, const std::string& path);
ParamTexture read_param_texture(const std::string& path);

/// Ellipsoid microfacet BRDF (Dong eq. 1 with eq. 14 shadowing) with each texel's parameters
/// (nearest texel; (u, v) in texture repeats) and a Fresnel term; invalid texels use the mean.
class EllipsoidTextureSvbrdf final : public Svbrdf {
 public:
  EllipsoidTextureSvbrdf(std::shared_ptr<const ParamTexture> tex, std::shared_ptr<const Fresnel> f);
  double eval(double u, double v, const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  std::optional<BrdfSample> sample(double u, double v, const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(double u, double v, const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;

 private:
  std::shared_ptr<const ParamTexture> tex_;
  std::shared_ptr<const Fresnel> f_;
};

}  // namespace microbrdf

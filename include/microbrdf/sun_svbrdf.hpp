#pragma once
// Sun 2002's analytic BRDF with spatially varying smoothness and colour from images (Sun's
// Fig. 11: (a) a smoothness texture on copper, (b) a colour texture, "metallic paints"), behind
// the Svbrdf interface the renderer draws with.
//
// Texture coordinates as everywhere (svbrdf.hpp): one unit = one repeat, the image wraps; u runs
// along the image's columns (left to right), v along its rows from the bottom up (v = 0 at the
// bottom edge), so an image appears upright on the preview objects. Nearest texel.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/sun2002.hpp"
#include "microbrdf/svbrdf.hpp"

namespace microbrdf::sun2002 {

/// An RGB image as a texture: values in [0, 1] as the file stores them (a PNG's sRGB-encoded
/// 8- or 16-bit values divided by their maximum; grey images give three equal channels; alpha is
/// ignored), or the linear floats of an OpenEXR / Radiance .hdr file. Row-major from the top.
struct TextureImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
  bool srgb_encoded = true;  ///< PNG: values are sRGB-encoded; EXR / HDR: linear
  std::string path;
};

/// Reads a .png (libpng), .exr or .hdr texture (by its signature), at most 4096 x 4096 texels.
/// Throws FileError naming the file (missing, not an image, corrupt, too large).
TextureImage read_texture_image(const std::string& path);

struct SunTextureOptions {
  double s = 5;                           ///< the smoothness where there is no smoothness map
  std::optional<TextureImage> s_map;      ///< grey value g (channel mean, clamped to [0, 1]) ...
  double s_min = 1, s_max = 20;           ///< ... gives s = s_min + g (s_max - s_min)
  std::optional<TextureImage> color_map;  ///< each texel's colour: R0 spectrum, eta = 1 (Sun 5.2)
  BrdfForm form = BrdfForm::Standard;
  FtpTerms ftp = FtpTerms::Both;
  std::shared_ptr<const Fresnel> fresnel;  ///< where there is no colour map (null: R = 1)
};

/// "MIN,MAX" (0 < MIN <= MAX), the smoothness range of a smoothness map. InputError otherwise.
std::pair<double, double> parse_s_range(const std::string& text);

/// The renderer's Sun 2002 options as typed on its command line (`render --sun-form, --sun-ftp,
/// --s-texture, --s-range, --color-texture`).
struct SunRenderOptions {
  std::string form = "standard", ftp = "both", s_texture, s_range = "1,20", color_texture;
  /// Whether any differs from the plain `--sun S` (then make_sun_svbrdf builds the material).
  bool given() const;
  /// Parses form, ftp and the range (InputError naming the value), reading no file.
  void check() const;
};

/// The material of those options: SunBrdf (as a UniformSvbrdf) without textures, else a
/// SunTextureSvbrdf reading the images (FileError naming the file). `s` is the smoothness of
/// `--sun` (unused with a smoothness map), `fresnel` the material (unused with a colour map).
std::shared_ptr<const Svbrdf> make_sun_svbrdf(const SunRenderOptions& o, double s,
                                              std::shared_ptr<const Fresnel> fresnel);

/// Sun's BRDF (sun2002::brdf) with s and the Fresnel term per texel. A colour texel (sRGB) becomes
/// a smooth reflectance spectrum of that colour (smooth_reflectance_from_linear_srgb), read as the
/// normal-incidence reflectance R0 of a metal with eta = 1 and kappa = 2 sqrt(R0 / (1 - R0)) (Sun
/// eqs. 5.9-5.11, the same as the `--color` material), and the exact conductor Fresnel equations
/// then give the angular behaviour. Colours are quantised to 8 bits per channel and fitted once
/// per distinct colour; linear components are clamped to [0.002, 0.98], and a colour too
/// saturated for a reflectance spectrum is moved towards the grey of the same luminance until it
/// fits (counted in desaturated_colours()). Sampling: Beckmann visible normals of the texel's
/// alpha = 2/s, as SunBrdf. Thread-safe after construction.
class SunTextureSvbrdf final : public Svbrdf {
 public:
  /// Throws InputError for s, s_min, s_max not > 0 or s_min > s_max.
  explicit SunTextureSvbrdf(SunTextureOptions o);
  double eval(double u, double v, const Vec3& wi, const Vec3& wo,
              double wavelength_m) const override;
  std::optional<BrdfSample> sample(double u, double v, const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  double pdf(double u, double v, const Vec3& wi, const Vec3& wo) const override;
  std::string describe() const override;

  /// The smoothness at (u, v).
  double smoothness(double u, double v) const;
  /// The normal-incidence reflectance at (u, v) and a wavelength (from the colour map, or the
  /// Fresnel term of the options at cos = 1).
  double normal_reflectance_at(double u, double v, double wavelength_m) const;
  std::size_t distinct_colours() const { return palette_.size() / kBands; }
  std::size_t desaturated_colours() const { return desaturated_; }

  /// kappa(lambda) of a colour texel is tabulated every 5 nm from 360 to 830 nm (the grid of
  /// the colour fit).
  static constexpr int kBands = 95;

 private:
  double texel_s(double u, double v) const;
  const float* texel_kappa(double u, double v) const;
  SunTextureOptions o_;
  std::vector<double> s_;            // per s-map texel
  std::vector<std::uint32_t> cidx_;  // per colour texel: palette entry
  std::vector<float> palette_;       // kBands kappa values per distinct colour
  std::size_t desaturated_ = 0;
};

}  // namespace microbrdf::sun2002

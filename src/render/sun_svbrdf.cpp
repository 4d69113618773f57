// Sun 2002's BRDF with smoothness and colour textures (include/microbrdf/sun_svbrdf.hpp).
#include "microbrdf/sun_svbrdf.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <sstream>
#include <tuple>

#include "microbrdf/envmap_image.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/sun_brdf.hpp"

namespace microbrdf::sun2002 {
namespace {

constexpr int kMaxTextureSide = 4096;

TextureImage read_png(const std::string& path, const std::vector<std::uint8_t>& bytes) {
  png_image img;
  std::memset(&img, 0, sizeof img);
  img.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_memory(&img, bytes.data(), bytes.size()))
    throw FileError(path, std::string("not a readable PNG (") + img.message + ")");
  if (img.width < 1 || img.height < 1 || img.width > kMaxTextureSide ||
      img.height > kMaxTextureSide) {
    png_image_free(&img);
    throw FileError(path, "texture of " + std::to_string(img.width) + " x " +
                              std::to_string(img.height) + " pixels: at most " +
                              std::to_string(kMaxTextureSide) + " per side");
  }
  img.format = PNG_FORMAT_RGB;  // 8-bit sRGB-encoded; grey and alpha are converted by libpng
  std::vector<std::uint8_t> px(PNG_IMAGE_SIZE(img));
  if (!png_image_finish_read(&img, nullptr, px.data(), 0, nullptr)) {
    const std::string msg = img.message;
    png_image_free(&img);
    throw FileError(path, "corrupt PNG (" + msg + ")");
  }
  TextureImage t;
  t.width = int(img.width);
  t.height = int(img.height);
  t.rgb.resize(px.size());
  for (std::size_t i = 0; i < px.size(); ++i) t.rgb[i] = float(px[i]) / 255.0f;
  t.srgb_encoded = true;
  t.path = path;
  return t;
}

std::size_t wrap_index(double u, int n) {
  const double f = u - std::floor(u);  // [0, 1)
  return std::min<std::size_t>(std::size_t(n) - 1, static_cast<std::size_t>(f * n));
}

// Texel of an image at (u, v): columns along u, rows from the bottom along v.
std::size_t texel(const TextureImage& t, double u, double v) {
  const std::size_t ix = wrap_index(u, t.width);
  const std::size_t iy = std::size_t(t.height) - 1 - wrap_index(v, t.height);
  return iy * std::size_t(t.width) + ix;
}

double band_nm(int b) { return 360.0 + 5.0 * b; }

// kappa(lambda) of a colour texel, tabulated every 5 nm; eta = 1.
class KappaBandsFresnel final : public Fresnel {
 public:
  explicit KappaBandsFresnel(const float* k) : k_(k) {}
  double eval(double cos_i, double wavelength_m) const override {
    const double x =
        std::clamp((wavelength_m * 1e9 - 360.0) / 5.0, 0.0, double(SunTextureSvbrdf::kBands - 1));
    const int i = std::min(int(x), SunTextureSvbrdf::kBands - 2);
    const double f = x - i, kappa = (1 - f) * k_[i] + f * k_[i + 1];
    return fresnel_conductor_siegel(cos_i, 1.0, kappa);
  }
  std::string describe() const override { return "texel colour (eta = 1)"; }

 private:
  const float* k_;
};

// kappa bands of a linear sRGB colour; false when the colour is too saturated.
bool colour_kappa(const Eigen::Vector3d& lin, float* out) {
  try {
    const Spectrum r0 = smooth_reflectance_from_linear_srgb(lin);
    const OpticalConstants c = from_normal_reflectance(r0, 1.0);
    for (int b = 0; b < SunTextureSvbrdf::kBands; ++b) out[b] = float(c.k(band_nm(b) * 1e-9));
    return true;
  } catch (const InputError&) {
    return false;
  }
}

}  // namespace

std::pair<double, double> parse_s_range(const std::string& text) {
  std::string t = text;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream is(t);
  double lo = 0, hi = 0;
  std::string rest;
  if (!(is >> lo >> hi) || (is >> rest) || !(lo > 0) || !(hi >= lo) || !std::isfinite(hi))
    throw InputError("s-range '" + text + "': expected MIN,MAX with 0 < MIN <= MAX");
  return {lo, hi};
}

bool SunRenderOptions::given() const {
  return form != "standard" || ftp != "both" || !s_texture.empty() || !color_texture.empty();
}

void SunRenderOptions::check() const {
  (void)parse_brdf_form(form);
  (void)parse_ftp_terms(ftp);
  (void)parse_s_range(s_range);
}

std::shared_ptr<const Svbrdf> make_sun_svbrdf(const SunRenderOptions& o, double s,
                                              std::shared_ptr<const Fresnel> fresnel) {
  o.check();
  const auto form = parse_brdf_form(o.form);
  const auto ftp = parse_ftp_terms(o.ftp);
  if (o.s_texture.empty() && o.color_texture.empty())
    return std::make_shared<UniformSvbrdf>(
        std::make_shared<SunBrdf>(s, form, std::move(fresnel), ftp));
  SunTextureOptions t;
  t.s = s;
  t.form = form;
  t.ftp = ftp;
  if (!o.s_texture.empty()) {
    t.s_map = read_texture_image(o.s_texture);
    std::tie(t.s_min, t.s_max) = parse_s_range(o.s_range);
  }
  if (!o.color_texture.empty())
    t.color_map = read_texture_image(o.color_texture);
  else
    t.fresnel = std::move(fresnel);
  return std::make_shared<SunTextureSvbrdf>(std::move(t));
}

TextureImage read_texture_image(const std::string& path) {
  require_regular_file(path);
  std::uint8_t magic[4] = {0, 0, 0, 0};
  {
    const auto head = read_file_bytes(path, std::uint64_t(1) << 28);
    if (head.size() >= 4) std::memcpy(magic, head.data(), 4);
    if (head.size() >= 8 && magic[0] == 0x89 && magic[1] == 'P' && magic[2] == 'N' &&
        magic[3] == 'G')
      return read_png(path, head);
  }
  const bool exr = magic[0] == 0x76 && magic[1] == 0x2f && magic[2] == 0x31 && magic[3] == 0x01;
  const bool hdr = magic[0] == '#' && magic[1] == '?';
  if (!exr && !hdr) throw FileError(path, "not a PNG, OpenEXR or Radiance .hdr image");
  const EnvmapImage e = read_envmap(path);
  if (e.width > kMaxTextureSide || e.height > kMaxTextureSide)
    throw FileError(path, "texture of " + std::to_string(e.width) + " x " +
                              std::to_string(e.height) + " pixels: at most " +
                              std::to_string(kMaxTextureSide) + " per side");
  TextureImage t;
  t.width = e.width;
  t.height = e.height;
  t.rgb = e.rgb;
  t.srgb_encoded = false;
  t.path = path;
  return t;
}

SunTextureSvbrdf::SunTextureSvbrdf(SunTextureOptions o) : o_(std::move(o)) {
  if (!(o_.s > 0) || !std::isfinite(o_.s))
    throw InputError("Sun 2002 texture: the smoothness s must be > 0");
  if (o_.s_map) {
    if (!(o_.s_min > 0) || !(o_.s_max >= o_.s_min) || !std::isfinite(o_.s_max))
      throw InputError("Sun 2002 smoothness texture: need 0 < s_min <= s_max, got " +
                       std::to_string(o_.s_min) + ", " + std::to_string(o_.s_max));
    const auto& m = *o_.s_map;
    s_.resize(std::size_t(m.width) * m.height);
    for (std::size_t i = 0; i < s_.size(); ++i) {
      const double g =
          std::clamp((double(m.rgb[3 * i]) + m.rgb[3 * i + 1] + m.rgb[3 * i + 2]) / 3, 0.0, 1.0);
      s_[i] = o_.s_min + g * (o_.s_max - o_.s_min);
    }
  }
  if (o_.color_map) {
    const auto& m = *o_.color_map;
    cidx_.resize(std::size_t(m.width) * m.height);
    std::map<std::uint32_t, std::uint32_t> seen;
    for (std::size_t i = 0; i < cidx_.size(); ++i) {
      std::uint32_t key = 0;
      for (int c = 0; c < 3; ++c) {
        double x = std::clamp(double(m.rgb[3 * i + c]), 0.0, 1.0);
        if (!m.srgb_encoded) x = srgb_encode(x);
        key = key << 8 | std::uint32_t(std::lround(x * 255));
      }
      const auto it = seen.find(key);
      if (it != seen.end()) {
        cidx_[i] = it->second;
        continue;
      }
      const std::uint32_t id = std::uint32_t(seen.size());
      seen.emplace(key, id);
      cidx_[i] = id;
      Eigen::Vector3d lin;
      for (int c = 0; c < 3; ++c)
        lin[c] = std::clamp(srgb_decode(double((key >> (16 - 8 * c)) & 0xff) / 255), 0.002, 0.98);
      palette_.resize(palette_.size() + kBands);
      float* out = &palette_[std::size_t(id) * kBands];
      if (colour_kappa(lin, out)) continue;
      ++desaturated_;
      const double y = 0.2126 * lin[0] + 0.7152 * lin[1] + 0.0722 * lin[2];
      bool ok = false;
      for (int step = 1; step <= 20 && !ok; ++step) {
        const double t = step / 20.0;
        ok = colour_kappa((1 - t) * lin + t * Eigen::Vector3d::Constant(y), out);
      }
      if (!ok) colour_kappa(Eigen::Vector3d::Constant(0.5), out);
    }
  }
}

double SunTextureSvbrdf::texel_s(double u, double v) const {
  return o_.s_map ? s_[texel(*o_.s_map, u, v)] : o_.s;
}

const float* SunTextureSvbrdf::texel_kappa(double u, double v) const {
  return &palette_[std::size_t(cidx_[texel(*o_.color_map, u, v)]) * kBands];
}

double SunTextureSvbrdf::smoothness(double u, double v) const { return texel_s(u, v); }

double SunTextureSvbrdf::normal_reflectance_at(double u, double v, double wavelength_m) const {
  if (o_.color_map) return KappaBandsFresnel(texel_kappa(u, v)).eval(1.0, wavelength_m);
  return o_.fresnel ? o_.fresnel->eval(1.0, wavelength_m) : 1.0;
}

double SunTextureSvbrdf::eval(double u, double v, const Vec3& wi, const Vec3& wo,
                              double wavelength_m) const {
  const double s = texel_s(u, v);
  if (o_.color_map) {
    const KappaBandsFresnel f(texel_kappa(u, v));
    return brdf(wi, wo, s, o_.form, &f, wavelength_m, o_.ftp);
  }
  return brdf(wi, wo, s, o_.form, o_.fresnel.get(), wavelength_m, o_.ftp);
}

std::optional<BrdfSample> SunTextureSvbrdf::sample(double u, double v, const Vec3& wi, double u1,
                                                   double u2, double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  return sample_visible_beckmann(BeckmannDistribution(2 / texel_s(u, v)), wi, u1, u2,
                                 [&](const Vec3& wo) { return eval(u, v, wi, wo, wavelength_m); });
}

double SunTextureSvbrdf::pdf(double u, double v, const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  return pdf_visible_beckmann(BeckmannDistribution(2 / texel_s(u, v)), wi, wo);
}

std::string SunTextureSvbrdf::describe() const {
  std::string d =
      "Sun 2002 eq. 3.5.3 (" +
      std::string(o_.form == BrdfForm::AsPublished ? "as published" : "standard microfacet form") +
      ")";
  if (o_.ftp != FtpTerms::Both) d += ", free travel probabilities: " + ftp_terms_name(o_.ftp);
  if (o_.s_map)
    d += ", smoothness texture " + o_.s_map->path + " (" + std::to_string(o_.s_map->width) + " x " +
         std::to_string(o_.s_map->height) + ", s " + std::to_string(o_.s_min) + " to " +
         std::to_string(o_.s_max) + ")";
  else
    d += ", s = " + std::to_string(o_.s);
  if (o_.color_map)
    d += ", colour texture " + o_.color_map->path + " (" + std::to_string(o_.color_map->width) +
         " x " + std::to_string(o_.color_map->height) + ", " + std::to_string(distinct_colours()) +
         " colours, " + std::to_string(desaturated_) + " desaturated; eta = 1, kappa from R0)";
  else
    d += ", " + (o_.fresnel ? o_.fresnel->describe() : std::string("R = 1"));
  return d;
}

}  // namespace microbrdf::sun2002

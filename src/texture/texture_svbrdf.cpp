// The SVBRDF of an ellipsoid parameter texture: Dong eq. 1 with the texel's ellipsoid NDF
// (eq. 10) and the separable shadowing G1 G1 of eqs. 13-14. The distribution is built per call
// from the texel's five floats (a few hundred ns), so a 2048^2 texture costs its 100 MB of
// floats and nothing more.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "microbrdf/texture.hpp"

namespace microbrdf {
namespace {

std::size_t wrap_index(double u, std::size_t n) {
  const double f = u - std::floor(u);  // [0, 1)
  return std::min(n - 1, static_cast<std::size_t>(f * static_cast<double>(n)));
}

}  // namespace

EllipsoidTextureSvbrdf::EllipsoidTextureSvbrdf(std::shared_ptr<const ParamTexture> tex,
                                               std::shared_ptr<const Fresnel> f)
    : tex_(std::move(tex)), f_(std::move(f)) {
  if (!tex_ || !f_)
    throw std::invalid_argument("EllipsoidTextureSvbrdf needs a texture and a Fresnel term");
  if (tex_->size() == 0) throw std::invalid_argument("EllipsoidTextureSvbrdf: empty texture");
  mean_ = tex_->mean_valid();
}

EllipsoidParams EllipsoidTextureSvbrdf::params_at(double u, double v) const {
  const std::size_t ix = wrap_index(u, tex_->nx), iy = wrap_index(v, tex_->ny);
  return tex_->valid[ix + tex_->nx * iy] ? tex_->at(ix, iy) : mean_;
}

double EllipsoidTextureSvbrdf::eval(double u, double v, const Vec3& wi, const Vec3& wo,
                                    double wavelength_m) const {
  const auto hv = reflection_half_vector(wi, wo);
  if (!hv) return 0;
  const EllipsoidDistribution d(params_at(u, v));
  const double g = d.G2(wi, wo, hv->h, true);
  if (g == 0) return 0;
  return f_->eval(hv->wi_dot_h, wavelength_m) * d.D(hv->h) * g / (4 * wi.z() * wo.z());
}

std::optional<BrdfSample> EllipsoidTextureSvbrdf::sample(double u, double v, const Vec3& wi,
                                                         double u1, double u2,
                                                         double wavelength_m) const {
  if (wi.z() <= 0) return std::nullopt;
  const EllipsoidDistribution d(params_at(u, v));
  const Vec3 m = d.sample_visible(wi, u1, u2);
  const double im = wi.dot(m);
  if (im <= 0) return std::nullopt;
  const Vec3 wo = 2 * im * m - wi;
  if (wo.z() <= 0) return std::nullopt;
  const double q = d.sampling_pdf(wi, m);
  BrdfSample s;
  s.wo = wo;
  s.pdf = q / (4 * im);
  if (!(s.pdf > 0)) return std::nullopt;
  const double g = d.G2(wi, wo, m, true);
  s.weight = f_->eval(im, wavelength_m) * g * d.D(m) * im / (wi.z() * q);
  return s;
}

double EllipsoidTextureSvbrdf::pdf(double u, double v, const Vec3& wi, const Vec3& wo) const {
  const auto hv = reflection_half_vector(wi, wo);
  if (!hv) return 0;
  const EllipsoidDistribution d(params_at(u, v));
  return d.sampling_pdf(wi, hv->h) / (4 * hv->wi_dot_h);
}

std::string EllipsoidTextureSvbrdf::describe() const {
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "ellipsoid-NDF texture %zu x %zu texels of %.4g um (mean alpha %.4g, %.4g), "
                "nearest texel, separable Smith G1 G1 (Dong eqs. 13-14), ",
                tex_->nx, tex_->ny, tex_->texel_m * 1e6, mean_.alpha_x, mean_.alpha_y);
  return buf + f_->describe();
}

std::shared_ptr<const Svbrdf> make_svbrdf(const BrdfSpec& spec, const MaterialSpec& material) {
  if (spec.kind == BrdfSpec::Kind::Texture) {
    // Each texel's ellipsoid parameters with the material's Fresnel term; (u, v) wraps.
    auto tex = std::make_shared<const ParamTexture>(read_param_texture(spec.texture));
    return std::make_shared<EllipsoidTextureSvbrdf>(tex, make_fresnel(material));
  }
  return std::make_shared<UniformSvbrdf>(make_brdf(spec, material));
}

}  // namespace microbrdf

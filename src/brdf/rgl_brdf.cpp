// The RGL `.bsdf` reconstruction as a Brdf (include/microbrdf/rgl_bsdf.hpp; docs/measured.md).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/marginal2d.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/rgl_coords.hpp"

namespace microbrdf {
namespace {

using namespace detail::rgl;
// Polar angle, accurate near the pole: 2 asin(|d - z| / 2).
double elevation(const Vec3& d) {
  const double dist = std::sqrt(d.x() * d.x() + d.y() * d.y() + (d.z() - 1) * (d.z() - 1));
  return 2 * std::asin(std::clamp(0.5 * dist, -1.0, 1.0));
}
// a with the sign flipped unless b < 0 (the renderers' symmetry folding).
double mulsign_neg(double a, double b) { return b < 0 ? a : -a; }

std::vector<double> to_double(const std::vector<float>& v) { return {v.begin(), v.end()}; }

}  // namespace

// The coordinates every lookup of a (wi, wo) pair needs, after folding.
struct Query {
  double theta_i, phi_i, theta_m, wi_dot_m;
  detail::Marginal2D::Vec2 u_wi, u_m;
};

struct RglBrdf::Impl {
  std::string path, description;
  detail::Marginal2D ndf, sigma, vndf, luminance, spectra;
  bool isotropic = true, jacobian = true;
  int reduction = 1;

  // Folds wi (and wo) into the stored azimuth range; returns the signs used.
  void fold(Vec3& wi, Vec3* wo, double& sx, double& sy) const {
    sx = sy = -1;
    if (reduction < 2) return;
    sy = wi.y();
    sx = reduction == 4 ? wi.x() : sy;
    wi.x() = mulsign_neg(wi.x(), sx);
    wi.y() = mulsign_neg(wi.y(), sy);
    if (wo) {
      wo->x() = mulsign_neg(wo->x(), sx);
      wo->y() = mulsign_neg(wo->y(), sy);
    }
  }

  Query query(const Vec3& wi_in, const Vec3& wo_in) const {
    Vec3 wi = wi_in, wo = wo_in;
    double sx, sy;
    fold(wi, &wo, sx, sy);
    const Vec3 m = (wi + wo).normalized();
    Query q;
    q.theta_i = elevation(wi);
    q.phi_i = std::atan2(wi.y(), wi.x());
    q.theta_m = elevation(m);
    q.wi_dot_m = wi.dot(m);
    const double phi_m = std::atan2(m.y(), m.x());
    q.u_wi = {theta2u(q.theta_i), phi2u(q.phi_i)};
    q.u_m = {theta2u(q.theta_m), phi2u(isotropic ? phi_m - q.phi_i : phi_m)};
    q.u_m[1] -= std::floor(q.u_m[1]);
    return q;
  }
};

RglBrdf::RglBrdf(const TensorFile& f, const std::string& path) : p_(std::make_unique<Impl>()) {
  p_->path = path;
  auto fail = [&](const std::string& what) -> void { throw FileError(path, what); };
  auto need = [&](const char* name, TensorDtype dt, std::size_t ndim) -> const TensorField& {
    const TensorField& t = f.field(name, path);
    if (t.dtype != dt || t.shape.size() != ndim)
      fail(std::string("field \"") + name + "\" has the wrong dtype or rank (expected " +
           (dt == TensorDtype::UInt8 ? "uint8" : "float32") + " with " + std::to_string(ndim) +
           " dimensions)");
    return t;
  };
  const auto& desc = need("description", TensorDtype::UInt8, 1);
  const auto& jac = need("jacobian", TensorDtype::UInt8, 1);
  const auto& theta_i = need("theta_i", TensorDtype::Float32, 1);
  const auto& phi_i = need("phi_i", TensorDtype::Float32, 1);
  const auto& ndf = need("ndf", TensorDtype::Float32, 2);
  const auto& sigma = need("sigma", TensorDtype::Float32, 2);
  const auto& vndf = need("vndf", TensorDtype::Float32, 4);
  const auto& lum = need("luminance", TensorDtype::Float32, 4);
  const bool rgb = f.find("spectra") == nullptr && f.find("rgb") != nullptr;
  const auto& spec = need(rgb ? "rgb" : "spectra", TensorDtype::Float32, 5);
  std::vector<double> wl;
  if (rgb) {
    const auto w = merl_channel_wavelengths();
    wl = {w[2] * 1e9, w[1] * 1e9, w[0] * 1e9};  // increasing: B, G, R
  } else {
    wl = to_double(need("wavelengths", TensorDtype::Float32, 1).as_float32(path));
  }
  const auto n_phi_i = phi_i.shape[0], n_theta_i = theta_i.shape[0];
  if (jac.shape[0] != 1) fail("field \"jacobian\" must hold one value");
  if (vndf.shape[0] != n_phi_i || vndf.shape[1] != n_theta_i || lum.shape[0] != n_phi_i ||
      lum.shape[1] != n_theta_i || lum.shape[2] != lum.shape[3] || spec.shape[0] != n_phi_i ||
      spec.shape[1] != n_theta_i || spec.shape[2] != wl.size() || spec.shape[3] != spec.shape[4] ||
      lum.shape[2] != spec.shape[3])
    fail(
        "inconsistent field shapes (vndf, luminance and spectra must share the theta_i/phi_i "
        "grid, luminance and spectra the sample grid)");
  p_->description.assign(desc.data.begin(), desc.data.end());
  p_->jacobian = jac.data[0] != 0;
  p_->isotropic = n_phi_i <= 2;
  const auto phi_v = to_double(phi_i.as_float32(path));
  const auto theta_v = to_double(theta_i.as_float32(path));
  try {
    p_->ndf = detail::Marginal2D(ndf.as_float32(path), ndf.shape[1], ndf.shape[0], {}, false);
    p_->sigma =
        detail::Marginal2D(sigma.as_float32(path), sigma.shape[1], sigma.shape[0], {}, false);
    p_->vndf = detail::Marginal2D(vndf.as_float32(path), vndf.shape[3], vndf.shape[2],
                                  {phi_v, theta_v}, true);
    p_->luminance = detail::Marginal2D(lum.as_float32(path), lum.shape[3], lum.shape[2],
                                       {phi_v, theta_v}, true);
    std::vector<float> s = spec.as_float32(path);
    if (rgb) {  // reorder the channel axis to B, G, R (increasing wavelength)
      const std::size_t block = spec.shape[3] * spec.shape[4];
      for (std::size_t k = 0; k < n_phi_i * n_theta_i; ++k)
        std::swap_ranges(s.begin() + (k * 3) * block, s.begin() + (k * 3 + 1) * block,
                         s.begin() + (k * 3 + 2) * block);
    }
    p_->spectra = detail::Marginal2D(s, spec.shape[4], spec.shape[3], {phi_v, theta_v, wl}, false);
  } catch (const std::invalid_argument& e) {
    fail(std::string("invalid tables: ") + e.what());
  }
  if (!p_->isotropic) {
    const double span = phi_v.back() - phi_v.front();
    p_->reduction = static_cast<int>(std::clamp(std::rint(2 * kPi / span), 1.0, 4.0));
  }
}

RglBrdf RglBrdf::load(const std::string& path) { return RglBrdf(read_tensor_file(path), path); }
RglBrdf::~RglBrdf() = default;
RglBrdf::RglBrdf(RglBrdf&&) noexcept = default;

bool RglBrdf::isotropic() const { return p_->isotropic; }
const std::string& RglBrdf::description() const { return p_->description; }
std::string RglBrdf::describe() const {
  return "RGL measured BSDF " + p_->path +
         (p_->description.empty() ? std::string() : " (" + p_->description + ")");
}

double RglBrdf::eval(const Vec3& wi_in, const Vec3& wo_in, double wavelength_m) const {
  if (wi_in.z() <= 0 || wo_in.z() <= 0) return 0;
  const Query q = p_->query(wi_in, wo_in);
  const double params[3] = {q.phi_i, q.theta_i, wavelength_m * 1e9};
  const auto s = p_->vndf.invert(q.u_m, params).first;
  double r = p_->spectra.eval(s, params);
  if (p_->jacobian) {
    const double sig = p_->sigma.eval(q.u_wi, nullptr);
    if (!(sig > 0)) return 0;
    r *= p_->ndf.eval(q.u_m, nullptr) / (4 * sig);
  }
  return r / wo_in.z();
}

std::optional<BrdfSample> RglBrdf::sample(const Vec3& wi_in, double u1, double u2,
                                          double wavelength_m) const {
  if (wi_in.z() <= 0) return std::nullopt;
  Vec3 wi = wi_in;
  double sx, sy;
  p_->fold(wi, nullptr, sx, sy);
  const double theta_i = elevation(wi), phi_i = std::atan2(wi.y(), wi.x());
  const double params[3] = {phi_i, theta_i, wavelength_m * 1e9};
  const auto [s, lum_pdf] = p_->luminance.sample({u2, u1}, params);
  const auto [u_m, vndf_pdf] = p_->vndf.sample(s, params);
  double phi_m = u2phi(u_m[1]);
  const double theta_m = u2theta(u_m[0]);
  if (p_->isotropic) phi_m += phi_i;
  const Vec3 m(std::cos(phi_m) * std::sin(theta_m), std::sin(phi_m) * std::sin(theta_m),
               std::cos(theta_m));
  const double wim = wi.dot(m);
  if (!(wim > 0)) return std::nullopt;
  const double jac = solid_angle_jacobian(u_m[0], theta_m) * 4 * wim;
  Vec3 wo = 2 * wim * m - wi;
  const double pdf = vndf_pdf * lum_pdf / jac;
  double r = p_->spectra.eval(s, params);
  if (p_->jacobian) {
    const double sig = p_->sigma.eval({theta2u(theta_i), phi2u(phi_i)}, nullptr);
    if (!(sig > 0)) return std::nullopt;
    r *= p_->ndf.eval(u_m, nullptr) / (4 * sig);
  }
  wo.x() = mulsign_neg(wo.x(), sx);
  wo.y() = mulsign_neg(wo.y(), sy);
  if (wo.z() <= 0 || !(pdf > 0) || !std::isfinite(r)) return std::nullopt;
  return BrdfSample{wo, r / pdf, pdf};
}

double RglBrdf::pdf(const Vec3& wi_in, const Vec3& wo_in) const {
  if (wi_in.z() <= 0 || wo_in.z() <= 0) return 0;
  const Query q = p_->query(wi_in, wo_in);
  const double params[2] = {q.phi_i, q.theta_i};
  const auto [s, vndf_pdf] = p_->vndf.invert(q.u_m, params);
  const double lum_pdf = p_->luminance.eval(s, params);
  return vndf_pdf * lum_pdf / (solid_angle_jacobian(q.u_m[0], q.theta_m) * 4 * q.wi_dot_m);
}

}  // namespace microbrdf

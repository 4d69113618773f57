// RGL `.bsdf` writer (include/microbrdf/export.hpp; docs/measured.md).
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "core/marginal2d.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/rgl_coords.hpp"

namespace microbrdf {
namespace {

using namespace detail::rgl;
Vec3 spherical(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}
double node(std::size_t i, std::size_t n) { return double(i) / double(n - 1); }

}  // namespace

std::vector<double> RglExportOptions::default_wavelengths() {
  std::vector<double> w(25);
  for (std::size_t i = 0; i < w.size(); ++i) w[i] = 360.0 + 470.0 * double(i) / 24.0;
  return w;
}

TensorFile rgl_tensor(const Brdf& brdf, const MicrofacetDistribution& ndf,
                      const RglExportOptions& o) {
  if (o.theta_i < 2 || o.ndf_phi < 2 || o.samples < 2 || (!o.isotropic && o.phi_i < 2))
    throw InputError("RGL export: every grid needs at least 2 nodes");
  // Two NDF nodes in theta are the pole and the horizon: no mass between them to sample from.
  if (o.ndf_theta < 3) throw InputError("RGL export: the NDF grid needs at least 3 nodes");
  if (o.wavelengths_nm.empty()) throw InputError("RGL export: no wavelengths");
  for (std::size_t i = 0; i + 1 < o.wavelengths_nm.size(); ++i)
    if (!(o.wavelengths_nm[i + 1] > o.wavelengths_nm[i]))
      throw InputError("RGL export: wavelengths must increase");
  if (!(o.theta_i_max > 0 && o.theta_i_max < kPi / 2))
    throw InputError("RGL export: theta_i_max must lie in (0, 90) deg");
  const std::size_t nt = o.ndf_theta, np = o.ndf_phi, ns = o.samples;
  const std::size_t nwl = o.wavelengths_nm.size();
  std::vector<double> theta_i(o.theta_i), phi_i(o.isotropic ? 1 : o.phi_i, 0.0);
  for (std::size_t k = 0; k < o.theta_i; ++k) theta_i[k] = o.theta_i_max * node(k, o.theta_i);
  if (!o.isotropic)
    for (std::size_t k = 0; k < o.phi_i; ++k) phi_i[k] = -kPi + 2 * kPi * node(k, o.phi_i);
  const std::size_t npi = phi_i.size(), nti = theta_i.size();

  // ndf and sigma on the (u_phi rows, u_theta columns) grid.
  std::vector<float> ndf_v(np * nt), sigma_v(np * nt);
  for (std::size_t j = 0; j < np; ++j)
    for (std::size_t i = 0; i < nt; ++i) {
      const double th = u2theta(node(i, nt)), ph = u2phi(node(j, np));
      ndf_v[j * nt + i] = static_cast<float>(ndf.D(spherical(th, ph)));
      // sigma at the horizon: its limit from just above (projected_area is 0 at v.z = 0).
      sigma_v[j * nt + i] =
          static_cast<float>(ndf.projected_area(spherical(std::min(th, kPi / 2 - 1e-4), ph)));
    }
  const detail::Marginal2D ndf_i(ndf_v, nt, np, {}, false), sigma_i(sigma_v, nt, np, {}, false);

  // vndf per incident node.
  std::vector<float> vndf_v(npi * nti * np * nt);
  for (std::size_t a = 0; a < npi; ++a)
    for (std::size_t b = 0; b < nti; ++b) {
      const Vec3 wi = spherical(theta_i[b], phi_i[a]);
      float* out = vndf_v.data() + (a * nti + b) * np * nt;
      for (std::size_t j = 0; j < np; ++j)
        for (std::size_t i = 0; i < nt; ++i) {
          const double u = node(i, nt), th = u2theta(u);
          const Vec3 m = spherical(th, u2phi(node(j, np)) + (o.isotropic ? phi_i[a] : 0.0));
          out[j * nt + i] =
              static_cast<float>(std::max(0.0, ndf_i.eval({u, node(j, np)}, nullptr)) *
                                 std::max(0.0, wi.dot(m)) * u * std::sin(th));
        }
    }
  const detail::Marginal2D vndf_i(vndf_v, nt, np, {phi_i, theta_i}, true);

  // spectra and luminance on the sample grid.
  std::vector<float> spec_v(npi * nti * nwl * ns * ns), lum_v(npi * nti * ns * ns);
  // Blocks of incident nodes, each in parallel; progress is reported between blocks from the
  // calling thread (it may throw to stop the export).
  const std::size_t total = npi * nti, block = 16;
  for (std::size_t k0 = 0; k0 < total; k0 += block) {
    const std::size_t k1 = std::min(total, k0 + block);
#pragma omp parallel for schedule(dynamic)
    for (std::size_t k = k0; k < k1; ++k) {
      const std::size_t a = k / nti, b = k % nti;
      const Vec3 wi = spherical(theta_i[b], phi_i[a]);
      const double params[2] = {phi_i[a], theta_i[b]};
      const double sig = sigma_i.eval({theta2u(theta_i[b]), phi2u(phi_i[a])}, nullptr);
      float* lum = lum_v.data() + (a * nti + b) * ns * ns;
      double lmax = 0;
      for (std::size_t j = 0; j < ns; ++j)
        for (std::size_t i = 0; i < ns; ++i) {
          const auto u_m = vndf_i.sample({node(i, ns), node(j, ns)}, params).first;
          const Vec3 m = spherical(u2theta(u_m[0]), u2phi(u_m[1]) + (o.isotropic ? phi_i[a] : 0.0));
          const Vec3 wo = 2 * wi.dot(m) * m - wi;
          const double d = ndf_i.eval(u_m, nullptr);
          double ysum = 0;
          for (std::size_t w = 0; w < nwl; ++w) {
            double r = 0;
            if (wo.z() > 0 && wi.dot(m) > 0 && d > 0 && sig > 0) {
              r = brdf.eval(wi, wo, o.wavelengths_nm[w] * 1e-9) * wo.z() * 4 * sig / d;
              if (!std::isfinite(r) || r < 0) r = 0;
            }
            spec_v[(((a * nti + b) * nwl + w) * ns + j) * ns + i] = static_cast<float>(r);
            ysum += r;
          }
          lum[j * ns + i] = static_cast<float>(ysum / double(nwl));
          lmax = std::max(lmax, ysum / double(nwl));
        }
      for (std::size_t q = 0; q < ns * ns; ++q)
        lum[q] = lmax > 0 ? std::max(lum[q], static_cast<float>(1e-4 * lmax)) : 1.0f;
    }
    if (o.progress) o.progress(double(k1) / double(total));
  }

  TensorFile f;
  const std::vector<std::uint8_t> desc(o.description.begin(), o.description.end());
  const std::uint8_t one = 1;
  const std::vector<double> wl(o.wavelengths_nm);
  f.fields.push_back(TensorField::uint8("description", {desc.size()}, desc));
  f.fields.push_back(TensorField::uint8("jacobian", {1}, std::span<const std::uint8_t>(&one, 1)));
  f.fields.push_back(TensorField::float32("theta_i", {nti}, std::span<const double>(theta_i)));
  f.fields.push_back(TensorField::float32("phi_i", {npi}, std::span<const double>(phi_i)));
  f.fields.push_back(TensorField::float32("ndf", {np, nt}, std::span<const float>(ndf_v)));
  f.fields.push_back(TensorField::float32("sigma", {np, nt}, std::span<const float>(sigma_v)));
  f.fields.push_back(
      TensorField::float32("vndf", {npi, nti, np, nt}, std::span<const float>(vndf_v)));
  f.fields.push_back(
      TensorField::float32("luminance", {npi, nti, ns, ns}, std::span<const float>(lum_v)));
  f.fields.push_back(
      TensorField::float32("spectra", {npi, nti, nwl, ns, ns}, std::span<const float>(spec_v)));
  f.fields.push_back(TensorField::float32("wavelengths", {nwl}, std::span<const double>(wl)));
  return f;
}

void write_rgl_bsdf(const Brdf& brdf, const MicrofacetDistribution& ndf,
                    const RglExportOptions& options, const std::string& path) {
  write_tensor_file(rgl_tensor(brdf, ndf, options), path);
}

namespace {

// splitmix64: a fixed, portable stream of uniforms for the isotropy probe.
struct Uniforms {
  std::uint64_t state = 0x9e3779b97f4a7c15ull;
  double operator()() {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return double(z >> 11) * 0x1.0p-53;
  }
};

Vec3 turned(const Vec3& v, double a) {
  const double c = std::cos(a), s = std::sin(a);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}

}  // namespace

bool brdf_is_isotropic(const Brdf& brdf, double wavelength_m) {
  if (dynamic_cast<const MerlBrdf*>(&brdf)) return true;
  if (const auto* r = dynamic_cast<const RglBrdf*>(&brdf)) return r->isotropic();
  Uniforms u;
  std::vector<std::pair<Vec3, Vec3>> pairs;
  for (int k = 0; k < 96; ++k) {
    const double ti = 1.3 * u(), ph = 2 * kPi * u();
    const Vec3 wi = spherical(ti, ph);
    Vec3 wo = spherical(1.3 * u(), 2 * kPi * u());
    if (k % 2 == 0)
      if (const auto s = brdf.sample(wi, u(), u(), wavelength_m); s && s->wo.z() > 0.05) wo = s->wo;
    pairs.emplace_back(wi, wo);
  }
  std::vector<double> base(pairs.size());
  double vmax = 0;
  for (std::size_t k = 0; k < pairs.size(); ++k) {
    base[k] = brdf.eval(pairs[k].first, pairs[k].second, wavelength_m);
    if (std::isfinite(base[k])) vmax = std::max(vmax, std::abs(base[k]));
  }
  if (!(vmax > 0)) return true;
  for (double a : {0.7, 1.9, 2.6, 4.0})
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      const double v =
          brdf.eval(turned(pairs[k].first, a), turned(pairs[k].second, a), wavelength_m);
      if (std::isnan(v) && std::isnan(base[k])) continue;
      if (!(std::abs(v - base[k]) <= 1e-3 * vmax)) return false;
    }
  return true;
}

std::shared_ptr<const MicrofacetDistribution> export_distribution(
    const std::shared_ptr<const Brdf>& brdf, const std::string& file) {
  if (const auto m = std::dynamic_pointer_cast<const MicrofacetBrdf>(brdf))
    return std::shared_ptr<const MicrofacetDistribution>(m, &m->distribution());
  if (file.empty()) return lobe_distribution(*brdf, 257);
  return about_file(file, [&] { return lobe_distribution(*brdf, 257); });
}

}  // namespace microbrdf

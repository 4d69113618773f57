// Total integrated scatter of the Rayleigh-Rice BRDF (include/microbrdf/rayleigh_rice.hpp):
// the closed form of the smooth-surface limit beside the integral of the first-order BRDF.
#include <cmath>
#include <nlohmann/json.hpp>

#include "microbrdf/error.hpp"
#include "microbrdf/rayleigh_rice.hpp"

namespace microbrdf {
namespace {

// The PSD's power at the frequencies that scatter into propagating directions for light from
// wi: the nodes with |lambda f - wi_xy| < 1, m^2.
double propagating_power(const AreaPsd& p, const Vec3& wi, double wavelength_m) {
  double band = 0;
  for (std::size_t iy = 0; iy < p.nfy; ++iy)
    for (std::size_t ix = 0; ix < p.nfx; ++ix) {
      const double ux = wavelength_m * p.fx(ix) - wi.x(), uy = wavelength_m * p.fy(iy) - wi.y();
      if (ux * ux + uy * uy < 1) band += p.at_node(ix, iy);
    }
  return band * p.dfx * p.dfy;
}

double rayleigh_factor(double sq, double theta_i, double wavelength_m) {
  const double g = 4 * M_PI * sq * std::cos(theta_i) / wavelength_m;
  return g * g;
}

}  // namespace

Tis total_integrated_scatter(const RayleighRiceBrdf& b, double wavelength_m, double theta_i) {
  Tis t;
  t.wavelength_m = wavelength_m;
  t.theta_i_rad = theta_i;
  const Vec3 wi = slice_light(theta_i);
  const std::complex<double> n = b.material().at(wavelength_m);
  t.reflectance = smooth_reflectance(wi.z(), n * n, b.polarisation());
  t.rayleigh_factor = rayleigh_factor(b.psd().sq, theta_i, wavelength_m);
  t.closed_form = t.rayleigh_factor * t.reflectance;
  t.integral = b.integrated_scatter(wi, wavelength_m);
  t.specular = b.specular_reflectance(wi, wavelength_m);
  t.propagating_sq_m = std::sqrt(propagating_power(b.psd(), wi, wavelength_m));
  return t;
}

nlohmann::json tis_json(const Tis& t) {
  return {
      {"wavelength_m", t.wavelength_m},
      {"theta_i_rad", t.theta_i_rad},
      {"theta_i_deg", t.theta_i_rad * 180 / M_PI},
      {"reflectance", t.reflectance},
      {"rayleigh_factor", t.rayleigh_factor},
      {"tis_closed_form", t.closed_form},
      {"tis_integral", t.integral},
      {"integral_over_closed_form",
       t.closed_form > 0 ? nlohmann::json(t.integral / t.closed_form) : nlohmann::json(nullptr)},
      {"specular_reflectance", t.specular},
      {"propagating_sq_m", t.propagating_sq_m}};
}

const std::vector<double>& tis_default_wavelengths() {
  static const std::vector<double> v = {405e-9, 555e-9, 633e-9, 1064e-9};
  return v;
}

const std::vector<double>& tis_default_angles() {
  static const std::vector<double> v = {0.0, 20 * M_PI / 180, 45 * M_PI / 180, 70 * M_PI / 180};
  return v;
}

nlohmann::json tis_table(const std::shared_ptr<const AreaPsd>& psd,
                         const OpticalConstants* material, const std::vector<double>& wavelengths,
                         const std::vector<double>& angles, Polarisation polarisation) {
  nlohmann::json out = nlohmann::json::array();
  std::optional<RayleighRiceBrdf> b;
  if (material) b.emplace(psd, *material, polarisation);
  for (double l : wavelengths)
    for (double t : angles) {
      if (b) {
        out.push_back(tis_json(total_integrated_scatter(*b, l, t)));
        continue;
      }
      out.push_back({{"wavelength_m", l},
                     {"theta_i_rad", t},
                     {"theta_i_deg", t * 180 / M_PI},
                     {"rayleigh_factor", rayleigh_factor(psd->sq, t, l)},
                     {"propagating_sq_m", std::sqrt(propagating_power(*psd, slice_light(t), l))}});
    }
  return out;
}

void add_psd_and_tis_json(nlohmann::json& j, const Surface& s, const std::string& name,
                          const OpticalConstants* material, std::vector<double> wavelengths,
                          std::vector<double> angles) {
  j["tis_material"] = material ? nlohmann::json(material->name) : nlohmann::json(nullptr);
  if (s.nx < 2 || s.ny < 2 || s.valid_count() == 0) {  // a profile has no areal PSD
    j["psd"] = nullptr;
    j["tis"] = nlohmann::json::array();
    return;
  }
  auto psd =
      std::make_shared<const AreaPsd>(about_file(name, [&] { return areal_psd(s, {}, name); }));
  if (wavelengths.empty()) wavelengths = tis_default_wavelengths();
  if (angles.empty()) angles = tis_default_angles();
  j["psd"] = psd_json(*psd);
  j["tis"] = tis_table(psd, material, wavelengths, angles);
}

}  // namespace microbrdf

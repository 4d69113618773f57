// The virtual in-plane gonioreflectometer (include/microbrdf/goniometer.hpp).
#include "microbrdf/goniometer.hpp"

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/microfacet_brdf.hpp"

namespace microbrdf {
namespace {
constexpr double kPi = 3.14159265358979323846, kDeg = kPi / 180;
}

double cone_average(const std::function<double(const Vec3&)>& f, const Vec3& c, double half,
                    const Vec3& axis) {
  const Vec3 t1 = axis.cross(c).normalized(), t2 = c.cross(t1);
  double num = 0, den = 0;
  for (int i = 0; i < kConeRings; ++i) {
    const double r = (i + 0.5) / kConeRings * half;
    for (int k = 0; k < kConeAzimuths; ++k) {
      const double ph = 2 * kPi * k / kConeAzimuths;
      const Vec3 w = std::cos(r) * c + std::sin(r) * (std::cos(ph) * t1 + std::sin(ph) * t2);
      num += std::sin(r) * w.z() * f(w);
      den += std::sin(r) * w.z();
    }
  }
  return num / den;
}

std::vector<GoniometerCurve> in_plane_goniometer(
    const MicroScene& scene, const GoniometerOptions& o,
    const std::function<void(const GoniometerCurve&)>& done) {
  const double half = o.cone_half_angle_rad;
  if (!(half > 0 && half < 20 * kDeg))
    throw InputError("the cone half-angle must be in (0, 20) deg");
  if (o.theta_i_rad.empty()) throw InputError("give angles of incidence");
  for (double a : o.theta_i_rad)
    if (!(a >= 0 && a < kPi / 2)) throw InputError("angles of incidence must be in [0, 90) deg");
  if (!(o.theta_r_step_deg > 0)) throw InputError("the exit angle step must be > 0");
  const bool ref = o.he_sigma_m > 0 && o.he_tau_m > 0;
  // The references use the Fresnel term of the first height field's mirror material (F = 1
  // otherwise), at the half-vector angle, as the microfacet facets see it.
  std::shared_ptr<const Fresnel> fresnel;
  for (const auto& hf : scene.desc().heightfields) {
    const MicroMaterial& m = scene.desc().materials[hf.material];
    if (m.kind == MicroMaterial::Kind::Mirror) fresnel = m.fresnel;
    break;
  }
  std::unique_ptr<MicrofacetBrdf> smith;
  if (ref)
    smith = std::make_unique<MicrofacetBrdf>(
        std::make_shared<BeckmannDistribution>(2 * o.he_sigma_m / o.he_tau_m),
        fresnel ? fresnel : std::make_shared<const PerfectMirrorFresnel>());
  const double lambda = scene.desc().wavelength_m;
  const double cp = std::cos(o.phi_i_rad), sp = std::sin(o.phi_i_rad);
  const Vec3 axis(-sp, cp, 0);  // perpendicular to the plane of incidence
  std::vector<double> tr;
  std::vector<Vec3> dirs;
  for (double t = o.theta_r_min_deg; t <= o.theta_r_max_deg + 1e-9; t += o.theta_r_step_deg) {
    if (std::abs(t) * kDeg + half >= kPi / 2) continue;
    tr.push_back(t);
    dirs.emplace_back(cp * std::sin(t * kDeg), sp * std::sin(t * kDeg), std::cos(t * kDeg));
  }
  std::vector<GoniometerCurve> out;
  for (std::size_t ia = 0; ia < o.theta_i_rad.size(); ++ia) {
    const double ti = o.theta_i_rad[ia];
    const Vec3 wi(-cp * std::sin(ti), -sp * std::sin(ti), std::cos(ti));
    GoniometerCurve c;
    c.theta_i_rad = ti;
    c.theta_r_deg = tr;
    TraceCounters counters;
    c.simulated =
        cap_brdf(scene, wi, dirs, half, o.rays, o.trace, o.seed + ia, &counters, o.isotropic);
    if (o.single_scatter) {
      TraceOptions t1 = o.trace;
      t1.max_depth = 1;
      c.simulated_single =
          cap_brdf(scene, wi, dirs, half, o.rays, t1, o.seed + ia, nullptr, o.isotropic);
    }
    for (const Vec3& d : dirs) {
      if (ref) {
        c.he1991.push_back(cone_average(
            [&](const Vec3& w) {
              return he1991_geometric_brdf(wi, w, o.he_sigma_m, o.he_tau_m, true, fresnel.get(),
                                           lambda);
            },
            d, half, axis));
        c.beckmann_smith.push_back(
            cone_average([&](const Vec3& w) { return smith->eval(wi, w, lambda); }, d, half, axis));
      }
      if (o.sh) c.sh.push_back(o.sh->eval(wi, d, lambda));
    }
    c.albedo = counters.energy_out / double(counters.incident_rays);
    c.energy_below = counters.energy_down / double(counters.incident_rays);
    if (done) done(c);
    out.push_back(std::move(c));
  }
  return out;
}

}  // namespace microbrdf

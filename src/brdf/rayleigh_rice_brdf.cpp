// First-order Rayleigh-Rice BRDF of a conductor (include/microbrdf/rayleigh_rice.hpp;
// docs/rayleigh_rice.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <vector>

#include "core/marginal2d.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/rayleigh_rice.hpp"

namespace microbrdf {
namespace {

using cd = std::complex<double>;

// 1 / z without the NaN and overflow care of the library's complex division (|z| is of order
// 1 to 100 here): the node sums spend most of their time in divisions otherwise.
cd reciprocal(cd z) {
  const double n = std::norm(z);
  return {z.real() / n, -z.imag() / n};
}

// The principal square root (non-negative real part, the branch Fresnel's W takes) without
// the library's hypot: |z| is far from overflow here, and the sums take one root per node.
cd principal_sqrt(cd z) {
  const double x = z.real(), y = z.imag();
  const double r = std::sqrt(x * x + y * y);
  if (r == 0) return 0.0;
  const double t = std::sqrt(0.5 * (r + std::fabs(x)));
  if (x >= 0) return {t, y / (2 * t)};
  return {std::fabs(y) / (2 * t), std::copysign(t, y)};
}

// What the amplitudes need of the incident direction: computed once per light direction and
// wavelength, so that a sum over many views pays for one complex square root per view.
struct Incident {
  cd eps, e1, wi, di_inv, ei_inv;
  double si;
};
Incident incident(double ci, double si, cd eps) {
  Incident in;
  in.eps = eps;
  in.e1 = eps - 1.0;
  in.wi = principal_sqrt(eps - si * si);
  in.di_inv = reciprocal(ci + in.wi);
  in.ei_inv = reciprocal(eps * ci + in.wi);
  in.si = si;
  return in;
}

// The amplitudes from cosines and sines (the BRDF has them from the directions directly, without
// a round trip through acos).
RrAmplitudes amplitudes(const Incident& in, double cs, double ss, double cphi, double sphi) {
  const cd ws = principal_sqrt(in.eps - ss * ss);
  const cd ds_inv = reciprocal(cs + ws), es_inv = reciprocal(in.eps * cs + ws);
  const cd a = in.e1 * in.di_inv, b = in.e1 * in.ei_inv;
  return {a * cphi * ds_inv, -a * ws * sphi * es_inv, -b * in.wi * sphi * ds_inv,
          b * (in.eps * in.si * ss - in.wi * ws * cphi) * es_inv};
}
RrAmplitudes amplitudes(double ci, double si, double cs, double ss, double cphi, double sphi,
                        cd eps) {
  return amplitudes(incident(ci, si, eps), cs, ss, cphi, sphi);
}

cd permittivity(const OpticalConstants& m, double wavelength_m) {
  const cd n = m.at(wavelength_m);
  return n * n;
}

struct Geometry {
  double ci, si, cs, ss, cphi, sphi;
};

// Both directions above the horizon; phi_s from the forward direction -wi_xy (from +x at normal
// incidence), counter-clockwise about +z.
std::optional<Geometry> geometry(const Vec3& wi, const Vec3& wo) {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return std::nullopt;
  Geometry g;
  g.ci = std::min(1.0, wi.z());
  g.cs = std::min(1.0, wo.z());
  // (not hypot: unit vectors neither overflow nor underflow, and hypot is slow)
  g.si = std::sqrt(wi.x() * wi.x() + wi.y() * wi.y());
  g.ss = std::sqrt(wo.x() * wo.x() + wo.y() * wo.y());
  double dx = 1, dy = 0;
  if (g.si > 1e-12) {
    dx = -wi.x() / g.si;
    dy = -wi.y() / g.si;
  }
  g.cphi = 1;
  g.sphi = 0;
  if (g.ss > 1e-15) {
    g.cphi = (wo.x() * dx + wo.y() * dy) / g.ss;
    g.sphi = (dx * wo.y() - dy * wo.x()) / g.ss;
  }
  return g;
}

}  // namespace

Polarisation parse_polarisation(const std::string& name) {
  if (name == "unpolarised" || name == "unpolarized") return Polarisation::Unpolarised;
  if (name == "s") return Polarisation::S;
  if (name == "p") return Polarisation::P;
  if (name == "ss") return Polarisation::SS;
  if (name == "sp") return Polarisation::SP;
  if (name == "ps") return Polarisation::PS;
  if (name == "pp") return Polarisation::PP;
  throw InputError("unknown polarisation '" + name + "' (unpolarised, s, p, ss, sp, ps or pp)");
}

std::string to_string(Polarisation p) {
  switch (p) {
    case Polarisation::S:
      return "s";
    case Polarisation::P:
      return "p";
    case Polarisation::SS:
      return "ss";
    case Polarisation::SP:
      return "sp";
    case Polarisation::PS:
      return "ps";
    case Polarisation::PP:
      return "pp";
    default:
      return "unpolarised";
  }
}

RrAmplitudes rayleigh_rice_amplitudes(double theta_i, double theta_s, double phi_s, cd eps) {
  return amplitudes(std::cos(theta_i), std::sin(theta_i), std::cos(theta_s), std::sin(theta_s),
                    std::cos(phi_s), std::sin(phi_s), eps);
}

double rayleigh_rice_q(const RrAmplitudes& a, Polarisation p) {
  const double ss = std::norm(a.ss), sp = std::norm(a.sp), ps = std::norm(a.ps),
               pp = std::norm(a.pp);
  switch (p) {
    case Polarisation::S:
      return ss + sp;
    case Polarisation::P:
      return ps + pp;
    case Polarisation::SS:
      return ss;
    case Polarisation::SP:
      return sp;
    case Polarisation::PS:
      return ps;
    case Polarisation::PP:
      return pp;
    default:
      return (ss + sp + ps + pp) / 2;
  }
}

std::array<double, 16> rayleigh_rice_mueller(const RrAmplitudes& a) {
  // Jones matrix (E_s, E_p)_out = J (E_s, E_p)_in; M = A (J (x) J*) A^-1 with the coherency
  // vector (E_s E_s*, E_s E_p*, E_p E_s*, E_p E_p*) and A its map to (I, Q, U, V).
  const cd j[2][2] = {{a.ss, a.ps}, {a.sp, a.pp}};
  cd k[4][4];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) k[r][c] = j[r / 2][c / 2] * std::conj(j[r % 2][c % 2]);
  const cd i(0, 1);
  const cd A[4][4] = {{1, 0, 0, 1}, {1, 0, 0, -1}, {0, 1, 1, 0}, {0, i, -i, 0}};
  // A A^H = 2 I, so A^-1 = A^H / 2.
  cd ak[4][4] = {};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      for (int m = 0; m < 4; ++m) ak[r][c] += A[r][m] * k[m][c];
  std::array<double, 16> out{};
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) {
      cd v = 0;
      for (int m = 0; m < 4; ++m) v += ak[r][m] * std::conj(A[c][m]);
      out[4 * r + c] = v.real() / 2;
    }
  return out;
}

RrAngles rayleigh_rice_angles(const Vec3& wi, const Vec3& wo) {
  const Vec3 a(wi.x(), wi.y(), std::max(wi.z(), 1e-300));
  const Vec3 b(wo.x(), wo.y(), std::max(wo.z(), 1e-300));
  const auto g = geometry(a, b);
  return {std::atan2(g->si, g->ci), std::atan2(g->ss, g->cs), std::atan2(g->sphi, g->cphi)};
}

double smooth_reflectance(double cos_i, cd eps, Polarisation p) {
  const double c = std::clamp(std::fabs(cos_i), 0.0, 1.0);
  const cd w = std::sqrt(eps - (1 - c * c));
  const double rs = std::norm((c - w) / (c + w)), rp = std::norm((eps * c - w) / (eps * c + w));
  switch (p) {
    case Polarisation::S:
    case Polarisation::SS:
      return rs;
    case Polarisation::P:
    case Polarisation::PP:
      return rp;
    case Polarisation::SP:
    case Polarisation::PS:
      return 0;
    default:
      return (rs + rp) / 2;
  }
}

RayleighRiceBrdf::RayleighRiceBrdf(std::shared_ptr<const AreaPsd> psd, OpticalConstants material,
                                   Polarisation polarisation)
    : psd_(std::move(psd)), material_(std::move(material)), pol_(polarisation) {
  if (!psd_ || psd_->value.empty()) throw InputError("Rayleigh-Rice: the PSD is empty");
}

double RayleighRiceBrdf::eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const {
  const auto g = geometry(wi, wo);
  if (!g) return 0;
  const double l = wavelength_m;
  const double s = psd_->at((wo.x() + wi.x()) / l, (wo.y() + wi.y()) / l);
  if (!(s > 0)) return 0;
  const auto a =
      amplitudes(g->ci, g->si, g->cs, g->ss, g->cphi, g->sphi, permittivity(material_, l));
  return 16 * M_PI * M_PI / (l * l * l * l) * g->ci * g->cs * rayleigh_rice_q(a, pol_) * s;
}

std::array<double, 16> RayleighRiceBrdf::mueller(const Vec3& wi, const Vec3& wo,
                                                 double wavelength_m) const {
  std::array<double, 16> m{};
  const auto g = geometry(wi, wo);
  if (!g) return m;
  const double l = wavelength_m;
  const double s = psd_->at((wo.x() + wi.x()) / l, (wo.y() + wi.y()) / l);
  if (!(s > 0)) return m;
  m = rayleigh_rice_mueller(
      amplitudes(g->ci, g->si, g->cs, g->ss, g->cphi, g->sphi, permittivity(material_, l)));
  const double scale = 16 * M_PI * M_PI / (l * l * l * l) * g->ci * g->cs * s;
  for (double& v : m) v *= scale;
  return m;
}

double RayleighRiceBrdf::specular_reflectance(const Vec3& wi, double wavelength_m) const {
  if (!(wi.z() > 0)) return 0;
  const double g = 4 * M_PI * psd_->sq * wi.z() / wavelength_m;
  return smooth_reflectance(wi.z(), permittivity(material_, wavelength_m), pol_) * std::exp(-g * g);
}

double RayleighRiceBrdf::integrated_scatter(const Vec3& wi, double wavelength_m) const {
  if (!(wi.z() > 0)) return 0;
  const double l = wavelength_m;
  const AreaPsd& p = *psd_;
  const double si = std::sqrt(wi.x() * wi.x() + wi.y() * wi.y());
  const Incident in = incident(std::min(1.0, wi.z()), si, permittivity(material_, l));
  // One partial sum per row, added in row order: the same bits with any number of threads.
  std::vector<double> rows(p.nfy, 0.0);
#pragma omp parallel for schedule(static)
  for (long iyl = 0; iyl < static_cast<long>(p.nfy); ++iyl) {
    const auto iy = static_cast<std::size_t>(iyl);
    const double uy = l * p.fy(iy) - wi.y();
    double sum = 0;
    for (std::size_t ix = 0; ix < p.nfx; ++ix) {
      const double s = p.at_node(ix, iy);
      if (!(s > 0)) continue;
      const double ux = l * p.fx(ix) - wi.x();
      const double r2 = ux * ux + uy * uy;
      if (r2 >= 1) continue;  // evanescent: no scattered wave
      const Vec3 wo(ux, uy, std::sqrt(1 - r2));
      const auto g = geometry(wi, wo);
      sum += g->cs * rayleigh_rice_q(amplitudes(in, g->cs, g->ss, g->cphi, g->sphi), pol_) * s;
    }
    rows[iy] = sum;
  }
  double sum = 0;
  for (double r : rows) sum += r;
  // f cos(theta_o) dw = f du dv = f lambda^2 dfx dfy.
  return 16 * M_PI * M_PI / (l * l) * wi.z() * sum * p.dfx * p.dfy;
}

double RayleighRiceBrdf::albedo(const Vec3& wi, double wavelength_m) const {
  return specular_reflectance(wi, wavelength_m) + integrated_scatter(wi, wavelength_m);
}

const detail::Marginal2D* RayleighRiceBrdf::lobe() const {
  std::call_once(lobe_once_, [this] {
    const AreaPsd& p = *psd_;
    const std::size_t n = p.nfx * p.nfy;
    try {
      check_memory("Rayleigh-Rice", mul_sat(n, 4 + 16) + mul_sat(p.nfy, 8),
                   "the PSD's sampling table");
      // The density is at() between the nodes: bilinear, with the zero-frequency estimate.
      std::vector<double> v(p.value);
      v[(p.nfy / 2) * p.nfx + p.nfx / 2] = p.zero_frequency_estimate();
      const double peak = *std::max_element(v.begin(), v.end());
      if (!(peak > 0)) return;
      std::vector<float> data(n);
      for (std::size_t i = 0; i < n; ++i) data[i] = static_cast<float>(v[i] / peak);
      lobe_ = std::make_shared<const detail::Marginal2D>(data, p.nfx, p.nfy,
                                                         std::vector<std::vector<double>>{}, true);
    } catch (const std::exception&) {
      lobe_ = nullptr;  // over the budget, or no mass: the cosine branch alone
    }
  });
  return lobe_.get();
}

double RayleighRiceBrdf::lobe_pdf(const Vec3& wi, const Vec3& wo) const {
  const detail::Marginal2D* m = lobe();
  if (!m || !(wo.z() > 0)) return 0;
  const AreaPsd& p = *psd_;
  const double l = kSamplingWavelength;
  const double wx = p.fx(p.nfx - 1) - p.fx(0), wy = p.fy(p.nfy - 1) - p.fy(0);
  const double x = ((wo.x() + wi.x()) / l - p.fx(0)) / wx;
  const double y = ((wo.y() + wi.y()) / l - p.fy(0)) / wy;
  if (!(x >= 0 && x <= 1 && y >= 0 && y <= 1)) return 0;
  // per unit square -> per (cycles/m)^2 -> per unit wo_xy (lambda^2) -> per steradian (cos)
  return m->eval({x, y}, nullptr) / (wx * wy) / (l * l) * wo.z();
}

std::optional<BrdfSample> RayleighRiceBrdf::sample(const Vec3& wi, double u1, double u2,
                                                   double wavelength_m) const {
  if (!(wi.z() > 0)) return std::nullopt;
  BrdfSample s;
  if (u1 < 0.5) {
    s.wo = Vec3(-wi.x(), -wi.y(), wi.z());
    s.delta = true;
    s.pdf = 0;
    s.weight = 2 * specular_reflectance(wi, wavelength_m);
    return s;
  }
  if (u1 < 0.75) {  // cosine-weighted; (u1 - 0.5) * 4 is a fresh uniform number
    const double v = (u1 - 0.5) * 4;
    const double r = std::sqrt(v), phi = 2 * M_PI * u2;
    const double z = std::sqrt(std::max(0.0, 1 - v));
    if (!(z > 0)) return std::nullopt;
    s.wo = Vec3(r * std::cos(phi), r * std::sin(phi), z);
  } else {  // the PSD's halo at the sampling wavelength
    const detail::Marginal2D* m = lobe();
    if (!m) return std::nullopt;
    const auto [pos, density] = m->sample({(u1 - 0.75) * 4, u2}, nullptr);
    (void)density;
    const AreaPsd& p = *psd_;
    const double l = kSamplingWavelength;
    const double fx = p.fx(0) + pos[0] * (p.fx(p.nfx - 1) - p.fx(0));
    const double fy = p.fy(0) + pos[1] * (p.fy(p.nfy - 1) - p.fy(0));
    const double x = l * fx - wi.x(), y = l * fy - wi.y(), r2 = x * x + y * y;
    if (!(r2 < 1)) return std::nullopt;  // evanescent at this wavelength
    s.wo = Vec3(x, y, std::sqrt(1 - r2));
  }
  s.pdf = pdf(wi, s.wo);
  if (!(s.pdf > 0)) return std::nullopt;
  s.weight = eval(wi, s.wo, wavelength_m) * s.wo.z() / s.pdf;
  return s;
}

double RayleighRiceBrdf::pdf(const Vec3& wi, const Vec3& wo) const {
  if (!(wi.z() > 0) || !(wo.z() > 0)) return 0;
  return 0.25 * (wo.z() / M_PI + lobe_pdf(wi, wo));
}

std::string RayleighRiceBrdf::describe() const {
  char buf[160];
  std::snprintf(buf, sizeof buf, "Rayleigh-Rice first order, %s, PSD %zux%zu %s, Sq %.4g nm",
                to_string(pol_).c_str(), psd_->nfx, psd_->nfy, to_string(psd_->window).c_str(),
                psd_->sq * 1e9);
  return std::string(buf) + ", " + material_.name + " (" + material_.source + ")";
}

}  // namespace microbrdf

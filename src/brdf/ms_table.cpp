// The tabulated multiple-scattering lobe (include/microbrdf/multiple_scattering.hpp, MsTable).
#include <omp.h>

#include <algorithm>
#include <cmath>

#include "core/splitmix64.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/multiple_scattering.hpp"
#include "microbrdf/quadrature.hpp"
#include "microbrdf/threads.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

// True when D and Lambda do not change under rotations about n (checked on a few directions
// against rotations by node steps): the table then needs one incidence azimuth only.
bool rotation_invariant(const MicrofacetDistribution& d) {
  const Vec3 probes[] = {Vec3(0.3, 0.1, 0.9).normalized(), Vec3(-0.5, 0.4, 0.6).normalized(),
                         Vec3(0.8, -0.2, 0.3).normalized()};
  for (const double phi : {0.7, 1.9, 3.3}) {
    const double c = std::cos(phi), s = std::sin(phi);
    for (const Vec3& p : probes) {
      const Vec3 r(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
      const double a = d.D(p), b = d.D(r), la = d.lambda(p), lb = d.lambda(r);
      if (std::abs(a - b) > 1e-12 * std::max(1.0, std::abs(a))) return false;
      if (std::abs(la - lb) > 1e-12 * std::max(1.0, std::abs(la))) return false;
    }
  }
  return true;
}

}  // namespace

Vec3 MsTable::direction(std::size_t k) const {
  const std::size_t it = k / np_, ip = k % np_;
  const double t = (static_cast<double>(it) + 0.5) * (kPi / 2) / static_cast<double>(nt_);
  const double p = 2 * kPi * static_cast<double>(ip) / static_cast<double>(np_);
  return Vec3(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
}

// Bilinear weights of the four nodes around v: calls get(k, weight) for each.
template <class Get>
double MsTable::interp(const Vec3& v, Get get) const {
  const double theta = std::acos(std::clamp(v.z(), -1.0, 1.0));
  double phi = std::atan2(v.y(), v.x());
  if (phi < 0) phi += 2 * kPi;
  const double ft = std::clamp(theta / (kPi / 2) * static_cast<double>(nt_) - 0.5, 0.0,
                               static_cast<double>(nt_ - 1));
  const auto t0 = static_cast<std::size_t>(ft);
  const std::size_t t1 = std::min(t0 + 1, nt_ - 1);
  const double a = ft - static_cast<double>(t0);
  const double fp = phi / (2 * kPi) * static_cast<double>(np_);
  const auto pf = static_cast<std::size_t>(fp);
  const std::size_t p0 = pf % np_, p1 = (pf + 1) % np_;
  const double b = fp - static_cast<double>(pf);
  return (1 - a) * ((1 - b) * get(t0 * np_ + p0) + b * get(t0 * np_ + p1)) +
         a * ((1 - b) * get(t1 * np_ + p0) + b * get(t1 * np_ + p1));
}

double MsTable::eval(const Vec3& wi, const Vec3& wo) const {
  if (nt_ == 0 || !(wi.z() > 0) || !(wo.z() > 0)) return 0;
  const std::size_t n = nodes();
  return interp(
      wi, [&](std::size_t i) { return interp(wo, [&](std::size_t j) { return f_[i * n + j]; }); });
}

double MsTable::energy(const Vec3& wi) const {
  if (nt_ == 0 || !(wi.z() > 0)) return 0;
  return interp(wi, [&](std::size_t i) { return e_[i]; });
}

void MsTable::fill_rotations() {
  // Row (theta_i, phi_p) is row (theta_i, 0) with every outgoing node turned by -phi_p.
  const std::size_t n = nodes();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t ip = i % np_, base = i - ip;
    if (ip == 0) continue;
    for (std::size_t j = 0; j < n; ++j) {
      const std::size_t jt = j / np_, jp = j % np_;
      f_[i * n + j] = f_[base * n + jt * np_ + (jp + np_ - ip) % np_];
    }
    e_[i] = e_[base];
  }
}

void MsTable::normalise_rows() {
  // The node values are point estimates and the interpolant is flat beyond the outermost theta
  // nodes, so its integral misses part of a lobe that rises towards the horizon. Each row is
  // scaled so that the integral of its interpolant, integral f_ms cos(theta_o) dwo, equals the
  // row's energy (the walks' own estimate, which needs no interpolation): pdf() then
  // integrates to the walk's exit probability.
  const std::size_t n = nodes();
  std::vector<double> x, w;
  gauss_legendre(48, x, w);
  const std::size_t nphi = std::max<std::size_t>(96, 4 * np_);
  std::vector<Vec3> q;
  std::vector<double> qw;
  for (std::size_t a = 0; a < x.size(); ++a) {
    const double u = 0.5 * (x[a] + 1), st = std::sqrt(std::max(0.0, 1 - u * u));
    for (std::size_t b = 0; b < nphi; ++b) {
      const double p = 2 * kPi * (static_cast<double>(b) + 0.5) / static_cast<double>(nphi);
      q.emplace_back(st * std::cos(p), st * std::sin(p), u);
      qw.push_back(0.5 * w[a] * u * 2 * kPi / static_cast<double>(nphi));
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    double integral = 0;
    for (std::size_t k = 0; k < q.size(); ++k)
      integral += qw[k] * interp(q[k], [&](std::size_t j) { return f_[i * n + j]; });
    if (integral > 0 && e_[i] > 0) {
      const double scale = e_[i] / integral;
      for (std::size_t j = 0; j < n; ++j) f_[i * n + j] *= scale;
    }
  }
}

MsTable tabulate_multiple_scattering(const MicrofacetRandomWalk& walk, const Fresnel* fresnel,
                                     double wavelength_m, const MsTableOptions& opt) {
  if (opt.theta_nodes < 1 || opt.phi_nodes < 1 || opt.walks < 1 || opt.energy_walks < 1)
    throw InputError(
        "multiple-scattering table: theta_nodes, phi_nodes, walks and energy_walks must be >= 1");
  MsTable t;
  t.nt_ = opt.theta_nodes;
  t.np_ = opt.phi_nodes;
  const std::size_t n = t.nodes();
  check_memory("multiple-scattering table", mul_sat(mul_sat(n, n + 1), sizeof(double)),
               "the multiple-scattering lobe table");
  t.f_.assign(n * n, 0.0);
  t.e_.assign(n, 0.0);
  std::vector<Vec3> dirs(n);
  std::vector<double> lam(n);
  for (std::size_t k = 0; k < n; ++k) {
    dirs[k] = t.direction(k);
    lam[k] = walk.lambda(dirs[k]);
  }
  // Isotropic distributions: the incidence azimuth 0 only, the rest by rotating the nodes.
  const bool iso = rotation_invariant(walk.distribution());
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < n; ++i)
    if (!iso || i % t.np_ == 0) rows.push_back(i);
  const int threads = resolve_thread_count(opt.threads);
  const auto nrows = static_cast<long>(rows.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long r = 0; r < nrows; ++r) {
    const std::size_t i = rows[static_cast<std::size_t>(r)];
    // One stream per incidence node: the row does not depend on the thread that computes it.
    WalkRng rng(detail::splitmix64(detail::chunk_seed(opt.seed, i)));
    double* out = &t.f_[i * n];
    for (std::size_t w = 0; w < opt.walks; ++w)
      walk.eval_cos_many(dirs[i], dirs.data(), lam.data(), n, rng, fresnel, wavelength_m, out, 2);
    const double inv = 1.0 / static_cast<double>(opt.walks);
    for (std::size_t j = 0; j < n; ++j) out[j] *= inv / dirs[j].z();
    // The energy from many more walks without next-event estimation (cheap, and the energy's
    // error is the one that shows in the furnace test and in pdf()'s normalisation).
    double energy = 0;
    for (std::size_t w = 0; w < opt.energy_walks; ++w)
      walk.eval_cos_many(dirs[i], nullptr, nullptr, 0, rng, fresnel, wavelength_m, nullptr, 2,
                         &energy);
    t.e_[i] = energy / static_cast<double>(opt.energy_walks);
  }
  if (iso) t.fill_rotations();
  t.normalise_rows();
  return t;
}

}  // namespace microbrdf

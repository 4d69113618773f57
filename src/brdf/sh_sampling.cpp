// Importance sampling of ShBrdf: per incident node a tabulated CDF over outgoing cells of
// max(f, 0) (f = rho cos cos, so the density follows rho cos(theta_o) for that wi), linearly
// interpolated between nodes by splitting the random number, and mixed with a cosine lobe.
// pdf() evaluates exactly the density sample() draws from, so weights are unbiased whatever the
// table resolution. The table is built once (std::call_once) and then only read: sample() and
// pdf() are safe from many threads.
#include <algorithm>
#include <cmath>

#include "microbrdf/brdf.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "sh_internal.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;

template <class Table>
void fill_table(Table& t, const ShOddBasis& basis, const Eigen::MatrixXd& m, bool iso) {
  t.isotropic = iso;
  t.n_ti = iso ? 45 : 24;
  t.n_pi = iso ? 1 : 32;
  t.n_to = iso ? 64 : 48;
  t.n_po = iso ? 128 : 96;
  t.d_ti = kPi / 2 / t.n_ti;
  t.d_pi = 2 * kPi / t.n_pi;
  t.d_to = kPi / 2 / t.n_to;
  t.d_po = 2 * kPi / t.n_po;
  t.z_edge.resize(t.n_to + 1);
  for (int r = 0; r <= t.n_to; ++r) t.z_edge[r] = r == t.n_to ? 0.0 : std::cos(r * t.d_to);
  t.inv_omega.resize(t.n_to);
  for (int r = 0; r < t.n_to; ++r) t.inv_omega[r] = 1 / (t.d_po * (t.z_edge[r] - t.z_edge[r + 1]));

  const int nb = basis.size(), nc = t.cells(), nn = t.n_ti * t.n_pi;
  Eigen::MatrixXd yo(nb, nc);  // basis at the cell centres
  for (int r = 0; r < t.n_to; ++r)
    for (int p = 0; p < t.n_po; ++p) {
      const double th = (r + 0.5) * t.d_to, ph = (p + 0.5) * t.d_po;
      basis.eval(Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)),
                 yo.col(r * t.n_po + p).data());
    }
  Eigen::MatrixXd yi(nb, nn);
  for (int k = 0; k < t.n_ti; ++k)
    for (int q = 0; q < t.n_pi; ++q) {
      const double th = (k + 0.5) * t.d_ti, ph = q * t.d_pi;
      basis.eval(Vec3(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th)),
                 yi.col(k * t.n_pi + q).data());
    }
  t.cdf.assign(static_cast<std::size_t>(nn) * (nc + 1), 0.0f);
  constexpr int kChunk = 64;  // nodes per matrix product (bounds the temporary to nc x 64)
  for (int n0 = 0; n0 < nn; n0 += kChunk) {
    const int cnt = std::min(kChunk, nn - n0);
    const Eigen::MatrixXd f = yo.transpose() * (m * yi.middleCols(n0, cnt));
    for (int j = 0; j < cnt; ++j) {
      std::vector<double> acc(nc + 1, 0.0);
      for (int c = 0; c < nc; ++c)
        acc[c + 1] = acc[c] + std::max(f(c, j), 0.0) / t.inv_omega[c / t.n_po];
      if (!(acc[nc] > 0))  // nothing reflected: uniform over solid angle
        for (int c = 0; c < nc; ++c) acc[c + 1] = acc[c] + 1 / t.inv_omega[c / t.n_po];
      float* out = t.cdf.data() + static_cast<std::size_t>(n0 + j) * (nc + 1);
      for (int c = 0; c <= nc; ++c) out[c] = static_cast<float>(acc[c] / acc[nc]);
      out[nc] = 1.0f;
    }
  }
}

struct Nodes {
  int n = 0;
  int idx[4];
  double w[4];
};

template <class Table>
Nodes find_nodes(const Table& t, double theta, double phi) {
  double x = theta / t.d_ti - 0.5;
  int k0 = static_cast<int>(std::floor(x));
  double fx = x - k0;
  if (k0 < 0) k0 = 0, fx = 0;
  if (k0 >= t.n_ti - 1) k0 = t.n_ti - 1, fx = 0;
  int q0 = 0, q1 = 0;
  double fy = 0;
  if (t.n_pi > 1) {
    double y = phi / t.d_pi;
    q0 = static_cast<int>(std::floor(y));
    fy = y - q0;
    q0 = ((q0 % t.n_pi) + t.n_pi) % t.n_pi;
    q1 = (q0 + 1) % t.n_pi;
  }
  Nodes n;
  auto add = [&](int k, int q, double w) {
    if (w > 0) {
      n.idx[n.n] = k * t.n_pi + q;
      n.w[n.n] = w;
      ++n.n;
    }
  };
  add(k0, q0, (1 - fx) * (1 - fy));
  add(k0, q1, (1 - fx) * fy);
  if (fx > 0) {
    add(k0 + 1, q0, fx * (1 - fy));
    add(k0 + 1, q1, fx * fy);
  }
  return n;
}

// Incident angles of wi; for an isotropic table also the rotation that brings wi to phi = 0.
struct Frame {
  double theta, phi;
  double c = 1, s = 0;  // rotate world -> local by -phi_i (isotropic only)
};

template <class Table>
Frame frame(const Table& t, const Vec3& wi) {
  Frame f;
  const double rho = std::hypot(wi.x(), wi.y());
  f.theta = std::atan2(rho, wi.z());
  f.phi = rho > 0 ? std::atan2(wi.y(), wi.x()) : 0.0;
  if (f.phi < 0) f.phi += 2 * kPi;
  if (t.isotropic && rho > 0) {
    f.c = wi.x() / rho;
    f.s = wi.y() / rho;
  }
  return f;
}

template <class Table>
double table_pdf(const Table& t, const Nodes& nodes, const Vec3& wl) {
  const double th = std::acos(std::clamp(wl.z(), -1.0, 1.0));
  double ph = std::atan2(wl.y(), wl.x());
  if (ph < 0) ph += 2 * kPi;
  const int r = std::min(static_cast<int>(th / t.d_to), t.n_to - 1);
  const int p = std::min(static_cast<int>(ph / t.d_po), t.n_po - 1);
  const int c = r * t.n_po + p;
  double sum = 0;
  for (int i = 0; i < nodes.n; ++i) {
    const float* cdf = t.node_cdf(nodes.idx[i]);
    sum += nodes.w[i] * (static_cast<double>(cdf[c + 1]) - cdf[c]);
  }
  return sum * t.inv_omega[r];
}

}  // namespace

const ShBrdf::SamplingTable& ShBrdf::table() const {
  std::call_once(lazy_->once, [this] {
    auto t = std::make_unique<SamplingTable>();
    fill_table(*t, basis_, m_, isotropic_);
    lazy_->table = std::move(t);
  });
  return *lazy_->table;
}

double ShBrdf::pdf(const Vec3& wi_, const Vec3& wo_) const {
  if (!(wi_.z() > 0) || !(wo_.z() > 0)) return 0.0;
  const Vec3 wi = wi_.normalized(), wo = wo_.normalized();
  const SamplingTable& t = table();
  const Frame fr = frame(t, wi);
  const Nodes nodes = find_nodes(t, fr.theta, fr.phi);
  const Vec3 wl(fr.c * wo.x() + fr.s * wo.y(), -fr.s * wo.x() + fr.c * wo.y(), wo.z());
  return t.cos_mix * wo.z() / kPi + (1 - t.cos_mix) * table_pdf(t, nodes, wl);
}

std::optional<BrdfSample> ShBrdf::sample(const Vec3& wi_, double u1, double u2,
                                         double wavelength_m) const {
  if (!(wi_.z() > 0)) return std::nullopt;
  const Vec3 wi = wi_.normalized();
  const SamplingTable& t = table();
  Vec3 wo;
  double u = std::clamp(u1, 0.0, std::nextafter(1.0, 0.0));
  if (u < t.cos_mix) {  // cosine lobe
    u /= t.cos_mix;
    const double r = std::sqrt(u), ph = 2 * kPi * u2;
    wo = Vec3(r * std::cos(ph), r * std::sin(ph), std::sqrt(std::max(0.0, 1 - u)));
  } else {
    u = (u - t.cos_mix) / (1 - t.cos_mix);
    const Frame fr = frame(t, wi);
    const Nodes nodes = find_nodes(t, fr.theta, fr.phi);
    int pick = nodes.n - 1;  // choose a node with its interpolation weight, reuse u
    double acc = 0;
    for (int i = 0; i < nodes.n; ++i) {
      if (u < acc + nodes.w[i] || i == nodes.n - 1) {
        pick = i;
        u = std::clamp((u - acc) / nodes.w[i], 0.0, std::nextafter(1.0, 0.0));
        break;
      }
      acc += nodes.w[i];
    }
    const float* cdf = t.node_cdf(nodes.idx[pick]);
    const int nc = t.cells();
    int c = static_cast<int>(std::upper_bound(cdf, cdf + nc + 1, static_cast<float>(u)) - cdf) - 1;
    c = std::clamp(c, 0, nc - 1);
    while (c > 0 && !(cdf[c + 1] > cdf[c])) --c;  // never land in an empty cell
    const double lo = cdf[c], pm = static_cast<double>(cdf[c + 1]) - lo;
    const double v = pm > 0 ? std::clamp((u - lo) / pm, 0.0, 1.0) : 0.5;
    const int r = c / t.n_po, p = c % t.n_po;
    const double z = t.z_edge[r] + v * (t.z_edge[r + 1] - t.z_edge[r]);
    const double s = std::sqrt(std::max(0.0, 1 - z * z)), ph = (p + u2) * t.d_po;
    const Vec3 wl(s * std::cos(ph), s * std::sin(ph), z);
    wo = Vec3(fr.c * wl.x() - fr.s * wl.y(), fr.s * wl.x() + fr.c * wl.y(), wl.z());
  }
  if (!(wo.z() > 0)) return std::nullopt;
  const double p = pdf(wi, wo);
  if (!(p > 0)) return std::nullopt;
  // Where the truncated expansion is <= 0 the sample is returned with weight 0 (absorbed), so the
  // directions drawn follow pdf() exactly.
  const double f = eval(wi, wo, wavelength_m);
  return BrdfSample{wo, f * wo.z() / p, p};
}

}  // namespace microbrdf

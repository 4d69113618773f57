// Spectral evaluation and sampling of materials (see material.hpp).
#include "render/material.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>

#ifdef __SSE2__
#include <emmintrin.h>
#endif

namespace microbrdf::pt {

FastSpectrum::FastSpectrum(const Spectrum& s) : l_(s.wavelengths()), v_(s.values()) {
  if (l_.size() < 2) return;
  const std::size_t cells = 4 * l_.size();
  inv_step_ = double(cells) / (l_.back() - l_.front());
  start_.resize(cells);
  for (std::size_t c = 0; c < cells; ++c) {
    const double left = l_.front() + double(c) / inv_step_;
    // One below upper_bound of the cell's left end (rounding of the cell index may put a
    // wavelength just left of its cell): never past the answer, which is >= 1 inside the range.
    const std::size_t i = std::size_t(std::upper_bound(l_.begin(), l_.end(), left) - l_.begin());
    start_[c] = std::uint32_t(std::max<std::size_t>(i, 2) - 1);
  }
}

SpectralMaterial::SpectralMaterial(std::shared_ptr<const Svbrdf> m) : m_(std::move(m)) {
  const auto* u = dynamic_cast<const UniformSvbrdf*>(m_.get());
  mf_ = u ? dynamic_cast<const MicrofacetBrdf*>(&u->brdf()) : nullptr;
  if (!mf_) return;
  d_ = &mf_->distribution();
  separable_ = mf_->describe().find("separable Smith") != std::string::npos;
  if (const auto* c = dynamic_cast<const ConductorFresnel*>(&mf_->fresnel())) {
    conductor_ = true;
    n_ = FastSpectrum(c->constants().n);
    k_ = FastSpectrum(c->constants().k);
  }
  // The analytic models sample their visible normals exactly: sampling_pdf = pdf_visible.
  visible_exact_ = d_->samples_visible_exactly();
  tab_ = dynamic_cast<const TabulatedDistribution*>(d_);
  if ((ggx_ = dynamic_cast<const GgxDistribution*>(d_))) {
    ggx_c_ = std::cos(ggx_->params().phi);
    ggx_s_ = std::sin(ggx_->params().phi);
  }
  if (!self_check()) {
    ggx_ = nullptr;
    tab_ = nullptr;
    mf_ = nullptr;
    d_ = nullptr;
    conductor_ = false;
  }
}

bool SpectralMaterial::self_check() const {
  // Light and view on a small spiral of directions, at two wavelengths: f, the MIS density and
  // the samples against the BRDF's own eval(), pdf() and sample().
  auto close = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::abs(b) + 1e-300; };
  for (int i = 0; i < 16; ++i) {
    const double ti = 0.1 + 0.09 * i, pi = 0.7 * i, to = 1.4 - 0.08 * i, po = 2.9 + 0.3 * i;
    const Vec3 wi(std::sin(ti) * std::cos(pi), std::sin(ti) * std::sin(pi), std::cos(ti));
    const Vec3 wo(std::sin(to) * std::cos(po), std::sin(to) * std::sin(po), std::cos(to));
    const double lambda[2] = {555e-9, 432e-9};
    Wavelengths w;
    prepare(lambda, 2, w);
    const View vw = view(wo);
    double f[2], pdf = 0;
    const bool nonzero = eval(0, 0, vw, wi, w, f, &pdf);
    for (int k = 0; k < 2; ++k)
      if (!close(f[k], mf_->eval(wi, wo, lambda[k]))) return false;
    if (nonzero && !close(pdf, mf_->pdf(wo, wi))) return false;
    Sample s;
    const double u1 = (i + 0.5) / 16, u2 = std::fmod(0.618 * i + 0.1, 1.0);
    const bool got = sample(0, 0, vw, u1, u2, w, s);
    const auto ref = mf_->sample(wo, u1, u2, lambda[0]);
    const bool has_ref = ref && ref->weight > 0 && ref->wo.z() > 0;
    if (got != has_ref) return false;
    if (got && (!close(s.pdf, ref->pdf) || !close(s.weight[0], ref->weight) ||
                (s.wo - ref->wo).norm() > 1e-12))
      return false;
  }
  return true;
}

void SpectralMaterial::prepare(const double* lambda_m, int n, Wavelengths& w) const {
  w.n = n;
  for (int k = 0; k < n; ++k) {
    w.lambda_m[k] = lambda_m[k];
    if (conductor_) {
      const double eta = n_(lambda_m[k]), kappa = k_(lambda_m[k]);
      w.e[k] = eta * eta - kappa * kappa;
      w.f4[k] = 4 * eta * eta * kappa * kappa;
    }
  }
}

SpectralMaterial::View SpectralMaterial::view(const Vec3& wv) const {
  View v;
  v.wv = wv;
  if (mf_ && wv.z() > 0) {
    const double lam = d_->lambda(wv);
    v.g1 = std::min(1.0, 1.0 / (1.0 + lam));  // MicrofacetDistribution::G1
    v.pa = wv.z() * (1.0 + lam);              // projected_area
    if (tab_) {
      v.mix = tab_->view_mix(wv);
      v.tab = true;
    }
  }
  return v;
}

double SpectralMaterial::fresnel(double cos_i, const Wavelengths& w, int k) const {
  if (!conductor_) return mf_->fresnel().eval(cos_i, w.lambda_m[k]);
  // fresnel_conductor_siegel with eta^2 - kappa^2 and 4 eta^2 kappa^2 from prepare() (the
  // same operations in the same order).
  const double c = std::min(std::abs(cos_i), 1.0);
  const double c2 = c * c, s2 = std::max(0.0, 1.0 - c2);
  const double t = w.e[k] - s2;
  const double a2b2 = std::sqrt(t * t + w.f4[k]);
  const double a = std::sqrt(std::max(0.0, 0.5 * (a2b2 + t)));
  const double rs = (a2b2 - 2 * a * c + c2) / (a2b2 + 2 * a * c + c2);
  const double rp =
      rs * (a2b2 * c2 - 2 * a * c * s2 + s2 * s2) / (a2b2 * c2 + 2 * a * c * s2 + s2 * s2);
  return 0.5 * (rs + rp);
}

// MicrofacetDistribution::G2(wl, wv, h) with G1(wv) from the view.
double SpectralMaterial::g2(const View& vw, const Vec3& wl, const Vec3& h) const {
  const Vec3& wv = vw.wv;
  if (wl.dot(h) * wl.z() <= 0 || wv.dot(h) * wv.z() <= 0 || wl.z() <= 0 || wv.z() <= 0) return 0;
  const double gi = std::min(1.0, 1.0 / (1.0 + d_->lambda(wl))), go = vw.g1;
  if (separable_) return gi * go;
  return 1.0 / (1.0 / gi + 1.0 / go - 1.0);
}

void SpectralMaterial::fresnel_all(double cos_i, const Wavelengths& w, double scale,
                                   double* out) const {
  const int n = w.n;
  if (!conductor_) {
    for (int k = 0; k < n; ++k) out[k] = mf_->fresnel().eval(cos_i, w.lambda_m[k]) * scale;
    return;
  }
  const double c = std::min(std::abs(cos_i), 1.0);
  const double c2 = c * c, s2 = std::max(0.0, 1.0 - c2);
  int k = 0;
#ifdef __SSE2__
  // Two wavelengths at a time: the same IEEE operations in the same order as fresnel(), so the
  // same values.
  const __m128d vc = _mm_set1_pd(c), vc2 = _mm_set1_pd(c2), vs2 = _mm_set1_pd(s2),
                two = _mm_set1_pd(2.0), half = _mm_set1_pd(0.5), zero = _mm_setzero_pd(),
                vscale = _mm_set1_pd(scale), s4 = _mm_set1_pd(s2 * s2);
  for (; k + 1 < n; k += 2) {
    const __m128d t = _mm_sub_pd(_mm_loadu_pd(&w.e[k]), vs2);
    const __m128d a2b2 = _mm_sqrt_pd(_mm_add_pd(_mm_mul_pd(t, t), _mm_loadu_pd(&w.f4[k])));
    // (max(x, 0) gives 0 for a NaN x, as std::max(0.0, x) does)
    const __m128d a = _mm_sqrt_pd(_mm_max_pd(_mm_mul_pd(half, _mm_add_pd(a2b2, t)), zero));
    const __m128d ac2 = _mm_mul_pd(_mm_mul_pd(two, a), vc);  // 2 a c
    const __m128d rs =
        _mm_div_pd(_mm_add_pd(_mm_sub_pd(a2b2, ac2), vc2), _mm_add_pd(_mm_add_pd(a2b2, ac2), vc2));
    const __m128d p1 = _mm_mul_pd(a2b2, vc2), p2 = _mm_mul_pd(ac2, vs2);
    const __m128d rp = _mm_div_pd(_mm_mul_pd(rs, _mm_add_pd(_mm_sub_pd(p1, p2), s4)),
                                  _mm_add_pd(_mm_add_pd(p1, p2), s4));
    _mm_storeu_pd(&out[k], _mm_mul_pd(_mm_mul_pd(half, _mm_add_pd(rs, rp)), vscale));
  }
#endif
  for (; k < n; ++k) out[k] = fresnel(cos_i, w, k) * scale;
}

bool SpectralMaterial::eval(double u, double v, const View& vw, const Vec3& wl,
                            const Wavelengths& w, double* f, double* pdf) const {
  const int n = w.n;
  if (!mf_) {
    bool any = false;
    m_->eval_spectral(u, v, wl, vw.wv, w.lambda_m, n, f);
    for (int k = 0; k < n; ++k) any |= f[k] != 0;
    if (pdf) *pdf = m_->pdf(u, v, vw.wv, wl);
    return any;
  }
  for (int k = 0; k < n; ++k) f[k] = 0;
  if (pdf) *pdf = 0;
  const Vec3& wv = vw.wv;
  if (wl.z() <= 0 || wv.z() <= 0) return false;
  const Vec3 hs = wl + wv;
  const double len = hs.norm();
  if (len == 0) return false;
  const Vec3 h = hs / len;
  // f = 0 (no NDF mass at h, or shadowed): nothing more is needed, the caller drops the sample
  // (tabulated NDFs are 0 over much of the disk, and their sampling density is the costly part).
  TabulatedLookup q;
  const double dh = d_of(vw, h, q);
  if (dh == 0) return false;
  if (pdf && tab_ && vw.tab) tab_->prefetch_pdf(vw.mix, q);  // (loads while G2 is computed)
  const double g = g2(vw, wl, h);
  if (g == 0) return false;
  const double geo = dh * g / (4 * wl.z() * wv.z());
  if (geo == 0) return false;
  if (pdf) {
    // MicrofacetBrdf::pdf(wv, wl) = sampling_pdf(wv, h) / (4 wv.h).
    const double vh = wv.dot(h);
    if (vh > 0)
      *pdf = visible_exact_ ? (vw.pa > 0 ? dh / (4 * vw.pa) : 0.0)
                            : sampling_pdf_of(vw, h, q) / (4 * vh);
  }
  fresnel_all(wl.dot(h), w, geo, f);
  return true;
}

double SpectralMaterial::sampling_pdf(double u, double v, const View& vw, const Vec3& wl) const {
  if (!mf_) return m_->pdf(u, v, vw.wv, wl);
  const Vec3& wv = vw.wv;
  if (wl.z() <= 0 || wv.z() <= 0) return 0;  // sample() never returns such directions
  const Vec3 hs = wl + wv;
  const double len = hs.norm();
  if (len == 0) return 0;
  const Vec3 h = hs / len;
  const double vh = wv.dot(h);
  if (!(vh > 0)) return 0;
  // As in eval(): MicrofacetBrdf::pdf(wv, wl) = sampling_pdf(wv, h) / (4 wv.h).
  if (visible_exact_) return vw.pa > 0 ? d_->D(h) / (4 * vw.pa) : 0.0;
  TabulatedLookup q;
  if (tab_ && vw.tab) tab_->lookup(h, q);
  return sampling_pdf_of(vw, h, q) / (4 * vh);
}

bool SpectralMaterial::sample(double u, double v, const View& vw, double u1, double u2,
                              const Wavelengths& w, Sample& s) const {
  const int n = w.n;
  const Vec3& wv = vw.wv;
  if (!mf_) {
    const auto b = m_->sample(u, v, wv, u1, u2, w.lambda_m[0]);
    if (!b || !(b->weight > 0) || !(b->wo.z() > 0)) return false;
    s.wo = b->wo;
    s.delta = b->delta;
    if (!b->delta) {
      if (!(b->pdf > 0 && std::isfinite(b->pdf))) return false;
      s.pdf = b->pdf;
      double f[kMaxWavelengths];
      m_->eval_spectral(u, v, s.wo, wv, w.lambda_m, n, f);
      s.target = 0;
      for (int k = 0; k < n; ++k) {
        s.weight[k] = f[k] * s.wo.z() / s.pdf;
        s.target += std::abs(f[k]);
      }
      s.target *= s.wo.z() / n;
    } else {
      s.pdf = 0;
      s.weight[0] = b->weight;
      for (int k = 1; k < n; ++k) {
        const auto bk = m_->sample(u, v, wv, u1, u2, w.lambda_m[k]);
        s.weight[k] = bk && (bk->wo - s.wo).squaredNorm() < 1e-12 ? bk->weight : 0.0;
      }
    }
    return true;
  }
  // MicrofacetBrdf::sample with D and G2 evaluated once for all wavelengths.
  if (wv.z() <= 0) return false;
  const Vec3 m =
      tab_ && vw.tab ? tab_->sample_visible(vw.mix, wv, u1, u2) : d_->sample_visible(wv, u1, u2);
  const double im = wv.dot(m);
  if (im <= 0) return false;
  const Vec3 wo = 2 * im * m - wv;
  if (wo.z() <= 0) return false;
  TabulatedLookup look;
  const double dm = d_of(vw, m, look);
  if (tab_ && vw.tab) tab_->prefetch_pdf(vw.mix, look);
  // (G2 before the density, which it does not change: the density's memory arrives meanwhile)
  const double g = g2(vw, wo, m);
  const double q =
      visible_exact_ ? (vw.pa > 0 ? im * dm / vw.pa : 0.0) : sampling_pdf_of(vw, m, look);
  const double pdf = q / (4 * im);
  if (!(pdf > 0 && std::isfinite(pdf))) return false;
  // f cos / pdf = F D G2 / (4 wv.z) / pdf.
  const double geo = dm * g / (4 * wv.z() * pdf);
  if (!(geo > 0)) return false;
  s.wo = wo;
  s.pdf = pdf;
  s.delta = false;
  s.target = dm / (4 * vw.pa);
  fresnel_all(im, w, geo, s.weight);
  return true;
}

bool SpectralMaterial::ris_terms(double u, double v, const View& vw, const Vec3& wl,
                                 const Wavelengths& w, double& pdf, double& target) const {
  pdf = target = 0;
  const Vec3& wv = vw.wv;
  if (!mf_) {
    if (!(wl.z() > 0)) return false;
    double f[kMaxWavelengths];
    eval(u, v, vw, wl, w, f, &pdf);
    for (int k = 0; k < w.n; ++k) target += std::abs(f[k]);
    target *= wl.z() / w.n;
    return target > 0;
  }
  if (wl.z() <= 0 || wv.z() <= 0 || !(vw.pa > 0)) return false;
  const Vec3 hs = wl + wv;
  const double len = hs.norm();
  if (len == 0) return false;
  const Vec3 h = hs / len;
  TabulatedLookup q;
  const double dh = d_of(vw, h, q);
  if (!(dh > 0)) return false;
  target = dh / (4 * vw.pa);
  if (visible_exact_) {
    pdf = target;
  } else {
    const double vh = wv.dot(h);
    pdf = vh > 0 ? sampling_pdf_of(vw, h, q) / (4 * vh) : 0.0;
  }
  return true;
}

bool SpectralMaterial::sample_direction(double u, double v, const View& vw, double u1, double u2,
                                        const Wavelengths& w, Vec3& wl, double& pdf,
                                        double& target) const {
  const Vec3& wv = vw.wv;
  if (!mf_) {
    Sample s;
    if (!sample(u, v, vw, u1, u2, w, s) || s.delta) return false;
    wl = s.wo;
    pdf = s.pdf;
    target = s.target;
    return target > 0;
  }
  if (wv.z() <= 0 || !(vw.pa > 0)) return false;
  const Vec3 m =
      tab_ && vw.tab ? tab_->sample_visible(vw.mix, wv, u1, u2) : d_->sample_visible(wv, u1, u2);
  const double im = wv.dot(m);
  if (im <= 0) return false;
  wl = 2 * im * m - wv;
  if (wl.z() <= 0) return false;
  TabulatedLookup q;
  const double dm = d_of(vw, m, q);
  target = dm / (4 * vw.pa);
  pdf = visible_exact_ ? target : sampling_pdf_of(vw, m, q) / (4 * im);
  return pdf > 0 && std::isfinite(pdf) && target > 0;
}

void SpectralMaterial::eval(double u, double v, const Vec3& wi, const Vec3& wo,
                            const double* lambda_m, int n, double* f) const {
  Wavelengths w;
  prepare(lambda_m, n, w);
  eval(u, v, view(wo), wi, w, f, nullptr);
}

}  // namespace microbrdf::pt

namespace microbrdf::pt {
namespace {

constexpr double kGolden = 0.6180339887498949;
constexpr int kMaxLattice = 16;

/// cos and sin of 2 pi frac(j phi) for j = -15..15 (index j + 15).
struct LatticeTurns {
  double c[2 * kMaxLattice - 1], s[2 * kMaxLattice - 1];
  LatticeTurns() {
    for (int j = -(kMaxLattice - 1); j < kMaxLattice; ++j) {
      const double o = j * kGolden, t = 2 * M_PI * (o - std::floor(o));
      c[j + kMaxLattice - 1] = std::cos(t);
      s[j + kMaxLattice - 1] = std::sin(t);
    }
  }
};

/// (u + o) mod 1 for o in (-1, 1), below 1.
double wrap(double u, double o) {
  double v = u + (o < 0 ? o + 1 : o);
  if (v >= 1) v -= 1;
  return std::min(v, 0x1.fffffffffffffp-1);
}

}  // namespace

void SpectralMaterial::lattice_directions(double u, double v, const View& vw, double u1, double u2,
                                          const Wavelengths& w, int M, int a, Vec3* wl, double* pdf,
                                          double* target, bool* ok) const {
  for (int k = 0; k < M; ++k) ok[k] = false;
  const Vec3& wv = vw.wv;
  if (wv.z() <= 0 || (mf_ && !(vw.pa > 0))) return;
  if (!ggx_) {
    for (int k = 0; k < M; ++k) {
      if (k == a) continue;
      const double o2 = (k - a) * kGolden;
      ok[k] = sample_direction(u, v, vw, wrap(u1, double(k - a) / M), wrap(u2, o2 - std::trunc(o2)),
                               w, wl[k], pdf[k], target[k]);
    }
    return;
  }
  // GgxDistribution::sample_visible (Heitz 2018) with the stretched view's frame once.
  static const LatticeTurns turns;
  const double ax = ggx_->params().alpha_x, ay = ggx_->params().alpha_y;
  const double c = ggx_c_, s = ggx_s_;
  const double lx = c * wv.x() + s * wv.y(), ly = -s * wv.x() + c * wv.y();
  const Vec3 vh = Vec3(ax * lx, ay * ly, wv.z()).normalized();
  const double lensq = vh.x() * vh.x() + vh.y() * vh.y();
  const Vec3 t1 = lensq > 0 ? Vec3(-vh.y(), vh.x(), 0) / std::sqrt(lensq) : Vec3(1, 0, 0);
  const Vec3 t2 = vh.cross(t1);
  const double sh = 0.5 * (1 + vh.z());
  const double phi = 2 * M_PI * u2, c0 = std::cos(phi), s0 = std::sin(phi);
  const double norm = 1 / (M_PI * ax * ay);
  const double i4pa = 1 / (4 * vw.pa), inv_m = 1.0 / M;
  for (int k = 0; k < M; ++k) {
    if (k == a) continue;
    const int j = k - a;
    const double r = std::sqrt(wrap(u1, j * inv_m));
    const double tc = turns.c[j + kMaxLattice - 1], ts = turns.s[j + kMaxLattice - 1];
    const double p1 = r * (c0 * tc - s0 * ts);
    double p2 = r * (s0 * tc + c0 * ts);
    p2 = (1 - sh) * std::sqrt(std::max(0.0, 1 - p1 * p1)) + sh * p2;
    const Vec3 n = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0, 1 - p1 * p1 - p2 * p2)) * vh;
    // The unstretched normal mu = (ax n.x, ay n.y, n.z) / |...| in the distribution's frame:
    // with l2 = |...|^2 and |n| = 1, GGX's q = |n|^2 / l2, so D = l2^2 / (pi ax ay), and the
    // reflection needs no normalisation of mu but a division by l2.
    const double nz = std::max(0.0, n.z());
    if (!(nz > 0)) continue;
    const Vec3 mu(ax * n.x(), ay * n.y(), nz);
    const double l2 = mu.squaredNorm();
    const Vec3 m(c * mu.x() - s * mu.y(), s * mu.x() + c * mu.y(), mu.z());  // not unit
    const double im = wv.dot(m);
    if (im <= 0) continue;
    wl[k] = (2 * im / l2) * m - wv;
    if (wl[k].z() <= 0) continue;
    target[k] = pdf[k] = l2 * l2 * norm * i4pa;
    ok[k] = pdf[k] > 0 && std::isfinite(pdf[k]);
  }
}

}  // namespace microbrdf::pt

#pragma once
// A material as the path tracer uses it: an Svbrdf evaluated at all hero wavelengths of a path
// at once, with everything that does not depend on the wavelength or on the light direction
// computed once.
//
// Fast path, for a uniform microfacet BRDF (UniformSvbrdf around a MicrofacetBrdf):
//  - per path (prepare()): the metal's optical constants n, k at the hero wavelengths (the
//    conductor Fresnel term then costs its formula alone);
//  - per shading point (view()): Smith's Lambda of the viewer direction, shared by G2 and the
//    sampling density of the light sample and of the BRDF sample;
//  - per direction: D(h) and G2 once, the Fresnel term per wavelength (the formula of
//    MicrofacetBrdf::eval), and the density with which the BRDF sampler draws that direction
//    (MIS). For the analytic distributions, whose sampler draws the visible normals exactly,
//    that density is D(h) / (4 sigma+(v)) and reuses D(h); otherwise sampling_pdf() is called
//    (a tabulated NDF: from the table look-up of D(h), with the view tables' weights of view()).
//  - sample(): the visible normal, the reflected direction, its density and f at every
//    wavelength with one evaluation of D and G2 (MicrofacetBrdf::sample and a separate eval
//    would compute them twice).
// MicrofacetBrdf has no accessor for its G2 choice: it is read from describe(). The fast path is
// checked against the BRDF's own eval(), pdf() and sample() on a spiral of direction pairs at
// construction and dropped if they differ. Any other Svbrdf is evaluated wavelength by
// wavelength through its interface.

#include <cstdint>
#include <memory>
#include <vector>

#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/svbrdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/spectral.hpp"

namespace microbrdf::pt {

/// A Spectrum's piecewise-linear interpolation (Spectrum::operator()) with the segment found
/// from a uniform grid of start indices instead of a binary search: the same segment and the same
/// arithmetic, so the same value.
class FastSpectrum {
 public:
  FastSpectrum() = default;
  explicit FastSpectrum(const Spectrum& s);
  double operator()(double wavelength_m) const {
    const std::size_t n = v_.size();
    if (n == 0) return 0;
    if (n == 1 || wavelength_m <= l_.front()) return v_.front();
    if (wavelength_m >= l_.back()) return v_.back();
    const double x = (wavelength_m - l_.front()) * inv_step_;
    std::size_t i = start_[std::min(std::size_t(x), start_.size() - 1)];
    while (l_[i] <= wavelength_m) ++i;  // the first node above: upper_bound's answer
    const double t = (wavelength_m - l_[i - 1]) / (l_[i] - l_[i - 1]);
    return v_[i - 1] + t * (v_[i] - v_[i - 1]);
  }

 private:
  std::vector<double> l_, v_;
  std::vector<std::uint32_t> start_;  // per grid cell: upper_bound of its left end
  double inv_step_ = 0;
};

class SpectralMaterial {
 public:
  /// What a path's hero wavelengths fix (prepare()).
  struct Wavelengths {
    int n = 0;
    // (left uninitialised: a path fills the first n; zeroing them per path costs measurably)
    double lambda_m[kMaxWavelengths];
    // conductor fast path: the constants of fresnel_conductor_siegel per wavelength
    double e[kMaxWavelengths], f4[kMaxWavelengths];  // eta^2 - kappa^2, 4 eta^2 kappa^2
  };
  /// What the viewer direction at a shading point fixes (view()).
  struct View {
    Vec3 wv = Vec3(0, 0, 1);
    double g1 = 0;  ///< Smith G1(wv) (fast path)
    double pa = 0;  ///< projected area sigma+(wv) = wv.z (1 + Lambda(wv)) (fast path)
    /// Tabulated NDFs: the visible-normal sampler's view tables for wv, once per shading point
    /// (valid when `tab` is set).
    TabulatedViewMix mix;
    bool tab = false;
  };
  /// A BRDF sample (sample()).
  struct Sample {
    Vec3 wo = Vec3(0, 0, 1);
    double pdf = 0;                  ///< per steradian; 0 for a delta lobe
    bool delta = false;              ///< weights from each wavelength's own sample()
    double weight[kMaxWavelengths];  ///< f cos / pdf per wavelength (the first n are set)
    double target = 0;               ///< ris_terms' target of wo
  };

  explicit SpectralMaterial(std::shared_ptr<const Svbrdf> m);
  void prepare(const double* lambda_m, int n, Wavelengths& w) const;
  View view(const Vec3& wv) const;
  /// f(wl, wv) at the path's wavelengths into f (wl = light, local frame); with `pdf`, also
  /// the BRDF sampler's density of wl (Svbrdf::pdf(u, v, wv, wl)). False when f = 0 everywhere
  /// (the fast path then leaves *pdf at 0 without computing it).
  bool eval(double u, double v, const View& vw, const Vec3& wl, const Wavelengths& w, double* f,
            double* pdf) const;
  /// The BRDF sampler's density of wl (per steradian) whatever f is there: eval() leaves *pdf
  /// at 0 where f = 0, but a sampler with a defensive component may still draw such directions,
  /// and a mixture of several materials' samplers (render variants) needs every density.
  double sampling_pdf(double u, double v, const View& vw, const Vec3& wl) const;
  /// A BRDF sample driven by the viewer direction; false when the sample is refused or carries
  /// no weight. Without the fast path: Svbrdf::sample at the first wavelength and eval() of the
  /// others (delta lobes: each wavelength's own sample() for the same numbers).
  bool sample(double u, double v, const View& vw, double u1, double u2, const Wavelengths& w,
              Sample& s) const;

  /// For resampled direct light (direct_ris.hpp): the BRDF sampler's density of wl (as eval's)
  /// and a target, a cheap stand-in for f cos that is positive wherever f is: on the fast path
  /// D(h) / (4 sigma+(wv)) (= f cos G1(wv) / (F G2); equal to the density for the analytic
  /// models), otherwise the mean over the wavelengths of |f| cos. False where the target is 0
  /// (then f = 0 too).
  bool ris_terms(double u, double v, const View& vw, const Vec3& wl, const Wavelengths& w,
                 double& pdf, double& target) const;
  /// A BRDF-sampled direction with its density and target (as sample(); on the fast path without
  /// G2 and the Fresnel term). False when the sample is refused or is a delta lobe's.
  bool sample_direction(double u, double v, const View& vw, double u1, double u2,
                        const Wavelengths& w, Vec3& wl, double& pdf, double& target) const;
  /// BRDF-sampled directions at the lattice points (u1 + j / M, u2 + j phi) mod 1 (phi the
  /// golden-ratio fraction) for j = -a .. M-1-a except j = 0 (the caller's own sample), into
  /// slot a + j of wl, pdf, target; ok[a + j] tells whether it was drawn. M <= 16.
  /// For GGX the view's stretched frame is computed once and the azimuths are turned by fixed
  /// rotations (the same directions as sample_direction up to rounding; no sin/cos per point).
  void lattice_directions(double u, double v, const View& vw, double u1, double u2,
                          const Wavelengths& w, int M, int a, Vec3* wl, double* pdf, double* target,
                          bool* ok) const;

  /// f(wi, wo) at n wavelengths (metres) into f; wi = light, wo = viewer (local frame).
  void eval(double u, double v, const Vec3& wi, const Vec3& wo, const double* lambda_m, int n,
            double* f) const;
  const Svbrdf& svbrdf() const { return *m_; }
  /// Materials with the same key fill the same Wavelengths in prepare() (the conductor's
  /// Fresnel object, or null when prepare() records only the wavelengths): one prepare() serves
  /// them all.
  const void* wavelength_key() const { return conductor_ ? &mf_->fresnel() : nullptr; }
  /// Whether the microfacet fast path is in use.
  bool fast() const { return mf_ != nullptr; }

 private:
  double fresnel(double c, const Wavelengths& w, int k) const;
  /// out[k] = fresnel(c, w, k) * scale for the path's wavelengths (two at a time with SSE2).
  void fresnel_all(double c, const Wavelengths& w, double scale, double* out) const;
  double g2(const View& vw, const Vec3& wl, const Vec3& h) const;
  bool self_check() const;

  std::shared_ptr<const Svbrdf> m_;
  const MicrofacetBrdf* mf_ = nullptr;
  const MicrofacetDistribution* d_ = nullptr;
  bool conductor_ = false;  // ConductorFresnel: n and k below
  FastSpectrum n_, k_;
  bool separable_ = false;
  bool visible_exact_ = false;  // sampling_pdf = the visible-normal density (analytic models)
  /// A tabulated NDF: D(h) and the sampling density from one table look-up, the view tables'
  /// weights once per shading point (View::mix), the density's memory requested before G2 is
  /// computed (the same numbers as D() and sampling_pdf()).
  const TabulatedDistribution* tab_ = nullptr;
  /// D(m) (with the look-up for sampling_pdf_of when tabulated).
  double d_of(const View& vw, const Vec3& m, TabulatedLookup& q) const {
    return tab_ && vw.tab ? tab_->lookup(m, q) : d_->D(m);
  }
  /// d_->sampling_pdf(wv, m) with d_of's look-up.
  double sampling_pdf_of(const View& vw, const Vec3& m, const TabulatedLookup& q) const {
    return tab_ && vw.tab ? tab_->sampling_pdf(vw.mix, m, q) : d_->sampling_pdf(vw.wv, m);
  }
  const GgxDistribution* ggx_ = nullptr;  // lattice_directions' GGX path
  double ggx_c_ = 1, ggx_s_ = 0;          // cos, sin of its phi
};

}  // namespace microbrdf::pt

// First-order Rayleigh-Rice BRDF (include/microbrdf/rayleigh_rice.hpp) against closed forms
// written here from the literature (Church, Elson & Bennett; Stover, Optical Scattering ch. 5),
// its normal-incidence symmetry, the TIS by an independent hemispherical quadrature, the Mueller
// matrix and the sampling contract.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <memory>
#include <nlohmann/json.hpp>

#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "surface_test_util.hpp"

using namespace microbrdf;
using cd = std::complex<double>;

namespace {

constexpr double kSigma = 5e-9;
double deg(double d) { return d * M_PI / 180; }

// ---- the references, written from the papers' formulas -----------------------------------
// Church / Elson & Bennett, complex index N = n + ik under vacuum, scattering azimuth phi from
// the forward direction. Q_ss is written with the Fresnel s transmission coefficients
// t_s(t) = 2 cos t / (cos t + sqrt(N^2 - sin^2 t)), as Q_ss = |(N^2 - 1) t_s(i) t_s(s) cos phi
// / (4 cos i cos s)|^2; Q_pp in Stover's form with the cosines of the refracted angles
// N cos t' = sqrt(N^2 - sin^2 t).
double church_q_ss(double ti, double ts, double phi, cd n) {
  const auto t_s = [&](double t) {
    return 2 * std::cos(t) / (std::cos(t) + std::sqrt(n * n - std::sin(t) * std::sin(t)));
  };
  return std::norm((n * n - 1.0) * t_s(ti) * t_s(ts) * std::cos(phi) /
                   (4 * std::cos(ti) * std::cos(ts)));
}
double church_q_pp(double ti, double ts, double phi, cd n) {
  const cd n2 = n * n;
  const cd ncos_i = std::sqrt(n2 - std::pow(std::sin(ti), 2));  // N cos(theta_i')
  const cd ncos_s = std::sqrt(n2 - std::pow(std::sin(ts), 2));
  const cd num = (n2 - 1.0) * (ncos_i * ncos_s * std::cos(phi) - n2 * std::sin(ti) * std::sin(ts));
  return std::norm(num / ((n2 * std::cos(ti) + ncos_i) * (n2 * std::cos(ts) + ncos_s)));
}
double church_q_sp(double ti, double ts, double phi, cd n) {
  const cd n2 = n * n, ncos_s = std::sqrt(n2 - std::pow(std::sin(ts), 2));
  return std::norm(
      (n2 - 1.0) * ncos_s * std::sin(phi) /
      ((std::cos(ti) + std::sqrt(n2 - std::pow(std::sin(ti), 2))) * (n2 * std::cos(ts) + ncos_s)));
}
double church_q_ps(double ti, double ts, double phi, cd n) {
  const cd n2 = n * n, ncos_i = std::sqrt(n2 - std::pow(std::sin(ti), 2));
  return std::norm(
      (n2 - 1.0) * ncos_i * std::sin(phi) /
      ((n2 * std::cos(ti) + ncos_i) * (std::cos(ts) + std::sqrt(n2 - std::pow(std::sin(ts), 2)))));
}
// The PSD of C(r) = sigma^2 exp(-r^2/tau^2), cycles/m.
double gaussian_psd(double f, double tau) {
  return M_PI * tau * tau * kSigma * kSigma * std::exp(-M_PI * M_PI * tau * tau * f * f);
}
// BRDF = 16 pi^2 / lambda^4 cos i cos s Q PSD(f), f = (sin s cos phi - sin i, sin s sin
// phi)/lambda.
double church_brdf(double ti, double ts, double phi, double lambda, double q, double tau) {
  const double fx = (std::sin(ts) * std::cos(phi) - std::sin(ti)) / lambda;
  const double fy = std::sin(ts) * std::sin(phi) / lambda;
  return 16 * M_PI * M_PI / std::pow(lambda, 4) * std::cos(ti) * std::cos(ts) * q *
         gaussian_psd(std::hypot(fx, fy), tau);
}
Vec3 direction(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// A generated Gaussian surface's PSD (no window: the generator's periodogram is exact).
std::shared_ptr<const AreaPsd> psd_of(std::size_t n, double dx, double tau) {
  PsdOptions o;
  o.window = PsdWindow::None;
  return std::make_shared<const AreaPsd>(
      areal_psd(test_util::isotropic_gaussian(n, dx, kSigma, tau, 5), o));
}
const std::shared_ptr<const AreaPsd>& psd_tau5() {  // tau 5 um: lobes of ~2 deg at 555 nm
  static const auto p = psd_of(1024, 0.25e-6, 5e-6);
  return p;
}

}  // namespace

TEST(rayleigh_rice, AmplitudesReduceToFresnelInTheMirrorDirection) {
  for (const char* m : {"Al", "Au", "Ag"})
    for (double l : {405e-9, 555e-9, 1064e-9}) {
      const cd n = metal(m).at(l);
      for (double t : {0.0, 20.0, 45.0, 70.0, 85.0}) {
        const auto a = rayleigh_rice_amplitudes(deg(t), deg(t), 0, n * n);
        const double r = fresnel_conductor(std::cos(deg(t)), n);  // the library's other code
        EXPECT_NEAR(rayleigh_rice_q(a, Polarisation::Unpolarised), r, 1e-12) << m << " " << t;
        EXPECT_NEAR(std::norm(a.ss) + std::norm(a.pp), 2 * r, 1e-12);
        EXPECT_EQ(std::norm(a.sp), 0.0);
        EXPECT_NEAR(smooth_reflectance(std::cos(deg(t)), n * n, Polarisation::Unpolarised), r,
                    1e-12);
      }
    }
}

TEST(rayleigh_rice, BrdfMatchesChurchElsonClosedFormsWithin2Percent) {
  // Al and Au at 555 nm, tau 5 um, sigma 5 nm: in-plane (both sides of the mirror direction),
  // out of plane and at oblique azimuths, wherever the closed form is above 1e-3 of its peak.
  const double lambda = 555e-9, tau = 5e-6;
  double worst = 0;
  int checked = 0;
  for (const char* m : {"Al", "Au"}) {
    const cd n = metal(m).at(lambda);
    for (auto pol : {Polarisation::S, Polarisation::P, Polarisation::Unpolarised}) {
      const RayleighRiceBrdf b(psd_tau5(), metal(m), pol);
      for (double ti : {0.0, 20.0, 45.0, 70.0}) {
        const Vec3 wi = direction(deg(ti), M_PI);  // light at azimuth 180 deg
        for (double phi : {0.0, 180.0, 3.0, 30.0, 90.0, -120.0})
          for (double dts = -8; dts <= 8; dts += 0.25) {
            const double ts = deg(ti + dts);
            if (ts <= 0 || ts >= M_PI / 2) continue;
            const double p = deg(phi);
            const double qss = church_q_ss(deg(ti), ts, p, n), qpp = church_q_pp(deg(ti), ts, p, n);
            const double qsp = church_q_sp(deg(ti), ts, p, n), qps = church_q_ps(deg(ti), ts, p, n);
            const double q = pol == Polarisation::S   ? qss + qsp
                             : pol == Polarisation::P ? qps + qpp
                                                      : (qss + qsp + qps + qpp) / 2;
            const double want = church_brdf(deg(ti), ts, p, lambda, q, tau);
            const double fx = (std::sin(ts) * std::cos(p) - std::sin(deg(ti))) / lambda;
            const double fy = std::sin(ts) * std::sin(p) / lambda;
            if (gaussian_psd(std::hypot(fx, fy), tau) < 1e-3 * gaussian_psd(0, tau)) continue;
            const double got = b.eval(wi, direction(ts, p), lambda);
            ASSERT_NEAR(got / want, 1.0, 0.02) << m << " " << to_string(pol) << " ti " << ti
                                               << " ts " << ti + dts << " phi " << phi;
            worst = std::max(worst, std::fabs(got / want - 1));
            ++checked;
          }
      }
    }
  }
  EXPECT_GT(checked, 1000);
  std::printf("Rayleigh-Rice vs closed forms: %d points, worst %.3f %%\n", checked, 100 * worst);
}

TEST(rayleigh_rice, InPlaneSAndPAreQssAndQppExactly) {
  // In the plane of incidence there is no cross-polarisation: s = ss, p = pp, to rounding.
  const Vec3 wi = slice_light(deg(45));
  for (double t = -80; t <= 80; t += 5) {
    const Vec3 wo = slice_view(deg(45), deg(t), SlicePlane::In);
    for (auto [a, b] :
         {std::pair{Polarisation::S, Polarisation::SS}, {Polarisation::P, Polarisation::PP}}) {
      const double fa = RayleighRiceBrdf(psd_tau5(), metal("Al"), a).eval(wi, wo, 555e-9);
      const double fb = RayleighRiceBrdf(psd_tau5(), metal("Al"), b).eval(wi, wo, 555e-9);
      EXPECT_NEAR(fa, fb, 1e-14 * std::max(fa, 1e-300)) << t;
    }
  }
}

TEST(rayleigh_rice, NormalIncidenceIsAzimuthallySymmetricExactly) {
  // Q summed over polarisations does not depend on phi at normal incidence (any eps) ...
  const cd n = metal("Au").at(633e-9);
  for (double ts : {5.0, 30.0, 60.0, 85.0}) {
    const double q0 =
        rayleigh_rice_q(rayleigh_rice_amplitudes(0, deg(ts), 0, n * n), Polarisation::Unpolarised);
    for (double phi = 0; phi < 360; phi += 7.5)
      EXPECT_NEAR(rayleigh_rice_q(rayleigh_rice_amplitudes(0, deg(ts), deg(phi), n * n),
                                  Polarisation::Unpolarised),
                  q0, 1e-15 * q0);
  }
  // ... and on an isotropic PSD with the square grid's symmetry the BRDF is invariant under the
  // grid's rotations by 90 deg and its mirrors, to rounding.
  auto p = std::make_shared<AreaPsd>();
  p->nfx = p->nfy = 129;
  p->dfx = p->dfy = 2e4;
  p->sq = kSigma;
  p->value.resize(129 * 129);
  for (std::size_t iy = 0; iy < 129; ++iy)
    for (std::size_t ix = 0; ix < 129; ++ix)
      p->value[iy * 129 + ix] = gaussian_psd(std::hypot(p->fx(ix), p->fy(iy)), 5e-6);
  const RayleighRiceBrdf b(p, metal("Au"), Polarisation::Unpolarised);
  const Vec3 wi(0, 0, 1);
  for (double ts : {0.5, 1.0, 2.0, 3.0})
    for (double phi = 0; phi < 90; phi += 11) {
      const double f0 = b.eval(wi, direction(deg(ts), deg(phi)), 633e-9);
      ASSERT_GT(f0, 0);
      for (double turn : {90.0, 180.0, 270.0}) {
        EXPECT_NEAR(b.eval(wi, direction(deg(ts), deg(phi + turn)), 633e-9), f0, 1e-12 * f0);
      }
      EXPECT_NEAR(b.eval(wi, direction(deg(ts), -deg(phi)), 633e-9), f0, 1e-12 * f0);
    }
  // Oblique light from any of the grid's four axes: turning light and view together by 90 deg
  // leaves the BRDF and every polarisation's Q as they were (f = (wo_xy + wi_xy) / lambda and
  // phi_s from the forward direction -wi_xy are the vector forms, not tied to the x axis).
  const auto turn = [](const Vec3& v) { return Vec3(-v.y(), v.x(), v.z()); };
  for (auto pol : {Polarisation::S, Polarisation::P, Polarisation::SP})
    for (double dt : {-1.0, 0.5, 2.0})
      for (double phi : {0.0, 20.0, -70.0}) {
        const RayleighRiceBrdf bp(p, metal("Au"), pol);
        const Vec3 w1 = direction(deg(30), M_PI), v1 = direction(deg(30 + dt), deg(phi));
        const double f1 = bp.eval(w1, v1, 633e-9);
        EXPECT_NEAR(bp.eval(turn(w1), turn(v1), 633e-9), f1, 1e-12 * f1 + 1e-300);
        const RrAngles a = rayleigh_rice_angles(turn(w1), turn(v1));
        EXPECT_NEAR(a.theta_i, deg(30), 1e-12);
        EXPECT_NEAR(a.theta_s, deg(30 + dt), 1e-12);
        EXPECT_NEAR(a.phi_s, deg(phi), 1e-12);
      }
}

TEST(rayleigh_rice, TisByHemisphericalQuadratureMatchesTheClosedForm) {
  // sigma 5 nm (sigma / lambda 0.005-0.012), tau 20 um (lobes of 0.3-1 deg, so the closed
  // form's smooth-surface limit holds), Al; a quadrature of eval() on polar rings around the
  // mirror direction (independent of the library's sum over PSD nodes).
  const auto psd = psd_of(1024, 0.5e-6, 20e-6);
  const RayleighRiceBrdf b(psd, metal("Al"), Polarisation::Unpolarised);
  double worst = 0, worst_sum = 0;
  for (double lambda : {405e-9, 555e-9, 633e-9, 1064e-9})
    for (double ti : {0.0, 20.0, 45.0, 70.0}) {
      const Vec3 wi = slice_light(deg(ti));
      const Vec3 r(-wi.x(), 0, wi.z()), e1(r.z(), 0, -r.x()), e2(0, 1, 0);
      // Rings of half-angle a about the mirror direction, dw = sin a da db, out to 12 lobe widths.
      const double amax = std::min(M_PI / 2, 12 * lambda / (M_PI * 20e-6) / std::cos(deg(ti)));
      const int na = 300, nb = 180;
      double tis = 0;
      for (int i = 0; i < na; ++i) {
        const double a = (i + 0.5) * amax / na;
        for (int j = 0; j < nb; ++j) {
          const double beta = (j + 0.5) * 2 * M_PI / nb;
          const Vec3 wo =
              std::cos(a) * r + std::sin(a) * (std::cos(beta) * e1 + std::sin(beta) * e2);
          if (wo.z() <= 0) continue;
          tis += b.eval(wi, wo, lambda) * wo.z() * std::sin(a);
        }
      }
      tis *= (amax / na) * (2 * M_PI / nb);
      const cd n = metal("Al").at(lambda);
      const double g = 4 * M_PI * psd->sq * std::cos(deg(ti)) / lambda;
      const double closed = g * g * fresnel_conductor(std::cos(deg(ti)), n);
      EXPECT_NEAR(tis / closed, 1.0, 0.02) << lambda << " " << ti;
      const Tis t = total_integrated_scatter(b, lambda, deg(ti));
      EXPECT_NEAR(t.closed_form / closed, 1.0, 1e-12);
      EXPECT_NEAR(t.integral / tis, 1.0, 0.01) << lambda << " " << ti;
      EXPECT_NEAR(t.specular, fresnel_conductor(std::cos(deg(ti)), n) * std::exp(-g * g), 1e-12);
      EXPECT_NEAR(b.albedo(wi, lambda), t.specular + t.integral, 1e-15);
      worst = std::max(worst, std::fabs(tis / closed - 1));
      worst_sum = std::max(worst_sum, std::fabs(t.integral / closed - 1));
    }
  std::printf("TIS: quadrature vs closed form worst %.3f %%, node sum vs closed form %.3f %%\n",
              100 * worst, 100 * worst_sum);
}

TEST(rayleigh_rice, MuellerMatrixIsThePureMatrixOfTheAmplitudes) {
  const RayleighRiceBrdf b(psd_tau5(), metal("Au"), Polarisation::Unpolarised);
  const RayleighRiceBrdf bs(psd_tau5(), metal("Au"), Polarisation::S);
  const RayleighRiceBrdf bp(psd_tau5(), metal("Au"), Polarisation::P);
  const Vec3 wi = slice_light(deg(30));
  for (double phi : {0.0, 25.0, 90.0, 200.0}) {
    const Vec3 wo = direction(deg(31), deg(phi));
    const auto m = b.mueller(wi, wo, 555e-9);
    const double f = b.eval(wi, wo, 555e-9);
    ASSERT_GT(f, 0);
    EXPECT_NEAR(m[0], f, 1e-12 * f);
    // s light is Stokes (1, 1, 0, 0), p light (1, -1, 0, 0); the detector takes I.
    EXPECT_NEAR(m[0] + m[1], bs.eval(wi, wo, 555e-9), 1e-12 * f);
    EXPECT_NEAR(m[0] - m[1], bp.eval(wi, wo, 555e-9), 1e-12 * f);
    // A Mueller matrix of one Jones matrix: sum M_ij^2 = 4 M_00^2.
    double s2 = 0;
    for (double v : m) s2 += v * v;
    EXPECT_NEAR(s2, 4 * m[0] * m[0], 1e-10 * m[0] * m[0]);
    if (phi == 0.0) {  // in plane: no s-p mixing
      EXPECT_NEAR(m[2], 0, 1e-14 * f);
      EXPECT_NEAR(m[3], 0, 1e-14 * f);
      EXPECT_NEAR(m[8], 0, 1e-14 * f);
    }
  }
}

TEST(rayleigh_rice, UnpolarisedBrdfIsReciprocal) {
  // f(wi, wo) = f(wo, wi): the frequency (wo + wi)_xy / lambda is symmetric, the PSD of real
  // heights is even, and Q_sp and Q_ps trade places.
  const RayleighRiceBrdf b(psd_tau5(), metal("Cu"), Polarisation::Unpolarised);
  std::uint64_t st = 99;
  auto u = [&] {
    st = st * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(st >> 11) * 0x1.0p-53;
  };
  int nonzero = 0;
  for (int i = 0; i < 200; ++i) {
    const double ti = deg(80 * u()), pi = 2 * M_PI * u();
    const Vec3 wi = direction(ti, pi);
    // a view near the mirror direction, where the BRDF is not 0
    const Vec3 wo =
        direction(std::clamp(ti + deg(6 * u() - 3), 0.01, 1.5), pi + M_PI + deg(10 * u() - 5));
    const double a = b.eval(wi, wo, 555e-9), c = b.eval(wo, wi, 555e-9);
    EXPECT_NEAR(a, c, 1e-12 * std::max(a, c) + 1e-300) << i;
    nonzero += a > 0;
  }
  EXPECT_GT(nonzero, 100);
}

TEST(rayleigh_rice, NormalIncidenceBackscatterIsAMirrorsMuellerMatrix) {
  // theta_i = theta_s = 0: the Jones matrix is a multiple of diag(1, -1) in the convention of
  // the amplitudes (Germer 1997), so M = M00 diag(1, 1, -1, -1).
  const cd n = metal("Ag").at(633e-9);
  for (double phi : {0.0, 0.7, 2.0}) {
    const auto m = rayleigh_rice_mueller(rayleigh_rice_amplitudes(0, 0, phi, n * n));
    const double want[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, -1, 0, 0, 0, 0, -1};
    const double q =
        std::norm((n * n - 1.0) / ((1.0 + n) * (1.0 + n)));  // |r|^2 at normal incidence
    // At phi != 0 the s and p axes of the scattered beam turn with phi: only phi = 0 is diagonal.
    if (phi == 0.0) {
      for (int i = 0; i < 16; ++i) EXPECT_NEAR(m[i], want[i] * q, 1e-14) << i;
    }
    EXPECT_NEAR(m[0], q, 1e-14);
  }
}

TEST(rayleigh_rice, SamplingReproducesTheAlbedoAndTheScatter) {
  // The weights' mean is the albedo (delta + TIS); the non-delta weights alone estimate the TIS,
  // at the sampling wavelength (the PSD branch draws the halo exactly) and away from it (the
  // halo is scaled by lambda / 555 nm; still unbiased).
  const RayleighRiceBrdf b(psd_tau5(), metal("Al"), Polarisation::Unpolarised);
  const int n = 100000;
  std::uint64_t st = 12345;
  auto u = [&] {
    st = st * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(st >> 11) * 0x1.0p-53;
  };
  for (double ti : {0.0, 30.0, 60.0})
    for (double lambda : {555e-9, 633e-9}) {
      const Vec3 wi = slice_light(deg(ti));
      double sum = 0, diffuse = 0;
      for (int i = 0; i < n; ++i) {
        const auto s = b.sample(wi, u(), u(), lambda);
        if (!s) continue;
        if (!s->delta) {
          ASSERT_NEAR(s->pdf, b.pdf(wi, s->wo), 1e-12 * s->pdf);
          diffuse += s->weight;
        }
        sum += s->weight;
      }
      const double tis = b.integrated_scatter(wi, lambda);
      // (the delta branch alone scatters the mean by R / sqrt(n) = 0.003)
      EXPECT_NEAR(sum / n, b.albedo(wi, lambda), 0.01) << ti << " " << lambda;
      EXPECT_NEAR(diffuse / n / tis, 1.0, 0.03) << ti << " " << lambda;
      std::printf("sampled TIS / TIS at %g deg, %g nm: %.4f\n", ti, lambda * 1e9,
                  diffuse / n / tis);
    }
  EXPECT_TRUE(b.lobes().delta);
  EXPECT_EQ(b.eval(slice_light(0.5), Vec3(0.1, 0, -0.99), 555e-9), 0.0);  // below the horizon
}

TEST(rayleigh_rice, ParsesNamesAndWritesTisJson) {
  EXPECT_EQ(parse_polarisation("unpolarized"), Polarisation::Unpolarised);
  EXPECT_EQ(parse_polarisation("pp"), Polarisation::PP);
  EXPECT_THROW(parse_polarisation("circular"), InputError);
  const RayleighRiceBrdf b(psd_tau5(), metal("Al"));
  const nlohmann::json j = tis_json(total_integrated_scatter(b, 633e-9, deg(20)));
  EXPECT_NEAR(j["theta_i_deg"].get<double>(), 20, 1e-12);
  EXPECT_NEAR(j["integral_over_closed_form"].get<double>(), 1, 0.05);
  EXPECT_THROW(RayleighRiceBrdf(std::make_shared<AreaPsd>(), metal("Al")), InputError);
}

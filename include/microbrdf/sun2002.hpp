#pragma once
// Sun 2002, "Deriving Analytic BRDFs of Metallic Rough Surfaces" (Purdue CSD TR 02-006):
// the free travel probability (FTP) Gamma_0, the analytic one-bounce BRDF (eq. 3.5.3) as
// published and in the standard microfacet form, Smith's masking for the same surface, and the
// numerical FTP experiment of the paper's section 4 (the BRDF behind the Brdf interface:
// sun_brdf.hpp). See docs/sun2002.md for the derivations,
// the paper's slips and what we do about them.
//
// Surface: Gaussian heights (rms sigma), correlation C(r) = exp(-r^2/tau^2), smoothness
// s = tau/sigma (eq. 3.4.22). Slopes per axis are Gaussian with std sqrt(2) sigma/tau =
// sqrt(2)/s (eq. 3.3.8), i.e. a Beckmann distribution of width alpha = 2/s.
//
// Conventions (docs/architecture.md): macro normal n = +z; directions point away from the surface;
// wi = towards the light (Sun's psi / l), wo = towards the viewer (Sun's v); angles in radians;
// BRDF in 1/sr. Directions need not be normalised.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf::sun2002 {

// ---------------------------------------------------------------------------------------------
// Free travel probability and Smith masking

/// Eq. 3.4.23, as published: Gamma_0(theta; s) = exp[-k_tau tan(theta) / (sqrt(2 pi) s)
/// exp(-s^2 / (4 tan^2 theta))], the probability that a ray leaving the mean plane (height 0)
/// at polar angle theta is not blocked by the surface. k_tau = k tau is Sun's constant of
/// eq. 3.4.1, fixed to 1 (eq. 3.4.21) by a dimensional argument only: it is a heuristic, left
/// as a parameter so it can be fitted to simulations. Gamma_0(0) = 1, Gamma_0(pi/2) = 0.
/// theta outside [0, pi/2] is clamped; s must be > 0 (InputError otherwise).
double ftp(double theta, double s, double k_tau = 1.0);

/// Smith's Lambda for a 1-D Gaussian profile with slope std sqrt(2)/s (equivalently the
/// isotropic Beckmann surface with alpha = 2/s): with a = s / (2 tan theta),
/// Lambda = (exp(-a^2) / (a sqrt(pi)) - erfc(a)) / 2. Lambda(0) = 0, Lambda -> inf at pi/2.
double smith_lambda(double theta, double s);

/// Smith's masking averaged over the heights of the starting points: G1 = 1 / (1 + Lambda).
double smith_g1(double theta, double s);

/// Smith's masking of a point on the mean plane (height 0) that faces the ray:
/// S(h = 0) = P(h < 0)^Lambda = 2^-Lambda (Smith 1967). This is what Gamma_0 and the
/// simulation of simulate_ftp() (start = LeavingAbove) describe.
double smith_at_mean_plane(double theta, double s);

/// Beckmann distribution of micro-normals for the surface: D(h) = s^2 exp(-s^2 tan^2(th)/4) /
/// (4 pi cos^4(th)), normalised so that the integral of D cos(th) over the hemisphere is 1.
double beckmann_ndf(double cos_theta_h, double s);

// ---------------------------------------------------------------------------------------------
// The analytic BRDF (eq. 3.5.3)

// The Fresnel factor R-bar(delta/2) is the shared Fresnel type (include/microbrdf/fresnel.hpp)
// evaluated at cos(delta/2) = wi . h and the given wavelength; a null pointer means R = 1 (a
// perfect mirror: the upper bound used for energy checks).

enum class BrdfForm {
  /// Eq. 3.5.3 as printed: R Gamma_0(th_i) Gamma_0(th_o) s^2 exp(-s^2 tan^2 th_h / 4) /
  /// (16 pi cos^3 th_h cos(delta/2)) = R G D(h) (h.n) / (4 (wi.h)).
  AsPublished,
  /// Standard microfacet form R D(h) G / (4 cos th_i cos th_o) with the same D (Beckmann,
  /// alpha = 2/s) and G = Gamma_0(th_i) Gamma_0(th_o).
  /// AsPublished / Standard = (h.n) cos th_i cos th_o / (wi.h) (docs/theory.md §5.2).
  Standard,
};

/// Which free travel probabilities the BRDF includes (the rows of Sun's Fig. 8): both
/// Gamma_0(th_i) Gamma_0(th_o) (eq. 3.5.3, the default), only the viewer's Gamma_0(th_o) (the
/// second row; wo = towards the viewer), only the light's Gamma_0(th_i), or none (the first
/// row). Without both terms the BRDF is not reciprocal (ViewOnly, LightOnly) or not energy
/// conserving at grazing angles (None): for reproducing the paper's comparison only.
enum class FtpTerms { Both, ViewOnly, LightOnly, None };

/// "both", "view", "light", "none" (InputError otherwise) and back.
FtpTerms parse_ftp_terms(const std::string& name);
std::string ftp_terms_name(FtpTerms t);
/// "standard" or "published" (InputError otherwise) and back.
BrdfForm parse_brdf_form(const std::string& name);
std::string brdf_form_name(BrdfForm f);

/// One evaluation. Returns 0 when either direction is at or below the horizon.
double brdf(const Eigen::Vector3d& wi, const Eigen::Vector3d& wo, double s, BrdfForm form,
            const Fresnel* fresnel = nullptr, double wavelength_m = 555e-9,
            FtpTerms ftp = FtpTerms::Both);

/// The factor AsPublished / Standard = (h.n) cos th_i cos th_o / (wi.h) for a pair of
/// directions above the horizon (0 otherwise).
double published_over_standard(const Eigen::Vector3d& wi, const Eigen::Vector3d& wo);

/// Directional albedo for light from wi: integral of brdf(wi, wo) cos th_o over the outgoing
/// hemisphere (by reciprocity the same as the albedo seen from wi), computed in half-vector
/// space (wo = reflect(wi, h), d omega_o = 4 (wi.h) d omega_h): composite Gauss-Legendre
/// with n_u nodes (rounded up to a multiple of 16) in u, tan(th_h) = 2u/s, u in [0, 7], and
/// an n_phi-point midpoint rule in azimuth. With weight_cos = false the cos th_o is left out
/// (Sun's eq. 5.1 integral).
double albedo(double theta_i, double s, BrdfForm form, const Fresnel* fresnel = nullptr,
              double wavelength_m = 555e-9, bool weight_cos = true, int n_u = 128, int n_phi = 128);

// ---------------------------------------------------------------------------------------------
// The numerical experiment of section 4

/// Which rays are counted. Sun starts a ray at "a point with z = 0 on the profile".
enum class FtpStart {
  /// Rays from zero crossings where the ray leaves above the profile (the profile's slope in
  /// the direction of travel is below the ray's, cot theta): the micro-area faces the ray, as
  /// it does for every micro-area that reflects into the ray in the BRDF. Default.
  LeavingAbove,
  /// Every zero crossing; rays that go straight into the profile count as blocked.
  AnyCrossing,
};

struct FtpSimParams {
  double s = 1;                        ///< smoothness tau / sigma (> 0)
  std::vector<double> theta;           ///< polar angles of the rays, rad, each in [0, pi/2]
  std::size_t crossings = 100000;      ///< at least this many zero crossings (each casts 2 rays)
  double samples_per_tau = 16;         ///< profile spacing dx = tau / samples_per_tau
  std::size_t profile_length = 65536;  ///< samples holding the crossings (plus margins)
  std::uint64_t seed = 1;              ///< same seed, same result (any thread count)
};

struct FtpSimPoint {
  double theta = 0;
  // Rays to +x and -x from every crossing; "leaving" = those that leave above the profile.
  std::size_t rays = 0, rays_leaving = 0, free = 0;
  double gamma_leaving = 0, se_leaving = 0;  ///< free / rays_leaving and its standard error
  double gamma_any = 0, se_any = 0;          ///< free / rays and its standard error
};

struct FtpSimResult {
  FtpSimParams params;
  std::size_t profiles = 0;   ///< profiles generated
  std::size_t crossings = 0;  ///< zero crossings used (each cast a ray both ways)
  std::size_t excluded = 0;   ///< crossings skipped for lack of margin (normally 0)
  double slope_rms = 0;       ///< measured rms slope of the profiles (expected sqrt(2)/s)
  std::vector<FtpSimPoint> points;
};

/// Sun's section 4 experiment, with many more rays: 1-D Gaussian profiles made by
/// generate_profiles() (moving average, tau = 1, sigma = 1/s), rays from the zero crossings
/// (linear interpolation between samples) at polar angle theta to both sides; a ray is
/// blocked when a profile sample ahead lies above it (the profile is piecewise linear, so
/// testing the samples is exact), free once it is above the profile's maximum. Crossings sit
/// in the middle profile_length samples, with margins either side long enough for that.
/// theta = pi/2 is not simulated (a horizontal ray from height 0 is always blocked: 0).
/// Standard errors by batches of 4096 samples (about 256 tau: independent). Deterministic.
/// OpenMP-parallel. Throws InputError for bad parameters.
FtpSimResult simulate_ftp(const FtpSimParams& p);

/// Least-squares k_tau of Gamma_0(theta; s, k_tau) (ftp()) against values g at the angles theta
/// (rad): golden-section search on log k_tau over [0.01, 100] (100 steps, relative accuracy
/// ~1e-20 in log k). NaN when theta is empty.
double fit_k_tau(double s, const std::vector<double>& theta, const std::vector<double>& g);

/// The largest deviation of a simulated curve from a model: the signed difference sim - model
/// with the largest magnitude, and the angle (rad) where it occurs.
struct FtpDeviation {
  double diff = 0, theta = 0;
  void take(double d, double t);
};

/// How one simulation of simulate_ftp() agrees with Sun's Gamma_0 (eq. 3.4.23, k_tau = 1), with
/// Smith's G1 and with Smith's masking at the mean plane, over the simulated angles (theta <
/// pi/2), and the k_tau that fits it best.
struct FtpAgreement {
  FtpDeviation leaving_minus_sun, leaving_minus_smith_g1, leaving_minus_smith_mean_plane,
      any_minus_sun;
  double best_k_tau_leaving = 0, best_k_tau_any = 0;  ///< fit_k_tau of the two counts (NaN: none)
  double max_standard_error_leaving = 0;              ///< over every point
  std::size_t rays = 0;                               ///< rays cast, all angles
};
FtpAgreement compare_ftp(const FtpSimResult& r);

}  // namespace microbrdf::sun2002

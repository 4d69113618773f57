#pragma once
// First-order Rayleigh-Rice (vector perturbation) scattering by a smooth, slightly rough
// conductor, from the scan's own PSD (psd.hpp). Theory and conventions: docs/rayleigh_rice.md.
//
//   f_ab(wi, wo) = (16 pi^2 / lambda^4) cos(theta_i) cos(theta_s) Q_ab PSD(fx, fy)   [1/sr]
//   f = (wo_xy + wi_xy) / lambda  (cycles/m), i.e. for light at azimuth 180 deg
//   fx = (sin theta_s cos phi_s - sin theta_i) / lambda,  fy = sin theta_s sin phi_s / lambda,
//
// phi_s the azimuth of wo from the plane of incidence (0 = forward, towards the mirror
// direction). Q_ab = |q_ab|^2 with the first-order amplitudes q_ab (a = incident, b = scattered
// polarisation, s or p) of Elson & Bennett / Church, for the permittivity eps = (n + i k)^2 of the
// metal under vacuum (rayleigh_rice_amplitudes). Valid when 4 pi sigma cos(theta) / lambda << 1
// and the slopes are small (sigma/lambda < ~0.05, rms slope < ~0.1).
//
// The specular part is a delta: R(theta_i) exp(-(4 pi sigma cos theta_i / lambda)^2) in the
// mirror direction (R of the incident polarisation; for `Unpolarised` (R_s + R_p) / 2). eval()
// returns the diffuse (first-order) part only; sample() returns the delta or a diffuse direction
// (see RayleighRiceBrdf::sample); albedo() is the sum of both.

#include <array>
#include <complex>
#include <memory>
#include <mutex>
#include <nlohmann/json_fwd.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/psd.hpp"

namespace microbrdf {

namespace detail {
class Marginal2D;  // src/core/marginal2d.hpp
}

/// Which first-order BRDF: incident s or p with the scattered light summed over both
/// polarisations (S, P), the average over incident polarisations (Unpolarised, = (Q_ss + Q_sp +
/// Q_ps + Q_pp) / 2), or one element (SS = s in, s out; SP = s in, p out; PS; PP).
enum class Polarisation { Unpolarised, S, P, SS, SP, PS, PP };
/// "unpolarised" (or "unpolarized"), "s", "p", "ss", "sp", "ps", "pp"; InputError otherwise.
Polarisation parse_polarisation(const std::string& name);
std::string to_string(Polarisation p);

/// The complex first-order amplitudes q_ab (a incident, b scattered; Q_ab = |q_ab|^2) for the
/// polar angles theta_i, theta_s (rad, in [0, pi/2]), the scattering azimuth phi_s (rad, 0 =
/// forward) and the relative permittivity eps of the substrate. With W(t) = sqrt(eps - sin^2 t)
/// (principal root) and D(t) = cos t + W(t), E(t) = eps cos t + W(t):
///   q_ss =   (eps - 1) cos phi_s / (D_i D_s)
///   q_sp = - (eps - 1) W_s sin phi_s / (D_i E_s)
///   q_ps = - (eps - 1) W_i sin phi_s / (E_i D_s)
///   q_pp =   (eps - 1) (eps sin theta_i sin theta_s - W_i W_s cos phi_s) / (E_i E_s)
/// The signs are those of Germer (Appl. Opt. 36, 8798, 1997), whose (s, p) bases make a mirror's
/// Jones matrix diag(1, -1) at normal incidence (Mueller diag(1, 1, -1, -1): reflection reverses
/// the handedness of circular light). In the mirror direction q_ss = -r_s and q_pp = -r_p
/// (Fresnel, r_s = (c - W)/(c + W), r_p = (eps c - W)/(eps c + W)): Q reduces to the Fresnel
/// reflectances there.
struct RrAmplitudes {
  std::complex<double> ss, sp, ps, pp;
};
RrAmplitudes rayleigh_rice_amplitudes(double theta_i, double theta_s, double phi_s,
                                      std::complex<double> eps);
/// Q for the polarisation `p` from the amplitudes.
double rayleigh_rice_q(const RrAmplitudes& a, Polarisation p);

/// The Mueller matrix of the amplitudes, row-major M[4 * row + col], for Stokes vectors
/// (I, Q, U, V) in each beam's own (s, p) basis: I = |E_s|^2 + |E_p|^2, Q = |E_s|^2 - |E_p|^2,
/// U = 2 Re(E_s E_p*), V = -2 Im(E_s E_p*). M[0] = (Q_ss + Q_sp + Q_ps + Q_pp) / 2.
std::array<double, 16> rayleigh_rice_mueller(const RrAmplitudes& a);

/// The angles of a pair of directions in the Rayleigh-Rice convention: theta_i, theta_s and the
/// azimuth phi_s of wo measured from the forward direction -wi_xy (counter-clockwise about +z).
/// At normal incidence the plane of incidence is taken as the x-z plane (phi_s from +x).
struct RrAngles {
  double theta_i = 0, theta_s = 0, phi_s = 0;
};
RrAngles rayleigh_rice_angles(const Vec3& wi, const Vec3& wo);

class RayleighRiceBrdf final : public Brdf {
 public:
  RayleighRiceBrdf(std::shared_ptr<const AreaPsd> psd, OpticalConstants material,
                   Polarisation polarisation = Polarisation::Unpolarised);
  /// The first-order (diffuse) BRDF, 1/sr: (16 pi^2 / lambda^4) cos_i cos_s Q PSD(f); 0 below
  /// the horizon and where f lies outside the PSD's band.
  double eval(const Vec3& wi, const Vec3& wo, double wavelength_m) const override;
  /// The BRDF's Mueller matrix (1/sr, row-major; element 0 is the unpolarised eval()).
  std::array<double, 16> mueller(const Vec3& wi, const Vec3& wo, double wavelength_m) const;
  /// With probability 1/2 the specular delta (weight 2 R exp(-g), delta = true); with 1/4 a
  /// direction drawn from the PSD itself as the halo at kSamplingWavelength has it (the
  /// bilinear PSD as a 2-D density, f -> wo_xy = lambda_ref f - wi_xy; nothing when that
  /// direction does not propagate); with 1/4 a cosine-weighted direction. The density does not
  /// depend on the wavelength (pdf() cannot), so the halo is matched exactly at 555 nm and
  /// scaled by lambda / 555 nm elsewhere; the cosine part keeps every direction reachable.
  /// The PSD's sampling table (about 20 bytes per node) is built on the first call; over the
  /// memory budget the PSD branch returns nothing instead.
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2,
                                   double wavelength_m) const override;
  /// The density of the non-delta branches of sample(): (cos(theta_o) / pi + p_psd(wo)) / 4.
  double pdf(const Vec3& wi, const Vec3& wo) const override;
  /// The wavelength whose halo sample() draws exactly, m.
  static constexpr double kSamplingWavelength = 555e-9;
  /// Specular reflectance plus the total integrated scatter (exact sum over the PSD's nodes).
  double albedo(const Vec3& wi, double wavelength_m) const override;
  Lobes lobes() const override { return {true, true, false}; }
  std::string describe() const override;

  /// R(theta_i) exp(-(4 pi Sq cos theta_i / lambda)^2): the delta lobe's weight.
  double specular_reflectance(const Vec3& wi, double wavelength_m) const;
  /// The integral of eval() cos(theta_o) over the hemisphere (the TIS), computed exactly on the
  /// PSD's nodes: with u = wo_xy, du dv = cos(theta_o) dw, so TIS = lambda^2 sum f(node) dfx dfy
  /// over the nodes whose direction propagates (|lambda f - wi_xy| < 1).
  double integrated_scatter(const Vec3& wi, double wavelength_m) const;

  const AreaPsd& psd() const { return *psd_; }
  const std::shared_ptr<const AreaPsd>& shared_psd() const { return psd_; }
  const OpticalConstants& material() const { return material_; }
  Polarisation polarisation() const { return pol_; }

 private:
  /// The PSD's sampling table (built once, on the first sample() or pdf(); null when there is
  /// no mass or no memory for it).
  const detail::Marginal2D* lobe() const;
  /// The density per steradian of the PSD branch of sample().
  double lobe_pdf(const Vec3& wi, const Vec3& wo) const;

  std::shared_ptr<const AreaPsd> psd_;
  OpticalConstants material_;
  Polarisation pol_;
  mutable std::once_flag lobe_once_;
  mutable std::shared_ptr<const detail::Marginal2D> lobe_;
};

/// The Mueller matrix along a slice (brdf_slice.hpp's angles and convention) as CSV: comment
/// lines, then angle_deg, m00 .. m33 (row-major, 1/sr), wo_x, wo_y, wo_z; one row per angle, the
/// same angles as tabulate_slice(b, theta_i, wavelength_m, plane, samples).
std::string mueller_slice_csv(const RayleighRiceBrdf& b, double theta_i, double wavelength_m,
                              SlicePlane plane, std::size_t samples);

/// Fresnel reflectance of the smooth metal for the polarisation (S and SS: R_s, P and PP: R_p,
/// Unpolarised: the mean; SP and PS: 0, a flat surface does not depolarise).
double smooth_reflectance(double cos_i, std::complex<double> eps, Polarisation p);

/// Total integrated scatter at one wavelength and angle of incidence.
struct Tis {
  double wavelength_m = 0, theta_i_rad = 0;
  double reflectance = 0;      ///< R(theta_i) of the smooth metal, for the polarisation
  double rayleigh_factor = 0;  ///< g = (4 pi Sq cos theta_i / lambda)^2
  double closed_form = 0;      ///< g R: the smooth-surface limit
  double integral = 0;         ///< the Rayleigh-Rice BRDF integrated over the hemisphere
  double specular = 0;         ///< R exp(-g): the delta lobe
  /// rms height of the PSD's nodes that scatter into propagating directions (|lambda f - wi_xy|
  /// < 1): the part of Sq the integral sees, m
  double propagating_sq_m = 0;
};
Tis total_integrated_scatter(const RayleighRiceBrdf& brdf, double wavelength_m, double theta_i_rad);
/// The record of `info --json` ("tis" entries): wavelength_m, theta_i_rad, theta_i_deg,
/// reflectance, rayleigh_factor, tis_closed_form, tis_integral, integral_over_closed_form,
/// specular_reflectance, propagating_sq_m.
nlohmann::json tis_json(const Tis& t);

/// 405, 555, 633 and 1064 nm; 0, 20, 45 and 70 deg (rad): the table of `info --json`.
const std::vector<double>& tis_default_wavelengths();
const std::vector<double>& tis_default_angles();
/// tis_json for every wavelength (m) and angle of incidence (rad), wavelength-major. Without a
/// material (nullptr) only the material-free numbers: wavelength_m, theta_i_rad, theta_i_deg,
/// rayleigh_factor (= TIS / R in the smooth limit) and propagating_sq_m.
nlohmann::json tis_table(const std::shared_ptr<const AreaPsd>& psd,
                         const OpticalConstants* material, const std::vector<double>& wavelengths,
                         const std::vector<double>& angles,
                         Polarisation polarisation = Polarisation::Unpolarised);

/// The `info --json` additions for one scan (`mb.statistics` gives the same): "psd" (psd_json of
/// the default estimator; null for a profile, one row or column, or a scan without valid
/// samples), "tis" (tis_table at the wavelengths and angles, the defaults when empty; an empty
/// list for a profile) and "tis_material" (the material's name, or null without one). `name`
/// names the scan in errors.
void add_psd_and_tis_json(nlohmann::json& record, const Surface& s, const std::string& name,
                          const OpticalConstants* material, std::vector<double> wavelengths = {},
                          std::vector<double> angles = {});

}  // namespace microbrdf

#pragma once
// Fresnel reflectance and the optical constants of materials (docs/theory.md §5.3-5.5).
//
// Conventions: cos_i = cosine of the angle of incidence, measured in the incident medium (a
// vacuum/air of index 1 unless said otherwise); eta = relative index n_t / n_i. The complex index
// is eta + i kappa (kappa >= 0 absorbs); the reflectance does not depend on the sign convention
// (eta - i kappa gives the same R). All reflectances are unpolarised: R = (R_s + R_p) / 2.

#include <complex>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "microbrdf/spectrum.hpp"

namespace microbrdf {

/// Exact unpolarised reflectance of a conductor, complex form (docs/theory.md §5.4):
/// cos_t = sqrt(1 - sin^2_i / eta~^2) (principal root), r_p = (eta~ c_i - c_t)/(eta~ c_i + c_t),
/// r_s = (c_i - eta~ c_t)/(c_i + eta~ c_t), R = (|r_s|^2 + |r_p|^2)/2. |cos_i| is used.
double fresnel_conductor(double cos_i, std::complex<double> eta);
/// The same in the real Siegel-Howell form (docs/theory.md §5.4); agrees to ~1e-15.
double fresnel_conductor_siegel(double cos_i, double eta, double kappa);
/// Sun 2002 eqs. 5.7-5.8 exactly as printed (5.8 with the squared term, 5.7's R_parallel): kept
/// only to document the error (see docs/models.md). Do not use for physics.
double fresnel_conductor_sun_as_printed(double cos_i, double eta, double kappa);

/// Exact unpolarised dielectric reflectance for relative index eta = n_t/n_i > 0. cos_i < 0
/// means the light arrives from the other side (the index is inverted). Total internal
/// reflection gives 1.
double fresnel_dielectric(double cos_i, double eta);

/// Schlick's approximation R0 + (1 - R0)(1 - cos_i)^5 (an option, never the default).
double fresnel_schlick(double cos_i, double r0);

/// Normal-incidence reflectance ((eta-1)^2 + kappa^2) / ((eta+1)^2 + kappa^2) (Sun eq. 5.9).
double normal_reflectance(double eta, double kappa);
/// kappa that gives normal-incidence reflectance r0 for a chosen eta (Sun eqs. 5.10-5.11):
/// kappa^2 = (r0 (eta+1)^2 - (eta-1)^2) / (1 - r0); eta = 1 gives kappa = 2 sqrt(r0/(1-r0)).
/// Throws InputError when r0 is outside [0, 1) or no real kappa exists for that eta.
double kappa_from_normal_reflectance(double r0, double eta = 1.0);

/// Complex refractive index n + i k as a function of wavelength (piecewise linear in the
/// tabulated wavelengths, constant beyond the ends).
struct OpticalConstants {
  std::string name;    ///< "Au", "custom", file name, ...
  std::string source;  ///< provenance ("Johnson & Christy 1972", "n=1.5 k=0", a path)
  Spectrum n, k;
  std::complex<double> at(double wavelength_m) const { return {n(wavelength_m), k(wavelength_m)}; }
  /// Normal-incidence reflectance as a spectrum on the colour grid 360..830 nm.
  Spectrum normal_reflectance_spectrum() const;
};

/// Names accepted by metal(): Au Ag Cu Al Fe Cr Ni Ti Pt Pt-Tselin SS-austenitic SS-ferritic.
std::vector<std::string> metal_names();
/// Built-in optical constants (embedded at build time from data/optical/*.csv). Case-insensitive;
/// the file stems ("Au_JohnsonChristy1972") are accepted too. Throws InputError listing the names.
OpticalConstants metal(std::string_view name);
/// Constant n, k.
OpticalConstants constant_index(double n, double k);
/// A CSV file with header "wavelength_nm,n,k" (the data/optical format; '#' comment lines and a
/// header of "wavelength_um,n,k" are accepted too). Throws FileError.
OpticalConstants read_optical_constants_csv(const std::string& path);
/// Sun 2002 section 5.2: eta = 1 (or the given eta) and kappa from a normal-incidence reflectance
/// spectrum; the angular behaviour then follows the exact Fresnel equations.
OpticalConstants from_normal_reflectance(const Spectrum& r0, double eta = 1.0);
/// From an sRGB colour (8-bit-style encoded values in [0, 1]): smooth reflectance spectrum with
/// that colour (smooth_reflectance_from_linear_srgb), then kappa(lambda) from R0 with eta = 1.
OpticalConstants from_srgb(double r, double g, double b);

/// A material's Fresnel term, F(cos_i, lambda).
class Fresnel {
 public:
  virtual ~Fresnel() = default;
  virtual double eval(double cos_i, double wavelength_m) const = 0;
  virtual std::string describe() const = 0;
};

class ConductorFresnel final : public Fresnel {
 public:
  explicit ConductorFresnel(OpticalConstants c) : c_(std::move(c)) {}
  /// The real Siegel form (5x faster than the complex one, equal to ~1e-13; see the tests).
  double eval(double cos_i, double wavelength_m) const override {
    return fresnel_conductor_siegel(cos_i, c_.n(wavelength_m), c_.k(wavelength_m));
  }
  std::string describe() const override;
  const OpticalConstants& constants() const { return c_; }

 private:
  OpticalConstants c_;
};

class DielectricFresnel final : public Fresnel {
 public:
  explicit DielectricFresnel(Spectrum eta) : eta_(std::move(eta)) {}
  double eval(double cos_i, double wavelength_m) const override {
    return fresnel_dielectric(cos_i, eta_(wavelength_m));
  }
  std::string describe() const override;

 private:
  Spectrum eta_;
};

class SchlickFresnel final : public Fresnel {
 public:
  explicit SchlickFresnel(Spectrum r0) : r0_(std::move(r0)) {}
  double eval(double cos_i, double wavelength_m) const override {
    return fresnel_schlick(cos_i, r0_(wavelength_m));
  }
  std::string describe() const override { return "Schlick approximation"; }

 private:
  Spectrum r0_;
};

/// F = 1 (white furnace tests, NDF-only studies).
class PerfectMirrorFresnel final : public Fresnel {
 public:
  double eval(double, double) const override { return 1.0; }
  std::string describe() const override { return "perfect mirror (F = 1)"; }
};

}  // namespace microbrdf

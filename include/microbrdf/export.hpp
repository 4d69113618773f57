#pragma once
// Renderer-ready materials: RGL `.bsdf` files (read by Mitsuba 3's `measured` plugin and
// pbrt-v4's MeasuredBxDF; layout in rgl_bsdf.hpp and docs/measured.md).
//
// The file is built from a Brdf and a microfacet distribution that parameterises it (the
// distribution only shapes the grids and the sampling; the BRDF the file reproduces is the
// Brdf's own):
//  - ndf, sigma: D(m) and the projected area sigma+(wi) = integral D <wi.m>+ dw on the
//    renderers' (u_theta, u_phi) grid, u_theta = sqrt(2 theta / pi), u_phi = (phi + pi)/(2 pi);
//  - vndf: D(m) <wi.m>+ u_theta sin(theta_m) per incident node (the visible normals per unit
//    (u_theta, u_phi));
//  - spectra: at each node s of the sample grid, m = vndf.sample(s), wo = reflect(wi, m),
//    R = f(wi, wo) cos(theta_o) 4 sigma(wi) / D(m) with D and sigma the file's own interpolants,
//    so the reconstruction returns f exactly at the nodes; luminance: the mean of R over the
//    wavelengths (floored at 1e-4 of the slice maximum so every direction stays samplable).
// Isotropic files store phi_i = [0] (m relative to the incident azimuth); anisotropic files
// store phi_i spanning [-pi, pi].

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/tensor_file.hpp"

namespace microbrdf {

struct RglExportOptions {
  bool isotropic = true;
  std::size_t theta_i = 24;        ///< incident elevations, evenly spaced over [0, theta_i_max]
  double theta_i_max = 1.5533430;  ///< rad (89 deg)
  std::size_t phi_i = 17;          ///< anisotropic: incident azimuths evenly over [-pi, pi]
  std::size_t ndf_theta = 64;      ///< ndf/sigma/vndf grid along u_theta (>= 2)
  std::size_t ndf_phi = 64;        ///< ... along u_phi (>= 2)
  std::size_t samples = 32;        ///< luminance/spectra grid per side (>= 2)
  std::vector<double> wavelengths_nm = default_wavelengths();
  std::string description = "microbrdf";
  /// Called from the calling thread with the fraction of incident nodes done (may throw to
  /// stop the export: nothing is written then).
  std::function<void(double)> progress;
  /// 360..830 nm in 25 steps (19.6 nm).
  static std::vector<double> default_wavelengths();
};

/// The tensor file of `brdf` parameterised by `ndf`. Throws InputError for grids below 2 nodes
/// or without wavelengths.
TensorFile rgl_tensor(const Brdf& brdf, const MicrofacetDistribution& ndf,
                      const RglExportOptions& options);
/// True when the BRDF is unchanged when wi and wo turn together about n: 96 pairs (half drawn
/// by the BRDF's own sampler, so narrow lobes are probed) at four turns agree within 1e-3 of the
/// largest value seen. MERL tables are isotropic by construction; RGL files say which they are.
bool brdf_is_isotropic(const Brdf& brdf, double wavelength_m = 550e-9);
/// The distribution that parameterises the export of `brdf`: a microfacet BRDF's own NDF
/// (analytic or tabulated), else lobe_distribution(brdf, 257) (measured_ndf.hpp). `file`, when
/// given, is the file the BRDF was read from: a BRDF without a lobe is then a FileError naming it.
std::shared_ptr<const MicrofacetDistribution> export_distribution(
    const std::shared_ptr<const Brdf>& brdf, const std::string& file = "");
/// rgl_tensor written atomically to `path`.
void write_rgl_bsdf(const Brdf& brdf, const MicrofacetDistribution& ndf,
                    const RglExportOptions& options, const std::string& path);

}  // namespace microbrdf

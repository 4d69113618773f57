#pragma once
// Effective NDFs inferred from measured BRDFs (Dong 2015 section 7, eq. 9; docs/measured.md):
//
//   D(h) = 4 |wi.n| |wo.n| f(wi, wo) / (F(wi.h) G(wi, wo)),   h = (wi + wo)/|wi + wo|,
//
// with G = 1 by default (Dong's assumption, good at the small angles a gonioreflectometer
// covers), or the height-correlated Smith G2 of the estimate itself (`smith`: the G = 1 table is
// turned into a distribution, its G2 divided out, twice).
//  - Full BRDFs (MERL, RGL, any Brdf) are read at a fixed angle theta_d between wi and wo
//    (default 14.14 deg, Dong's setting; wi.h = cos(theta_d / 2)): at each disk node h,
//    wi, wo = cos(theta_d/2) h +- sin(theta_d/2) b with b = (-h_y, h_x, 0)/|(h_x, h_y)| (wi and wo
//    at equal elevation; b = +y at the pole). A NaN BRDF value (no data) gives a NaN node.
//  - Point sets (goniometer CSV) are splatted onto the disk with a Gaussian kernel of standard
//    deviation `kernel_sigma` in disk coordinates (default: the median distance between a point's
//    half vector and its nearest neighbour's): each node is the kernel-weighted mean of the
//    points' D values (Nadaraya-Watson), NaN where the summed weight is below exp(-2) (no point
//    within two kernel widths). Only the rows at the wavelength nearest `wavelength_m` are used.
// Nodes outside the unit disk are 0 (the table convention); the table is NOT renormalised (its
// scale is the BRDF's), meta.method = "measured".

#include <cstddef>
#include <memory>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Widest point-set kernel (std in disk coordinates, ~rad near the pole): 30 deg. A wider one
/// averages the whole lobe into one value (and costs a pass over the whole table per point).
inline constexpr double kMaxKernelSigma = 30 * 3.14159265358979323846 / 180;

struct EffectiveNdfOptions {
  double theta_d = 14.14 * 3.14159265358979323846 / 180;  ///< angle between wi and wo, rad
  std::size_t resolution = 1025;
  double wavelength_m = 550e-9;
  bool smith = false;       ///< divide by the Smith G2 of the estimate (default G = 1)
  double kernel_sigma = 0;  ///< point sets: kernel std in disk coordinates, (0, kMaxKernelSigma];
                            ///< 0 = automatic
};

/// Eq. 9 on a full BRDF read at the fixed theta_d. Throws InputError for theta_d outside
/// (0, 180) deg or a resolution below 5.
TabulatedNdf effective_ndf(const Brdf& brdf, const Fresnel& fresnel,
                           const EffectiveNdfOptions& options);
/// Eq. 9 on a goniometer point set, splatted with the Gaussian kernel. Throws InputError when no
/// point has both directions above the horizon.
TabulatedNdf effective_ndf(const GonioData& data, const Fresnel& fresnel,
                           const EffectiveNdfOptions& options);
/// Nodes of the table that hold a measurement (finite values inside the disk).
std::size_t measured_nodes(const TabulatedNdf& t);

/// A distribution that follows a BRDF's lobe, to parameterise its `.bsdf` export (export.hpp):
/// eq. 9 with F = 1 (at fixed theta_d, F(wi.h) is one constant, so the shape is exact), NaN and
/// negative nodes set to 0, every node floored at 1e-4 of the maximum so that no direction is
/// lost, normalised. Throws InputError when the BRDF has no positive value at theta_d.
std::shared_ptr<MicrofacetDistribution> lobe_distribution(const Brdf& brdf,
                                                          std::size_t resolution = 513,
                                                          double wavelength_m = 550e-9);

/// A measured file that holds a full BRDF, by its extension: `.binary` (MERL) or `.bsdf` (RGL).
/// Throws InputError naming the file for a goniometer `.csv` (a point set, not a full BRDF) or
/// an unknown extension; FileError for a file that does not read.
std::unique_ptr<Brdf> read_measured_brdf(const std::string& path);
/// Eq. 9 on any measured file, by its extension: `.csv` (goniometer points), `.binary` (MERL) or
/// `.bsdf` (RGL). meta.sources = {path}. `fresnel` is the material's Fresnel term (a
/// PerfectMirrorFresnel gives the NDF's shape, F = 1). Throws as the readers and
/// effective_ndf do (InputError for `options`); FileError naming the file for what is wrong with
/// its data: no point usable, no node measured (all NaN), or a negative BRDF anywhere.
TabulatedNdf measured_ndf_file(const std::string& path, const Fresnel& fresnel,
                               const EffectiveNdfOptions& options);
/// "<path>: warning: measured at X nm, not at the requested Y nm ..." when the table `t` (from
/// measured_ndf_file) is at a wavelength more than 0.5 nm from `requested_m`; "" otherwise.
std::string wavelength_warning(const TabulatedNdf& t, double requested_m, const std::string& path);

}  // namespace microbrdf

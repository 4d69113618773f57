#pragma once
// Materials and preview scenes for Mitsuba 3 and pbrt-v4 (docs/measured.md):
//  - an analytic BRDF as a GGX rough conductor: Mitsuba 3 `roughconductor` (distribution ggx,
//    alpha_u, alpha_v, eta/k spectrum files) and pbrt-v4 `conductor` (uroughness, vroughness,
//    remaproughness false, eta/k spectrum files); spectrum files are "wavelength_nm value" lines
//    from 360 to 830 nm in 5 nm steps;
//  - a tabulated or measured BRDF as a `measured` material that references an RGL `.bsdf` file;
//  - a scene with that material on a unit sphere: Mitsuba under an environment map (or a
//    constant emitter), pbrt-v4 under a uniform infinite light (pbrt-v4 environment maps must be
//    equal-area octahedral images, which microbrdf does not write).
// Approximations the renderers force (the ellipsoid's skew, a rotated anisotropy axis) are
// listed in `notes`; every note goes into the files as a comment.

#include <string>
#include <vector>

#include "microbrdf/fresnel.hpp"
#include "microbrdf/microfacet.hpp"

namespace microbrdf {

struct RoughConductor {
  double alpha_u = 0.1;  ///< GGX width along the surface's u (tangent) axis
  double alpha_v = 0.1;  ///< GGX width along v
  OpticalConstants constants;
  std::vector<std::string> notes;  ///< approximations made, one sentence each
};

/// The GGX rough conductor nearest a distribution, with the material's optical constants: what
/// its registered model (ndf_model.hpp, export_lobe) says GGX holds exactly as it is; any other
/// (Beckmann, the ellipsoid, whose skew neither renderer has, heavy-tailed models, two-lobe
/// mixtures) through a GGX fit (fit.hpp, sqrt objective) of the distribution tabulated on 257^2
/// nodes. Every approximation is a note: "nearest GGX of ..." with what the model says has no
/// equivalent, and for anisotropy axes turned by phi from the surface's u axis, that the
/// renderers align alpha_u with u.
RoughConductor nearest_rough_conductor(const MicrofacetDistribution& d,
                                       const OpticalConstants& constants);

struct SceneExportOptions {
  std::string envmap;  ///< Mitsuba: environment map copied next to the scene; "" = constant
  int width = 256, height = 256, spp = 64;
};

/// The files written, relative to `dir` (created if missing). Each file is written atomically.
/// Throws FileError.
std::vector<std::string> export_mitsuba(const RoughConductor& m, const std::string& dir,
                                        const SceneExportOptions& o);
/// `bsdf_file` is the `.bsdf` file's name inside `dir`. File names are escaped for each format
/// (pbrt-v4 string escapes; XML character entities and references) and read back as the same
/// bytes; a name an XML attribute cannot hold (bytes that are not UTF-8, control characters
/// other than tab, newline and carriage return) throws FileError naming it before anything is
/// written (Mitsuba only: pbrt takes any bytes).
std::vector<std::string> export_mitsuba_measured(const std::string& bsdf_file,
                                                 const std::string& dir,
                                                 const SceneExportOptions& o,
                                                 const std::vector<std::string>& notes = {});
std::vector<std::string> export_pbrt(const RoughConductor& m, const std::string& dir,
                                     const SceneExportOptions& o);
std::vector<std::string> export_pbrt_measured(const std::string& bsdf_file, const std::string& dir,
                                              const SceneExportOptions& o,
                                              const std::vector<std::string>& notes = {});

/// "wavelength_nm value" lines, 360..830 nm in 5 nm steps.
std::string spectrum_file_text(const Spectrum& s, const std::string& comment);

}  // namespace microbrdf

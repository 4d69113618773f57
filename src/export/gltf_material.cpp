// The glTF material of a BRDF spec: GGX widths, KHR_materials_anisotropy parameters, base colour
// and what glTF cannot represent (include/microbrdf/gltf_export.hpp, docs/gltf.md).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/gltf_export.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_model.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf {

GltfAnisotropy gltf_anisotropy(const AnisotropicAlpha& a, bool* clamped) {
  if (!(a.alpha_x > 0 && a.alpha_y > 0 && std::isfinite(a.alpha_x) && std::isfinite(a.alpha_y) &&
        std::isfinite(a.phi)))
    throw InputError(fmt::format("glTF: GGX widths must be positive and finite (got {} x {})",
                                 a.alpha_x, a.alpha_y));
  // The wider axis is glTF's anisotropy direction (its alpha only grows with the strength).
  double wide = a.alpha_x, narrow = a.alpha_y, phi = a.phi;
  if (narrow > wide) {
    std::swap(wide, narrow);
    phi += M_PI / 2;
  }
  const bool over = wide > 1;
  if (clamped) *clamped = over;
  wide = std::min(wide, 1.0);
  narrow = std::min(narrow, 1.0);
  GltfAnisotropy g;
  g.roughness = std::sqrt(narrow);
  g.strength = narrow < 1 ? std::sqrt((wide - narrow) / (1 - narrow)) : 0.0;
  // The direction is an axis: fold into (-pi/2, pi/2].
  phi = std::remainder(phi, M_PI);
  if (phi <= -M_PI / 2) phi += M_PI;
  g.rotation = g.strength > 0 ? phi : 0.0;
  return g;
}

AnisotropicAlpha ggx_from_gltf(const GltfAnisotropy& g) {
  const double ar = g.roughness * g.roughness, s2 = g.strength * g.strength;
  return {ar * (1 - s2) + s2, ar, g.rotation};
}

namespace {

/// The largest difference between glTF's Schlick (per linear sRGB channel, F0 = the base
/// colour) and the material's own Fresnel term (its spectrum under D65 to linear sRGB), over
/// 0..89 deg of incidence in 1 deg steps; "" when below 1e-3.
std::string fresnel_warning(const MaterialSpec& material, const std::array<double, 3>& f0) {
  const auto fresnel = make_fresnel(material);
  double worst = 0;
  int worst_deg = 0, worst_ch = 0;
  for (int deg = 0; deg <= 89; ++deg) {
    const double c = std::cos(deg * M_PI / 180);
    const Eigen::Vector3d rgb = xyz_to_linear_srgb(
        reflectance_to_xyz([&](double lambda) { return fresnel->eval(c, lambda); }));
    for (int ch = 0; ch < 3; ++ch) {
      const double schlick = f0[ch] + (1 - f0[ch]) * std::pow(1 - c, 5);
      if (std::abs(schlick - rgb[ch]) > worst) {
        worst = std::abs(schlick - rgb[ch]);
        worst_deg = deg;
        worst_ch = ch;
      }
    }
  }
  if (worst < 1e-3) return "";
  static constexpr const char* kChannel[3] = {"red", "green", "blue"};
  return fmt::format(
      "Fresnel: glTF's metals use Schlick's approximation per RGB channel with F0 = the base "
      "colour, not the material's {}; the reflectance differs by up to {:.3f} (linear sRGB, {} "
      "channel) at {} deg incidence",
      fresnel->describe(), worst, kChannel[worst_ch], worst_deg);
}

/// Normal-incidence reflectance under D65 in linear sRGB, as `brdf color` prints it, clipped to
/// glTF's [0, 1].
std::array<double, 3> base_colour(const MaterialSpec& material, std::vector<std::string>& warn) {
  if (material.form == MaterialSpec::Form::Perfect) return {1, 1, 1};
  const OpticalConstants c = optical_constants(material);
  const Eigen::Vector3d rgb =
      xyz_to_linear_srgb(reflectance_to_xyz(c.normal_reflectance_spectrum()));
  std::array<double, 3> out{};
  for (int i = 0; i < 3; ++i) out[i] = std::clamp(rgb[i], 0.0, 1.0);
  if (rgb.maxCoeff() > 1 || rgb.minCoeff() < 0)
    warn.push_back(fmt::format(
        "base colour: the normal-incidence reflectance {:.4f} {:.4f} {:.4f} (linear sRGB) lies "
        "outside the sRGB gamut; glTF holds it clipped to [0, 1]",
        rgb[0], rgb[1], rgb[2]));
  return out;
}

/// The GGX fit of a table, with a warning naming what was fitted and the fit's distance.
AnisotropicAlpha ggx_fit(const TabulatedNdf& table, const std::string& what,
                         std::vector<std::string>& warn) {
  FitOptions fo;
  fo.model = "ggx";
  const FitResult r = fit_ndf(table, fo);
  warn.push_back(fmt::format(
      "shape: glTF's microfacet distribution is GGX; {} becomes the GGX fit alpha_x {:.4g}, "
      "alpha_y {:.4g}, phi {:.4g} deg (Hellinger distance {:.3g}, relative L2 error {:.3g}), "
      "with GGX's Smith shadowing",
      what, r.params.at("alpha_x"), r.params.at("alpha_y"), r.phi * 180 / M_PI + 0.0, r.hellinger,
      r.relative_l2_error));
  if (!r.at_bound.empty())
    warn.back() += "; the fit ended on " + r.at_bound + " (its optimum may lie beyond that bound)";
  return {r.params.at("alpha_x"), r.params.at("alpha_y"), r.phi};
}

/// The texture's per-texel GGX (each ellipsoid without its tilts), invalid texels the mean.
GltfTextureMaps texture_maps(const ParamTexture& t, const std::string& path,
                             std::vector<std::string>& warn) {
  check_memory(path, mul_sat(t.size(), sizeof(AnisotropicAlpha)), "the glTF texture maps");
  GltfTextureMaps maps;
  maps.nx = t.nx;
  maps.ny = t.ny;
  maps.texel.resize(t.size());
  const EllipsoidParams mean = t.mean_valid();
  double tilt2 = 0;
  std::size_t over = 0;
  for (std::size_t iy = 0; iy < t.ny; ++iy)
    for (std::size_t ix = 0; ix < t.nx; ++ix) {
      const std::size_t i = ix + t.nx * iy;
      const EllipsoidParams p = t.valid[i] ? t.at(ix, iy) : mean;
      maps.texel[i] = {p.alpha_x, p.alpha_y, -p.theta_z};
      tilt2 += p.theta_x * p.theta_x + p.theta_y * p.theta_y;
      over += std::max(p.alpha_x, p.alpha_y) > 1;
    }
  warn.push_back(fmt::format(
      "texture: each texel's ellipsoid NDF becomes the GGX of its widths and theta_z; its tilts "
      "(rms sqrt(theta_x^2 + theta_y^2) = {:.3g} deg over the texels) have no glTF equivalent; "
      "{} invalid texels take the mean; the texture SVBRDF's separable shadowing G1 G1 becomes "
      "GGX's height-correlated Smith term; glTF stores the per-texel values in 8 bits",
      std::sqrt(tilt2 / double(t.size())) * 180 / M_PI, t.size() - t.valid_count()));
  if (over)
    warn.push_back(fmt::format("texture: {} texels wider than alpha 1 are clamped to 1", over));
  return maps;
}

/// Grey F0 for a BRDF without a material (SH): glTF's GGX of widths `a` with F = F0 reflects at
/// normal incidence what the BRDF does (directional albedos at 550 nm).
double albedo_matched_f0(const Brdf& brdf, const AnisotropicAlpha& a) {
  const MicrofacetBrdf ggx(std::make_shared<GgxDistribution>(a.alpha_x, a.alpha_y, a.phi),
                           std::make_shared<PerfectMirrorFresnel>(), false);
  const Vec3 n(0, 0, 1);
  return std::clamp(directional_albedo(brdf, n, 550e-9) / directional_albedo(ggx, n, 550e-9), 0.0,
                    1.0);
}

}  // namespace

GltfMaterial gltf_material(const BrdfSpec& spec, const MaterialSpec& material) {
  using Kind = BrdfSpec::Kind;
  if (spec.kind == Kind::Lambertian || spec.kind == Kind::Mirror)
    throw InputError("glTF: " + spec.describe() +
                     " has no glTF metal equivalent; give a microfacet, Kirchhoff, Sun, SH or "
                     "texture BRDF");
  if (spec.uses_material() && material.form == MaterialSpec::Form::Dielectric)
    throw InputError("glTF: the export writes metals (metallic 1); a dielectric is not one");
  GltfMaterial m;
  m.describe = spec.describe() + (spec.uses_material() ? ", " + material.describe() : "");
  m.name = "microbrdf " + m.describe;
  auto& warn = m.warnings;
  if (spec.kind == Kind::Analytic) {
    const auto d = make_distribution(spec.model);
    // What the model says GGX holds exactly as it is; the others (Beckmann, the ellipsoid and
    // its skew, heavy tails): the GGX fit of the 257^2 table, as the Mitsuba and pbrt exports do.
    NdfExportLobe lobe;
    lobe.exact = false;
    if (!d->model_name().empty()) lobe = ndf_model(d->model_name()).export_lobe(d->model_values());
    if (lobe.exact) {
      m.ggx = {lobe.alpha_x, lobe.alpha_y, lobe.phi};
    } else {
      m.ggx = ggx_fit(tabulate(*d, spec.model.model, 257), "the " + d->describe(), warn);
      if (!lobe.note.empty()) warn.push_back(lobe.note);
    }
  } else if (spec.kind == Kind::Tabulated) {
    m.ggx = ggx_fit(read_ndf(spec.ndf), "the tabulated NDF " + spec.ndf, warn);
  } else if (spec.kind == Kind::Texture) {
    const ParamTexture t = read_param_texture(spec.texture);
    const EllipsoidParams mean = t.mean_valid();
    m.ggx = {mean.alpha_x, mean.alpha_y, -mean.theta_z};
    m.texture.push_back(texture_maps(t, spec.texture, warn));
  } else {
    // Kirchhoff, Sun 2002, SH: the GGX fit of the BRDF's eq. 9 lobe (measured_ndf.hpp).
    const auto brdf = make_brdf(spec, material);
    const auto lobe = lobe_distribution(*brdf, 257);
    m.ggx = ggx_fit(tabulate(*lobe, "lobe", 257),
                    "the lobe (Dong 2015 eq. 9, 550 nm) of the " + spec.describe(), warn);
    if (spec.kind == Kind::Sh) {
      const double f0 = albedo_matched_f0(*brdf, m.ggx);
      m.base_color = {f0, f0, f0};
      warn.push_back(fmt::format(
          "colour: the SH BRDF has no material; the base colour is the grey F0 {:.4f} that gives "
          "glTF's GGX the BRDF's directional albedo at normal incidence (550 nm)",
          f0));
    }
  }
  if (spec.multiple_scattering)
    warn.push_back(
        "multiple scattering: glTF's GGX counts one bounce between microfacets; the light of "
        "--multiple-scattering is not in the material");
  if (spec.separable_g)
    warn.push_back(
        "shadowing: glTF uses GGX's height-correlated Smith G2, not the separable G1 G1 "
        "(--separable-g)");
  if (spec.uses_material()) {
    m.base_color = base_colour(material, warn);
    const std::string f = fresnel_warning(material, m.base_color);
    if (!f.empty()) warn.push_back(f);
  }
  bool clamped = false;
  (void)gltf_anisotropy(m.ggx, &clamped);
  if (clamped)
    warn.push_back(fmt::format(
        "width: glTF's alpha roughness is at most 1; the GGX widths {:.4g} x {:.4g} are clamped "
        "to 1",
        m.ggx.alpha_x, m.ggx.alpha_y));
  return m;
}

}  // namespace microbrdf

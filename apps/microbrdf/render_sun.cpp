// The Sun 2002 flags of `microbrdf render` (render_sun.hpp).
#include "render_sun.hpp"

#include <optional>

#include "microbrdf/error.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf::cli {

const char* const kRenderSunHelp =
    "Sun 2002 options: --sun-form standard|published, --sun-ftp both|view|light|none (the rows\n"
    "of Sun's Fig. 8), --s-texture FILE (smoothness from an image's grey value mapped to\n"
    "--s-range MIN,MAX; replaces --sun) and --color-texture FILE (each texel's sRGB colour as\n"
    "a metal of eta = 1, Sun 5.2; replaces the material flags): PNG, EXR or HDR images, u along\n"
    "the columns, v up the rows, wrapping (Sun's Fig. 11).\n";

void add_render_sun_flags(CLI::App* c, sun2002::SunRenderOptions& o) {
  c->add_option("--sun-form", o.form,
                "With --sun: standard (microfacet form) or published (eq. 3.5.3 as printed)")
      ->capture_default_str();
  c->add_option("--sun-ftp", o.ftp,
                "With --sun: free travel probabilities both, view (viewer only), light or none "
                "(Sun's Fig. 8 rows)")
      ->capture_default_str();
  c->add_option("--s-texture", o.s_texture,
                "Sun 2002 BRDF with the smoothness from an image (.png/.exr/.hdr): grey value "
                "0..1 mapped linearly to --s-range; replaces --sun");
  c->add_option("--s-range", o.s_range, "With --s-texture: MIN,MAX smoothness for black, white")
      ->capture_default_str();
  c->add_option("--color-texture", o.color_texture,
                "With --sun or --s-texture: each texel's sRGB colour as a metal (eta = 1, kappa "
                "from the colour's reflectance spectrum; Sun 5.2) instead of --metal");
}

BrdfSpec render_brdf_spec(const SpecFlags& spec, const sun2002::SunRenderOptions& sun) {
  const auto it = spec.text.find("sun");
  if (!sun.s_texture.empty() && it != spec.text.end() && !it->second.empty())
    throw InputError("--s-texture gives the smoothness of the Sun 2002 BRDF: leave out --sun");
  std::optional<BrdfSpec> fallback;
  if (!sun.s_texture.empty()) {
    fallback = BrdfSpec{};
    fallback->kind = BrdfSpec::Kind::Sun;
    fallback->sun_s = sun2002::parse_s_range(sun.s_range).first;
  }
  const BrdfSpec b = brdf_spec(spec, fallback);
  if (sun.given() && b.kind != BrdfSpec::Kind::Sun)
    throw InputError(
        "--sun-form, --sun-ftp and --color-texture go with the Sun 2002 BRDF (--sun S or "
        "--s-texture FILE)");
  if (!sun.color_texture.empty() && has_material(spec.keys()))
    throw InputError(
        "--color-texture gives each texel's material: leave out --metal, --n/--k, --nk-csv, "
        "--r0 and --color");
  sun.check();
  return b;
}

std::vector<std::shared_ptr<const Svbrdf>> render_materials(const SpecFlags& spec,
                                                            const sun2002::SunRenderOptions& sun) {
  BrdfSpec b = render_brdf_spec(spec, sun);
  // A pixel averages many BRDF values: few walks each cost less than the noise they add.
  if (b.multiple_scattering && b.ms_walks == 0) b.ms_walks = 4;
  const MaterialSpec mat = material_spec(spec, MaterialSpec::named_metal("Al"));
  if (b.kind == BrdfSpec::Kind::Sun && sun.given())
    return {sun2002::make_sun_svbrdf(sun, b.sun_s, make_fresnel(mat))};
  return {make_svbrdf(b, mat)};
}

}  // namespace microbrdf::cli

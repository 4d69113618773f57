// `microbrdf brdf slice|color`: any BRDF of the project (analytic microfacet, tabulated NDF,
// Kirchhoff, Sun 2002, spherical harmonics, Lambertian, mirror) along in-plane / out-of-plane
// cuts, and the normal-incidence colour of a material. The SH subcommands: cmd_brdf_sh.cpp.
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/brdf_slice.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/units.hpp"
#include "rayleigh_rice_flags.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct BrdfArgs {
  SpecFlags spec;
  RayleighRiceFlags rr;
  std::string theta_i = "30deg", plane = "in", wavelength = "555nm", output, plot;
  bool log_y = false;
  std::size_t samples = 721;
  bool json = false;
};

void run_slice(const BrdfArgs& a) {
  if (a.output.empty() && a.plot.empty())
    throw InputError("give an output: -o slice.csv and/or --plot slice.png|svg");
  check_plot_name("--plot", a.plot);
  const double ti = parse_angle(a.theta_i), lambda = parse_length(a.wavelength);
  if (!(ti >= 0 && ti < M_PI / 2)) throw InputError("--theta-i must lie in [0, 90) deg");
  const SlicePlane plane = parse_slice_plane(a.plane);
  check_rayleigh_rice_flags(a.rr, a.spec);
  BrdfSpec spec;
  RayleighRiceSource rr;
  std::shared_ptr<const Brdf> bp;
  if (a.rr.given()) {
    rr = rayleigh_rice_from_flags(a.rr, a.spec);
    bp = rr.brdf;
  } else {
    bp = brdf_from_flags(a.spec, &spec);
    warn_single_dk_table(a.spec, "brdf slice");
  }
  const Brdf& b = *bp;
  std::string label = a.rr.given() ? "Rayleigh-Rice, " + to_string(rr.brdf->polarisation()) + ", " +
                                         rr.brdf->material().name
                                   : spec.describe();
  if (const auto* mf = dynamic_cast<const MicrofacetBrdf*>(bp.get());
      mf && spec.kind == BrdfSpec::Kind::Analytic && !a.rr.given())
    label = mf->distribution().describe();
  const auto s = tabulate_slice(b, ti, lambda, plane, a.samples);
  const SlicePeak peak = slice_peak(s);
  if (!a.output.empty())
    write_file_atomic(a.output, a.rr.mueller()
                                    ? mueller_slice_csv(*rr.brdf, ti, lambda, plane, a.samples)
                                    : slice_csv(s, b.describe(), ti, lambda, plane));
  if (!a.plot.empty()) slice_plot(s, label, ti, lambda, plane, a.log_y).write(a.plot);
  const double albedo = b.albedo(slice_light(ti), lambda);
  if (a.json) {
    nlohmann::json j = {{"output", a.output},
                        {"plot", a.plot},
                        {"ndf", spec.ndf},
                        {"sh", spec.sh},
                        {"model", b.describe()},
                        {"theta_i_rad", ti},
                        {"wavelength_m", lambda},
                        {"plane", a.plane},
                        {"samples", s.value.size()},
                        {"peak_brdf_per_sr", peak.value},
                        {"peak_angle_deg", peak.angle_deg},
                        {"directional_albedo", albedo}};
    if (a.rr.given()) j["rayleigh_rice"] = rayleigh_rice_json(a.rr, rr, ti, lambda);
    print_json(j);
  } else {
    std::printf(
        "%s\n  wrote %zu angles to %s; peak %.6g /sr at %.3f deg; directional albedo %.5f\n",
        b.describe().c_str(), s.value.size(),
        (a.output.empty() ? a.plot
         : a.plot.empty() ? a.output
                          : a.output + " and " + a.plot)
            .c_str(),
        peak.value, peak.angle_deg, albedo);
  }
}

void run_color(const BrdfArgs& a) {
  const auto mat = optical_constants(material_spec(a.spec, std::nullopt));
  const auto r = mat.normal_reflectance_spectrum();
  const auto xyz = reflectance_to_xyz(r);
  const auto rgb = xyz_to_linear_srgb(xyz);
  const auto c8 = linear_srgb_to_srgb8(rgb);
  if (a.json) {
    print_json({{"material", mat.name},
                {"source", mat.source},
                {"illuminant", "D65"},
                {"observer", "CIE 1931 2 deg"},
                {"xyz", {xyz[0], xyz[1], xyz[2]}},
                {"linear_srgb", {rgb[0], rgb[1], rgb[2]}},
                {"srgb8", {c8[0], c8[1], c8[2]}},
                {"hex", srgb8_hex(c8)},
                {"out_of_gamut", rgb.maxCoeff() > 1 || rgb.minCoeff() < 0}});
    return;
  }
  std::printf("%s (%s)\n", mat.name.c_str(), mat.source.c_str());
  std::printf("  normal-incidence reflectance under D65, CIE 1931 2 deg, white = Y 1\n");
  std::printf("  XYZ          %.4f %.4f %.4f\n", xyz[0], xyz[1], xyz[2]);
  std::printf(
      "  linear sRGB  %.4f %.4f %.4f%s\n", rgb[0], rgb[1], rgb[2],
      rgb.maxCoeff() > 1 || rgb.minCoeff() < 0 ? "  (outside the sRGB gamut; clipped below)" : "");
  std::printf("  sRGB 8-bit   %d %d %d  %s\n", c8[0], c8[1], c8[2], srgb8_hex(c8).c_str());
}

}  // namespace

void register_brdf(CLI::App& app) {
  auto a = std::make_shared<BrdfArgs>();
  auto* brdf = app.add_subcommand(
      "brdf",
      "Any BRDF of the project along cuts (Dong 2015 eq. 1, Kirchhoff, Sun 2002, spherical "
      "harmonics), SH files (Westin 1992) and material colours");
  brdf->require_subcommand(1);
  register_brdf_sh(brdf);
  brdf->footer(
      "Frame: n = +z, light and view point away from the surface, BRDF in 1/sr. Slices: the\n"
      "light lies at azimuth 180 deg; in-plane angles are signed with the mirror direction at\n"
      "+theta_i (docs/models.md). BRDFs: --model/--alpha*, --ndf, --kirchhoff, --sun, --sh,\n"
      "--lambertian, --mirror, --rayleigh-rice SCAN (smooth metals: Sq << lambda, small\n"
      "slopes; first-order vector perturbation theory with s/p/Mueller). Materials: --metal\n"
      "NAME, --n/--k, --nk-csv FILE, --r0 R or --color COLOUR, with --fresnel exact|schlick.\n"
      "Angles take units (30deg, 0.5rad; a bare number is degrees).\n\n"
      "Examples:\n"
      "  microbrdf brdf slice --model ggx --alpha 0.1 --metal Cu --theta-i 30deg -o slice.csv\n"
      "  microbrdf brdf slice --ndf scan_ndf.npy --metal Al --theta-i 45deg -o s.csv --plot s.png\n"
      "  microbrdf brdf slice --model ellipsoid --alpha-x 0.05 --alpha-y 0.2 --theta-x 5deg \\\n"
      "      --metal Al --theta-i 45deg --plane out --wavelength 633nm -o out.csv --json\n"
      "  microbrdf brdf slice --sun 2 --n 0.2 --k 3.0 --theta-i 30deg -o sun.csv\n"
      "  microbrdf brdf slice --rayleigh-rice polished.x3p --metal Al --wavelength 633nm \\\n"
      "      --theta-i 20deg --polarisation s -o rr_s.csv --log-y --plot rr_s.png --json\n"
      "  microbrdf brdf sh-project --model ggx --alpha 0.3 --metal Al --lmax 16 -o ggx.shbrdf\n"
      "  microbrdf brdf slice --sh ggx.shbrdf --theta-i 45deg -o sh.csv --plot sh.png\n"
      "  microbrdf brdf info --sh sim.shbrdf --json\n"
      "  microbrdf brdf color --color '#e6c27a' --json");
  const auto add_source = [a](CLI::App* c) {
    add_brdf_flags(c, a->spec, kFlagAllBrdfs);
    add_material_flags(c, a->spec, "");
    c->add_option("--wavelength", a->wavelength, "Wavelength (with unit)")
        ->capture_default_str()
        ->check(wavelength());
  };

  auto* sl = brdf->add_subcommand("slice", "Tabulate a BRDF along an in-plane or out-of-plane cut");
  add_source(sl);
  sl->add_option("--theta-i", a->theta_i, "Angle of incidence")
      ->capture_default_str()
      ->check(polar_angle());
  sl->add_option("--plane", a->plane,
                 "in (plane of incidence) or out (across it, through the mirror direction)")
      ->capture_default_str();
  sl->add_option("--samples", a->samples, "Number of angles over [-90, 90] deg")
      ->capture_default_str()
      ->check(count_in(2, 1e7, "a slice finer than 2e-5 deg holds nothing new"));
  add_rayleigh_rice_flags(sl, a->rr);
  sl->add_option("-o,--output", a->output,
                 "Output CSV (angle_deg, brdf_per_sr, wo; with --polarisation mueller: "
                 "angle_deg, m00..m33, wo)");
  sl->add_option("--plot", a->plot, "Plot of the slice (.png or .svg)");
  sl->add_flag("--log-y", a->log_y, "Logarithmic BRDF axis in the plot");
  sl->add_flag("--json", a->json, "Print a JSON summary on stdout");
  sl->callback([a] { run_guarded("brdf slice", [&] { run_slice(*a); }); });

  auto* co =
      brdf->add_subcommand("color", "Normal-incidence colour of a material (D65, CIE 1931, sRGB)");
  add_material_flags(co, a->spec, "");
  co->add_flag("--json", a->json, "Print JSON on stdout");
  co->callback([a] { run_guarded("brdf color", [&] { run_color(*a); }); });
}

}  // namespace microbrdf::cli

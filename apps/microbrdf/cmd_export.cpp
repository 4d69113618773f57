// `microbrdf export bsdf|mitsuba|pbrt`: renderer-ready materials (docs/measured.md), from a
// measured file or the BRDF and material flags of every other command (spec_flags.hpp).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "cli_progress.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/scene_export.hpp"
#include "microbrdf/texture.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

namespace fs = std::filesystem;
struct GridArgs {
  bool isotropic = false, anisotropic = false;
  std::size_t theta_i = 24, phi_i = 17, ndf_grid = 64, samples = 32, wavelengths = 25;
};

struct ExportArgs {
  std::string input, output, bsdf, envmap;
  SpecFlags spec;
  GridArgs grid;
  bool json = false;
};

/// The BRDF to export and, for analytic models (and a parameter texture's mean), its
/// distribution and optical constants (what a rough conductor needs).
struct Source {
  std::shared_ptr<const Brdf> brdf;
  std::shared_ptr<const MicrofacetDistribution> analytic;
  std::optional<OpticalConstants> constants;
  std::string what;  ///< for the file's description and the messages
};

void say(const char* cmd, const std::string& line) {
  std::fprintf(stderr, "microbrdf export %s: %s\n", cmd, line.c_str());
}

Source source_of(const ExportArgs& a, const char* cmd) {
  Source s;
  const nlohmann::json keys = a.spec.keys();
  if (!a.input.empty()) {
    if (!keys.empty())
      throw InputError("give a measured FILE or the BRDF/material flags, not both");
    s.brdf = read_measured_brdf(a.input);
    s.what = fs::path(a.input).filename().string();
    return s;
  }
  if (keys.empty())
    throw InputError(
        "give a measured FILE (.binary, .bsdf) or a BRDF (--model/--alpha, --ndf, --kirchhoff, "
        "--sun, --sh, --texture, --lambertian) with its material");
  const BrdfSpec spec = brdf_spec(a.spec);
  warn_single_dk_table(a.spec, "export " + std::string(cmd));
  const MaterialSpec material =
      spec.uses_material() ? material_spec(a.spec, std::nullopt) : MaterialSpec{};
  s.what = spec.describe() + (spec.uses_material() ? ", " + material.describe() : "");
  if (spec.kind == BrdfSpec::Kind::Mirror)
    throw InputError("--mirror: an ideal mirror is a delta lobe, which a .bsdf table cannot hold");
  if (spec.kind == BrdfSpec::Kind::Texture) {
    const EllipsoidParams p = read_param_texture(spec.texture).mean_valid();
    auto d = std::make_shared<EllipsoidDistribution>(p);
    s.brdf = std::make_shared<MicrofacetBrdf>(d, make_fresnel(material), spec.separable_g);
    s.analytic = d;
    say(cmd,
        "the parameter texture is spatially varying: exporting the ellipsoid of its mean "
        "valid texel (" +
            d->describe() + ")");
  } else {
    s.brdf = make_brdf(spec, material);
    if (spec.kind == BrdfSpec::Kind::Analytic && !spec.multiple_scattering)
      s.analytic = std::shared_ptr<const MicrofacetDistribution>(
          s.brdf, &static_cast<const MicrofacetBrdf&>(*s.brdf).distribution());
  }
  if (s.analytic) s.constants = optical_constants(material);
  return s;
}

RglExportOptions grid_options(const GridArgs& g, const Brdf& brdf, const std::string& what,
                              const char* cmd) {
  if (g.isotropic && g.anisotropic) throw InputError("give --isotropic or --anisotropic, not both");
  RglExportOptions o;
  if (g.isotropic || g.anisotropic) {
    o.isotropic = g.isotropic;
  } else {
    o.isotropic = brdf_is_isotropic(brdf);
    say(cmd, std::string(o.isotropic ? "isotropic" : "anisotropic") + " BRDF: " +
                 (o.isotropic ? "one incident azimuth (phi_i = [0])"
                              : std::to_string(g.phi_i) + " incident azimuths") +
                 " (--isotropic / --anisotropic to choose)");
  }
  o.theta_i = g.theta_i;
  o.phi_i = g.phi_i;
  o.ndf_theta = o.ndf_phi = g.ndf_grid;
  o.samples = g.samples;
  o.wavelengths_nm.resize(g.wavelengths);
  for (std::size_t i = 0; i < g.wavelengths; ++i)
    o.wavelengths_nm[i] = 360.0 + 470.0 * double(i) / double(g.wavelengths - 1);
  o.description = "microbrdf export of " + what;
  return o;
}

void preflight(const ExportArgs& a, bool dir) {
  Preflight pre;
  if (!a.input.empty()) pre.input("file", a.input);
  if (!a.bsdf.empty()) pre.input("--bsdf", a.bsdf);
  check_spec_files(pre, a.spec);
  dir ? pre.output_dir("-o", a.output) : pre.output("-o", a.output, {".bsdf"});
  if (!a.envmap.empty()) pre.envmap("--envmap", a.envmap);
  pre.done();
}

void run_bsdf(const ExportArgs& a) {
  preflight(a, false);
  const Source s = source_of(a, "bsdf");
  RglExportOptions o = grid_options(a.grid, *s.brdf, s.what, "bsdf");
  Progress progress("export bsdf", false, 0.25, "spectra");
  o.progress = progress.fraction_callback();
  // The grids follow the BRDF's own NDF (microfacet BRDFs) or its lobe (eq. 9 shape).
  const auto d = export_distribution(s.brdf, a.input);
  {
    // One output file, renamed into place at once: it may commit now, so its size can be read.
    OutputGroup::Bypass direct;
    write_rgl_bsdf(*s.brdf, *d, o, a.output);
  }
  const auto bytes = fs::file_size(a.output);
  if (a.json)
    print_json({{"input", a.input.empty() ? s.what : a.input},
                {"output", a.output},
                {"isotropic", o.isotropic},
                {"theta_i", o.theta_i},
                {"phi_i", o.isotropic ? 1 : o.phi_i},
                {"ndf_grid", a.grid.ndf_grid},
                {"samples", o.samples},
                {"wavelengths", a.grid.wavelengths},
                {"bytes", bytes}});
  else
    std::printf("%s -> %s (%s, %zu theta_i, %zu x %zu samples, %zu wavelengths, %.1f MB)\n",
                (a.input.empty() ? s.what : a.input).c_str(), a.output.c_str(),
                o.isotropic ? "isotropic" : "anisotropic", o.theta_i, o.samples, o.samples,
                a.grid.wavelengths, double(bytes) / 1e6);
}

void run_scene(const ExportArgs& a, bool mitsuba) {
  const char* cmd = mitsuba ? "mitsuba" : "pbrt";
  preflight(a, true);
  SceneExportOptions so;
  so.envmap = a.envmap;
  std::vector<std::string> files;
  std::vector<std::string> notes;
  if (!a.bsdf.empty()) {
    if (!a.input.empty() || !a.spec.keys().empty())
      throw InputError("--bsdf: give the .bsdf file alone (no measured FILE or BRDF flags)");
    (void)RglBrdf::load(a.bsdf);  // refuse a broken file before writing anything
    const std::string name = fs::path(a.bsdf).filename().string();
    files = mitsuba ? export_mitsuba_measured(name, a.output, so)
                    : export_pbrt_measured(name, a.output, so);
    if (std::error_code ec; !fs::equivalent(a.bsdf, fs::path(a.output) / name, ec)) {
      write_file_atomic((fs::path(a.output) / name).string(),
                        read_file_bytes(a.bsdf, std::uint64_t{1} << 32));
      files.push_back(name);
    }
  } else {
    const Source s = source_of(a, cmd);
    if (s.analytic) {
      const RoughConductor m = nearest_rough_conductor(*s.analytic, *s.constants);
      for (const auto& n : m.notes) say(cmd, n);
      files = mitsuba ? export_mitsuba(m, a.output, so) : export_pbrt(m, a.output, so);
    } else {
      // Tabulated and measured BRDFs: a `measured` material referencing a .bsdf written here.
      const std::string name =
          a.input.empty() ? "material.bsdf" : fs::path(a.input).stem().string() + ".bsdf";
      const RglExportOptions o = grid_options(a.grid, *s.brdf, s.what, cmd);
      notes.push_back("the BRDF (" + s.what + ") as an RGL .bsdf table: " + name);
      files = mitsuba ? export_mitsuba_measured(name, a.output, so, notes)
                      : export_pbrt_measured(name, a.output, so, notes);
      write_rgl_bsdf(*s.brdf, *export_distribution(s.brdf, a.input), o,
                     (fs::path(a.output) / name).string());
      files.push_back(name);
    }
  }
  if (a.json) {
    print_json({{"output", a.output}, {"files", files}});
  } else {
    for (const auto& f : files) std::printf("%s\n", (fs::path(a.output) / f).string().c_str());
  }
}

void add_grid_flags(CLI::App* c, GridArgs& g) {
  c->add_flag("--isotropic", g.isotropic, "Store one incident azimuth (phi_i = [0])");
  c->add_flag("--anisotropic", g.anisotropic,
              "Store incident azimuths over 2 pi (default: whichever the BRDF is, tested)");
  c->add_option("--theta-i", g.theta_i, "Incident elevations over [0, 89] deg")
      ->capture_default_str()
      ->check(count_in(2, 512));
  c->add_option("--phi-i", g.phi_i, "Incident azimuths (anisotropic files)")
      ->capture_default_str()
      ->check(count_in(3, 512));
  c->add_option("--ndf-grid", g.ndf_grid, "ndf/sigma/vndf nodes per axis")
      ->capture_default_str()
      ->check(count_in(3, 512));
  c->add_option("--samples", g.samples, "luminance/spectra nodes per axis")
      ->capture_default_str()
      ->check(count_in(2, 512));
  c->add_option("--wavelengths", g.wavelengths, "Wavelengths over 360-830 nm")
      ->capture_default_str()
      ->check(count_in(2, 512));
}

void add_source_flags(CLI::App* c, ExportArgs& a) {
  c->add_option("file", a.input, "Measured BRDF: .binary (MERL) or .bsdf (RGL)");
  add_export_source_flags(c, a.spec);
}

}  // namespace

void register_export(CLI::App& app) {
  auto* e = app.add_subcommand("export", "Materials for renderers: .bsdf, Mitsuba, pbrt, glTF");
  e->require_subcommand(1);
  auto a = std::make_shared<ExportArgs>();
  auto* b = e->add_subcommand("bsdf", "Write a BRDF as an RGL .bsdf tensor file");
  b->footer(
      "The RGL format of Mitsuba 3's `measured` plugin and pbrt-v4's MeasuredBxDF (Dupuy & Jakob "
      "2018).\n"
      "The BRDF is a measured FILE or any BRDF of the model/material flags (microbrdf's own, "
      "height-\n"
      "correlated Smith by default); the file returns it exactly at its sample nodes. The grids "
      "follow\n"
      "the BRDF's NDF (microfacet BRDFs) or its lobe. Isotropic or anisotropic: as the BRDF is "
      "(tested),\n"
      "or --isotropic / --anisotropic. Defaults: 24 theta_i, 17 phi_i (anisotropic), 64 x 64 ndf "
      "grid,\n"
      "32 x 32 samples, 25 wavelengths 360-830 nm: about 3.0 MB isotropic, 50 MB anisotropic; "
      "median\n"
      "error of f cos(theta_o) on the lobe 0.07-0.25 % for GGX lobes (docs/measured.md).\n\n"
      "Examples:\n"
      "  microbrdf export bsdf --model ggx --alpha 0.3 --n 1.2 --k 3.5 -o g.bsdf\n"
      "  microbrdf export bsdf --model ggx --alpha-x 0.1 --alpha-y 0.3 --metal Al -o a.bsdf\n"
      "  microbrdf export bsdf --ndf ndf.npy --metal Fe -o t.bsdf\n"
      "  microbrdf export bsdf alum.binary --theta-i 32 --samples 48 -o alum.bsdf");
  add_source_flags(b, *a);
  b->add_option("-o,--output", a->output, "Output .bsdf file")->required();
  add_grid_flags(b, a->grid);
  b->add_flag("--json", a->json, "Print a JSON summary on stdout");
  b->callback([a] { run_guarded("export bsdf", [&] { run_bsdf(*a); }); });

  for (bool mitsuba : {true, false}) {
    auto s = std::make_shared<ExportArgs>();
    auto* c = e->add_subcommand(
        mitsuba ? "mitsuba" : "pbrt",
        mitsuba ? "Mitsuba 3 material + sphere scene" : "pbrt-v4 material + sphere scene");
    c->footer(
        std::string("Writes material.") + (mitsuba ? "xml" : "pbrt") + " and scene." +
        (mitsuba ? "xml" : "pbrt") +
        " into DIR. An analytic model (and a parameter texture's mean)\n"
        "becomes a GGX rough conductor (" +
        (mitsuba ? "roughconductor, alpha_u/alpha_v" : "conductor, uroughness/vroughness") +
        ", eta/k spectrum files in nm);\n"
        "Beckmann and the ellipsoid (whose skew the renderers lack) become the nearest GGX, "
        "said in the\n"
        "files and on stderr. Tabulated, Kirchhoff, measured BRDFs (FILE) become a `measured` "
        "material\n"
        "referencing a .bsdf written into DIR (grid flags as for `export bsdf`); --bsdf uses "
        "an existing one.\n" +
        (mitsuba ? "--envmap FILE lights the sphere with that map (copied); default: a "
                   "constant emitter.\n"
                 : "pbrt-v4 wants equal-area environment maps: the scene uses a uniform "
                   "infinite light.\n") +
        "\nExamples:\n  microbrdf export " + (mitsuba ? "mitsuba" : "pbrt") +
        " --model ellipsoid --alpha-x 0.1 --alpha-y 0.3 --theta-x 5deg --metal Al -o scene/\n"
        "  microbrdf export " +
        (mitsuba ? "mitsuba" : "pbrt") + " --bsdf alum.bsdf -o scene/");
    add_source_flags(c, *s);
    c->add_option("--bsdf", s->bsdf, "An existing .bsdf file (from `export bsdf`), copied");
    c->add_option("-o,--output", s->output, "Output directory")->required();
    if (mitsuba) c->add_option("--envmap", s->envmap, "Environment map (EXR/HDR lat-long)");
    add_grid_flags(c, s->grid);
    c->add_flag("--json", s->json, "Print a JSON summary on stdout");
    c->callback([s, mitsuba] {
      run_guarded(mitsuba ? "export mitsuba" : "export pbrt", [&] { run_scene(*s, mitsuba); });
    });
  }
}

}  // namespace microbrdf::cli

// `microbrdf predict SCAN... -o DIR`: the whole pipeline (statistics, NDFs, fits, BRDF slices,
// renders, texture synthesis) into DIR/report.html and DIR/summary.json. The work is
// microbrdf::predict (predict.hpp); this file only maps flags to options.
#include <cstdio>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "cli_threads.hpp"
#include "commands.hpp"
#include "kirchhoff_flags.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/predict.hpp"
#include "microbrdf/units.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

// The library's defaults, read once (a PredictOptions temporary per default would copy its
// std::function members for nothing).
const PredictOptions& predict_defaults() {
  static const PredictOptions d;
  return d;
}

struct PredictArgs {
  std::vector<std::string> inputs, strips;
  ReadFlags read;
  SpecFlags material;
  std::string output, filter_sigma = "1um", wavelength = "555nm";
  std::string theta_i = "20,45,70", envmap, texel = "53um";
  std::string measured, instrument_fwhm = "0", instrument, render_ndf = "filtered", theory = "auto";
  std::size_t sweep_resolution = predict_defaults().filter_sigma_sweep_resolution;
  std::size_t resolution = 1025, texture_size = 128;
  double envmap_scale = 1;
  int render_width = predict_defaults().render_width, spp = predict_defaults().render_spp;
  int threads = 0;
  std::uint64_t seed = 1;
  bool kirchhoff = false, no_render = false, json = false, quiet = false;
  std::string renders = "all";
  KirchhoffFlags dk;
};

void run(const PredictArgs& a) {
  // Cheap checks first: predict can run for minutes before it reaches the renders.
  scan_inputs(a.inputs);
  Preflight pre;
  for (const auto& path : a.strips) pre.input("--strips", path);
  if (!a.measured.empty()) pre.input("--measured", a.measured);
  pre.output_dir("-o", a.output);
  check_spec_files(pre, a.material);
  if (!a.envmap.empty()) pre.envmap("--envmap", a.envmap);
  pre.done();
  const MaterialSpec material = material_spec(a.material, MaterialSpec::named_metal("Fe"));
  if (!has_material(a.material.keys()) &&
      mpi_is_root())  // even with --quiet: it changes every number
    std::fprintf(stderr,
                 "microbrdf predict: note: no material given: iron (Fe) assumed for the Fresnel "
                 "term of every BRDF, render and export; give --metal (e.g. --metal Al) or "
                 "--n/--k\n");
  PredictOptions o;
  o.inputs = a.inputs;
  o.read = read_options(a.read);
  o.leveling = LevelingSpec::parse(a.read.level);
  o.material = material;
  o.filter_sigma_auto = a.filter_sigma == "auto";
  if (!o.filter_sigma_auto) o.filter_sigma_m = parse_length(a.filter_sigma);
  o.filter_sigma_sweep_resolution = a.sweep_resolution;
  o.render_ndf = a.render_ndf;
  o.theory = a.theory;
  o.wavelength_m = parse_length(a.wavelength);
  o.ndf_resolution = a.resolution;
  o.kirchhoff = a.kirchhoff;
  o.kirchhoff_options = kirchhoff_options(a.dk, a.wavelength);  // bad values fail before the run
  o.slice_theta_i_rad.clear();
  std::stringstream ss(a.theta_i);
  for (std::string item; std::getline(ss, item, ',');)
    o.slice_theta_i_rad.push_back(parse_angle(item));
  o.render = !a.no_render && a.renders != "none";
  if (a.renders != "all" && a.renders != "measured" && a.renders != "none")
    throw InputError("--renders '" + a.renders + "': give all, measured or none");
  o.render_models = a.renders == "all";
  o.envmap_path = a.envmap;
  o.envmap_scale = a.envmap_scale;
  o.render_width = a.render_width;
  o.render_spp = a.spp;
  if (!a.strips.empty()) {
    if (a.strips.size() != 2) throw InputError("--strips takes two scans: ALONG ACROSS");
    o.strips_along = {a.strips[0]};
    o.strips_across = {a.strips[1]};
  }
  o.texel_m = parse_length(a.texel);
  o.texture_size = a.texture_size;
  o.measured_path = a.measured;
  o.instrument_fwhm_rad = parse_angle(a.instrument_fwhm);
  o.instrument_path = a.instrument;
  o.seed = a.seed;
  o.threads = bounded_threads("predict", a.threads);
  if (!a.quiet)
    o.log = [](const std::string& line) {
      std::fprintf(stderr, "microbrdf predict: %s\n", line.c_str());
    };
  const PredictResult r = predict(o, a.output);
  if (!mpi_is_root()) return;  // under mpirun rank 0 writes the report (docs/scale.md)
  if (a.json) {
    print_json({{"dir", r.dir},
                {"report", r.report_path},
                {"summary", r.summary_path},
                {"scans", r.summary["inputs"].size()},
                {"fits", r.summary["fits"]},
                {"warnings", r.summary["warnings"]},
                {"timing", r.summary["timing"]},
                {"mpi", r.summary["mpi"]}});
  } else {
    std::printf("%s\n%s\n", r.report_path.c_str(), r.summary_path.c_str());
  }
}

}  // namespace

void register_predict(CLI::App& app) {
  auto a = std::make_shared<PredictArgs>();
  auto* c = app.add_subcommand(
      "predict", "Everything from scans: statistics, NDFs, fits, BRDF slices, renders, report");
  c->footer(
      "Runs every stage that applies and writes DIR/report.html (self-contained: open it in a\n"
      "browser) and DIR/summary.json (every number of the report, SI units; docs/report.md):\n"
      "  1. inputs: read, level (--level, plane by default), statistics (Sq, Sa, skewness,\n"
      "     kurtosis, rms slopes, correlation lengths), height previews;\n"
      "  2. NDFs: naive and filtered (--filter-sigma, default 1um; Dong 2015 sec. 5.1), and the\n"
      "     Kirchhoff D_K with --kirchhoff (at --wavelength, tiles of --patch; slower);\n"
      "     --filter-sigma auto first sweeps sigma for the filtered NDF nearest D_K (Hellinger\n"
      "     distance, --sweep-resolution tables); the report compares naive, filtered and D_K\n"
      "     and says which one the renders use (--render-ndf, default filtered);\n"
      "     the scattering regime (Rayleigh parameter, rms slope, correlation length against\n"
      "     --wavelength) picks the theory of the predicted BRDF (--theory auto): Rayleigh-Rice\n"
      "     from the scans' PSD on smooth metals, D_K over lambda_q (computed for it) in\n"
      "     between, the filtered NDF on rough ones; summary.json \"regime\" says why;\n"
      "  3. fits: ellipsoid, Beckmann and GGX fits of the filtered NDF;\n"
      "  4. BRDF slices in and out of the plane of incidence at --theta-i for the predicted\n"
      "     BRDF, the fits (and D_K), with the material's Fresnel term (--metal, default Fe;\n"
      "     --n/--k; --nk-csv; --r0; --color; --fresnel exact|schlick);\n"
      "  5. renders: the cylinder pair of Dong Fig. 10 and a sphere (--envmap FILE, else built-in\n"
      "     area lights) and a plate under a small light, each also with every fit (and D_K):\n"
      "     SSIM, RMS error and render noise per scene (--render-width, --spp; --no-render\n"
      "     skips); the fits as Mitsuba 3 / pbrt-v4 materials in DIR/export/;\n"
      "  6. with --strips ALONG ACROSS: per-texel fits (--texel) and a synthesised parameter\n"
      "     texture (--texture-size texels, --seed), and a render of it;\n"
      "  7. with --measured FILE: the predicted NDFs against the measurement's effective NDF\n"
      "     (Dong eq. 9; --instrument-fwhm), images, cuts and errors on the measured nodes.\n"
      "Many scans are processed one at a time (under mpirun, over all ranks: docs/scale.md).\n"
      "Same inputs and --seed give the same summary.json (apart from its \"timing\" and \"mpi\"\n"
      "objects). On an error nothing is left in DIR; an earlier\n"
      "predict output in DIR is replaced only on success.\n\n"
      "Examples:\n"
      "  microbrdf predict scan.x3p -o report/\n"
      "  microbrdf predict 'scans/*.dat' --metal Al --filter-sigma 1um --kirchhoff -o out/\n"
      "  microbrdf predict brushed.x3p --level none --envmap studio.exr --spp 64 -o out/\n"
      "  microbrdf predict patch.x3p --strips along.x3p across.x3p --texel 53um -o out/");
  c->add_option("files", a->inputs, "Height maps (files, directories, globs, @manifest)")
      ->required();
  add_read_flags(c, a->read, "plane");
  c->add_option("-o,--output", a->output, "Output folder (created; an earlier report is replaced)")
      ->required();
  add_material_flags(c, a->material, "default: Fe");
  add_filter_sigma_flags(c, a->filter_sigma, a->sweep_resolution, "Filtered NDF: ");
  c->add_option("--theory", a->theory,
                "Scattering theory of the predicted BRDF (slices, renders): auto (the one valid "
                "for the scans at normal incidence and --wavelength: rayleigh-rice for smooth "
                "metals, kirchhoff in between, geometric for rough ones; docs/regime.md) | "
                "geometric | kirchhoff | rayleigh-rice. Forcing one outside its validity warns")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "geometric", "kirchhoff", "rayleigh-rice"}));
  c->add_option("--render-ndf", a->render_ndf,
                "NDF of the geometric BRDF: naive | filtered | kirchhoff (= --theory kirchhoff)")
      ->capture_default_str()
      ->check(CLI::IsMember({"naive", "filtered", "kirchhoff"}));
  c->add_option("--resolution", a->resolution, "NDF table size N")
      ->capture_default_str()
      ->check(count_in(65, 4097));
  c->add_flag("--kirchhoff", a->kirchhoff, "Also compute the Kirchhoff D_K (wave optics)");
  c->add_option("--wavelength", a->wavelength, "lambda_q of D_K and the wavelength of the slices")
      ->capture_default_str()
      ->check(wavelength());
  add_kirchhoff_flags(c, a->dk, "D_K (--kirchhoff, --filter-sigma auto): ");
  c->add_option("--theta-i", a->theta_i, "Angles of incidence of the BRDF slices, comma-separated")
      ->capture_default_str()
      ->check(angle_in(0, 89.9 * M_PI / 180, true));
  c->add_option("--envmap", a->envmap, "Equirectangular EXR/HDR environment map for the renders");
  c->add_option("--envmap-scale", a->envmap_scale, "Multiplies the map")
      ->capture_default_str()
      ->check(positive_number(1e6));
  c->add_option("--render-width", a->render_width, "Width of the renders, pixels")
      ->capture_default_str()
      ->check(count_in(16, 4096));
  c->add_option("--spp", a->spp, "Samples per pixel of the renders")
      ->capture_default_str()
      ->check(count_in(1, 65536));
  c->add_flag("--no-render", a->no_render, "Skip the renders (= --renders none)");
  c->add_option("--renders", a->renders,
                "all (the measured NDF and every model along shared paths, the strip, studio "
                "renders, swatch), measured (the measured NDF's three scenes only: quick) or none")
      ->capture_default_str();
  c->add_option("--strips", a->strips, "Exemplar strips ALONG ACROSS the brushing (texture)")
      ->expected(2);
  c->add_option("--texel", a->texel, "Texel size of the per-texel fits")
      ->capture_default_str()
      ->check(distance());
  c->add_option("--texture-size", a->texture_size, "Synthesised texture size, texels per side")
      ->capture_default_str()
      ->check(count_in(8, 8192));
  c->add_option("--measured", a->measured,
                "Compare with a measurement: goniometer .csv, MERL .binary, RGL .bsdf or an "
                "effective NDF table (docs/measured.md)");
  c->add_option("--instrument-fwhm", a->instrument_fwhm,
                "With --measured: Gaussian instrument signature (FWHM angle) applied to every "
                "predicted NDF (filtered, D_K) before the comparison")
      ->capture_default_str()
      ->check(angle_in(0, M_PI / 2));
  c->add_option("--instrument", a->instrument,
                "With --measured: a measured instrument signature (an NDF table) instead");
  c->add_option("--seed", a->seed, "Seed of the renders and the texture synthesis")
      ->capture_default_str();
  c->add_option("--threads", a->threads,
                "Threads (0 = all cores); the same count gives bit-identical numbers")
      ->capture_default_str();
  c->add_flag("--quiet", a->quiet, "No progress on stderr");
  c->add_flag("--json", a->json, "Print a JSON object (paths, fits, timing) on stdout");
  c->callback([a] { run_guarded("predict", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

// `microbrdf ndf FILE... --method naive|filtered -o OUT`: the geometric NDF of one scan or of a
// scan set (each scan estimated on its own, averaged by projected area; Dong 2015 section 5.1).
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct NdfArgs {
  std::vector<std::string> inputs;
  ReadFlags read;
  std::string method = "filtered";
  std::string filter_sigma = "1um";
  std::size_t resolution = 1025;
  double min_support = 0.5;
  std::string output, preview, instrument_fwhm;
  bool zoom = false;
  bool json = false;
};

nlohmann::json ndf_json(const TabulatedNdf& ndf, const std::string& output) {
  auto mn = ndf.mean_normal();
  auto pk = ndf.peak();
  const auto& m = ndf.meta;
  double sx = ndf.rms_slope(0), sy = ndf.rms_slope(M_PI / 2);
  return {{"method", m.method},
          {"resolution", ndf.resolution()},
          {"integral", ndf.integral()},
          {"mean_normal", {mn.x(), mn.y(), mn.z()}},
          {"peak", {pk.x(), pk.y(), pk.z()}},
          {"slope_rms_x", sx},
          {"slope_rms_y", sy},
          {"beckmann_alpha_x", std::sqrt(2.0) * sx},
          {"beckmann_alpha_y", std::sqrt(2.0) * sy},
          {"samples_used", m.samples_used},
          {"samples_skipped", m.samples_skipped},
          {"projected_area_m2", m.projected_area_m2},
          {"filter_sigma_m", m.filter_sigma_m},
          {"wavelength_m", m.wavelength_m},
          {"leveling", m.leveling},
          {"notes", m.notes},
          {"inputs", m.sources},
          {"output", output}};
}

void run(const NdfArgs& a) {
  NdfEstimateOptions o;
  if (a.method == "naive")
    o.method = NdfMethod::Naive;
  else if (a.method == "filtered")
    o.method = NdfMethod::Filtered;
  else
    throw InputError("unknown --method '" + a.method +
                     "' (naive | filtered; kirchhoff comes with the Kirchhoff issue)");
  o.filter_sigma = parse_length(a.filter_sigma);
  o.resolution = a.resolution;
  o.min_support = a.min_support;
  if (a.resolution < 17 || a.resolution > 8193)
    throw InputError("--resolution must be in 17..8193");
  auto paths = expand_scan_inputs(a.inputs);
  NdfAccumulator acc(o);
  bool warned = false;
  for (std::size_t i = 0; i < paths.size(); ++i) {
    progress("ndf", i, paths.size(), paths[i]);
    Surface s = load_surface(paths[i], a.read, nullptr);
    if (o.method == NdfMethod::Filtered && !warned && o.filter_sigma < std::max(s.dx, s.dy)) {
      std::fprintf(stderr,
                   "microbrdf ndf: warning: filter sigma %s is below the sample spacing %s of %s: "
                   "the fit sees "
                   "few neighbours and approaches the naive estimate\n",
                   format_length(o.filter_sigma).c_str(),
                   format_length(std::max(s.dx, s.dy)).c_str(), paths[i].c_str());
      warned = true;
    }
    acc.add(s);
  }
  TabulatedNdf ndf = acc.result();
  if (!a.instrument_fwhm.empty()) {
    const double fwhm = parse_angle(a.instrument_fwhm);
    ndf = convolve_angular_gaussian(ndf, fwhm);
    char note[96];
    std::snprintf(note, sizeof note, "convolved with an angular Gaussian of FWHM %.4g deg",
                  fwhm * 180 / M_PI);
    ndf.meta.notes = note;
  }
  write_ndf(ndf, a.output);
  if (!a.preview.empty()) {
    NdfPreviewOptions po;
    po.zoom = a.zoom;
    write_ndf_preview(ndf, a.preview, po);
  }
  if (a.json) {
    print_json(ndf_json(ndf, a.output));
  } else {
    std::fprintf(stderr,
                 "microbrdf ndf: %s NDF of %zu scan(s) -> %s (%zu x %zu); %zu elements used, %zu "
                 "skipped; rms slope x "
                 "%.4g, y %.4g (Beckmann alpha %.4g, %.4g)\n",
                 ndf.meta.method.c_str(), paths.size(), a.output.c_str(), ndf.resolution(),
                 ndf.resolution(), ndf.meta.samples_used, ndf.meta.samples_skipped,
                 ndf.rms_slope(0), ndf.rms_slope(M_PI / 2), std::sqrt(2.0) * ndf.rms_slope(0),
                 std::sqrt(2.0) * ndf.rms_slope(M_PI / 2));
  }
}

}  // namespace

void register_ndf(CLI::App& app) {
  auto a = std::make_shared<NdfArgs>();
  auto* cmd = app.add_subcommand(
      "ndf", "Normal distribution function of height maps (tabulated on the disk)");
  cmd->footer(
      "Methods (Dong 2015 section 5.1):\n"
      "  naive     two triangles per grid cell (split along the (ix,iy)-(ix+1,iy+1) diagonal), "
      "each\n"
      "            adding its projected area at its normal; triangles touching an invalid sample "
      "are skipped.\n"
      "  filtered  at each valid sample, the normal of the plane fitted by least squares weighted "
      "with a\n"
      "            2-D Gaussian of std --filter-sigma (1 um, about two wavelengths of green "
      "light);\n"
      "            holes are handled exactly (weights x mask). Samples whose weighted support is "
      "below\n"
      "            --min-support of the full-grid value (borders, holes) are skipped and counted.\n"
      "Output: N x N table on the projected disk, m_x = -1 + 2 ix/(N-1), D per steradian, "
      "normalised so\n"
      "that the integral of D(m)(m.n) over the hemisphere is 1; .npy (+ .json sidecar) or .exr.\n"
      "Many scans are estimated one by one and averaged by projected area.\n\n"
      "Examples:\n"
      "  microbrdf ndf scan.x3p -o ndf.npy --preview ndf.png --zoom\n"
      "  microbrdf ndf 'scans/*.dat' --method filtered --filter-sigma 1um -o ndf.exr --json\n"
      "  microbrdf ndf scan.x3p --method naive --resolution 513 -o naive.npy");
  cmd->add_option("files", a->inputs, "Height maps (files, directories, globs, @manifest)")
      ->required();
  add_read_flags(cmd, a->read, "plane");
  cmd->add_option("--method", a->method, "naive | filtered")->capture_default_str();
  cmd->add_option("--filter-sigma", a->filter_sigma, "Gaussian std of the local plane fit")
      ->capture_default_str();
  cmd->add_option("--resolution", a->resolution, "Table size N (odd keeps a node at the centre)")
      ->capture_default_str();
  cmd->add_option("--min-support", a->min_support,
                  "Filtered: minimum weighted support, fraction of the full kernel")
      ->capture_default_str();
  cmd->add_option(
      "--instrument-fwhm", a->instrument_fwhm,
      "Convolve with an angular Gaussian of this FWHM (a gonioreflectometer's signature, e.g. "
      "1.5deg as in Dong sec. 7); conserves the integral");
  cmd->add_option("-o,--output", a->output, "Output table (.npy or .exr)")->required();
  cmd->add_option("--preview", a->preview, "Write a log-scale false-colour PNG of the NDF");
  cmd->add_flag("--zoom", a->zoom, "Add a zoom panel around the peak to the preview (narrow NDFs)");
  cmd->add_flag("--json", a->json, "Print a JSON summary on stdout");
  cmd->callback([a] { run_guarded("ndf", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

// `microbrdf ndf FILE... --method naive|filtered|kirchhoff -o OUT`: the geometric NDF of one scan
// or of a scan set (each scan estimated on its own, averaged by projected area; Dong 2015 section
// 5.1), or the Kirchhoff distribution D_K (Dong section 6 and App. A; docs/kirchhoff.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/ndf_convolve.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/ndf_scanset.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"
#include "ndf_args.hpp"

namespace microbrdf::cli {

nlohmann::json ndf_json(const TabulatedNdf& ndf, const NdfArgs& a) {
  auto mn = ndf.mean_normal();
  auto pk = ndf.peak();
  const auto& m = ndf.meta;
  const Eigen::Matrix2d cov = ndf.slope_covariance();  // one pass over the table
  const double sx = std::sqrt(std::max(0.0, cov(0, 0))), sy = std::sqrt(std::max(0.0, cov(1, 1)));
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
          {"instrument_fwhm_rad", parse_angle(a.instrument_fwhm)},
          {"instrument", a.instrument},
          {"output", a.output}};
}

// The instrument signature (every method), the table (-o) and, when asked, its preview.
void write_outputs(TabulatedNdf& ndf, const NdfArgs& a) {
  std::vector<TabulatedNdf> one{std::move(ndf)};
  write_outputs(one, 0, a);
  ndf = std::move(one[0]);
}

void write_outputs(std::vector<TabulatedNdf>& layers, std::size_t primary, const NdfArgs& a) {
  std::unique_ptr<TabulatedNdf> sig;
  if (!a.instrument.empty()) sig = std::make_unique<TabulatedNdf>(read_ndf(a.instrument));
  const double fwhm = parse_angle(a.instrument_fwhm);
  if (sig || fwhm != 0)  // without an instrument the tables are written as they are (no copy)
    for (auto& t : layers) t = apply_instrument(t, fwhm, sig.get());
  if (!write_ndf_stack(layers, primary, a.output))
    std::fprintf(stderr,
                 "microbrdf ndf: warning: %s: an .exr holds one table, so only D_K at lambda_q "
                 "%s was written (the stack over lambda_q needs .npy)\n",
                 a.output.c_str(), format_length(layers[primary].meta.wavelength_m).c_str());
  if (a.preview.empty()) return;
  NdfPreviewOptions po;
  po.zoom = a.zoom;
  write_ndf_preview(layers[primary], a.preview, po);
}

// Reading and levelling of the scan set (distributed over MPI ranks when run under mpirun).
ScanSetOptions scan_set_options(const NdfArgs& a, std::size_t scans) {
  ScanSetOptions set;
  set.read = read_options(a.read);
  set.leveling = LevelingSpec::parse(a.read.level);
  if (scans == 0) throw InputError("no scan given");
  (void)apply_instrument(TabulatedNdf(3), parse_angle(a.instrument_fwhm), nullptr);  // bad FWHM
  return set;
}

namespace {

void run_kirchhoff(const NdfArgs& a) {
  KirchhoffOptions o = kirchhoff_options(a.dk, a.wavelength);
  o.direct = a.direct;
  o.resolution = a.resolution;
  if (a.resolution < 17 || a.resolution > 8193)
    throw InputError("--resolution must be in 17..8193");
  auto paths = scan_inputs(a.inputs);
  // D_K takes ~25 s per scan at 1025^2: report the overall fraction on stderr in 10 % steps.
  Progress dk_progress("ndf", false, 0.1, "kirchhoff D_K");
  o.progress = [&](double all) { dk_progress.fraction(all); };
  ScanSetOptions set = scan_set_options(a, paths.size());
  set.on_scan = [&](std::size_t i, const std::string& path, const nlohmann::json& scan) {
    progress("ndf", i, paths.size(), path);
    const double dx = scan.at("dx_m").get<double>(), dy = scan.at("dy_m").get<double>();
    const double nyq = M_PI / std::max(dx, dy), qm = 4 * M_PI / o.wavelength_q;
    if (i == 0 && nyq < qm)
      std::fprintf(
          stderr,
          "microbrdf ndf: warning: sample spacing %s is above lambda_q/4 = %s: |q| exceeds "
          "the Nyquist frequency of the scan; nodes beyond it are %s\n",
          format_length(std::max(dx, dy)).c_str(), format_length(o.wavelength_q / 4).c_str(),
          o.nyquist_mask ? "set to 0 (--keep-aliases keeps them)" : "aliases (kept)");
    const double samples = scan.at("nx").get<double>() * scan.at("ny").get<double>();
    if (i == 0 && o.direct && samples * static_cast<double>(a.resolution * a.resolution) > 5e10)
      std::fprintf(stderr,
                   "microbrdf ndf: warning: --direct on %.0f samples x %zu^2 nodes will take very "
                   "long; the fast method agrees to ~1e-5\n",
                   samples, a.resolution);
  };
  WorkStats stats;
  auto acc = accumulate_kirchhoff_scans(paths, o, set, &stats);
  if (!acc) return;  // rank 0 writes the outputs
  std::vector<TabulatedNdf> layers = acc->stack_result();
  std::size_t primary = 0;
  while (layers[primary].meta.wavelength_m != o.wavelength_q) ++primary;
  write_outputs(layers, primary, a);
  const TabulatedNdf& ndf = layers[primary];
  // D_K integrates to about 1 before normalising (Parseval); a larger departure means the
  // discretisation (table, tiles, sampling) misses or duplicates scattered power.
  const double raw = acc->raw_integral();
  const bool raw_off = std::abs(raw - 1) > 0.02;
  if (raw_off)
    std::fprintf(stderr,
                 "microbrdf ndf: warning: the Kirchhoff D_K integrated to %.4g (%+.1f%%) before "
                 "it was normalised to 1; treat its shape as approximate (a finer --resolution, "
                 "--dk-supersample or a larger --patch brings it nearer 1; docs/kirchhoff.md)\n",
                 raw, 100 * (raw - 1));
  if (a.json) {
    auto j = ndf_json(ndf, a);
    j["mpi"] = stats.to_json("scans_per_rank");
    const auto& in = acc->last_info();
    nlohmann::json lqs = nlohmann::json::array();
    for (const auto& t : layers) lqs.push_back(t.meta.wavelength_m);
    j["kirchhoff"] = {{"wavelength_q_m", o.wavelength_q},
                      {"stack", a.dk.stack},
                      {"stack_wavelengths_q_m", lqs},
                      {"patch_m", {o.patch_x, o.patch_y}},
                      {"patches", acc->patches()},
                      {"window", to_string(o.window)},
                      {"accuracy", o.accuracy},
                      {"direct", o.direct},
                      {"terms", in.terms},
                      {"height_half_range_m", in.height_half_range},
                      {"raw_integral", acc->raw_integral()},
                      {"raw_integral_warning", raw_off},
                      {"integration", to_string(o.integration)},
                      {"supersample", acc->supersample()},
                      {"points_per_triangle", in.points_per_triangle},
                      {"nyquist_mask", o.nyquist_mask},
                      {"aliased_fraction", acc->aliased_fraction()},
                      {"notes", ndf.meta.notes}};
    print_json(j);
  } else {
    std::fprintf(stderr,
                 "microbrdf ndf: kirchhoff D_K (lambda_q %s%s) of %zu scan(s), %zu patch(es), "
                 "window %s -> %s (%zu x %zu); integral before normalising %.4g; rms slope x "
                 "%.4g, y %.4g\n",
                 format_length(o.wavelength_q).c_str(),
                 layers.size() > 1
                     ? (" and a stack of " + std::to_string(layers.size()) + " tables over " +
                        format_length(layers.front().meta.wavelength_m) + " .. " +
                        format_length(layers.back().meta.wavelength_m))
                           .c_str()
                     : "",
                 paths.size(), acc->patches(), to_string(o.window).c_str(), a.output.c_str(),
                 ndf.resolution(), ndf.resolution(), acc->raw_integral(), ndf.rms_slope(0),
                 ndf.rms_slope(M_PI / 2));
  }
}

void run(const NdfArgs& a) {
  // Cheap checks first: a D_K can take minutes before it reaches the writer.
  Preflight pre;
  pre.output("-o", a.output, {".npy", ".exr"});
  if (!a.preview.empty()) pre.output("--preview", a.preview, {".png"});
  if (!a.instrument.empty()) pre.input("--instrument", a.instrument);
  pre.done();
  if (a.method == "kirchhoff" && a.filter_sigma == "auto")
    throw InputError("--filter-sigma auto applies to --method filtered");
  if (a.method == "kirchhoff") return run_kirchhoff(a);
  run_geometric(a);
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
      "            --filter-sigma auto sweeps sigma (log-spaced from the sample spacing to 1/8 of "
      "the\n"
      "            field, at most 128 spacings, then refined around the minimum) and takes the one "
      "whose\n"
      "            table is nearest to D_K at --wavelength (Kirchhoff flags apply) by Hellinger "
      "distance,\n"
      "            on --sweep-resolution tables; the curve goes to <output "
      "stem>_filter_sigma.csv.\n"
      "  kirchhoff the Kirchhoff distribution D_K (Dong eq. 6) at lambda_q = --wavelength: the\n"
      "            surface integral of (q.m) exp(-i q.s), q = 4 pi h / lambda_q, over the\n"
      "            piecewise-linear surface through the samples: by the midpoint rule per sample\n"
      "            with central-difference slopes (the default: 20-60x faster, about 1% relative\n"
      "            L1 off on brushed steel at 110 nm, more on steeper or coarser scans), or\n"
      "            exactly, triangle by triangle (--dk-integration exact: the reference). Invalid "
      "samples are left out. Each scan is cut into tiles of about\n"
      "            --patch (the coherence area, Dong App. A) and the intensities averaged. When a\n"
      "            node spacing is coarser than lambda_q / (2 x tile side), node values are\n"
      "            averages over the node's cell (--dk-supersample auto), so that the table\n"
      "            integrates to about 1 before normalising; the JSON reports that integral and\n"
      "            a departure above 2% warns. Fast method: Chebyshev series in q_z x NUFFTs at\n"
      "            the node frequencies (--accuracy bounds the dropped tail; 1e-3 gives ~1e-5\n"
      "            relative L1 vs the direct sums); --direct sums every node directly (slow:\n"
      "            small patches only). See docs/kirchhoff.md.\n"
      "Output: N x N table on the projected disk, m_x = -1 + 2 ix/(N-1), D per steradian, "
      "normalised so\n"
      "that the integral of D(m)(m.n) over the hemisphere is 1; .npy (+ .json sidecar) or .exr.\n"
      "Many scans are estimated one by one and averaged by projected area.\n\n"
      "Examples:\n"
      "  microbrdf ndf scan.x3p -o ndf.npy --preview ndf.png --zoom\n"
      "  microbrdf ndf 'scans/*.dat' --method filtered --filter-sigma 1um -o ndf.exr --json\n"
      "  microbrdf ndf scan.x3p --method naive --resolution 513 -o naive.npy\n"
      "  microbrdf ndf scan.x3p --filter-sigma auto --wavelength 555nm -o ndf.npy --json\n"
      "  microbrdf ndf 'scans/*.x3p' --method kirchhoff --wavelength 555nm --window hann -o "
      "dk.npy");
  cmd->add_option("files", a->inputs, "Height maps (files, directories, globs, @manifest)")
      ->required();
  add_read_flags(cmd, a->read, "plane");
  cmd->add_option("--method", a->method, "naive | filtered | kirchhoff")->capture_default_str();
  add_filter_sigma_flags(cmd, a->filter_sigma, a->sweep_resolution, "Filtered: ");
  cmd->add_option("--resolution", a->resolution, "Table size N (odd keeps a node at the centre)")
      ->capture_default_str()
      ->check(count_in(17, 8193));
  cmd->add_option("--min-support", a->min_support,
                  "Filtered: minimum weighted support, fraction of the full kernel")
      ->check(number_in(0, 1))  // a share of the kernel's weight
      ->capture_default_str();
  cmd->add_option("--instrument-fwhm", a->instrument_fwhm,
                  "Any method: convolve with an angular Gaussian of this FWHM (a "
                  "gonioreflectometer's signature, e.g. 1.5deg as in Dong sec. 7); conserves "
                  "the integral")
      ->check(angle_in(0, M_PI / 2));
  cmd->add_option("--instrument", a->instrument,
                  "Any method: convolve with a measured signature (an NDF table, e.g. a "
                  "mirror's effective NDF) instead");
  cmd->add_option("--wavelength", a->wavelength, "Kirchhoff: lambda_q (Dong eq. 5)")
      ->capture_default_str()
      ->check(wavelength());
  add_kirchhoff_flags(cmd, a->dk, "Kirchhoff: ");
  cmd->add_flag("--direct", a->direct, "Kirchhoff: direct sums on every node (slow reference)");
  cmd->add_option("-o,--output", a->output, "Output table (.npy or .exr)")->required();
  cmd->add_option("--preview", a->preview, "Write a log-scale false-colour PNG of the NDF");
  cmd->add_flag("--zoom", a->zoom, "Add a zoom panel around the peak to the preview (narrow NDFs)");
  cmd->add_flag("--json", a->json, "Print a JSON summary on stdout");
  cmd->callback([a] { run_guarded("ndf", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

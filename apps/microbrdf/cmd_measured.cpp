// `microbrdf measured ndf|compare`: effective NDFs from measured BRDFs (Dong 2015 section 7,
// eq. 9) and predicted-versus-measured comparisons (docs/measured.md).
#include <fmt/format.h>

#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_compare.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/units.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

struct NdfArgs {
  std::string input, output, theta_d = "14.14deg", shadowing = "none", kernel, wavelength = "550nm";
  std::size_t resolution = 1025;
  bool json = false;
  SpecFlags material;
};

void run_ndf(const NdfArgs& a) {
  EffectiveNdfOptions o;
  o.theta_d = parse_angle(a.theta_d);
  if (a.resolution < 5 || a.resolution > 8193) throw InputError("--resolution must lie in 5..8193");
  o.resolution = a.resolution;
  o.wavelength_m = parse_length(a.wavelength);
  if (a.shadowing != "none" && a.shadowing != "smith")
    throw InputError("--shadowing must be none or smith");
  o.smith = a.shadowing == "smith";
  if (!a.kernel.empty()) {
    o.kernel_sigma = parse_angle(a.kernel);  // disk units ~ rad near the pole
    if (!(o.kernel_sigma > 0 && o.kernel_sigma <= kMaxKernelSigma))
      throw InputError(fmt::format("--kernel must lie in (0, {:.0f}] deg (got {})",
                                   kMaxKernelSigma * kDeg, a.kernel));
  }
  // Fresnel: the material's when given (the table then has the NDF's own scale, G aside), else
  // F = 1 (the NDF's shape: at fixed theta_d, F(wi.h) is one constant for full BRDFs).
  const bool has_f = has_material(a.material.keys());
  if (!has_f && a.material.keys().contains("fresnel"))
    throw InputError("--fresnel needs a material (--metal, --n/--k, --nk-csv, --r0, --color)");
  const std::shared_ptr<const Fresnel> fresnel =
      has_f ? make_fresnel(material_spec(a.material, std::nullopt))
            : std::make_shared<PerfectMirrorFresnel>();
  TabulatedNdf t = measured_ndf_file(a.input, *fresnel, o);
  if (const std::string w = wavelength_warning(t, o.wavelength_m, a.input); !w.empty())
    std::fprintf(stderr, "microbrdf measured ndf: %s\n", w.c_str());
  if (has_f)
    t.meta.notes += "; F = " + material_spec(a.material, std::nullopt).describe();
  else
    t.meta.notes += "; F = 1 (shape only: the table's scale is F(wi.h) times the true NDF's)";
  write_ndf(t, a.output);
  std::fprintf(stderr,
               "microbrdf measured ndf: G %s, F %s; unmeasured nodes are NaN (%zu of the disk "
               "nodes hold data)\n",
               o.smith ? "= Smith G2 of the estimate" : "= 1 (Dong's assumption)",
               has_f ? "of the material" : "= 1 (no material given: the NDF's shape)",
               measured_nodes(t));
  if (a.json) {
    print_json({{"input", a.input},
                {"output", a.output},
                {"method", t.meta.method},
                {"resolution", t.resolution()},
                {"theta_d_rad", o.theta_d},
                {"wavelength_m", t.meta.wavelength_m},
                {"shadowing", o.smith ? "smith" : "none"},
                {"measured_nodes", measured_nodes(t)},
                {"samples_used", t.meta.samples_used},
                {"samples_skipped", t.meta.samples_skipped},
                {"notes", t.meta.notes}});
  } else {
    std::printf("%s -> %s (%zu x %zu, theta_d %.4g deg)\n  %s\n", a.input.c_str(), a.output.c_str(),
                t.resolution(), t.resolution(), o.theta_d * kDeg, t.meta.notes.c_str());
  }
}

struct CompareArgs {
  std::string measured, fwhm = "0", instrument, report;
  std::vector<std::string> predicted;
  bool json = false;
};

void run_compare(const CompareArgs& a) {
  const double fwhm = parse_angle(a.fwhm);
  if (fwhm < 0) throw InputError("--instrument-fwhm must not be negative");
  if (fwhm > 0 && !a.instrument.empty())
    throw InputError("give --instrument-fwhm or --instrument, not both");
  const TabulatedNdf measured = read_ndf(a.measured);
  std::unique_ptr<TabulatedNdf> sig;
  if (!a.instrument.empty()) sig = std::make_unique<TabulatedNdf>(read_ndf(a.instrument));
  nlohmann::json all = nlohmann::json::array();
  for (std::size_t k = 0; k < a.predicted.size(); ++k) {
    const TabulatedNdf p = read_ndf(a.predicted[k]);
    // A measured table without a measured node is that file's problem.
    const NdfComparison c =
        about_file(a.measured, [&] { return compare_ndfs(measured, p, fwhm, sig.get()); });
    if (!a.report.empty()) {
      const std::string dir =
          a.predicted.size() == 1
              ? a.report
              : (std::filesystem::path(a.report) / std::filesystem::path(a.predicted[k]).stem())
                    .string();
      write_compare_report(measured, instrument_view(p, measured.resolution(), fwhm, sig.get()), c,
                           dir);
    }
    nlohmann::json j = comparison_json(c);
    j["predicted"] = a.predicted[k];
    all.push_back(j);
    if (!a.json)
      std::printf(
          "%s vs %s: %zu measured nodes, scale %.4g, relative L2 %.4g, Hellinger %.4g, "
          "width ratios (predicted/measured) x %.4g y %.4g\n",
          a.predicted[k].c_str(), a.measured.c_str(), c.nodes, c.scale, c.relative_l2, c.hellinger,
          c.alpha_x_ratio, c.alpha_y_ratio);
  }
  if (a.json)
    print_json({{"measured", a.measured},
                {"instrument_fwhm_rad", fwhm},
                {"instrument", a.instrument},
                {"comparisons", all}});
}

}  // namespace

void register_measured(CLI::App& app) {
  auto* m = app.add_subcommand("measured", "Measured BRDFs: effective NDFs and comparisons");
  m->require_subcommand(1);
  auto a = std::make_shared<NdfArgs>();
  auto* n = m->add_subcommand("ndf", "Effective NDF of a measured BRDF (Dong 2015 eq. 9)");
  n->footer(
      "D(h) = 4 |wi.n| |wo.n| f(wi, wo) / (F(wi.h) G). G = 1 by default (Dong's assumption; "
      "--shadowing smith\n"
      "divides by the Smith G2 of the estimate). F: the material flags' Fresnel term; without "
      "them F = 1,\n"
      "the NDF's shape (for full BRDFs read at fixed theta_d, F(wi.h) is one constant). Full BRDFs "
      "(.binary MERL, .bsdf RGL) are read "
      "at the\n"
      "fixed angle --theta-d between wi and wo; goniometer points (.csv) are splatted with a "
      "Gaussian kernel\n"
      "(--kernel, default: the median nearest-neighbour distance of the half vectors). Nodes "
      "without data\n"
      "are NaN (unmeasured), never 0; `fit` ignores them. Formats: docs/measured.md.\n\n"
      "Examples:\n"
      "  microbrdf measured ndf goni.csv --n 1.6 --k 3.2 -o eff.npy\n"
      "  microbrdf fit eff.npy --model ggx --json\n"
      "  microbrdf measured ndf alum.binary --theta-d 14.14deg --resolution 513 -o eff.npy");
  n->add_option("file", a->input, "Measured BRDF: .csv (goniometer), .binary (MERL), .bsdf (RGL)")
      ->required();
  n->add_option("-o,--output", a->output, "Output NDF table (.npy + sidecar, or .exr)")->required();
  n->add_option("--theta-d", a->theta_d, "Angle between wi and wo (full BRDFs)")
      ->capture_default_str()
      ->check(angle_in(0, M_PI));
  n->add_option("--resolution", a->resolution, "Table nodes per side")
      ->capture_default_str()
      ->check(count_in(5, 8193));
  n->add_option("--shadowing", a->shadowing, "none (G = 1) | smith")->capture_default_str();
  n->add_option("--kernel", a->kernel, "Point sets: kernel std (angle near the pole)")
      ->check(angle_in(0, kMaxKernelSigma));
  n->add_option("--wavelength", a->wavelength, "Wavelength read (nearest in the file)")
      ->capture_default_str()
      ->check(wavelength());
  add_material_flags(n, a->material, "default: none, F = 1: the NDF's shape");
  n->add_flag("--json", a->json, "Print a JSON summary on stdout");
  n->callback([a] { run_guarded("measured ndf", [&] { run_ndf(*a); }); });

  auto c = std::make_shared<CompareArgs>();
  auto* cc = m->add_subcommand("compare", "Predicted NDFs against a measured effective NDF");
  cc->footer(
      "Each prediction is convolved with the instrument signature (--instrument-fwhm Gaussian, "
      "or\n"
      "--instrument MIRROR.npy: a mirror's effective NDF, as Dong did), sampled at the measured "
      "nodes\n"
      "and compared on the measured (non-NaN) nodes only: least-squares scale, relative L2, "
      "Hellinger,\n"
      "and GGX width ratios. --report DIR writes compare.json, measured.png / predicted.png (one "
      "colour\n"
      "scale) and slices.csv / slices.png (along and across the measured alpha_x axis).\n\n"
      "Example:\n"
      "  microbrdf measured compare eff.npy predicted.npy --instrument-fwhm 1.5deg --report cmp/");
  cc->add_option("measured", c->measured, "Measured effective NDF (from `measured ndf`)")
      ->required();
  cc->add_option("predicted", c->predicted, "Predicted NDF tables")->required();
  cc->add_option("--instrument-fwhm", c->fwhm, "Gaussian instrument signature (FWHM angle)")
      ->check(angle_in(0, M_PI / 2));
  cc->add_option("--instrument", c->instrument, "Measured instrument signature (an NDF table)");
  cc->add_option("--report", c->report, "Write images, slices and compare.json here");
  cc->add_flag("--json", c->json, "Print a JSON summary on stdout");
  cc->callback([c] { run_guarded("measured compare", [&] { run_compare(*c); }); });
}

}  // namespace microbrdf::cli

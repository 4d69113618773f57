// `microbrdf fit NDF --model ellipsoid|beckmann|ggx|...|mixture:A+B`: parametric fit of a
// tabulated NDF (Dong 2015 section 8, Fig. 12) with any registered model (ndf_model.hpp).
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/ndf_io.hpp"

namespace microbrdf::cli {
namespace {

struct FitArgs {
  std::string input;
  std::string model = "ellipsoid";
  std::string objective = "sqrt";
  std::string sampling = "auto";
  int subsamples = 0;
  std::string report;
  std::string table;
  bool json = false;
};

void run(const FitArgs& a) {
  FitOptions o;
  o.model = parse_fit_model(a.model);
  o.objective = parse_fit_objective(a.objective);
  o.sampling = parse_fit_sampling(a.sampling);
  if (a.subsamples < 0 || a.subsamples > 8) throw InputError("--subsamples must lie in 0..8");
  o.tent_subsamples = a.subsamples;
  const TabulatedNdf ndf = read_ndf(a.input);
  const FitResult r = about_file(a.input, [&] { return fit_ndf(ndf, o); });
  // Tables written before they recorded their sampling: say what was assumed (stderr; --json
  // carries table_sampling_recorded).
  if (o.sampling == FitSampling::Auto && !r.table_sampling_recorded)
    std::fprintf(stderr,
                 "microbrdf fit: warning: %s does not record how it was sampled; assumed %s "
                 "(from its method '%s'); give --sampling node|tent to override\n",
                 a.input.c_str(),
                 r.table_sampling == "point" ? "point samples of the NDF"
                                             : "cell-integrated estimates (a histogram)",
                 ndf.meta.method.c_str());
  if (!a.report.empty()) write_fit_report(ndf, r, a.report);
  // The fitted model as a table (any model, two-lobe mixtures included): what `export bsdf
  // --ndf` and the other exporters take.
  if (!a.table.empty()) write_ndf(fit_table(r, ndf.resolution()), a.table);
  if (a.json) {
    nlohmann::json j = fit_result_json(r);
    j["input"] = a.input;
    if (!a.report.empty()) j["report"] = a.report;
    if (!a.table.empty()) j["table"] = a.table;
    print_json(j);
    return;
  }
  constexpr double deg = 180.0 / 3.14159265358979323846;
  std::printf("%s fit of %s (%s sampling, %s objective)\n", r.model.c_str(), a.input.c_str(),
              fit_sampling_name(r.sampling).c_str(), fit_objective_name(r.objective).c_str());
  if (!r.window.full())
    std::printf("  zoomed table: m_x %.6g..%.6g, m_y %.6g..%.6g\n", r.window.x0(), r.window.x1(),
                r.window.y0(), r.window.y1());
  // One line per parameter, angles in degrees (phi also as the ellipsoid convention's theta_z).
  const NdfModel& model = ndf_model(r.model);
  for (std::size_t i = 0; i < r.params.size(); ++i) {
    const NdfParam& q = model.params()[i];
    const double v = r.params.values[i];
    if (q.name == "phi")
      std::printf("  phi (alpha_x axis) %.6g deg  (theta_z %.6g deg)\n", v * deg, -v * deg + 0.0);
    else if (q.unit == "rad")
      std::printf("  %s %.6g deg\n", q.name.c_str(), v * deg);
    else
      std::printf("  %s %.6g\n", q.name.c_str(), v);
  }
  std::printf("  rms error %.4g 1/sr, relative L2 error %.4g, Hellinger %.4g\n", r.rms_error,
              r.relative_l2_error, r.hellinger);
  std::printf(
      "  %d iterations, %s (%s), %.3g s\n", r.iterations,
      r.converged
          ? "converged"
          : (r.at_bound.empty() ? "NOT converged" : "NOT converged: at " + r.at_bound).c_str(),
      r.termination.c_str(), r.seconds);
  if (!a.report.empty()) std::printf("  report in %s\n", a.report.c_str());
  if (!a.table.empty()) std::printf("  fitted table in %s\n", a.table.c_str());
}

}  // namespace

void register_fit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* c = app.add_subcommand("fit", "Fit a parametric NDF (" + ndf_model_names(", ") +
                                          ", or a two-lobe mixture) to a tabulated NDF");
  c->footer(
      "Fits the parameters (alpha_x, alpha_y, theta_x, theta_y, theta_z) of the ellipsoid NDF "
      "(Dong 2015\n"
      "eqs. 10-12), (alpha_x, alpha_y, phi) of anisotropic Beckmann/GGX, or the parameters of "
      "any\n"
      "other registered model (--model lists them), to a table written by `ndf` or `tabulate`. "
      "The\n"
      "ellipsoid turns its axes by -theta_z (Beckmann/GGX phi = -theta_z, also reported as "
      "theta_z),\n"
      "theta_x > 0 tilts the peak towards +y, theta_y > 0 towards -x; theta_z is reported in "
      "(-90, 90] deg.\n"
      "mixture:A+B fits w D_A + (1 - w) D_B of two registered models jointly (a narrow core and "
      "a wide\n"
      "tail; JSON params {weight, lobe1, lobe2}).\n"
      "Objective: least squares on sqrt(D) over the disk (Hellinger distance; variance-"
      "stabilised\n"
      "histogram counts). Sampling: the model is point-sampled at the nodes (tables that record\n"
      "\"sampling\": \"point\": `tabulate`, Kirchhoff, measured) or averaged over each node's "
      "bilinear tent\n"
      "cell (\"cell\": histograms of normals); auto follows the table (older files without the "
      "record:\n"
      "inferred from their method, with a warning). Zoomed tables are fitted on their window.\n"
      "Errors over the disk nodes: rms_error = sqrt(mean (T-M)^2) (1/sr), relative_l2_error = "
      "|T-M|/|T|.\n"
      "--report DIR writes fit.json, compare.png (measured | fit | residual), slices.png, "
      "measured.png, fit.png.\n\n"
      "Examples:\n"
      "  microbrdf fit ndf.npy --model ellipsoid\n"
      "  microbrdf fit ndf.npy --model beckmann --json\n"
      "  microbrdf fit ndf.exr --model ggx --report fit-ggx/\n"
      "  microbrdf fit ndf.npy --model mixture:ggx+beckmann --table two_lobes.npy --json\n"
      "  microbrdf export bsdf --ndf two_lobes.npy --metal Al -o two_lobes.bsdf");
  c->add_option("ndf", a->input, "Tabulated NDF (.npy with sidecar, or .exr)")->required();
  c->add_option("--model", a->model, ndf_model_names(" | ") + " | mixture:A+B")
      ->capture_default_str();
  c->add_option("--objective", a->objective, "sqrt | linear | log (on D, with a floor)")
      ->capture_default_str();
  c->add_option("--sampling", a->sampling, "auto | node | tent: how the model meets the table")
      ->capture_default_str();
  c->add_option("--subsamples", a->subsamples,
                "Tent quadrature points per node spacing (0 = from the lobe width)")
      ->capture_default_str();
  c->add_option("--report", a->report, "Write images and fit.json into this directory");
  c->add_option("--table", a->table,
                "Write the fitted model as a table (.npy or .exr, the input's resolution and "
                "sampling) for `export ... --ndf`");
  c->add_flag("--json", a->json, "Print a JSON summary on stdout");
  c->callback([a] { run_guarded("fit", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

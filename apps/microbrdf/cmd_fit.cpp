// `microbrdf fit NDF --model ellipsoid|beckmann|ggx`: parametric fit of a tabulated NDF
// (Dong 2015 section 8, Fig. 12).
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
  if (a.json) {
    nlohmann::json j = fit_result_json(r);
    j["input"] = a.input;
    if (!a.report.empty()) j["report"] = a.report;
    print_json(j);
    return;
  }
  const auto& p = r.params;
  constexpr double deg = 180.0 / 3.14159265358979323846;
  std::printf("%s fit of %s (%s sampling, %s objective)\n", fit_model_name(r.model).c_str(),
              a.input.c_str(), fit_sampling_name(r.sampling).c_str(),
              fit_objective_name(r.objective).c_str());
  if (!r.window.full())
    std::printf("  zoomed table: m_x %.6g..%.6g, m_y %.6g..%.6g\n", r.window.x0(), r.window.x1(),
                r.window.y0(), r.window.y1());
  std::printf("  alpha_x %.6g  alpha_y %.6g\n", p.alpha_x, p.alpha_y);
  if (r.model == FitModel::Ellipsoid)
    std::printf("  theta_x %.6g deg  theta_y %.6g deg  theta_z %.6g deg\n", p.theta_x * deg,
                p.theta_y * deg, p.theta_z * deg);
  else
    std::printf("  phi (alpha_x axis) %.6g deg  (theta_z %.6g deg)\n", r.phi * deg,
                p.theta_z * deg);
  std::printf("  rms error %.4g 1/sr, relative L2 error %.4g, Hellinger %.4g\n", r.rms_error,
              r.relative_l2_error, r.hellinger);
  std::printf(
      "  %d iterations, %s (%s), %.3g s\n", r.iterations,
      r.converged
          ? "converged"
          : (r.at_bound.empty() ? "NOT converged" : "NOT converged: at " + r.at_bound).c_str(),
      r.termination.c_str(), r.seconds);
  if (!a.report.empty()) std::printf("  report in %s\n", a.report.c_str());
}

}  // namespace

void register_fit(CLI::App& app) {
  auto a = std::make_shared<FitArgs>();
  auto* c = app.add_subcommand("fit", "Fit an ellipsoid, Beckmann or GGX NDF to a tabulated NDF");
  c->footer(
      "Fits the parameters (alpha_x, alpha_y, theta_x, theta_y, theta_z) of the ellipsoid NDF "
      "(Dong 2015\n"
      "eqs. 10-12) or (alpha_x, alpha_y, theta_z) of anisotropic Beckmann/GGX to a table written "
      "by\n"
      "`ndf` or `tabulate`. Angles use the ellipsoid convention of `tabulate` for every model: "
      "the\n"
      "anisotropy axes are turned by -theta_z (Beckmann/GGX phi = -theta_z), theta_x > 0 tilts "
      "the peak\n"
      "towards +y, theta_y > 0 towards -x; theta_z is reported in (-90, 90] deg.\n"
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
      "  microbrdf fit ndf.exr --model ggx --report fit-ggx/");
  c->add_option("ndf", a->input, "Tabulated NDF (.npy with sidecar, or .exr)")->required();
  c->add_option("--model", a->model, "ellipsoid | beckmann | ggx")->capture_default_str();
  c->add_option("--objective", a->objective, "sqrt | linear | log (on D, with a floor)")
      ->capture_default_str();
  c->add_option("--sampling", a->sampling, "auto | node | tent: how the model meets the table")
      ->capture_default_str();
  c->add_option("--subsamples", a->subsamples,
                "Tent quadrature points per node spacing (0 = from the lobe width)")
      ->capture_default_str();
  c->add_option("--report", a->report, "Write images and fit.json into this directory");
  c->add_flag("--json", a->json, "Print a JSON summary on stdout");
  c->callback([a] { run_guarded("fit", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

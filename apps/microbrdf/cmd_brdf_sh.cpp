// `microbrdf brdf info|sh-project|sh-estimate`: spherical-harmonic BRDF files (Westin 1992): a
// file's summary, the projection of any BRDF onto the basis, and Westin's Monte Carlo estimator
// fed by exits sampled from a known BRDF.
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/units.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct ShArgs {
  SpecFlags spec;
  int lmax = 12, n_theta = 0;
  std::size_t incident = 100000;
  int rays = 1;
  std::uint64_t seed = 1;
  std::string wavelength = "555nm", output;
  bool json = false;
};

nlohmann::json albedo_json(const ShBrdf& b) {
  nlohmann::json t = nlohmann::json::array();
  for (const auto& p : sh_albedo_table(b))
    t.push_back({{"theta_i_deg", p.theta_i_deg}, {"albedo", p.albedo}});
  return t;
}

void run_info(const ShArgs& a) {
  const auto bp = brdf_from_flags(a.spec);
  const auto* b = dynamic_cast<const ShBrdf*>(bp.get());
  const std::string path = a.spec.text.at("sh");
  const int n = b->basis().size();
  const double hemi = sh_hemispherical_albedo(*b);
  const ShRinging ring = sh_ringing(*b);
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(path, ec);
  const auto alb = albedo_json(*b);
  if (a.json) {
    print_json({{"path", path},
                {"lmax", b->lmax()},
                {"size", n},
                {"coefficients", static_cast<long long>(n) * n},
                {"file_bytes", ec ? 0 : bytes},
                {"isotropic", b->isotropic()},
                {"albedo", alb},
                {"hemispherical_albedo", hemi},
                {"negative_fraction", ring.negative_fraction},
                {"min_cosine_weighted", ring.min_cosine_weighted},
                {"max_cosine_weighted", ring.max_cosine_weighted},
                {"describe", b->describe()},
                {"meta", b->meta()}});
    return;
  }
  std::printf("%s\n  %s\n", path.c_str(), b->describe().c_str());
  std::printf("  %d x %d coefficients (%lld in the full basis would be %d x %d), %s\n", n, n,
              static_cast<long long>(n) * n, sh_count(b->lmax()), sh_count(b->lmax()),
              ec ? "size unknown" : (std::to_string(bytes) + " bytes").c_str());
  std::printf("  directional albedo:");
  for (const auto& e : alb)
    std::printf(" %g deg %.4f;", e["theta_i_deg"].get<double>(), e["albedo"].get<double>());
  std::printf("\n  hemispherical albedo %.4f\n", hemi);
  std::printf("  rho cos cos on a 72 x 648 direction grid: %.2f %% negative (min %.4g, max %.4g)\n",
              100 * ring.negative_fraction, ring.min_cosine_weighted, ring.max_cosine_weighted);
  if (b->meta().contains("q"))
    std::printf("  convergence Q (W92 eq. 27, 1/J^2) %.4g\n", b->meta()["q"].get<double>());
  std::printf("  meta %s\n", b->meta().dump().c_str());
}

void check_lmax(int lmax) {
  if (lmax < 1 || lmax > kShMaxL)
    throw InputError("--lmax must lie in [1, " + std::to_string(kShMaxL) + "]");
}

void run_project(const ShArgs& a) {
  if (a.output.empty()) throw InputError("give the output: -o FILE.shbrdf");
  check_lmax(a.lmax);
  BrdfSpec spec;
  const auto src = brdf_from_flags(a.spec, &spec);
  const double lambda = parse_length(a.wavelength);
  const int nt = a.n_theta > 0 ? a.n_theta : a.lmax + 8;
  std::fprintf(stderr, "brdf sh-project: lmax %d, %d x %d quadrature nodes per hemisphere...\n",
               a.lmax, nt, 2 * nt);
  const bool schlick =
      spec.uses_material() && material_spec(a.spec, std::nullopt).fresnel == FresnelMode::Schlick;
  auto b = ShBrdf::project(*src, a.lmax, lambda, nt,
                           {{"ndf", spec.ndf},
                            {"fresnel", schlick ? "schlick" : "exact"},
                            {"separable_g", spec.separable_g}});
  b.save(a.output);
  const auto alb = albedo_json(b);
  if (a.json) {
    print_json({{"output", a.output},
                {"lmax", b.lmax()},
                {"size", b.basis().size()},
                {"model", src->describe()},
                {"wavelength_m", lambda},
                {"n_theta", nt},
                {"isotropic", b.isotropic()},
                {"albedo", alb}});
    return;
  }
  std::printf(
      "%s\n  wrote %s: lmax %d, %d x %d coefficients; albedo at 0/45/75 deg %.4f %.4f %.4f\n",
      src->describe().c_str(), a.output.c_str(), b.lmax(), b.basis().size(), b.basis().size(),
      alb[0]["albedo"].get<double>(), alb[2]["albedo"].get<double>(),
      alb[4]["albedo"].get<double>());
}

void run_estimate(const ShArgs& a) {
  check_lmax(a.lmax);
  if (static_cast<double>(a.incident) * static_cast<double>(a.rays) > kMaxSamples)
    throw InputError("--incident x --rays: " + std::to_string(a.incident) + " x " +
                     std::to_string(a.rays) + " exits: " + kWhySamples);
  const auto src = brdf_from_flags(a.spec);
  const double lambda = parse_length(a.wavelength);
  const ShEstimator e = sh_estimate_chunked(
      *src, a.lmax, a.incident, a.rays, a.seed, lambda,
      [](std::size_t done, std::size_t n) { progress("brdf sh-estimate", done, n, "chunk"); });
  auto b = ShBrdf::from_estimator(e, {{"source", "synthetic estimate from " + src->describe()},
                                      {"seed", a.seed},
                                      {"wavelength_m", lambda},
                                      {"rays_per_incident", a.rays}});
  if (!a.output.empty()) b.save(a.output);
  const auto alb = albedo_json(b);
  const double m10 = b.matrix()(sh_odd_index(1, 0), sh_odd_index(1, 0));
  if (a.json) {
    print_json({{"output", a.output},
                {"source", src->describe()},
                {"lmax", b.lmax()},
                {"size", b.basis().size()},
                {"incident_count", e.incident_count()},
                {"ray_count", e.ray_count()},
                {"q", e.q()},
                {"mean_energy", e.mean_energy()},
                {"m_10_10", m10},
                {"albedo", alb}});
    return;
  }
  std::printf(
      "%s\n  %zu incident directions x %d rays, lmax %d: Q = %.4g, mean energy %.5f, "
      "m_(1,0),(1,0) = %.5f\n  albedo at 0/45/75 deg %.4f %.4f %.4f%s%s\n",
      src->describe().c_str(), e.incident_count(), a.rays, b.lmax(), e.q(), e.mean_energy(), m10,
      alb[0]["albedo"].get<double>(), alb[2]["albedo"].get<double>(),
      alb[4]["albedo"].get<double>(), a.output.empty() ? "" : "; wrote ", a.output.c_str());
}

}  // namespace

void register_brdf_sh(CLI::App* brdf) {
  auto a = std::make_shared<ShArgs>();
  const auto add_source = [a](CLI::App* c) {
    add_brdf_flags(c, a->spec, kFlagAllBrdfs);
    add_material_flags(c, a->spec, "");
    c->add_option("--wavelength", a->wavelength, "Wavelength (with unit)")
        ->capture_default_str()
        ->check(wavelength());
  };
  auto* in = brdf->add_subcommand(
      "info", "Summary of a spherical-harmonic BRDF file: lmax, size, albedos, ringing, metadata");
  add_brdf_flags(in, a->spec, kFlagSh);
  in->add_flag("--json", a->json, "Print JSON on stdout");
  in->footer(
      "Albedo a(theta_i) = integral rho cos(theta_o) dw_o of the truncated expansion (exact, at\n"
      "azimuth 0); hemispherical albedo = (1/pi) integral a cos(theta_i) dw_i; 'negative' is the\n"
      "fraction of a direction grid where the expansion of rho cos cos rings below 0.\n"
      "Example: microbrdf brdf info --sh sim.shbrdf --json");
  in->callback([a] { run_guarded("brdf info", [&] { run_info(*a); }); });

  auto* pj = brdf->add_subcommand("sh-project",
                                  "Project a BRDF onto spherical harmonics (a .shbrdf file)");
  add_source(pj);
  pj->add_option("--lmax", a->lmax, "Highest SH order l (1..128); lmax (lmax+1)/2 functions kept")
      ->capture_default_str()
      ->check(count_in(1, 128));
  pj->add_option("--n-theta", a->n_theta,
                 "Gauss-Legendre nodes in cos(theta) per hemisphere (x 2 in phi); default lmax + 8")
      ->check(count_in(0, 1024, "the cost grows as n_theta^4 BRDF evaluations"));
  pj->add_option("-o,--output", a->output, "Output .shbrdf file")->required();
  pj->add_flag("--json", a->json, "Print a JSON summary on stdout");
  pj->footer(
      "Stores M with rho cos(theta_i) cos(theta_o) = Y(wi)^T M Y(wo) (odd completion, theory "
      "6.3);\ncost ~ (2 n_theta^2)^2 BRDF evaluations (threads).\n"
      "Example: microbrdf brdf sh-project --model beckmann --alpha 0.31 --metal Al --lmax 20 "
      "-o b.shbrdf");
  pj->callback([a] { run_guarded("brdf sh-project", [&] { run_project(*a); }); });

  auto* es = brdf->add_subcommand(
      "sh-estimate",
      "Westin's Monte Carlo estimator fed by exits sampled from a known BRDF (no geometry)");
  add_source(es);
  es->add_option("--lmax", a->lmax, "Highest SH order l (1..128)")
      ->capture_default_str()
      ->check(count_in(1, 128));
  es->add_option("--incident", a->incident, "Number of incident directions N (cosine-weighted)")
      ->capture_default_str()
      ->check(count_in(1, kMaxSamples, kWhySamples));
  es->add_option("--rays", a->rays, "Exits drawn per incident direction")
      ->capture_default_str()
      ->check(count_in(1, kMaxSamples, kWhySamples));
  es->add_option("--seed", a->seed, "Random seed (result independent of the thread count)")
      ->capture_default_str();
  es->add_option("-o,--output", a->output, "Output .shbrdf file (optional)");
  es->add_flag("--json", a->json, "Print a JSON summary on stdout");
  es->footer(
      "Checks the estimator of W92 eqs. 17/25 with the constants of docs/theory.md §6.4 and its\n"
      "convergence measure Q (eq. 27, 1/J^2), which falls as N^-1/2.\n"
      "Examples:\n"
      "  microbrdf brdf sh-estimate --lambertian 1 --lmax 8 --incident 1000000 --json\n"
      "  microbrdf brdf sh-estimate --model ggx --alpha 0.3 --metal Al --lmax 12 --incident 100000 "
      "-o est.shbrdf");
  es->callback([a] { run_guarded("brdf sh-estimate", [&] { run_estimate(*a); }); });
}

}  // namespace microbrdf::cli

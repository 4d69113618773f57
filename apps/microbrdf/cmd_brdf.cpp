// `microbrdf brdf slice|color|info|sh-project`: the microfacet BRDF (Dong 2015 eq. 1) of a metal
// for an analytic NDF, or a spherical-harmonic BRDF file (Westin 1992, --sh), along in-plane /
// out-of-plane cuts; the normal-incidence colour of a material; a summary of a .shbrdf file; and
// the projection of an analytic BRDF onto spherical harmonics.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <sstream>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct MaterialArgs {
  std::string metal, nk_csv, rgb;
  double n = 0, k = -1, r0 = -1;
};

struct BrdfArgs : ModelFlags {
  MaterialArgs mat;
  std::string ndf;  ///< tabulated NDF file (.npy/.exr) instead of an analytic model
  std::string sh;   ///< spherical-harmonic BRDF file (.shbrdf) instead of model + material
  int l_filter = -1;
  double filter_width = 0;
  int lmax = 12, n_theta = 0;
  bool iso_average = false;
  double lambert = -1;
  std::size_t incident = 100000;
  int rays = 1;
  std::uint64_t seed = 1;
  bool model_given = false;
  std::string theta_i = "30deg", plane = "in", wavelength = "555nm", output, plot;
  bool log_y = false;
  std::string fresnel = "exact";
  std::size_t samples = 721;
  bool separable = false, json = false;
};

void add_material_flags(CLI::App* c, MaterialArgs& m) {
  c->add_option(
      "--metal", m.metal, "Built-in optical constants: " + [] {
        std::string s;
        for (const auto& n : metal_names()) s += (s.empty() ? "" : " ") + n;
        return s;
      }());
  c->add_option("--n", m.n, "Custom refractive index n (with --k)");
  c->add_option("--k", m.k, "Custom extinction coefficient k (with --n)");
  c->add_option("--nk-csv", m.nk_csv, "CSV file 'wavelength_nm,n,k' with the optical constants");
  c->add_option("--r0", m.r0,
                "Normal-incidence reflectance (Sun 2002 5.2: eta = 1, kappa = 2 sqrt(R0/(1-R0)))");
  c->add_option("--rgb", m.rgb,
                "sRGB colour 'r,g,b' (0..1 or 0..255) or '#rrggbb': smooth spectrum, eta = 1");
}

OpticalConstants material(const MaterialArgs& m) {
  int given =
      !m.metal.empty() + (m.n > 0 || m.k >= 0) + !m.nk_csv.empty() + (m.r0 >= 0) + !m.rgb.empty();
  if (given != 1)
    throw InputError("give exactly one material: --metal, --n/--k, --nk-csv, --r0 or --rgb");
  if (!m.metal.empty()) return metal(m.metal);
  if (!m.nk_csv.empty()) return read_optical_constants_csv(m.nk_csv);
  if (m.r0 >= 0) return from_normal_reflectance(Spectrum::constant(m.r0), 1.0);
  if (!m.rgb.empty()) {
    double c[3];
    std::string s = m.rgb;
    if (s.size() == 7 && s[0] == '#') {
      for (int i = 0; i < 3; ++i) c[i] = std::stoi(s.substr(1 + 2 * i, 2), nullptr, 16) / 255.0;
    } else {
      std::replace(s.begin(), s.end(), ',', ' ');
      std::istringstream is(s);
      if (!(is >> c[0] >> c[1] >> c[2]))
        throw InputError("--rgb: expected 'r,g,b' or '#rrggbb', got '" + m.rgb + "'");
      if (c[0] > 1 || c[1] > 1 || c[2] > 1)
        for (double& v : c) v /= 255.0;
    }
    return from_srgb(c[0], c[1], c[2]);
  }
  if (!(m.n > 0) || m.k < 0) throw InputError("--n and --k go together (n > 0, k >= 0)");
  return constant_index(m.n, m.k);
}

std::shared_ptr<MicrofacetDistribution> distribution(const BrdfArgs& a) {
  if (!a.ndf.empty()) {
    if (a.model_given || a.alpha > 0 || a.alpha_x > 0 || a.alpha_y > 0 || a.phi != "0" ||
        a.theta_x != "0" || a.theta_y != "0" || a.theta_z != "0")
      throw InputError(
          "--ndf replaces the analytic model: do not combine it with --model, --alpha*, --phi or "
          "--theta-x/y/z");
    return std::make_shared<TabulatedDistribution>(read_ndf(a.ndf));
  }
  const NdfSpec s = ndf_spec(a);
  return make_distribution(s);
}

void check_plot_name(const std::string& path) {
  if (path.empty()) return;
  auto dot = path.find_last_of('.');
  std::string ext = dot == std::string::npos ? "" : path.substr(dot + 1);
  for (auto& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != "png" && ext != "svg")
    throw InputError("--plot " + path + ": plots are written as .png or .svg");
}

bool material_given(const MaterialArgs& m) {
  return !m.metal.empty() || m.n > 0 || m.k >= 0 || !m.nk_csv.empty() || m.r0 >= 0 ||
         !m.rgb.empty();
}

// The microfacet BRDF the model / --ndf / material flags describe.
std::shared_ptr<MicrofacetBrdf> microfacet_brdf(const BrdfArgs& a) {
  auto d = distribution(a);
  auto mat = material(a.mat);
  std::shared_ptr<const Fresnel> f;
  if (a.fresnel == "exact")
    f = std::make_shared<ConductorFresnel>(mat);
  else if (a.fresnel == "schlick")
    f = std::make_shared<SchlickFresnel>(mat.normal_reflectance_spectrum());
  else
    throw InputError("--fresnel must be exact or schlick");
  return std::make_shared<MicrofacetBrdf>(d, f, a.separable);
}

// A .shbrdf file, optionally Gibbs-damped (--l-filter/--filter-width).
std::shared_ptr<ShBrdf> sh_brdf(const BrdfArgs& a) {
  auto b = std::make_shared<ShBrdf>(ShBrdf::load(a.sh));
  if (a.l_filter >= 0 || a.filter_width > 0) {
    if (a.l_filter < 0 || !(a.filter_width > 0))
      throw InputError("--l-filter and --filter-width go together (l_filter >= 0, width > 0)");
    b = std::make_shared<ShBrdf>(b->damped(a.l_filter, a.filter_width));
  }
  if (a.iso_average) b = std::make_shared<ShBrdf>(b->isotropic_average());
  return b;
}

void run_slice(const BrdfArgs& a) {
  if (a.output.empty() && a.plot.empty())
    throw InputError("give an output: -o slice.csv and/or --plot slice.png|svg");
  check_plot_name(a.plot);
  std::shared_ptr<const Brdf> bp;
  std::shared_ptr<const ShBrdf> sh;
  std::string label;
  if (!a.sh.empty()) {
    if (a.model_given || a.alpha > 0 || a.alpha_x > 0 || a.alpha_y > 0 || !a.ndf.empty() ||
        material_given(a.mat))
      throw InputError(
          "--sh replaces the model and the material: do not combine it with --model, --alpha*, "
          "--ndf or material flags");
    sh = sh_brdf(a);
    bp = sh;
    label = "SH BRDF " + a.sh;
  } else {
    if (a.l_filter >= 0 || a.filter_width > 0 || a.iso_average)
      throw InputError("--l-filter, --filter-width and --isotropic-average apply to --sh only");
    auto mf = microfacet_brdf(a);
    label = a.ndf.empty() ? mf->distribution().describe() : "tabulated NDF " + a.ndf;
    bp = mf;
  }
  const Brdf& b = *bp;
  const double ti = parse_angle(a.theta_i), lambda = parse_length(a.wavelength);
  if (!(ti >= 0 && ti < M_PI / 2)) throw InputError("--theta-i must lie in [0, 90) deg");
  if (a.plane != "in" && a.plane != "out") throw InputError("--plane must be in or out");
  auto s =
      tabulate_slice(b, ti, lambda, a.plane == "in" ? SlicePlane::in : SlicePlane::out, a.samples);
  std::string text = "# microbrdf brdf slice: " + b.describe() + "\n";
  char line[160];
  std::snprintf(line, sizeof line,
                "# theta_i %.6g deg, wavelength %s, %s-plane; angle: ", ti * 180 / M_PI,
                format_length(lambda).c_str(), a.plane.c_str());
  text += line;
  text += a.plane == "in" ? "signed theta_o in the plane of incidence (mirror at +theta_i)\n"
                          : "angle from the mirror direction across the plane of incidence\n";
  text += "angle_deg,brdf_per_sr,wo_x,wo_y,wo_z\n";
  double peak = 0, peak_angle = 0;
  for (std::size_t i = 0; i < s.value.size(); ++i) {
    std::snprintf(line, sizeof line, "%.6f,%.9g,%.9f,%.9f,%.9f\n", s.angle_deg[i], s.value[i],
                  s.wo[i].x(), s.wo[i].y(), s.wo[i].z());
    text += line;
    if (s.value[i] > peak) peak = s.value[i], peak_angle = s.angle_deg[i];
  }
  if (!a.output.empty()) write_file_atomic(a.output, text);
  if (!a.plot.empty()) {
    Plot p;
    char title[200];
    std::snprintf(title, sizeof title, "BRDF, %s: θi = %g°, λ = %s",
                  a.plane == "in" ? "plane of incidence" : "across the plane of incidence",
                  ti * 180 / M_PI, format_length(lambda).c_str());
    p.title = title;
    p.x.label = a.plane == "in" ? "viewing angle θo (deg; mirror direction at +θi)"
                                : "angle from the mirror direction across the plane (deg)";
    p.y.label = "BRDF (1/sr)";
    p.x.min = -90;
    p.x.max = 90;
    if (a.log_y) p.y.scale = AxisScale::Log;
    PlotSeries series;
    if (label.size() > 70) label = label.substr(0, 67) + "...";
    series.label = label;
    for (std::size_t i = 0; i < s.value.size(); ++i) {
      if (a.log_y && !(s.value[i] > 0)) continue;
      series.x.push_back(s.angle_deg[i]);
      series.y.push_back(s.value[i]);
    }
    if (series.x.empty()) throw InputError("--plot: the BRDF is zero along the whole slice");
    p.add(series);
    p.write(a.plot);
  }
  Vec3 wi(-std::sin(ti), 0, std::cos(ti));
  // The SH expansion has an exact albedo (hemisphere integrals of the basis).
  const double albedo = sh ? sh->albedo(wi) : directional_albedo_sampled(b, wi, lambda, 256);
  if (a.json) {
    print_json({{"output", a.output},
                {"plot", a.plot},
                {"ndf", a.ndf},
                {"sh", a.sh},
                {"model", b.describe()},
                {"theta_i_rad", ti},
                {"wavelength_m", lambda},
                {"plane", a.plane},
                {"samples", s.value.size()},
                {"peak_brdf_per_sr", peak},
                {"peak_angle_deg", peak_angle},
                {"directional_albedo", albedo}});
  } else {
    std::printf(
        "%s\n  wrote %zu angles to %s; peak %.6g /sr at %.3f deg; directional albedo %.5f\n",
        b.describe().c_str(), s.value.size(),
        (a.output.empty() ? a.plot
         : a.plot.empty() ? a.output
                          : a.output + " and " + a.plot)
            .c_str(),
        peak, peak_angle, albedo);
  }
}

// Albedo a(theta_i) of an SH BRDF at azimuth 0 for a few angles (the expansion's exact integral).
nlohmann::json albedo_table(const ShBrdf& b) {
  nlohmann::json t = nlohmann::json::array();
  for (double deg : {0.0, 30.0, 45.0, 60.0, 75.0, 85.0}) {
    const double r = deg * M_PI / 180;
    t.push_back({{"theta_i_deg", deg}, {"albedo", b.albedo(Vec3(std::sin(r), 0, std::cos(r)))}});
  }
  return t;
}

void run_info(const BrdfArgs& a) {
  if (a.sh.empty()) throw InputError("give the file: brdf info --sh FILE.shbrdf");
  const auto b = sh_brdf(a);
  const auto& basis = b->basis();
  const int n = basis.size();
  const Eigen::Map<const Eigen::VectorXd> h(basis.hemisphere_integrals().data(), n);
  const double hemi = h.dot(b->matrix() * h) / M_PI;
  // Ringing diagnostic: where is the truncated f = rho cos cos negative? Grid of 9 x 8 incident
  // and 18 x 36 outgoing directions (cell centres), as one matrix product.
  std::vector<Vec3> wi, wo;
  for (int t = 0; t < 9; ++t)
    for (int p = 0; p < 8; ++p) {
      const double th = (t + 0.5) * M_PI / 18, ph = p * M_PI / 4;
      wi.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  for (int t = 0; t < 18; ++t)
    for (int p = 0; p < 36; ++p) {
      const double th = (t + 0.5) * M_PI / 36, ph = (p + 0.5) * M_PI / 18;
      wo.emplace_back(std::sin(th) * std::cos(ph), std::sin(th) * std::sin(ph), std::cos(th));
    }
  Eigen::MatrixXd yi(n, wi.size()), yo(n, wo.size());
  for (std::size_t k = 0; k < wi.size(); ++k) basis.eval(wi[k], yi.col(k).data());
  for (std::size_t k = 0; k < wo.size(); ++k) basis.eval(wo[k], yo.col(k).data());
  const Eigen::MatrixXd f = yi.transpose() * b->matrix() * yo;
  const double neg = static_cast<double>((f.array() < 0).count()) / static_cast<double>(f.size());
  const double fmin = f.minCoeff(), fmax = f.maxCoeff();
  std::error_code ec;
  const auto bytes = std::filesystem::file_size(a.sh, ec);
  const auto alb = albedo_table(*b);
  if (a.json) {
    print_json({{"path", a.sh},
                {"lmax", b->lmax()},
                {"size", n},
                {"coefficients", static_cast<long long>(n) * n},
                {"file_bytes", ec ? 0 : bytes},
                {"isotropic", b->isotropic()},
                {"albedo", alb},
                {"hemispherical_albedo", hemi},
                {"negative_fraction", neg},
                {"min_cosine_weighted", fmin},
                {"max_cosine_weighted", fmax},
                {"describe", b->describe()},
                {"meta", b->meta()}});
    return;
  }
  std::printf("%s\n  %s\n", a.sh.c_str(), b->describe().c_str());
  std::printf("  %d x %d coefficients (%lld in the full basis would be %d x %d), %s\n", n, n,
              static_cast<long long>(n) * n, sh_count(b->lmax()), sh_count(b->lmax()),
              ec ? "size unknown" : (std::to_string(bytes) + " bytes").c_str());
  std::printf("  directional albedo:");
  for (const auto& e : alb)
    std::printf(" %g deg %.4f;", e["theta_i_deg"].get<double>(), e["albedo"].get<double>());
  std::printf("\n  hemispherical albedo %.4f\n", hemi);
  std::printf("  rho cos cos on a 72 x 648 direction grid: %.2f %% negative (min %.4g, max %.4g)\n",
              100 * neg, fmin, fmax);
  if (b->meta().contains("q"))
    std::printf("  convergence Q (W92 eq. 27, 1/J^2) %.4g\n", b->meta()["q"].get<double>());
  std::printf("  meta %s\n", b->meta().dump().c_str());
}

void run_project(const BrdfArgs& a) {
  if (a.output.empty()) throw InputError("give the output: -o FILE.shbrdf");
  if (a.lmax < 1 || a.lmax > kShMaxL)
    throw InputError("--lmax must lie in [1, " + std::to_string(kShMaxL) + "]");
  auto mf = microfacet_brdf(a);
  const double lambda = parse_length(a.wavelength);
  const int nt = a.n_theta > 0 ? a.n_theta : a.lmax + 8;
  std::fprintf(stderr, "brdf sh-project: lmax %d, %d x %d quadrature nodes per hemisphere...\n",
               a.lmax, nt, 2 * nt);
  auto b = ShBrdf::project(*mf, a.lmax, lambda, nt,
                           {{"ndf", a.ndf}, {"fresnel", a.fresnel}, {"separable_g", a.separable}});
  b.save(a.output);
  const auto alb = albedo_table(b);
  if (a.json) {
    print_json({{"output", a.output},
                {"lmax", b.lmax()},
                {"size", b.basis().size()},
                {"model", mf->describe()},
                {"wavelength_m", lambda},
                {"n_theta", nt},
                {"isotropic", b.isotropic()},
                {"albedo", alb}});
    return;
  }
  std::printf(
      "%s\n  wrote %s: lmax %d, %d x %d coefficients; albedo at 0/45/75 deg %.4f %.4f %.4f\n",
      mf->describe().c_str(), a.output.c_str(), b.lmax(), b.basis().size(), b.basis().size(),
      alb[0]["albedo"].get<double>(), alb[2]["albedo"].get<double>(),
      alb[4]["albedo"].get<double>());
}

// A Lambertian reflector of albedo a (cosine-weighted sampling, weight a), the exact reference
// of docs/theory.md §6.3 for `brdf sh-estimate --lambert`.
class LambertBrdf final : public Brdf {
 public:
  explicit LambertBrdf(double a) : a_(a) {}
  double eval(const Vec3& wi, const Vec3& wo, double) const override {
    return wi.z() > 0 && wo.z() > 0 ? a_ / M_PI : 0.0;
  }
  std::optional<BrdfSample> sample(const Vec3& wi, double u1, double u2, double) const override {
    if (!(wi.z() > 0)) return std::nullopt;
    const double r = std::sqrt(u1), p = 2 * M_PI * u2, z = std::sqrt(std::max(0.0, 1 - u1));
    if (!(z > 0)) return std::nullopt;
    return BrdfSample{Vec3(r * std::cos(p), r * std::sin(p), z), a_, z / M_PI};
  }
  double pdf(const Vec3& wi, const Vec3& wo) const override {
    return wi.z() > 0 && wo.z() > 0 ? wo.z() / M_PI : 0.0;
  }
  std::string describe() const override { return "Lambertian, albedo " + std::to_string(a_); }

 private:
  double a_;
};

void run_estimate(const BrdfArgs& a) {
  if (a.lmax < 1 || a.lmax > kShMaxL)
    throw InputError("--lmax must lie in [1, " + std::to_string(kShMaxL) + "]");
  if (a.incident < 1 || a.rays < 1) throw InputError("--incident and --rays must be >= 1");
  std::shared_ptr<const Brdf> src;
  if (a.lambert >= 0) {
    if (a.model_given || a.alpha > 0 || a.alpha_x > 0 || !a.ndf.empty() || material_given(a.mat))
      throw InputError("--lambert replaces the model and the material");
    src = std::make_shared<LambertBrdf>(a.lambert);
  } else {
    src = microfacet_brdf(a);
  }
  const double lambda = parse_length(a.wavelength);
  // 16 chunks with seeds seed*1000003 + c, estimated in parallel and merged in order: the result
  // depends on the seed only, not on the thread count.
  const int chunks = static_cast<int>(std::min<std::size_t>(16, a.incident));
  std::vector<ShEstimator> part(chunks, ShEstimator(a.lmax));
  int done = 0;
#pragma omp parallel for schedule(dynamic, 1)
  for (int c = 0; c < chunks; ++c) {
    const std::size_t n = a.incident / chunks + (static_cast<std::size_t>(c) < a.incident % chunks);
    sh_estimate_by_sampling(part[c], *src, n, a.rays, a.seed * 1000003ull + c, lambda);
#pragma omp critical
    progress("brdf sh-estimate", static_cast<std::size_t>(done++), chunks, "chunk");
  }
  for (int c = 1; c < chunks; ++c) part[0].merge(part[c]);
  const ShEstimator& e = part[0];
  auto b = ShBrdf::from_estimator(e, {{"source", "synthetic estimate from " + src->describe()},
                                      {"seed", a.seed},
                                      {"wavelength_m", lambda},
                                      {"rays_per_incident", a.rays}});
  if (!a.output.empty()) b.save(a.output);
  const auto alb = albedo_table(b);
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

void run_color(const BrdfArgs& a) {
  auto mat = material(a.mat);
  auto r = mat.normal_reflectance_spectrum();
  auto xyz = reflectance_to_xyz(r);
  auto rgb = xyz_to_linear_srgb(xyz);
  auto c8 = linear_srgb_to_srgb8(rgb);
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
      "Microfacet BRDF of a metal (Dong 2015 eq. 1), spherical-harmonic BRDF files (Westin 1992) "
      "and material colours");
  brdf->require_subcommand(1);
  brdf->footer(
      "Frame: n = +z, light and view point away from the surface, BRDF in 1/sr. The light lies at\n"
      "azimuth 180 deg; in-plane angles are signed with the mirror direction at +theta_i.\n"
      "Materials: --metal NAME, --n/--k, --nk-csv FILE, --r0 R, or --rgb COLOUR (smooth "
      "spectrum).\n\n"
      "Examples:\n"
      "  microbrdf brdf slice --model ggx --alpha 0.1 --metal Cu --theta-i 30deg -o slice.csv\n"
      "  microbrdf brdf slice --ndf scan_ndf.npy --metal Al --theta-i 45deg -o s.csv --plot s.png\n"
      "  microbrdf brdf slice --model ellipsoid --alpha-x 0.05 --alpha-y 0.2 --theta-x 5deg "
      "--metal Al \\\n"
      "      --theta-i 45 --plane out --wavelength 633nm -o out.csv --json\n"
      "  microbrdf brdf sh-project --model ggx --alpha 0.3 --metal Al --lmax 16 -o ggx.shbrdf\n"
      "  microbrdf brdf slice --sh ggx.shbrdf --theta-i 45deg -o sh.csv --plot sh.png\n"
      "  microbrdf brdf info --sh sim.shbrdf --json\n"
      "  microbrdf brdf color --metal Au\n"
      "  microbrdf brdf color --rgb '#e6c27a' --json");

  auto* sl = brdf->add_subcommand("slice",
                                  "Tabulate the BRDF along an in-plane or out-of-plane cut (CSV)");
  add_model_flags(sl, *a)->each([a](const std::string&) { a->model_given = true; });
  sl->add_option("--ndf", a->ndf,
                 "Tabulated NDF (.npy with its .json sidecar, or .exr; from `microbrdf ndf` or "
                 "`tabulate`) instead of --model/--alpha");
  sl->add_option("--sh", a->sh,
                 "Spherical-harmonic BRDF file (.shbrdf, Westin 1992; from `simulate` or "
                 "`brdf sh-project`) instead of a model and a material; grey, so --wavelength is "
                 "ignored");
  sl->add_option("--l-filter", a->l_filter,
                 "With --sh: Gibbs damping, keep l <= L_FILTER, attenuate above by "
                 "exp(-(l-L_FILTER)^2/(2 WIDTH^2))");
  sl->add_option("--filter-width", a->filter_width, "With --sh: the damping width WIDTH (in l)");
  sl->add_flag("--isotropic-average", a->iso_average,
               "With --sh: average over rotations about n (for surfaces known to be isotropic)");
  add_material_flags(sl, a->mat);
  sl->add_option("--fresnel", a->fresnel, "exact (complex-index Fresnel) or schlick")
      ->capture_default_str();
  sl->add_flag("--separable-g", a->separable,
               "Separable Smith G1 G1 (Dong eq. 13) instead of height-correlated");
  sl->add_option("--theta-i", a->theta_i, "Angle of incidence")->capture_default_str();
  sl->add_option("--plane", a->plane,
                 "in (plane of incidence) or out (across it, through the mirror direction)")
      ->capture_default_str();
  sl->add_option("--wavelength", a->wavelength, "Wavelength (with unit)")->capture_default_str();
  sl->add_option("--samples", a->samples, "Number of angles over [-90, 90] deg")
      ->capture_default_str();
  sl->add_option("-o,--output", a->output, "Output CSV (angle_deg, brdf_per_sr, wo)");
  sl->add_option("--plot", a->plot, "Plot of the slice (.png or .svg)");
  sl->add_flag("--log-y", a->log_y, "Logarithmic BRDF axis in the plot");
  sl->add_flag("--json", a->json, "Print a JSON summary on stdout");
  sl->callback([a] { run_guarded("brdf slice", [&] { run_slice(*a); }); });

  auto* in = brdf->add_subcommand(
      "info", "Summary of a spherical-harmonic BRDF file: lmax, size, albedos, ringing, metadata");
  in->add_option("--sh", a->sh, "The .shbrdf file")->required();
  in->add_option("--l-filter", a->l_filter,
                 "Gibbs damping: keep l <= L_FILTER (with --filter-width)");
  in->add_option("--filter-width", a->filter_width, "Gibbs damping width (in l)");
  in->add_flag("--isotropic-average", a->iso_average, "Average over rotations about n first");
  in->add_flag("--json", a->json, "Print JSON on stdout");
  in->footer(
      "Albedo a(theta_i) = integral rho cos(theta_o) dw_o of the truncated expansion (exact, at\n"
      "azimuth 0); hemispherical albedo = (1/pi) integral a cos(theta_i) dw_i; 'negative' is the\n"
      "fraction of a direction grid where the expansion of rho cos cos rings below 0.\n"
      "Example: microbrdf brdf info --sh sim.shbrdf --json");
  in->callback([a] { run_guarded("brdf info", [&] { run_info(*a); }); });

  auto* pj = brdf->add_subcommand(
      "sh-project", "Project a microfacet BRDF onto spherical harmonics (a .shbrdf file)");
  add_model_flags(pj, *a)->each([a](const std::string&) { a->model_given = true; });
  pj->add_option("--ndf", a->ndf, "Tabulated NDF file instead of --model/--alpha");
  add_material_flags(pj, a->mat);
  pj->add_option("--fresnel", a->fresnel, "exact or schlick")->capture_default_str();
  pj->add_flag("--separable-g", a->separable, "Separable Smith G1 G1 (Dong eq. 13)");
  pj->add_option("--wavelength", a->wavelength, "Wavelength (with unit)")->capture_default_str();
  pj->add_option("--lmax", a->lmax, "Highest SH order l (1..128); lmax (lmax+1)/2 functions kept")
      ->capture_default_str();
  pj->add_option(
      "--n-theta", a->n_theta,
      "Gauss-Legendre nodes in cos(theta) per hemisphere (x 2 in phi); default lmax + 8");
  pj->add_option("-o,--output", a->output, "Output .shbrdf file")->required();
  pj->add_flag("--json", a->json, "Print a JSON summary on stdout");
  pj->footer(
      "Stores M with rho cos(theta_i) cos(theta_o) = Y(wi)^T M Y(wo) (odd completion, theory "
      "6.3);\n"
      "cost ~ (2 n_theta^2)^2 BRDF evaluations (threads).\n"
      "Example: microbrdf brdf sh-project --model beckmann --alpha 0.31 --metal Al --lmax 20 "
      "-o b.shbrdf");
  pj->callback([a] { run_guarded("brdf sh-project", [&] { run_project(*a); }); });

  auto* es = brdf->add_subcommand(
      "sh-estimate",
      "Westin's Monte Carlo estimator fed by exits sampled from a known BRDF (no geometry)");
  add_model_flags(es, *a)->each([a](const std::string&) { a->model_given = true; });
  es->add_option("--ndf", a->ndf, "Tabulated NDF file instead of --model/--alpha");
  add_material_flags(es, a->mat);
  es->add_option("--fresnel", a->fresnel, "exact or schlick")->capture_default_str();
  es->add_option("--lambert", a->lambert,
                 "A Lambertian reflector of this albedo instead of a model and a material");
  es->add_option("--wavelength", a->wavelength, "Wavelength (with unit)")->capture_default_str();
  es->add_option("--lmax", a->lmax, "Highest SH order l (1..128)")->capture_default_str();
  es->add_option("--incident", a->incident, "Number of incident directions N (cosine-weighted)")
      ->capture_default_str();
  es->add_option("--rays", a->rays, "Exits drawn per incident direction")->capture_default_str();
  es->add_option("--seed", a->seed, "Random seed (result independent of the thread count)")
      ->capture_default_str();
  es->add_option("-o,--output", a->output, "Output .shbrdf file (optional)");
  es->add_flag("--json", a->json, "Print a JSON summary on stdout");
  es->footer(
      "Checks the estimator of W92 eqs. 17/25 with the constants of docs/theory.md §6.4 and its\n"
      "convergence measure Q (eq. 27, 1/J^2), which falls as N^-1/2.\n"
      "Examples:\n"
      "  microbrdf brdf sh-estimate --lambert 1 --lmax 8 --incident 1000000 --json\n"
      "  microbrdf brdf sh-estimate --model ggx --alpha 0.3 --metal Al --lmax 12 --incident 100000 "
      "-o est.shbrdf");
  es->callback([a] { run_guarded("brdf sh-estimate", [&] { run_estimate(*a); }); });

  auto* co =
      brdf->add_subcommand("color", "Normal-incidence colour of a material (D65, CIE 1931, sRGB)");
  add_material_flags(co, a->mat);
  co->add_flag("--json", a->json, "Print JSON on stdout");
  co->callback([a] { run_guarded("brdf color", [&] { run_color(*a); }); });
}

}  // namespace microbrdf::cli

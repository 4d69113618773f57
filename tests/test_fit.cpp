// Parametric NDF fits (issue 7, acceptance 1 and 2): parameter recovery from tabulated models,
// Beckmann widths of Gaussian surfaces, ellipsoid vs Beckmann on the brushed presets.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "microbrdf/fit.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"

using namespace microbrdf;

namespace {

constexpr double kPi = 3.14159265358979323846;

struct Case {
  std::string model;
  EllipsoidParams p;
  std::size_t n;
};

// The table as `microbrdf tabulate` makes it.
TabulatedNdf table_of(const Case& c) {
  NdfSpec s;
  s.model = c.model;
  s.alpha_x = c.p.alpha_x;
  s.alpha_y = c.p.alpha_y;
  if (c.model == "ellipsoid") {
    s.theta_x = c.p.theta_x;
    s.theta_y = c.p.theta_y;
    s.theta_z = c.p.theta_z;
  } else {
    s.phi = -c.p.theta_z;
  }
  return tabulate(*make_distribution(s), c.model, c.n);
}

double theta_z(const FitResult& r) {
  return r.params.has("theta_z") ? r.params.at("theta_z") : -r.params.at("phi");
}

// The case's parameters by the model's names.
NdfParams named(const Case& c) {
  if (c.model == "ellipsoid") return ndf_params(c.p);
  return ndf_model(c.model).named({c.p.alpha_x, c.p.alpha_y, -c.p.theta_z});
}

void expect_recovered(const FitResult& r, const EllipsoidParams& t, const std::string& what) {
  SCOPED_TRACE(what);
  EXPECT_NEAR(r.params.at("alpha_x") / t.alpha_x, 1.0, 0.01);
  EXPECT_NEAR(r.params.at("alpha_y") / t.alpha_y, 1.0, 0.01);
  // (Beckmann/GGX: no tilts, theta_z = -phi in the ellipsoid convention.)
  EXPECT_NEAR(r.params.get("theta_x", 0), t.theta_x, 1e-3);
  EXPECT_NEAR(r.params.get("theta_y", 0), t.theta_y, 1e-3);
  EXPECT_NEAR(theta_z(r), t.theta_z, 1e-3);
  EXPECT_TRUE(r.converged) << r.termination;
  EXPECT_LT(r.relative_l2_error, 1e-3);
}

FitResult fit(const TabulatedNdf& t, const std::string& model) {
  FitOptions o;
  o.model = parse_fit_model(model);
  return fit_ndf(t, o);
}

}  // namespace

TEST(fit, TemplatedModelsMatchTabulate) {
  // Zero objective at the true parameters (with the renormalising amplitude) for every model:
  // the fitter's templated D equals microfacet.cpp's D at the nodes.
  for (const Case& c :
       {Case{"beckmann", {0.1, 0.25, 0, 0, 0.3}, 129}, Case{"ggx", {0.05, 0.2, 0, 0, -0.5}, 129},
        Case{"ellipsoid", {0.08, 0.2, 0.1, -0.05, 0.3}, 129}}) {
    const TabulatedNdf t = table_of(c);
    double raw = 0;
    std::sscanf(t.meta.notes.substr(t.meta.notes.find("normalising") + 12).c_str(), "%lf", &raw);
    ASSERT_GT(raw, 0);
    FitOptions o;
    o.model = parse_fit_model(c.model);
    o.sampling = FitSampling::Node;
    o.objective = FitObjective::Linear;
    const double at_truth = fit_objective(t, o, named(c), 1 / raw);
    Case off = c;
    off.p.alpha_x *= 1.01;
    const double perturbed = fit_objective(t, o, named(off), 1 / raw);
    EXPECT_LT(at_truth, 1e-12 * perturbed) << c.model;
  }
}

TEST(fit, RecoversBeckmannAndGgx) {
  for (const Case& c :
       {Case{"beckmann", {0.1, 0.25, 0, 0, 0.3}, 257},
        Case{"beckmann", {0.3, 0.12, 0, 0, -0.7}, 257}, Case{"ggx", {0.05, 0.2, 0, 0, -0.5}, 257},
        Case{"ggx", {0.4, 0.3, 0, 0, 0.1}, 257}}) {
    const FitResult r = fit(table_of(c), c.model);
    expect_recovered(r, c.p, c.model);
    EXPECT_NEAR(r.phi, -c.p.theta_z, 1e-3);
  }
}

TEST(fit, RecoversSkewedEllipsoids) {
  for (const Case& c : {Case{"ellipsoid", {0.08, 0.2, 0.1, -0.05, 0.3}, 257},
                        Case{"ellipsoid", {0.3, 0.15, -0.2, 0.15, -0.6}, 257},
                        Case{"ellipsoid", {0.1, 0.1, 0.05, 0.08, 0}, 257}}) {
    expect_recovered(fit(table_of(c), c.model), c.p, "ellipsoid");
  }
}

TEST(fit, RecoversNarrowLobesAtN1025) {
  // alpha = 0.007 spans ~3.6 node spacings at N = 1025 (Dong Fig. 12's stainless #4 width).
  for (const Case& c :
       {Case{"ggx", {0.007, 0.14, 0, 0, 0}, 1025}, Case{"beckmann", {0.007, 0.14, 0, 0, 0.2}, 1025},
        Case{"ellipsoid", {0.007, 0.14, 0.02, -0.01, 0.05}, 1025},
        Case{"ellipsoid", {0.007, 0.007, 0.03, 0.02, 0}, 1025}}) {
    expect_recovered(fit(table_of(c), c.model), c.p, c.model + " narrow");
  }
}

// A lobe narrower than the table resolves (alpha 1e-4 at node spacing 0.0078, like a smooth
// optical flat's histogram): the fit ends on the lower alpha bound, says so, and is not
// converged (its optimum lies beyond the box).
TEST(fit, FitAtTheAlphaBoundIsNotConverged) {
  for (const char* model : {"beckmann", "ellipsoid"}) {
    SCOPED_TRACE(model);
    TabulatedNdf t = table_of(Case{model, {0.0001, 0.0001, 0, 0, 0}, 257});
    t.meta.method = "naive";  // a histogram: tent sampling
    t.meta.sampling = "cell";
    const FitResult r = fit(t, model);
    EXPECT_EQ(r.sampling, FitSampling::Tent);
    EXPECT_LE(std::min(r.params.at("alpha_x"), r.params.at("alpha_y")), 2 * t.spacing());
    EXPECT_FALSE(r.converged);
    EXPECT_NE(r.at_bound.find("the lower alpha bound"), std::string::npos) << r.at_bound;
    const auto j = fit_result_json(r);
    EXPECT_FALSE(j.at("converged").get<bool>());
    EXPECT_EQ(j.at("at_bound").get<std::string>(), r.at_bound);
  }
  // Inside the box: no bound, converged.
  const Case c{"beckmann", {0.05, 0.02, 0, 0, 0.3}, 257};
  const FitResult r = fit(table_of(c), "beckmann");
  EXPECT_TRUE(r.converged && r.solver_converged) << r.termination;
  EXPECT_TRUE(r.at_bound.empty()) << r.at_bound;
  EXPECT_TRUE(fit_result_json(r).at("at_bound").is_null());
}

TEST(fit, TentSamplingForHistogramTables) {
  // A table holding tent-cell averages (what bilinear splatting of many samples converges to):
  // the tent forward operator recovers alpha; point sampling would be biased for narrow lobes.
  // alpha_x = 0.0035 at N = 513 spans the same ~1.8 node spacings as 0.007 at N = 1025.
  for (const std::string model : {"beckmann", "ggx"}) {
    NdfSpec spec;
    spec.model = model;
    spec.alpha_x = 0.0035;
    spec.alpha_y = 0.015;
    spec.phi = -0.1;
    TabulatedNdf t = tabulate_tent(*make_distribution(spec), model, 513, 6);
    t.meta.method = "filtered";  // as if estimated from a surface: auto chooses tent
    FitOptions o;
    o.model = parse_fit_model(model);
    const FitResult r = fit_ndf(t, o);
    EXPECT_EQ(r.sampling, FitSampling::Tent);
    expect_recovered(r, {0.0035, 0.015, 0, 0, 0.1}, "tent " + model);
    o.sampling = FitSampling::Node;
    const FitResult rn = fit_ndf(t, o);
    std::printf(
        "tent-averaged %s (0.0035, 0.015) at N = 513: tent fit alpha_x %.6f (s = %d), "
        "node fit %.6f\n",
        model.c_str(), r.params.at("alpha_x"), r.tent_subsamples, rn.params.at("alpha_x"));
    EXPECT_GT(std::abs(rn.params.at("alpha_x") / 0.0035 - 1), 0.01) << model;
  }
}

// Point-sampled tables (what `tabulate` writes, meta.sampling "point"): the fit compares the
// model at the nodes, so widths down to 4 node spacings come back within 0.5%, also for tables
// whose files predate the sampling record (inferred from the model name). Forcing the
// cell-average forward model on the same tables makes the narrow ones measurably too narrow
// (the difference the record exists for).
TEST(fit, PointSampledTablesDownToFourNodes) {
  const std::size_t n = 257;
  const double delta = 2.0 / (n - 1);
  for (const std::string model : {"ellipsoid", "beckmann", "ggx"})
    for (double nodes : {4.0, 6.0, 10.0, 20.0}) {
      const double a = nodes * delta;
      const Case c{model, {a, 1.7 * a, model == "ellipsoid" ? 0.02 : 0.0, 0, 0.3}, n};
      TabulatedNdf t = table_of(c);
      ASSERT_EQ(t.meta.sampling, "point");
      for (bool recorded : {true, false}) {
        SCOPED_TRACE(model + " " + std::to_string(nodes) + " nodes" +
                     (recorded ? "" : ", sampling not recorded"));
        if (!recorded) t.meta.sampling.clear();
        FitOptions o;
        o.model = parse_fit_model(model);
        const FitResult r = fit_ndf(t, o);
        EXPECT_EQ(r.sampling, FitSampling::Node);
        EXPECT_EQ(r.table_sampling, "point");
        EXPECT_EQ(r.table_sampling_recorded, recorded);
        EXPECT_NEAR(r.params.at("alpha_x") / c.p.alpha_x, 1.0, 0.005);
        EXPECT_NEAR(r.params.at("alpha_y") / c.p.alpha_y, 1.0, 0.005);
        EXPECT_TRUE(r.converged) << r.termination;
        if (recorded && nodes == 4.0) {
          o.sampling = FitSampling::Tent;
          const FitResult rt = fit_ndf(t, o);
          std::printf(
              "%s alpha_x %.5f (%.0f nodes) N = %zu: node fit %.5f (%+.3f%%), "
              "cell-average fit %.5f (%+.3f%%)\n",
              model.c_str(), a, nodes, n, r.params.at("alpha_x"),
              100 * (r.params.at("alpha_x") / a - 1), rt.params.at("alpha_x"),
              100 * (rt.params.at("alpha_x") / a - 1));
          EXPECT_GT(std::abs(rt.params.at("alpha_x") / a - 1), 0.005);
        }
      }
    }
}

// The table's record wins over its method name: a "naive" table that says it holds point
// samples is fitted at the nodes, a model-named table that says "cell" with tent averages.
TEST(fit, RecordedSamplingOverridesTheMethodName) {
  TabulatedNdf t = table_of(Case{"beckmann", {0.03, 0.05, 0, 0, 0}, 257});
  t.meta.method = "naive";
  t.meta.sampling = "point";
  FitOptions o;
  o.model = "beckmann";
  EXPECT_EQ(fit_ndf(t, o).sampling, FitSampling::Node);
  t.meta.sampling.clear();  // no record: inferred from "naive", a histogram
  EXPECT_EQ(fit_ndf(t, o).sampling, FitSampling::Tent);
  EXPECT_FALSE(fit_ndf(t, o).table_sampling_recorded);
  NdfMetadata m;
  for (const char* point : {"beckmann", "GGX", "ellipsoid", "kirchhoff", "measured", "lobe"}) {
    m.method = point;
    EXPECT_EQ(ndf_sampling(m), "point") << point;
  }
  for (const char* cell : {"naive", "filtered", "ggx-tent", ""}) {
    m.method = cell;
    EXPECT_EQ(ndf_sampling(m), "cell") << cell;
  }
  TabulatedNdf tent = tabulate_tent(*make_distribution(NdfSpec{}), "ggx", 65, 2);
  EXPECT_EQ(tent.meta.sampling, "cell");
}

// A zoomed table (a window of the disk plane): alpha 0.002 spans a quarter of a node at
// N = 257 on the whole disk but 10 nodes on a window of half-width 0.025; fits of point samples
// and of cell averages on the window recover it within 0.5%, with the window in their result.
TEST(fit, ZoomedTableResolvesANarrowLobe) {
  const NdfWindow w = zoom_window(0.003, -0.002, 0.025);
  for (const std::string model : {"beckmann", "ggx", "ellipsoid"}) {
    SCOPED_TRACE(model);
    NdfSpec s;
    s.model = model;
    s.alpha_x = 0.002;
    s.alpha_y = 0.003;
    if (model == "ellipsoid")
      s.theta_x = 0.002;
    else
      s.phi = 0.2;
    const TabulatedNdf t = tabulate(*make_distribution(s), model, 257, w);
    EXPECT_EQ(t.window(), w);
    EXPECT_NEAR(t.integral(), 1.0, 1e-12);
    FitOptions o;
    o.model = parse_fit_model(model);
    const FitResult r = fit_ndf(t, o);
    EXPECT_NEAR(r.params.at("alpha_x") / 0.002, 1.0, 0.005);
    EXPECT_NEAR(r.params.at("alpha_y") / 0.003, 1.0, 0.005);
    EXPECT_TRUE(r.converged) << r.termination << " " << r.at_bound;
    EXPECT_EQ(r.window, w);
    EXPECT_LT(r.relative_l2_error, 1e-3);
    const TabulatedNdf m = fit_table(r, t.resolution());
    EXPECT_EQ(m.window(), w);
    const auto j = fit_result_json(r);
    EXPECT_NEAR(j.at("window").at("x").at(0).get<double>(), w.x0(), 1e-15);
    // Cell averages on the same window (a histogram's table): the tent forward model on the
    // window's cells recovers the widths too.
    TabulatedNdf tc = tabulate_tent(*make_distribution(s), model, 257, 4, w);
    tc.normalise();
    const FitResult rt = fit_ndf(tc, o);
    EXPECT_EQ(rt.sampling, FitSampling::Tent);
    EXPECT_NEAR(rt.params.at("alpha_x") / 0.002, 1.0, 0.005);
    EXPECT_NEAR(rt.params.at("alpha_y") / 0.003, 1.0, 0.005);
  }
}

TEST(fit, NelderMeadReferenceAgrees) {
  const Case c{"ggx", {0.05, 0.2, 0, 0, -0.5}, 65};
  const TabulatedNdf t = table_of(c);
  FitOptions o;
  o.model = "ggx";
  o.solver = FitSolver::NelderMead;
  const FitResult r = fit_ndf(t, o);
  EXPECT_NEAR(r.params.at("alpha_x") / 0.05, 1, 2e-3);
  EXPECT_NEAR(r.params.at("alpha_y") / 0.2, 1, 2e-3);
  EXPECT_NEAR(theta_z(r), -0.5, 2e-3);
}

TEST(fit, BeckmannOfGaussianSurfaceIsTwoSigmaOverTau) {
  // Naive NDF of a Gaussian surface: Gaussian slopes, Beckmann alpha_u = 2 sigma / tau_u
  // (docs/theory.md §3.4; forward-difference bias (1 - Delta^2/(4 tau^2)) = -0.25% at tau = 10 dx).
  struct G {
    double tau_x, tau_y, angle;
  };
  for (const G& g : {G{1.1e-6, 1.1e-6, 0.0}, G{1.1e-6, 2.2e-6, 30 * kPi / 180}}) {
    GaussianSurfaceParams p;
    p.nx = p.ny = 1024;
    p.dx = p.dy = 110e-9;
    p.sigma = 0.1e-6;
    p.tau_x = g.tau_x;
    p.tau_y = g.tau_y;
    p.angle = g.angle;
    p.seed = 7;
    NdfEstimateOptions eo;
    eo.method = NdfMethod::Naive;
    eo.resolution = 257;
    const TabulatedNdf t = estimate_ndf(generate_gaussian(p), eo);
    FitOptions o;
    o.model = "beckmann";
    const FitResult r = fit_ndf(t, o);
    const double ax = 2 * p.sigma / g.tau_x, ay = 2 * p.sigma / g.tau_y;
    std::printf(
        "gaussian tau (%.2g, %.2g) um: beckmann alpha (%.4f, %.4f) vs 2 sigma/tau (%.4f, "
        "%.4f), phi %.2f deg, rel L2 %.3g\n",
        g.tau_x * 1e6, g.tau_y * 1e6, r.params.at("alpha_x"), r.params.at("alpha_y"), ax, ay,
        r.phi * 180 / kPi, r.relative_l2_error);
    EXPECT_NEAR(r.params.at("alpha_x") / ax, 1, 0.03);
    EXPECT_NEAR(r.params.at("alpha_y") / ay, 1, 0.03);
    if (g.tau_x != g.tau_y) {
      EXPECT_NEAR(r.phi, g.angle, 0.02);
    }
  }
}

struct Pair {
  FitResult e, b;
};
Pair fit_both(const TabulatedNdf& t, const std::string& name) {
  FitOptions o;
  o.model = "ellipsoid";
  Pair p{fit_ndf(t, o), {}};
  o.model = "beckmann";
  p.b = fit_ndf(t, o);
  std::printf(
      "%s: ellipsoid (%.4f, %.4f) theta (%.4f, %.4f, %.4f) rel L2 %.4f hellinger %.4f | "
      "beckmann (%.4f, %.4f) rel L2 %.4f hellinger %.4f\n",
      name.c_str(), p.e.params.at("alpha_x"), p.e.params.at("alpha_y"), p.e.params.at("theta_x"),
      p.e.params.at("theta_y"), p.e.params.at("theta_z"), p.e.relative_l2_error, p.e.hellinger,
      p.b.params.at("alpha_x"), p.b.params.at("alpha_y"), p.b.relative_l2_error, p.b.hellinger);
  return p;
}

TEST(fit, BrushedPresetsFig12) {
  // Dong Fig. 12 on the synthetic presets (filtered NDF, 1 um). Their depth varies over the
  // surface (log-normal modulation), so the NDF is a scale mixture of Gaussian lobes with heavier
  // tails than Beckmann: the ellipsoid fits it better than Beckmann, as for Dong's measured
  // metals, with widths near Dong's ellipsoid column (0.0074, 0.142) / (0.0208, 0.469).
  struct P {
    std::string name;
    std::size_t res;
    double along, across;
  };
  for (const P& pr : {P{"stainless4", 1025, 0.0074, 0.142}, P{"aluminium4", 513, 0.0208, 0.469}}) {
    BrushedParams bp = brushed_preset(pr.name);
    bp.nx = 2048;
    bp.ny = 512;
    NdfEstimateOptions eo;
    eo.method = NdfMethod::Filtered;
    eo.filter_sigma_m = 1e-6;
    eo.resolution = pr.res;
    const Pair f = fit_both(estimate_ndf(generate_brushed(bp), eo), pr.name);
    EXPECT_LT(f.e.relative_l2_error, f.b.relative_l2_error) << pr.name;
    EXPECT_LT(f.e.hellinger, f.b.hellinger) << pr.name;
    EXPECT_TRUE(f.e.converged && f.b.converged);
    EXPECT_NEAR(f.e.params.at("alpha_x") / pr.along, 1.0, 0.3) << pr.name;
    EXPECT_NEAR(f.e.params.at("alpha_y") / pr.across, 1.0, 0.15) << pr.name;
    // Beckmann is wider than the ellipsoid, as in Fig. 12 (its tails are lighter).
    EXPECT_GT(f.b.params.at("alpha_y"), f.e.params.at("alpha_y")) << pr.name;
  }
}

TEST(fit, EllipsoidBeatsBeckmannOnMixedRoughness) {
  // Roughness that varies from place to place (Dong Fig. 11) makes the average NDF a scale
  // mixture of Beckmann lobes: heavier-tailed than any one of them (GGX is itself a scale mixture
  // of Gaussians), and the ellipsoid fits it better than Beckmann, as in Dong Fig. 12.
  TabulatedNdf mix(257);
  for (double k : {0.5, 0.75, 1.0, 1.5, 2.0})
    mix.add(tabulate(BeckmannDistribution(0.05 * k, 0.2 * k, 0.0), "beckmann", 257), 0.2);
  mix.meta.method = "filtered";
  const Pair f = fit_both(mix, "Beckmann scale mixture");
  EXPECT_LT(f.e.relative_l2_error, f.b.relative_l2_error);
  EXPECT_LT(f.e.hellinger, f.b.hellinger);
}

TEST(fit, ReportAndCliJson) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("microbrdf_fit_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const Case c{"ellipsoid", {0.08, 0.2, 0.1, -0.05, 0.3}, 129};
  const TabulatedNdf t = table_of(c);
  write_ndf(t, (dir / "t.npy").string());
  const std::string out = (dir / "out.json").string();
  const std::string cmd = std::string(MICROBRDF_CLI) + " fit " + (dir / "t.npy").string() +
                          " --model ellipsoid --json --report " + (dir / "rep").string() + " > " +
                          out;
  ASSERT_EQ(std::system(cmd.c_str()), 0);
  std::ifstream in(out);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("model"), "ellipsoid");
  for (const char* k : {"alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z"})
    EXPECT_TRUE(j.at("params").contains(k)) << k;
  EXPECT_NEAR(j.at("params").at("theta_x").get<double>(), 0.1, 1e-3);
  EXPECT_LT(j.at("relative_l2_error").get<double>(), 1e-3);
  EXPECT_GE(j.at("rms_error").get<double>(), 0.0);
  for (const char* f : {"fit.json", "compare.png", "slices.png", "measured.png", "fit.png"})
    EXPECT_TRUE(fs::exists(dir / "rep" / f)) << f;
  EXPECT_NE(std::system((std::string(MICROBRDF_CLI) + " fit " + (dir / "t.npy").string() +
                         " --model nonsense 2>/dev/null")
                            .c_str()),
            0);
  fs::remove_all(dir);
}

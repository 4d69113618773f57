// `predict` (issue 8): the summary holds what the library computes directly, the same inputs and
// seed give the same summary, bad inputs leave no output folder behind, and the report embeds
// every image it shows.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/image_metrics.hpp"
#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/predict.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/statistics.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "microbrdf/texture.hpp"
#include "report/predict_stages.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

/// A fresh folder under the system temp dir, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("microbrdf-predict-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

/// An anisotropic Gaussian surface (long correlation along x, as a brushed metal) with a tilt,
/// so the default plane levelling has something to remove.
std::string make_scan(const TempDir& t) {
  GaussianSurfaceParams g;
  g.nx = 192;
  g.ny = 160;
  g.dx = g.dy = 0.25e-6;
  g.sigma = 0.05e-6;
  g.tau_x = 6e-6;
  g.tau_y = 1.5e-6;
  g.seed = 7;
  Surface s = generate_gaussian(g);
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) s.at(ix, iy) += 0.01 * ix * s.dx - 0.02 * iy * s.dy;
  const std::string path = t / "scan.x3p";
  write_surface(s, path);
  return path;
}

PredictOptions small_options(const std::string& scan) {
  PredictOptions o;
  o.inputs = {scan};
  o.ndf_resolution = 257;
  o.slice_theta_i_rad = {0.5};
  o.slice_samples = 101;
  o.render = false;
  // The geometric path, whatever the scan's regime (the automatic choice: cli.predict_regime).
  o.theory = "geometric";
  return o;
}

std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

nlohmann::json without_timing(nlohmann::json j) {
  j.erase("timing");
  j.erase("mpi");  // seconds per rank
  return j;
}

/// Files and folders in `dir` (to see that nothing was left behind).
std::size_t entries(const fs::path& dir) {
  return static_cast<std::size_t>(std::distance(fs::directory_iterator(dir), {}));
}

}  // namespace

TEST(Predict, SummaryHoldsWhatTheLibraryComputes) {
  TempDir t;
  const std::string scan = make_scan(t);
  const PredictOptions o = small_options(scan);
  const PredictResult r = predict(o, t / "out");
  const auto& s = r.summary;
  ASSERT_TRUE(fs::exists(r.report_path));
  ASSERT_TRUE(fs::exists(r.summary_path));
  EXPECT_EQ(nlohmann::json::parse(slurp(r.summary_path)), s);

  // The same steps by hand.
  Surface surf = read_surface(scan);
  level_surface(surf, LevelingSpec{});
  const SurfaceStats st = compute_stats(surf);
  const auto& js = s["inputs"][0]["stats"];
  EXPECT_DOUBLE_EQ(js["sq_m"].get<double>(), st.sq);
  EXPECT_DOUBLE_EQ(js["sa_m"].get<double>(), st.sa);
  EXPECT_DOUBLE_EQ(js["slope_rms_x"].get<double>(), st.slope_rms_x);
  EXPECT_DOUBLE_EQ(js["corr_length_y_m"].get<double>(), st.corr_length_y);
  EXPECT_EQ(s["inputs"][0]["leveling"], "plane");

  NdfEstimateOptions no;
  no.resolution = 257;
  no.filter_sigma_m = 1e-6;
  const TabulatedNdf ndf = estimate_ndf(surf, no);
  const auto& jf = s["ndf"]["filtered"];
  EXPECT_NEAR(jf["slope_rms_x"].get<double>(), ndf.rms_slope(0), 1e-12);
  EXPECT_NEAR(jf["slope_rms_y"].get<double>(), ndf.rms_slope(M_PI / 2), 1e-12);
  EXPECT_NEAR(jf["integral"].get<double>(), 1.0, 1e-9);
  // Long correlation along x: smoother along x, and the report says the smooth axis is x.
  EXPECT_LT(jf["slope_rms_x"].get<double>(), 0.5 * jf["slope_rms_y"].get<double>());
  EXPECT_NEAR(jf["smooth_axis_angle_rad"].get<double>(), 0.0, 0.05);

  // The lobe spans a few nodes of the 257^2 table: predict tabulates the filtered normals again
  // on a zoomed window (ndf.filtered.zoom) and fits that table.
  ASSERT_TRUE(jf.contains("zoom"));
  const auto& jw = jf["zoom"]["window"];
  const double x0 = jw["x"][0].get<double>(), x1 = jw["x"][1].get<double>();
  const double y0 = jw["y"][0].get<double>(), y1 = jw["y"][1].get<double>();
  NdfEstimateOptions zo = no;
  zo.window = zoom_window(0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.5 * (x1 - x0));
  const TabulatedNdf zoom = estimate_ndf(surf, zo);
  EXPECT_EQ(read_ndf((fs::path(t / "out") / "ndf_filtered_zoom.npy").string()).values(),
            zoom.values());
  EXPECT_GE(4 * std::min(zoom.rms_slope(0), zoom.rms_slope(M_PI / 2)) / zoom.spacing(), 10.0);
  FitOptions fo;
  fo.model = "ellipsoid";
  const FitResult fr = fit_ndf(zoom, fo);
  const auto& jfit = s["fits"][0];
  EXPECT_EQ(jfit["source"], "filtered_zoom");
  EXPECT_EQ(jfit["model"], "ellipsoid");
  EXPECT_NEAR(jfit["params"]["alpha_x"].get<double>(), fr.params.at("alpha_x"),
              1e-9 * fr.params.at("alpha_x"));
  EXPECT_NEAR(jfit["params"]["alpha_y"].get<double>(), fr.params.at("alpha_y"),
              1e-9 * fr.params.at("alpha_y"));
  EXPECT_LT(fr.params.at("alpha_x"), fr.params.at("alpha_y"));
  EXPECT_FALSE(jfit.contains("seconds"));  // wall time only under "timing"

  // Directional albedo of the measured BRDF: the library's estimator on the same BRDF, and
  // physically between a good fraction of R0 and 1 for a metal.
  auto f = std::make_shared<ConductorFresnel>(metal("Fe"));
  MicrofacetBrdf b(std::make_shared<TabulatedDistribution>(ndf), f);
  const Vec3 wi(-std::sin(0.5), 0, std::cos(0.5));
  const double a = directional_albedo_sampled(b, wi, 555e-9, 128);
  const double a_report = s["brdf"]["albedo"][0]["albedo"]["measured"].get<double>();
  EXPECT_NEAR(a_report, a, 1e-12);
  const double r0 = s["material"]["r0_555nm"].get<double>();
  EXPECT_GT(a_report, 0.8 * r0);
  EXPECT_LT(a_report, 1.0);

  // The peak of the in-plane slice sits at the mirror direction (within the slice step and the
  // NDF's tilt) and the slices of every model are in the summary.
  for (const auto& sl : s["brdf"]["slices"]) {
    EXPECT_EQ(sl["values_per_sr"].size(), 4u);  // measured + three fits
    if (sl["plane"] == "in") {
      EXPECT_NEAR(sl["peak"]["measured"]["angle_deg"].get<double>(), 0.5 * 180 / M_PI, 1.0);
    }
  }
  EXPECT_TRUE(s["renders"].contains("skipped"));
  EXPECT_TRUE(s["texture"].contains("skipped"));
  EXPECT_TRUE(s["timing"].contains("total_s"));
}

TEST(Predict, ReportEmbedsEveryImageAndShowsNoNan) {
  TempDir t;
  PredictOptions o = small_options(make_scan(t));
  const PredictResult r = predict(o, t / "out");
  std::string html = slurp(r.report_path);
  // The glTF view's library (three.js from npm, in inert text/plain elements marked data-npm)
  // is code, not what a reader sees: its "null"s are JavaScript. Everything else is checked.
  for (std::size_t at;
       (at = html.find("<script type=\"text/plain\" id=\"mbg-mod-")) != std::string::npos;) {
    const std::size_t end = html.find("</script>", at);
    ASSERT_NE(end, std::string::npos);
    ASSERT_NE(html.substr(at, 200).find("data-npm=\"three@"), std::string::npos);
    html.erase(at, end + 9 - at);
  }
  std::size_t imgs = 0, pos = 0;
  while ((pos = html.find("<img ", pos)) != std::string::npos) {
    ++imgs;
    const auto src = html.find("src=\"", pos);
    ASSERT_NE(src, std::string::npos);
    EXPECT_EQ(html.compare(src + 5, 22, "data:image/png;base64,"), 0);
    EXPECT_NE(html[src + 27], '"');  // non-empty payload
    pos = src;
  }
  EXPECT_GE(imgs, 4u);  // height map, two NDFs, fit comparison
  EXPECT_NE(html.find("<svg"), std::string::npos);
  for (const char* bad : {">nan", ">NaN", ">inf", " nan ", " inf ", "null"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;
  // Every SVG's ids are unique in the page (glyphs of one plot must not show in another).
  EXPECT_EQ(html.find("id=\"glyph"), std::string::npos);
}

TEST(Predict, SameInputsAndSeedGiveTheSameSummary) {
  TempDir t;
  PredictOptions o = small_options(make_scan(t));
  o.render = true;
  o.render_width = 24;
  o.render_spp = 2;
  const PredictResult a = predict(o, t / "a");
  const PredictResult b = predict(o, t / "b");
  ASSERT_TRUE(a.summary["renders"].is_array());
  EXPECT_EQ(without_timing(a.summary).dump(), without_timing(b.summary).dump());
  EXPECT_EQ(slurp(t / "a/img/render_sphere.png"), slurp(t / "b/img/render_sphere.png"));
  // And the seed matters for the renders only where they sample: another seed, other pixels.
  o.seed = 2;
  const PredictResult c = predict(o, t / "c");
  EXPECT_NE(slurp(t / "a/img/render_sphere.png"), slurp(t / "c/img/render_sphere.png"));
}

TEST(Predict, BadInputsLeaveNoOutput) {
  TempDir t;
  const std::string scan = make_scan(t);
  const std::size_t before = entries(t.path);
  auto expect_nothing_left = [&] {
    EXPECT_FALSE(fs::exists(t / "out"));
    EXPECT_EQ(entries(t.path), before);  // no staging folder either
  };
  PredictOptions o = small_options(t / "missing.x3p");
  EXPECT_THROW(predict(o, t / "out"), FileError);
  expect_nothing_left();

  o = small_options(scan);
  o.material = MaterialSpec::named_metal("unobtainium");
  EXPECT_THROW(predict(o, t / "out"), InputError);
  expect_nothing_left();

  o = small_options(scan);
  o.strips_along = {scan};
  EXPECT_THROW(predict(o, t / "out"), InputError);
  expect_nothing_left();

  // A corrupt scan fails in the middle of the run: the staging folder goes away.
  { std::ofstream(t / "corrupt.x3p") << "not a zip archive"; }
  o = small_options(t / "corrupt.x3p");
  try {
    predict(o, t / "out");
    ADD_FAILURE() << "corrupt input accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("corrupt.x3p"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(t / "out"));
  EXPECT_EQ(entries(t.path), before + 1);  // just the corrupt file we made
}

TEST(Predict, ReplacesItsOwnOutputButNoOtherFolder) {
  TempDir t;
  const std::string scan = make_scan(t);
  PredictOptions o = small_options(scan);
  predict(o, t / "out");
  o.material = MaterialSpec::named_metal("Al");
  const PredictResult r = predict(o, t / "out");  // an earlier report: replaced
  EXPECT_EQ(nlohmann::json::parse(slurp(r.summary_path))["material"]["name"], "Al");

  // A trailing slash names the same folder (the staging folder goes beside it, not into it).
  predict(o, t / "out/");
  EXPECT_TRUE(fs::exists(t / "out/summary.json"));
  EXPECT_EQ(entries(t.path), 2u);  // scan.x3p and out
  EXPECT_THROW(predict(o, t / "."), InputError);

  fs::create_directories(t / "mine");
  { std::ofstream(t / "mine/notes.txt") << "keep"; }
  EXPECT_THROW(predict(o, t / "mine"), FileError);
  EXPECT_EQ(slurp(t / "mine/notes.txt"), "keep");
}

TEST(Predict, StripsGiveASynthesisedTexture) {
  TempDir t;
  auto strip = [&](std::size_t nx, std::size_t ny, std::uint64_t seed, const std::string& name) {
    BrushedParams b = brushed_preset("stainless4");
    b.nx = nx;
    b.ny = ny;
    b.dx = b.dy = 0.25e-6;
    b.seed = seed;
    const std::string path = t / name;
    write_surface(generate_brushed(b), path);
    return path;
  };
  PredictOptions o = small_options(make_scan(t));
  o.strips_along = {strip(256, 40, 2, "along.x3p")};    // 8 x 1 texels of 8 um
  o.strips_across = {strip(40, 256, 3, "across.x3p")};  // 1 x 8 texels
  o.texel_m = 8e-6;
  o.texel_resolution = 65;
  o.texture_size = 16;
  o.render = true;
  o.render_width = 16;
  o.render_spp = 1;
  const PredictResult r = predict(o, t / "out");
  const auto& tx = r.summary["texture"];
  ASSERT_FALSE(tx.contains("skipped")) << tx.dump();
  EXPECT_EQ(tx["along"]["nx"], 8);
  EXPECT_EQ(tx["along"]["ny"], 1);
  EXPECT_EQ(tx["across"]["nx"], 1);
  EXPECT_EQ(tx["across"]["ny"], 8);
  EXPECT_EQ(tx["synthesised"]["nx"], 16);
  // Widths below a texel-table node are refitted on zoomed tables; both counts are reported.
  EXPECT_GT(tx["along"]["alpha_zoomed"].get<int>(), 0) << tx["along"].dump();
  EXPECT_TRUE(tx["across"].contains("alpha_lifted_to_min"));
  // The textured render is described like the other renders (the report reads every field; a
  // missing one was a use-after-free under ASan).
  ASSERT_TRUE(tx.contains("render"));
  for (const char* key : {"file", "width", "spp", "uv_scale", "lights"})
    EXPECT_TRUE(tx["render"].contains(key)) << key;
  // The file holds what the summary describes.
  const ParamTexture back = read_param_texture(t / "out/texture.exr");
  ASSERT_EQ(back.nx, 16u);
  const ChannelStats st = channel_stats(back, 1);
  EXPECT_NEAR(tx["synthesised"]["channels"]["alpha_y"]["mean"].get<double>(), st.mean,
              1e-6 * st.mean);
  // Brushed: smoother along the brushing (x) than across, in the exemplar fits.
  EXPECT_LT(tx["along"]["channels"]["alpha_x"]["mean"].get<double>(),
            tx["along"]["channels"]["alpha_y"]["mean"].get<double>());
  EXPECT_TRUE(fs::exists(t / "out/img/render_texture.png"));
  // glTF 2.0 of the texture and of each fit, beside the report (docs/gltf.md).
  ASSERT_TRUE(tx.contains("gltf"));
  EXPECT_EQ(tx["gltf"]["file"], "export/texture.glb");
  EXPECT_GT(fs::file_size(t / "out/export/texture.glb"), 1000u);
  ASSERT_FALSE(r.summary["exports"]["materials"].empty());
  for (const auto& m : r.summary["exports"]["materials"]) {
    const std::string f = m["gltf"]["file"];
    EXPECT_EQ(f, "export/gltf_" + m["model"].get<std::string>() + ".glb");
    EXPECT_TRUE(fs::exists(t / ("out/" + f))) << f;
    EXPECT_NE(slurp(t / "out/report.html").find("href=\"" + f + "\""), std::string::npos) << f;
  }
}

// A real Zygo MetroPro scan (tests/data/metropro-1.dat, provenance in tests/data/README.md):
// its ACF never falls to 1/e along y within the scan, so that correlation length does not exist;
// the summary says null and the report says so in words, never "nan".
TEST(Predict, RealScanWithACorrelationLengthBeyondTheScan) {
  TempDir t;
  PredictOptions o = small_options(std::string(MICROBRDF_TEST_DATA) + "/metropro-1.dat");
  o.ndf_resolution = 129;
  const PredictResult r = predict(o, t / "out");
  const auto& in = r.summary["inputs"][0];
  EXPECT_EQ(in["stats"]["nx"], 640);
  EXPECT_NEAR(in["stats"]["dx_m"].get<double>(), 1.0982520e-6, 1e-12);
  // Plane removed: Sq 13.3 nm (tests/data/README.md reference: 1.3335e-08 m).
  EXPECT_NEAR(in["stats"]["sq_m"].get<double>(), 1.3335e-8, 2e-11);
  EXPECT_TRUE(in["stats"]["corr_length_y_m"].is_null());
  EXPECT_TRUE(in["stats"]["corr_length_x_m"].is_number());
  EXPECT_NE(in["instrument"].get<std::string>().find("Zygo"), std::string::npos);
  const std::string html = slurp(r.report_path);
  EXPECT_NE(html.find("not reached (ACF stays above 1/e over the scan)"), std::string::npos);
  EXPECT_EQ(html.find(">nan"), std::string::npos);
}

// A perfectly flat scan: every normal is n and the NDF is one node (moments 0/0 where a formula
// divides by Sq). The summary is strict JSON, equal in memory and on disk; the report shows no nan.
TEST(Predict, FlatScanGivesNoNan) {
  TempDir t;
  Surface s(64, 48, 0.5e-6, 0.5e-6);
  for (auto& z : s.z) z = 0;
  write_surface(s, t / "flat.x3p");
  PredictOptions o = small_options(t / "flat.x3p");
  o.leveling = LevelingSpec::parse("none");
  o.ndf_resolution = 129;
  const PredictResult r = predict(o, t / "out");
  const std::string html = slurp(r.report_path);
  for (const char* bad : {">nan", ">-nan", ">inf", "nan<", "inf<"})
    EXPECT_EQ(html.find(bad), std::string::npos) << bad;
  EXPECT_EQ(nlohmann::json::parse(slurp(r.summary_path)), r.summary);
  EXPECT_EQ(r.summary["inputs"][0]["stats"]["sq_m"], 0.0);
  EXPECT_NEAR(r.summary["ndf"]["filtered"]["slope_rms_x"].get<double>(), 0.0, 1e-12);
}

namespace {

// RMS over pixels of a luminance vector.
double rms(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x * x;
  return std::sqrt(s / static_cast<double>(v.size()));
}

}  // namespace

TEST(Predict, NoiseFromTheHalvesOfOneRenderMatchesTwoIndependentRenders) {
  // The comparison strip knows the reference render's noise from the two halves of its samples
  // (report::render_split), without a second render. Check that estimate against its definition:
  // two renders with other seeds differ by sqrt(2) x the noise of one. For the Sobol' sampler
  // the halves of one sequence are slightly anti-correlated, so the estimate may err high (by
  // 8% here), never much low. Cylinder pair under the courtyard map, copper GGX (0.08, 0.3),
  // 48 x 48 px, 16 spp, rendered as the strip renders it: along shared paths with a model
  // (here a wider GGX), whose sampler shares in drawing the directions.
  report::PredictScene sc;
  sc.geometry.kind = PreviewScene::Cylinders;
  sc.lights.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr";
  auto b = std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.08, 0.3),
                                            std::make_shared<ConductorFresnel>(metal("Cu")));
  const std::vector<std::shared_ptr<const Svbrdf> > mats{std::make_shared<UniformSvbrdf>(b)};
  auto wide = std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.12, 0.4),
                                               std::make_shared<ConductorFresnel>(metal("Cu")));
  const std::vector<std::vector<std::shared_ptr<const Svbrdf> > > variants{
      mats, {std::make_shared<UniformSvbrdf>(wide)}};
  RenderOptions o;
  o.width = o.height = 48;
  o.spp = 16;
  o.threads = 2;
  std::vector<double> estimates, independent;
  for (std::uint64_t seed : {1, 21, 41}) {
    o.seed = seed;
    std::vector<double> n1, n2;
    const RenderImage a = report::render_split(sc, variants, o, n1).front();
    o.seed = seed + 10;
    const RenderImage c = report::render_split(sc, variants, o, n2).front();
    const auto ya = detail::luminance(a.rgb), yc = detail::luminance(c.rgb);
    std::vector<double> diff(ya.size());
    for (std::size_t i = 0; i < ya.size(); ++i) diff[i] = (ya[i] - yc[i]) / std::sqrt(2.0);
    estimates.push_back(0.5 * (rms(n1) + rms(n2)));
    independent.push_back(rms(diff));
    // The average of the halves is an image of the scene, not of the noise: far above it.
    EXPECT_GT(rms(ya), 2 * rms(n1));
  }
  double e = 0, r = 0;
  for (std::size_t k = 0; k < estimates.size(); ++k) e += estimates[k], r += independent[k];
  std::printf("noise from halves %.5g, from independent renders %.5g (ratio %.3f)\n", e / 3, r / 3,
              e / r);
  // 2304 pixels each: the RMS of either estimate scatters by a few per cent.
  EXPECT_GT(e / r, 0.95);
  EXPECT_LT(e / r, 1.25);
  // One sample per pixel: a second render, and the same relation.
  o.spp = 1;
  o.seed = 5;
  std::vector<double> n1;
  const auto one = report::render_split(sc, variants, o, n1);
  ASSERT_EQ(one.size(), 2u);
  EXPECT_EQ(one[0].rgb.size(), 48u * 48u * 3u);
  EXPECT_GT(rms(n1), 0);
}

TEST(Predict, StudioViewFromTheSharedPassMatchesItsOwnRender) {
  // predict's studio view: the first variant under the studio map as a second light set of the
  // compared scene's pass at twice the size, 2 x 2 pixels averaged (report::half_size). Against
  // the studio view rendered on its own at the half size with 4x the samples: image means
  // within 1.5%, per-pixel agreement at the noise level; half_size is the exact block mean.
  report::PredictScene sc;
  sc.geometry.kind = PreviewScene::Sphere;
  sc.lights.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_courtyard.exr";
  RenderLights studio;
  studio.envmap_path = std::string(MICROBRDF_DATA) + "/envmaps/blender_studio.exr";
  auto metal_ggx = [](double ax, double ay) -> std::shared_ptr<const Svbrdf> {
    return std::make_shared<UniformSvbrdf>(
        std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(ax, ay),
                                         std::make_shared<ConductorFresnel>(metal("Cu"))));
  };
  const std::vector<std::vector<std::shared_ptr<const Svbrdf> > > variants{{metal_ggx(0.1, 0.3)},
                                                                           {metal_ggx(0.15, 0.35)}};
  RenderOptions o;
  o.width = o.height = 48;
  o.spp = 64;
  o.threads = 2;
  o.direct = DirectLight::Mis;
  o.variant_weights = {1, 1};
  std::vector<double> noise;
  const auto imgs = report::render_split(sc, variants, o, noise, {studio});
  ASSERT_EQ(imgs.size(), 3u);  // two variants under the courtyard, the first under the studio
  const RenderImage shared = report::half_size(imgs[2]);
  ASSERT_EQ(shared.width, 24);
  ASSERT_EQ(shared.height, 24);
  EXPECT_FLOAT_EQ(
      shared.rgb[3 * (5 * 24 + 7) + 1],
      float((double(imgs[2].rgb[3 * (10 * 48 + 14) + 1]) + imgs[2].rgb[3 * (10 * 48 + 15) + 1] +
             imgs[2].rgb[3 * (11 * 48 + 14) + 1] + imgs[2].rgb[3 * (11 * 48 + 15) + 1]) /
            4));
  RenderOptions alone = o;
  alone.width = alone.height = 24;
  alone.spp = 4 * o.spp;
  alone.variant_weights.clear();
  const RenderImage own = render(sc.geometry, variants.front(), studio, alone);
  const auto ys = detail::luminance(shared.rgb), yo = detail::luminance(own.rgb);
  double ms = 0, mo = 0;
  for (std::size_t i = 0; i < ys.size(); ++i) ms += ys[i], mo += yo[i];
  EXPECT_NEAR(ms / mo, 1.0, 0.015);
  std::vector<double> d(ys.size());
  for (std::size_t i = 0; i < ys.size(); ++i) d[i] = ys[i] - yo[i];
  // The difference of two independent estimates: noise, far below the image itself.
  EXPECT_LT(rms(d), 0.25 * rms(yo));
  RenderImage odd;
  odd.width = 3;
  odd.height = 2;
  odd.rgb.assign(18, 1.0f);
  EXPECT_THROW(report::half_size(odd), std::invalid_argument);
}

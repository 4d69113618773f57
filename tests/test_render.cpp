// The preview renderer: furnace, mirror, MIS consistency, determinism, anisotropy.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <string>

#include "microbrdf/brdf.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/lambertian_brdf.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/mirror_brdf.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/spectrum.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/distribution2d.hpp"
#include "render/envmap.hpp"
#include "render/material.hpp"
#include "render/scene.hpp"
#include "render/spectral.hpp"
#include "render_test_util.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;
using namespace std::string_literals;

namespace {

const std::string kEnvmaps = std::string(MICROBRDF_DATA) + "/envmaps";

std::vector<std::shared_ptr<const Svbrdf>> one(std::shared_ptr<const Brdf> b) {
  return {std::make_shared<UniformSvbrdf>(std::move(b))};
}

RenderOptions small(int size, int spp, int wavelengths = 4) {
  RenderOptions o;
  o.width = o.height = size;
  o.spp = spp;
  o.wavelengths = wavelengths;
  o.threads = 2;
  return o;
}

using test::mean_rgb;

/// A scratch directory for this process, removed at exit.
std::string temp_dir() {
  struct Dir {
    std::string path;
    Dir() {
      path =
          (fs::temp_directory_path() / ("microbrdf_render_" + std::to_string(::getpid()))).string();
      fs::create_directories(path);
    }
    ~Dir() {
      std::error_code ec;
      fs::remove_all(path, ec);
    }
  };
  static Dir d;
  return d.path;
}

/// A smooth synthetic sky: colour varying slowly with direction (no detail finer than a pixel
/// of the render), written as a Radiance file.
std::string smooth_envmap() {
  pt::RgbFloatImage img;
  img.width = 256;
  img.height = 128;
  img.rgb.resize(256 * 128 * 3);
  for (int r = 0; r < 128; ++r)
    for (int c = 0; c < 256; ++c) {
      const double th = M_PI * (r + 0.5) / 128, ph = 2 * M_PI * (c + 0.5) / 256;
      float* p = &img.rgb[(r * 256 + c) * 3];
      p[0] = float(0.6 + 0.4 * std::cos(th));
      p[1] = float(0.5 + 0.3 * std::sin(ph) * std::sin(th));
      p[2] = float(0.4 + 0.3 * std::cos(ph) * std::sin(th) + 0.2 * (1 - std::cos(th)));
    }
  const std::string path = temp_dir() + "/smooth.hdr";
  pt::write_radiance_hdr(img, path);
  return path;
}

}  // namespace

TEST(Render, FurnaceLambertianSphereIsOne) {
  RenderScene sc;
  sc.kind = PreviewScene::FurnaceSphere;
  RenderLights l;
  l.uniform_white_env = true;
  for (MisMode mode : {MisMode::Mis, MisMode::BrdfOnly, MisMode::LightOnly}) {
    // Light sampling alone wastes half its samples below the horizon: more samples.
    auto o = small(32, mode == MisMode::LightOnly ? 512 : 64);
    o.mis = mode;
    auto img = render(sc, one(std::make_shared<LambertianBrdf>(1.0)), l, o);
    // Only the sphere's pixels (the centre 16 x 16 lies inside it).
    Eigen::Vector3d m = Eigen::Vector3d::Zero();
    for (int y = 8; y < 24; ++y)
      for (int x = 8; x < 24; ++x)
        for (int c = 0; c < 3; ++c) m[c] += img.rgb[(y * 32 + x) * 3 + c] / 256.0;
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], 1.0, 0.01) << "mode " << int(mode) << " ch " << c;
  }
}

TEST(Render, FurnaceHalfAlbedoSphereIsHalf) {
  RenderScene sc;
  sc.kind = PreviewScene::FurnaceSphere;
  RenderLights l;
  l.uniform_white_env = true;
  auto img = render(sc, one(std::make_shared<LambertianBrdf>(0.5)), l, small(32, 32));
  double m = 0;
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x) m += img.rgb[(y * 32 + x) * 3 + 1] / 256.0;
  EXPECT_NEAR(m, 0.5, 0.005);  // a convex object sees only the sky: one bounce
}

TEST(Render, MirrorSphereReflectsTheEnvironment) {
  // An ideal mirror (a delta lobe: pdf 0) on the sphere: each pixel must show the map in the
  // mirror direction of the camera ray (a smooth map, so the pixel footprint hardly matters).
  const std::string env = smooth_envmap();
  RenderScene sc;
  sc.kind = PreviewScene::Sphere;
  RenderLights l;
  l.envmap_path = env;
  const int n = 48;
  auto o = small(n, 64, 16);
  auto img = render(sc, one(std::make_shared<SpecularMirrorBrdf>()), l, o);
  const pt::EnvironmentMap map(pt::read_envmap_image(env));
  const pt::Camera cam = pt::preview_camera(PreviewScene::Sphere);
  int checked = 0, wx = 0, wy = 0;
  double worst = 0, mean_err = 0;
  Eigen::Vector3d bias = Eigen::Vector3d::Zero();
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x) {
      const Eigen::Vector3d d = cam.direction(x + 0.5, y + 0.5, n, n);
      const Eigen::Vector3d oc = cam.position;  // sphere at the origin, radius 1
      const double b = oc.dot(d), disc = b * b - (oc.squaredNorm() - 1);
      Eigen::Vector3d want;
      bool inside = disc > 0.05;  // away from the silhouette
      if (inside) {
        const Eigen::Vector3d p = oc + (-b - std::sqrt(disc)) * d, nrm = p.normalized();
        want = map.rgb(d - 2 * d.dot(nrm) * nrm);
      } else if (disc < -0.05) {
        want = map.rgb(d);  // the background
      } else {
        continue;
      }
      for (int c = 0; c < 3; ++c) {
        const double got = img.rgb[(y * n + x) * 3 + c];
        const double err = std::abs(got - want[c]) / want[c];
        bias[c] += (got - want[c]) / want[c];
        mean_err += err / 3;
        if (err > worst) worst = err, wx = x, wy = y;
      }
      ++checked;
    }
  EXPECT_GT(checked, n * n * 3 / 4);
  // Hero-wavelength colour noise (64 spp x 16 wavelengths) is about 1% per pixel.
  EXPECT_LT(worst, 0.06) << "largest relative pixel error, at " << wx << ", " << wy;
  EXPECT_LT(mean_err / checked, 0.01);
  for (int c = 0; c < 3; ++c) EXPECT_LT(std::abs(bias[c] / checked), 0.003) << "channel " << c;
}

TEST(Render, MisAgreesWithEachStrategy) {
  // A rough copper sphere under a smooth map and a large sphere light: MIS, BRDF sampling alone
  // and light sampling alone estimate the same image. (Small bright sources make BRDF sampling
  // alone too noisy for a 2% test; CLI runs with the bundled maps agree within their noise.)
  RenderScene sc;
  sc.kind = PreviewScene::Sphere;
  RenderLights l;
  l.envmap_path = smooth_envmap();
  l.spheres.push_back({Eigen::Vector3d(3, 3, 3), 1.5, Eigen::Vector3d(4, 4, 4)});
  auto d = std::make_shared<GgxDistribution>(0.3);
  auto b = std::make_shared<MicrofacetBrdf>(d, std::make_shared<ConductorFresnel>(metal("Cu")));
  Eigen::Vector3d m[3];
  int i = 0;
  for (MisMode mode : {MisMode::Mis, MisMode::BrdfOnly, MisMode::LightOnly}) {
    auto o = small(16, 1024);
    o.mis = mode;
    m[i++] = mean_rgb(render(sc, one(b), l, o));
  }
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(m[1][c] / m[0][c], 1.0, 0.02) << "brdf only, channel " << c;
    EXPECT_NEAR(m[2][c] / m[0][c], 1.0, 0.02) << "light only, channel " << c;
  }
}

TEST(Render, SameSeedSameImageWhateverTheThreads) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  auto b = std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(0.05, 0.2),
                                            std::make_shared<ConductorFresnel>(metal("Al")));
  auto o = small(16, 4);
  o.threads = 1;
  const auto a1 = render(sc, one(b), l, o);
  o.threads = 2;
  const auto a2 = render(sc, one(b), l, o);
  EXPECT_EQ(a1.rgb, a2.rgb);
  o.seed = 2;
  const auto a3 = render(sc, one(b), l, o);
  EXPECT_NE(a1.rgb, a3.rgb);
}

TEST(Render, BrushingDirectionTurnsTheHighlight) {
  // Turning the tangent by 90 degrees (Dong Fig. 10's left vs right cylinder) changes the image
  // of an anisotropic surface and leaves an isotropic one's unchanged up to noise. Measured on
  // 4 x 4-pixel block means, against the difference between two seeds at the same angle.
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  auto f = std::make_shared<ConductorFresnel>(metal("Fe"));
  auto aniso =
      std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(0.007, 0.14), f);
  auto iso = std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(0.07), f);
  auto block_diff = [](const RenderImage& a, const RenderImage& c) {
    double diff = 0, sum = 0;
    for (int by = 0; by < 8; ++by)
      for (int bx = 0; bx < 8; ++bx) {
        double ma = 0, mc = 0;
        for (int y = 4 * by; y < 4 * by + 4; ++y)
          for (int x = 4 * bx; x < 4 * bx + 4; ++x)
            for (int ch = 0; ch < 3; ++ch) {
              ma += a.rgb[(y * 32 + x) * 3 + ch];
              mc += c.rgb[(y * 32 + x) * 3 + ch];
            }
        diff += std::abs(ma - mc);
        sum += ma;
      }
    return diff / sum;
  };
  auto run = [&](std::shared_ptr<const Brdf> b, double angle, std::uint64_t seed) {
    auto o = small(32, 64);
    o.seed = seed;
    sc.brush_angle_rad = angle;
    return render(sc, one(b), l, o);
  };
  const auto iso0 = run(iso, 0, 1), iso0b = run(iso, 0, 2), iso90 = run(iso, M_PI / 2, 3);
  const auto an0 = run(aniso, 0, 1), an0b = run(aniso, 0, 2), an90 = run(aniso, M_PI / 2, 3);
  const double noise_iso = block_diff(iso0, iso0b), noise_an = block_diff(an0, an0b);
  const double d_iso = block_diff(iso0, iso90), d_an = block_diff(an0, an90);
  EXPECT_LT(d_iso, 1.5 * noise_iso + 0.01) << "noise " << noise_iso;
  EXPECT_GT(d_an, 0.15);
  EXPECT_GT(d_an, 3 * noise_an) << "noise " << noise_an;
}

TEST(Render, RadianceHdrRoundTripAndExrAgreement) {
  pt::RgbFloatImage img;
  img.width = 9;
  img.height = 4;
  for (int i = 0; i < 36; ++i)
    img.rgb.insert(img.rgb.end(), {float(0.01 * (i + 1)), float(i * 3.5), float(1e-3 * i)});
  const std::string p = temp_dir() + "/rt.hdr";
  pt::write_radiance_hdr(img, p);
  const auto back = pt::read_envmap_image(p);
  ASSERT_EQ(back.width, 9);
  ASSERT_EQ(back.height, 4);
  for (int i = 0; i < 36; ++i) {
    const float m = std::max({img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]});
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(back.rgb[3 * i + c], img.rgb[3 * i + c], 0.008 * m);
  }
  // The studio map in both encodings (RLE RGBE and DWAB EXR) agrees to RGBE's precision.
  const auto e = pt::read_envmap_image(kEnvmaps + "/blender_studio.exr");
  const auto h = pt::read_envmap_image(kEnvmaps + "/blender_studio.hdr");
  ASSERT_EQ(e.width, 1024);
  ASSERT_EQ(h.width, 1024);
  ASSERT_EQ(e.height, h.height);
  double worst = 0;
  std::size_t at = 0;
  for (std::size_t i = 0; i < e.rgb.size() / 3; ++i) {
    const float m = std::max({e.rgb[3 * i], e.rgb[3 * i + 1], e.rgb[3 * i + 2], 1e-2f});
    for (int c = 0; c < 3; ++c) {
      const double err = std::abs(std::max(e.rgb[3 * i + c], 0.0f) - h.rgb[3 * i + c]) / m;
      if (err > worst) worst = err, at = i;
    }
  }
  EXPECT_LT(worst, 0.01) << "pixel " << at << ": exr " << e.rgb[3 * at] << " " << e.rgb[3 * at + 1]
                         << " " << e.rgb[3 * at + 2] << ", hdr " << h.rgb[3 * at] << " "
                         << h.rgb[3 * at + 1] << " " << h.rgb[3 * at + 2];
}

TEST(Render, CorruptRadianceFilesAreRefused) {
  auto bad = [](const std::string& text) {
    std::vector<std::uint8_t> d(text.begin(), text.end());
    EXPECT_THROW(pt::read_radiance_hdr_bytes(d, "bad.hdr"), FileError) << text;
  };
  bad("#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 2\n");      // no pixels
  bad("#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 1 +X 1\nabcd");  // XYZE
  bad("#?RADIANCE\n\n+Y 1 +X 1\nabcd");                          // orientation
  bad("#?RADIANCE\n\n-Y 100000 +X 100000\nabcd");                // huge
  bad("#?RADIANCE\n\n-Y 1 +X 8\n\x02\x02\x00\x08\xff\x01"s);     // run overflows
  bad("#?RADIANCE\nFORMAT=32-bit_rle_rgbe");                     // truncated header
  std::vector<std::uint8_t> ok = {'#', '?', 'R', 'G', 'B', 'E', '\n', '\n', '-', 'Y', ' ',
                                  '1', ' ', '+', 'X', ' ', '1', '\n', 128,  64,  32,  129};
  const auto img = pt::read_radiance_hdr_bytes(ok, "ok.hdr");
  EXPECT_NEAR(img.rgb[0], (128 + 0.5) / 128.0, 1e-6);
}

TEST(Render, EnvironmentSamplingPdfIntegratesToOne) {
  const pt::EnvironmentMap map(pt::read_envmap_image(kEnvmaps + "/blender_courtyard.exr"), 1.0,
                               0.7);
  // Integral of pdf over the sphere (midpoint rule on a fine grid) and the pdf of sampled
  // directions matching pdf().
  double sum = 0;
  const int nt = 1024, np = 2048;
  for (int i = 0; i < nt; ++i)
    for (int j = 0; j < np; ++j) {
      const double th = M_PI * (i + 0.5) / nt, ph = 2 * M_PI * (j + 0.5) / np;
      const Eigen::Vector3d d(std::sin(th) * std::cos(ph), std::cos(th),
                              std::sin(th) * std::sin(ph));
      sum += map.pdf(d) * std::sin(th) * (M_PI / nt) * (2 * M_PI / np);
    }
  EXPECT_NEAR(sum, 1.0, 2e-3);
  for (int k = 0; k < 100; ++k) {
    double pdf;
    Eigen::Vector3d rgb;
    const auto d = map.sample((k + 0.5) / 100, std::fmod(k * 0.618, 1.0), pdf, &rgb);
    EXPECT_NEAR(map.pdf(d), pdf, 1e-6 * pdf + 1e-9);
    EXPECT_EQ(map.rgb(d), rgb);
  }
}

TEST(Render, BadInputsAreRefused) {
  RenderScene sc;
  RenderLights none;
  auto m = one(std::make_shared<LambertianBrdf>(0.5));
  EXPECT_THROW(render(sc, m, none, small(8, 1)), InputError);  // no light
  RenderLights l;
  l.uniform_white_env = true;
  auto three = m;
  three.push_back(m[0]);
  three.push_back(m[0]);
  EXPECT_THROW(render(sc, three, l, small(8, 1)), InputError);  // cylinders take 1 or 2
  EXPECT_THROW(parse_preview_scene("teapot"), InputError);
  sc.kind = PreviewScene::Obj;
  sc.obj_path = "/nonexistent.obj";
  EXPECT_THROW(render(sc, m, l, small(8, 1)), FileError);
  l.uniform_white_env = false;
  l.envmap_path = "/nonexistent.hdr";
  sc.kind = PreviewScene::Sphere;
  EXPECT_THROW(render(sc, m, l, small(8, 1)), FileError);
}

TEST(Render, EnvironmentDistributionDrawsCellsWithTheirWeights) {
  // 8 x 4 cells with uneven weights (one empty): frequencies of 400 000 draws match the weights
  // within 5 standard deviations, and the reported density is w_i n / sum.
  std::vector<double> w(32);
  double sum = 0;
  for (int i = 0; i < 32; ++i) sum += (w[i] = i == 5 ? 0.0 : 1 + (i * 7) % 11);
  const pt::PiecewiseConstant2D d(w, 8, 4);
  std::vector<int> count(32, 0);
  std::uint64_t s = 12345;
  auto uni = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return double(s >> 11) * 0x1.0p-53;
  };
  const int n = 400000;
  for (int k = 0; k < n; ++k) {
    double u, v, pdf;
    const double u1 = uni(), u2 = uni();
    d.sample(u1, u2, u, v, pdf);
    const int col = int(u * 8), row = int(v * 4);
    ASSERT_NEAR(pdf, w[row * 8 + col] * 32 / sum, 1e-5);
    ++count[row * 8 + col];
  }
  for (int i = 0; i < 32; ++i) {
    const double p = w[i] / sum, sd = std::sqrt(n * p * (1 - p));
    EXPECT_NEAR(count[i], n * p, 5 * sd + 1e-9) << "cell " << i;
  }
}

TEST(Render, SpectralMaterialEqualsTheBrdf) {
  // The microfacet fast path (D G2 once, Fresnel per wavelength) gives what eval() gives, for
  // both shadowing forms; other BRDFs go through eval() per wavelength.
  auto f = std::make_shared<ConductorFresnel>(metal("Au"));
  for (bool separable : {false, true}) {
    auto b = std::make_shared<MicrofacetBrdf>(
        std::make_shared<EllipsoidDistribution>(EllipsoidParams{0.05, 0.3, 0.1, -0.05, 0.4}), f,
        separable);
    const pt::SpectralMaterial m(std::make_shared<UniformSvbrdf>(b));
    EXPECT_TRUE(m.fast());
    const double lambda[3] = {400e-9, 555e-9, 700e-9};
    for (int i = 0; i < 50; ++i) {
      const double ti = 0.03 * i, to = 1.5 - 0.029 * i, p = 0.37 * i;
      const Vec3 wi(std::sin(ti), 0, std::cos(ti));
      const Vec3 wo(std::sin(to) * std::cos(p), std::sin(to) * std::sin(p), std::cos(to));
      double got[3];
      m.eval(0.3, 0.7, wi, wo, lambda, 3, got);
      for (int k = 0; k < 3; ++k)
        EXPECT_NEAR(got[k], b->eval(wi, wo, lambda[k]), 1e-12 * b->eval(wi, wo, lambda[k]));
    }
  }
  const pt::SpectralMaterial lam(one(std::make_shared<LambertianBrdf>(0.5))[0]);
  EXPECT_FALSE(lam.fast());
}

TEST(Render, ExrOutputReadsBack) {
  RenderImage img;
  img.width = 5;
  img.height = 3;
  for (int i = 0; i < 45; ++i) img.rgb.push_back(float(0.01 * i * i));
  img.settings = "test";
  const std::string p = temp_dir() + "/out.exr";
  write_render_exr(img, p);
  const auto back = pt::read_exr_rgb(p);
  ASSERT_EQ(back.width, 5);
  ASSERT_EQ(back.height, 3);
  for (int i = 0; i < 45; ++i) EXPECT_NEAR(back.rgb[i], img.rgb[i], 1e-3 * img.rgb[i] + 1e-6);
  EXPECT_THROW(write_render_exr(RenderImage{}, temp_dir() + "/empty.exr"), FileError);
  EXPECT_FALSE(fs::exists(temp_dir() + "/empty.exr"));
}

TEST(Render, OneMaterialPerCylinder) {
  // The cylinder pair takes one material per cylinder: white on the left, half grey on the
  // right, under the white sky. Each cylinder sees mostly the sky, a little of its neighbour.
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.uniform_white_env = true;
  std::vector<std::shared_ptr<const Svbrdf>> m = {one(std::make_shared<LambertianBrdf>(1.0))[0],
                                                  one(std::make_shared<LambertianBrdf>(0.5))[0]};
  const auto img = render(sc, m, l, small(40, 64));
  auto column_mean = [&](int x) {
    double s = 0;
    for (int y = 10; y < 30; ++y) s += img.rgb[(y * 40 + x) * 3 + 1] / 20;
    return s;
  };
  // Pixel columns through the middle of each cylinder (x = -0.5 and +0.5 at the axis plane).
  EXPECT_NEAR(column_mean(11), 1.0, 0.03);
  EXPECT_NEAR(column_mean(28), 0.5, 0.03);
}

TEST(Render, UpsamplingBasisReproducesColours) {
  // The three basis spectra have the linear sRGB colours (1,0,0), (0,1,0), (0,0,1) under the
  // renderer's own XYZ estimator (mean over uniform wavelengths), and they sum to 1 (white is
  // flat).
  const auto& t = pt::SpectralTables::get();
  const Eigen::Matrix3d to_rgb = xyz_to_linear_srgb_matrix();
  Eigen::Matrix3d rgb = Eigen::Matrix3d::Zero();
  const int n = 47000;
  double lo = 1e9;
  for (int i = 0; i < n; ++i) {
    const double l = 360 + 470 * (i + 0.5) / n;
    const Eigen::Vector3d b = t.basis(l), w = t.xyz_weight(l);
    EXPECT_NEAR(b.sum(), 1.0, 1e-12);
    lo = std::min(lo, b.minCoeff());
    for (int c = 0; c < 3; ++c) rgb.col(c) += to_rgb * w * b[c] / n;
  }
  // (The smooth spectra were fitted with the 5 nm sums; the renderer integrates continuously.)
  EXPECT_LT((rgb - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 3e-3) << rgb;
  EXPECT_GT(lo, -0.2) << lo;  // mild negative dips where another primary rises  // bounded (basis
                              // spectra may dip below 0 where another primary rises)
  // White (flat 1) maps to (1, 1, 1).
  Eigen::Vector3d white = Eigen::Vector3d::Zero();
  for (int i = 0; i < n; ++i) white += to_rgb * t.xyz_weight(360 + 470 * (i + 0.5) / n) / n;
  EXPECT_LT((white - Eigen::Vector3d::Ones()).cwiseAbs().maxCoeff(), 2e-3) << white.transpose();
}

TEST(Render, RadianceReaderSurvivesMutations) {
  // 3000 randomly mutated copies of the head of a real run-length-encoded map (a poor man's
  // fuzzer; run under ASan too): each is read or refused with FileError, nothing else.
  const std::string path = kEnvmaps + "/blender_studio.hdr";
  std::vector<std::uint8_t> full = read_file_bytes(path, 1u << 26);
  std::vector<std::uint8_t> head(full.begin(), full.begin() + 24000);
  std::uint64_t s = 99;
  auto next = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return s >> 33;
  };
  int refused = 0;
  for (int it = 0; it < 3000; ++it) {
    auto d = head;
    const int edits = 1 + int(next() % 8);
    for (int e = 0; e < edits; ++e) d[next() % d.size()] = std::uint8_t(next());
    if (it % 3 == 0) d.resize(next() % d.size());
    try {
      pt::read_radiance_hdr_bytes(d, "mutated.hdr");
    } catch (const FileError&) {
      ++refused;
    }
  }
  EXPECT_GT(refused, 0);
}

TEST(Render, NormalizingExposureTakesTheBrightestPixelsToWhite) {
  // 10^4 pixels whose largest channel runs 0.0004 ... 4 (one channel per pixel in turn): the
  // 99.9th percentile is 3.9964 (the 9991st value), so the exposure is -log2(3.9964); a firefly
  // of 10^6 moves it by one place only; the median gives about -1; a black image gets 0.
  RenderImage img;
  img.width = 10000;
  img.height = 1;
  img.rgb.assign(30000, 0.0f);
  for (int i = 0; i < 10000; ++i) img.rgb[3 * i + i % 3] = 0.0004f * float(i + 1);
  EXPECT_NEAR(normalizing_exposure(img), -std::log2(3.9964), 1e-5);
  img.rgb[0] = 1e6f;  // a firefly
  EXPECT_NEAR(normalizing_exposure(img), -std::log2(3.9968), 1e-5);
  EXPECT_NEAR(normalizing_exposure(img, 0.5), -1, 1e-3);
  std::fill(img.rgb.begin(), img.rgb.end(), 0.0f);
  EXPECT_EQ(normalizing_exposure(img), 0.0);
}

TEST(Render, FastPixelLookupEqualsTheDefinition) {
  // pixel_of (polynomial guess, exact tests against the pixel edges) against pixel_of_exact
  // (acos, atan2) for random directions, directions on and next to the pixel edges, the poles
  // and the seam, with and without a rotation; and direction_in_pixel against direction().
  for (double rot : {0.0, 0.7, -2.1}) {
    const pt::EnvironmentMap map(pt::read_envmap_image(kEnvmaps + "/blender_courtyard.exr"), 1.0,
                                 rot);
    const int w = map.width(), h = map.height();
    std::uint64_t s = 99;
    auto uni = [&] {
      s = s * 6364136223846793005ull + 1442695040888963407ull;
      return double(s >> 11) * 0x1.0p-53;
    };
    auto check = [&](const Eigen::Vector3d& d) {
      int c0, r0, c1, r1;
      map.pixel_of(d, c0, r0);
      map.pixel_of_exact(d, c1, r1);
      return c0 == c1 && r0 == r1;
    };
    int bad = 0;
    for (int k = 0; k < 200000; ++k) {
      const double z = 2 * uni() - 1, phi = 2 * M_PI * uni(), r = std::sqrt(1 - z * z);
      bad += !check(Eigen::Vector3d(r * std::cos(phi), z, r * std::sin(phi)));
    }
    EXPECT_EQ(bad, 0);
    // Centres and points 1e-9 of a pixel inside each edge of a grid of pixels (the two lookups
    // may differ only by rounding exactly on an edge).
    bad = 0;
    for (int r = 0; r < h; r += 7)
      for (int c = 0; c < w; c += 5)
        for (double fu : {1e-9, 0.5, 1 - 1e-9})
          for (double fv : {1e-9, 0.5, 1 - 1e-9}) {
            double st;
            const Eigen::Vector3d d = map.direction_in_pixel(c, fu, r, fv, st);
            const Eigen::Vector3d ref = map.direction((c + fu) / w, (r + fv) / h);
            ASSERT_LT((d - ref).norm(), 1e-14);
            ASSERT_NEAR(st, std::sin(M_PI * (r + fv) / h), 1e-14);
            int c0, r0;
            map.pixel_of(d, c0, r0);
            bad += c0 != c || r0 != r;
            bad += !check(d);
          }
    EXPECT_EQ(bad, 0);
    // Directions swept through y in steps finer than the table of rows by y that pixel_of reads
    // (8 cells per row), and 1e-13 either side of every row edge, at several azimuths.
    bad = 0;
    for (int i = 0; i <= 64 * h; ++i)
      for (double phi : {0.3, 2.0, -1.1}) {
        const double y = 1 - 2.0 * i / (64.0 * h), r = std::sqrt(std::max(0.0, 1 - y * y));
        bad += !check(Eigen::Vector3d(r * std::cos(phi), y, r * std::sin(phi)));
      }
    for (int row = 1; row < h; ++row)
      for (double dy : {-1e-13, 1e-13}) {
        const double y = std::cos(M_PI * row / h) + dy, r = std::sqrt(1 - y * y);
        bad += !check(Eigen::Vector3d(r * 0.6, y, r * 0.8));
      }
    EXPECT_EQ(bad, 0);
    // The poles, and directions exactly on a pixel edge (there either side is right: both
    // lookups round, and a sampled direction never lies on an edge).
    for (const Eigen::Vector3d& d :
         {Eigen::Vector3d(0, 1, 0), Eigen::Vector3d(0, -1, 0), Eigen::Vector3d(1e-300, 1, 0),
          Eigen::Vector3d(0, 0.6, 0.8), Eigen::Vector3d(0, 0.6, -0.8),
          Eigen::Vector3d(-0.8, 0.6, 0)}) {
      int c0, r0, c1, r1;
      map.pixel_of(d, c0, r0);
      map.pixel_of_exact(d, c1, r1);
      const int dc = std::abs(c0 - c1);
      EXPECT_TRUE(dc <= 1 || dc == w - 1) << d.transpose();
      EXPECT_LE(std::abs(r0 - r1), 1) << d.transpose();
    }
  }
}

TEST(Render, FastSpectrumEqualsSpectrum) {
  for (const char* name : {"Cu", "Au", "SS-austenitic", "Al"}) {
    const OpticalConstants c = metal(name);
    for (const Spectrum* sp : {&c.n, &c.k}) {
      const pt::FastSpectrum f(*sp);
      for (int i = 0; i <= 20000; ++i) {
        const double l = 300e-9 + 600e-9 * i / 20000;
        ASSERT_EQ(f(l), (*sp)(l)) << name << " " << l;
      }
      for (double l : sp->wavelengths()) {  // the nodes themselves and their neighbours
        ASSERT_EQ(f(l), (*sp)(l));
        ASSERT_EQ(f(std::nextafter(l, 0.0)), (*sp)(std::nextafter(l, 0.0)));
        ASSERT_EQ(f(std::nextafter(l, 1.0)), (*sp)(std::nextafter(l, 1.0)));
      }
    }
  }
}

TEST(Render, SpectralMaterialSamplesLikeTheBrdf) {
  // The fast path's BRDF sample (direction, density, weight per wavelength), the light sample's
  // f and MIS density against MicrofacetBrdf::sample / eval / pdf, for analytic and tabulated
  // distributions (GGX, Beckmann, a 257^2 table), conductors and a Schlick Fresnel term.
  auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  auto schlick = std::make_shared<SchlickFresnel>(Spectrum::constant(0.5));
  std::vector<std::shared_ptr<MicrofacetBrdf>> brdfs = {
      std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.08, 0.3, 0.2), cu),
      std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(0.2, 0.05), schlick,
                                       true),
      std::make_shared<MicrofacetBrdf>(std::make_shared<TabulatedDistribution>(tabulate(
                                           BeckmannDistribution(0.3, 0.15), "beckmann", 257)),
                                       cu)};
  const double lambda[4] = {380e-9, 480e-9, 600e-9, 790e-9};
  for (const auto& b : brdfs) {
    const pt::SpectralMaterial m(std::make_shared<UniformSvbrdf>(b));
    ASSERT_TRUE(m.fast()) << b->describe();
    pt::SpectralMaterial::Wavelengths w;
    m.prepare(lambda, 4, w);
    int sampled = 0;
    for (int i = 0; i < 400; ++i) {
      const double tv = 1.5 * (i % 20) / 20, pv = 0.31 * i;
      const Vec3 wv(std::sin(tv) * std::cos(pv), std::sin(tv) * std::sin(pv), std::cos(tv));
      const auto view = m.view(wv);
      const double u1 = (i + 0.5) / 400, u2 = std::fmod(0.618034 * i, 1.0);
      pt::SpectralMaterial::Sample s;
      const bool got = m.sample(0, 0, view, u1, u2, w, s);
      const auto ref = b->sample(wv, u1, u2, lambda[0]);
      ASSERT_EQ(got, ref && ref->weight > 0 && ref->wo.z() > 0) << i;
      if (!got) continue;
      ++sampled;
      EXPECT_LT((s.wo - ref->wo).norm(), 1e-12);
      EXPECT_NEAR(s.pdf, ref->pdf, 1e-10 * ref->pdf);
      for (int k = 0; k < 4; ++k) {
        const double f = b->eval(s.wo, wv, lambda[k]);
        EXPECT_NEAR(s.weight[k], f * s.wo.z() / ref->pdf, 1e-9 * s.weight[k]) << k;
      }
      // The sampled direction as a light sample: f and the MIS density.
      double f[4], pdf = 0;
      m.eval(0, 0, view, s.wo, w, f, &pdf);
      EXPECT_NEAR(pdf, b->pdf(wv, s.wo), 1e-9 * pdf);
      for (int k = 0; k < 4; ++k) EXPECT_NEAR(f[k], b->eval(s.wo, wv, lambda[k]), 1e-12 * f[k]);
    }
    EXPECT_GT(sampled, 300);
  }
}

TEST(Render, HalfImagesSplitTheSamples) {
  // The two half images are the means of samples [0, spp/2) and [spp/2, spp): the full image
  // is their count-weighted mean, they differ from each other (disjoint samples), the full
  // image is the same as without halves, and everything is independent of the thread count.
  RenderScene sc;
  RenderLights l;
  l.envmap_path = smooth_envmap();
  auto mats =
      one(std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.1, 0.2),
                                           std::make_shared<ConductorFresnel>(metal("Au"))));
  for (int spp : {8, 7}) {
    RenderOptions o = small(24, spp);
    const RenderImage plain = render(sc, mats, l, o);
    o.half_images = true;
    const RenderImage a = render(sc, mats, l, o);
    o.threads = 1;
    const RenderImage b = render(sc, mats, l, o);
    ASSERT_EQ(a.half_rgb[0].size(), a.rgb.size());
    ASSERT_EQ(a.half_rgb[1].size(), a.rgb.size());
    EXPECT_EQ(a.rgb, plain.rgb);
    EXPECT_EQ(a.rgb, b.rgb);
    EXPECT_EQ(a.half_rgb[0], b.half_rgb[0]);
    EXPECT_EQ(a.half_rgb[1], b.half_rgb[1]);
    const double n0 = spp / 2, n1 = spp - spp / 2;
    double diff = 0, mean = 0;
    for (std::size_t i = 0; i < a.rgb.size(); ++i) {
      EXPECT_NEAR(a.rgb[i], (n0 * a.half_rgb[0][i] + n1 * a.half_rgb[1][i]) / spp,
                  1e-5 * std::abs(a.rgb[i]) + 1e-7);
      diff += std::abs(a.half_rgb[0][i] - a.half_rgb[1][i]);
      mean += a.rgb[i];
    }
    EXPECT_GT(diff, 1e-3 * mean);
  }
  RenderOptions one_spp = small(8, 1);
  one_spp.half_images = true;
  EXPECT_THROW(render(sc, mats, l, one_spp), InputError);
}

TEST(Render, SpectralMaterialFresnelEqualsTheConductorFormula) {
  // The per-path constants and the two-wavelengths-at-a-time evaluation give the conductor
  // Fresnel term of the metal's n and k exactly as one wavelength at a time does, for every
  // wavelength count.
  auto b = std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.2),
                                            std::make_shared<ConductorFresnel>(metal("Cu")));
  const pt::SpectralMaterial m(std::make_shared<UniformSvbrdf>(b));
  ASSERT_TRUE(m.fast());
  for (int n : {1, 2, 3, 4, 7, 8, 16}) {
    double lambda[16];
    for (int k = 0; k < n; ++k) lambda[k] = (360 + 470.0 * (k + 0.3) / n) * 1e-9;
    pt::SpectralMaterial::Wavelengths w;
    m.prepare(lambda, n, w);
    const pt::SpectralMaterial::View view = m.view(Vec3(0.3, -0.2, std::sqrt(1 - 0.13)));
    for (double t : {0.0, 0.4, 1.1, 1.5}) {
      const Vec3 wl(std::sin(t), 0.1 * std::sin(t), std::cos(t));
      double f[16];
      if (!m.eval(0, 0, view, wl.normalized(), w, f, nullptr)) continue;
      for (int k = 0; k < n; ++k) {
        // Against the BRDF (products in another order: to rounding), and exactly against the
        // one-wavelength (scalar) evaluation.
        const double ref = b->eval(wl.normalized(), view.wv, lambda[k]);
        EXPECT_NEAR(f[k], ref, 1e-14 * ref) << n << " " << k;
        pt::SpectralMaterial::Wavelengths w1;
        m.prepare(&lambda[k], 1, w1);
        double f1;
        m.eval(0, 0, view, wl.normalized(), w1, &f1, nullptr);
        EXPECT_EQ(f[k], f1) << n << " " << k;
      }
    }
  }
}

TEST(Render, VisibleWavelengthSamplingIsExact) {
  // The hero wavelengths drawn by the visible-wavelength density: each weight is 1 / (470 nm q)
  // with q the density of the tabulated map (within 5% of the sech^2 form; against a
  // histogram), so
  // the weights of uniformly spread u average to 1 (the estimator of the integral over 360..830
  // nm is unbiased); the wavelengths of one path are the map of u + k / n.
  double sum = 0;
  const int m = 200000;
  std::vector<int> hist(47, 0);
  for (int i = 0; i < m; ++i) {
    double l[1], w[1];
    pt::visible_hero_wavelengths((i + 0.5) / m, 1, l, w);
    sum += w[0];
    ASSERT_NEAR(w[0], 1 / (470 * pt::VisibleWavelengths::pdf(l[0])), 5e-2 * w[0]);
    ++hist[std::min(46, int((l[0] - 360) / 10))];
  }
  EXPECT_NEAR(sum / m, 1.0, 1e-4);
  for (int b = 0; b < 47; ++b) {  // the fraction of draws in each 10 nm band against the density
    double p = 0;
    for (int j = 0; j < 100; ++j) p += pt::VisibleWavelengths::pdf(360 + 10 * b + 0.1 * (j + 0.5));
    EXPECT_NEAR(double(hist[b]) / m, p * 0.1, 2e-4) << b;
  }
  double l4[4], w4[4];
  pt::visible_hero_wavelengths(0.3, 4, l4, w4);
  for (int k = 0; k < 4; ++k) {
    double l1[1], w1[1];
    pt::visible_hero_wavelengths(std::fmod(0.3 + k / 4.0, 1.0), 1, l1, w1);
    EXPECT_NEAR(l4[k], l1[0], 1e-9);
  }
}

TEST(Render, EnvironmentMapWiderThanItsTablesIsAnInputError) {
  // The sampling tables index columns with 16 bits: a wider map is refused with a message, not
  // a library exception (65535 columns pass).
  for (int w : {65535, 65536}) {
    pt::RgbFloatImage img;
    img.width = w;
    img.height = 2;
    img.rgb.assign(static_cast<std::size_t>(w) * 2 * 3, 1.0f);
    if (w <= 65535) {
      EXPECT_NO_THROW(pt::EnvironmentMap(img, 1.0, 0.0));
    } else {
      try {
        pt::EnvironmentMap m(img, 1.0, 0.0);
        ADD_FAILURE() << "a map of 65536 columns was accepted";
      } catch (const InputError& e) {
        EXPECT_NE(std::string(e.what()).find("65535"), std::string::npos) << e.what();
      }
    }
  }
}

namespace {

/// Rec. 709 luminance of pixel i.
double pixel_luminance(const RenderImage& img, std::size_t i) {
  return 0.2126 * img.rgb[3 * i] + 0.7152 * img.rgb[3 * i + 1] + 0.0722 * img.rgb[3 * i + 2];
}

/// The difference of the mean luminances of two renders of the same scene and a bound on its
/// noise: the images are cut into 4 x 4 blocks, whose mean differences d_b are independent
/// (every pixel has its own random numbers) and of mean 0 when both estimators are unbiased;
/// the bound is 4 standard errors of their mean, from the spread of the d_b about it.
struct MeanDifference {
  double diff = 0, bound = 0, mean = 0;
};
MeanDifference mean_difference(const RenderImage& a, const RenderImage& b) {
  MeanDifference r;
  double sum2 = 0;
  int blocks = 0;
  for (int by = 0; by + 4 <= a.height; by += 4)
    for (int bx = 0; bx + 4 <= a.width; bx += 4) {
      double d = 0;
      for (int y = by; y < by + 4; ++y)
        for (int x = bx; x < bx + 4; ++x) {
          const std::size_t i = std::size_t(y) * a.width + x;
          d += (pixel_luminance(a, i) - pixel_luminance(b, i)) / 16;
          r.mean += pixel_luminance(b, i) / 16;
        }
      r.diff += d;
      sum2 += d * d;
      ++blocks;
    }
  r.diff /= blocks;
  r.mean /= blocks;
  r.bound = 4 * std::sqrt((sum2 / blocks - r.diff * r.diff) / (blocks - 1));
  return r;
}

std::shared_ptr<const Brdf> glossy_copper() {
  return std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.08, 0.3),
                                          std::make_shared<ConductorFresnel>(metal("Cu")));
}

RenderImage render_with(const RenderScene& sc, const std::shared_ptr<const Brdf>& b,
                        const RenderLights& l, RenderOptions o, DirectLight direct) {
  o.direct = direct;
  return render(sc, one(b), l, o);
}

}  // namespace

TEST(Render, ResampledDirectLightAgreesWithMisInTheMean) {
  // RIS and MIS estimate the same image: glossy copper cylinders under the courtyard map (the
  // case RIS is for), the plate under its disk light (an area light alone), a rough copper
  // sphere under a smooth map with a sphere light and a point light (delta lights and lights in
  // front of the map), and a Lambertian sphere (a material off the microfacet fast path).
  struct Case {
    std::string name;
    PreviewScene scene;
    RenderLights lights;
    std::shared_ptr<const Brdf> brdf;
    int size, spp;
  };
  std::vector<Case> cases;
  RenderLights courtyard;
  courtyard.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  cases.push_back(
      {"cylinders, courtyard", PreviewScene::Cylinders, courtyard, glossy_copper(), 32, 512});
  RenderLights disk;
  disk.disks.push_back(dong_plate_light());
  cases.push_back(
      {"plate, disk light", PreviewScene::Plate, disk,
       std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.3, 0.3),
                                        std::make_shared<ConductorFresnel>(metal("Cu"))),
       32, 256});
  RenderLights mixed;
  mixed.envmap_path = smooth_envmap();
  mixed.spheres.push_back({Eigen::Vector3d(3, 3, 3), 1.5, Eigen::Vector3d(4, 4, 4)});
  mixed.points.push_back({Eigen::Vector3d(-3, 2, 3), Eigen::Vector3d(20, 20, 20)});
  cases.push_back(
      {"sphere, map + sphere + point light", PreviewScene::Sphere, mixed,
       std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.3),
                                        std::make_shared<ConductorFresnel>(metal("Cu"))),
       16, 1024});
  cases.push_back({"Lambertian sphere, courtyard", PreviewScene::Sphere, courtyard,
                   std::make_shared<LambertianBrdf>(0.8), 16, 256});
  for (const auto& c : cases) {
    RenderScene sc;
    sc.kind = c.scene;
    const auto o = small(c.size, c.spp);
    const auto ris = render_with(sc, c.brdf, c.lights, o, DirectLight::Ris);
    const auto mis = render_with(sc, c.brdf, c.lights, o, DirectLight::Mis);
    EXPECT_NE(ris.rgb, mis.rgb) << c.name << ": RIS not in use";
    const auto d = mean_difference(ris, mis);
    EXPECT_LT(std::abs(d.diff), d.bound) << c.name << ": mean " << d.mean;
    EXPECT_LT(d.bound, 0.02 * d.mean) << c.name << ": too noisy a test";  // it can detect 2%
  }
}

TEST(Render, ResampledDirectLightFurnace) {
  // A white Lambertian sphere where every direction sees radiance 1 (a uniform white sky and a
  // sphere light of radiance 1 in front of it, so that RIS is in use) renders to 1: RIS counts
  // the light once, and the continuation adds none of it again.
  RenderScene sc;
  sc.kind = PreviewScene::FurnaceSphere;
  RenderLights l;
  l.uniform_white_env = true;
  l.spheres.push_back({Eigen::Vector3d(0, 2.5, 1), 1.0, Eigen::Vector3d(1, 1, 1)});
  auto o = small(32, 64);
  o.direct = DirectLight::Ris;
  const auto img = render(sc, one(std::make_shared<LambertianBrdf>(1.0)), l, o);
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x)
      for (int c = 0; c < 3; ++c) m[c] += img.rgb[(y * 32 + x) * 3 + c] / 256.0;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(m[c], 1.0, 0.01) << "channel " << c;
}

TEST(Render, ResampledDirectLightLowersTheNoiseUnderAMap) {
  // Glossy copper cylinders under the courtyard map, equal samples: the seed-to-seed difference
  // of RIS images is well below that of MIS images (measured: 0.43 of it at 32 x 32, 64 spp).
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  auto noise = [&](DirectLight direct) {
    auto o = small(32, 64);
    const auto a = render_with(sc, glossy_copper(), l, o, direct);
    o.seed = 2;
    const auto b = render_with(sc, glossy_copper(), l, o, direct);
    double d2 = 0, m = 0;
    const std::size_t n = a.rgb.size() / 3;
    for (std::size_t i = 0; i < n; ++i) {
      const double d = pixel_luminance(a, i) - pixel_luminance(b, i);
      d2 += d * d / n;
      m += (pixel_luminance(a, i) + pixel_luminance(b, i)) / (2 * n);
    }
    return std::sqrt(d2 / 2) / m;
  };
  const double ris = noise(DirectLight::Ris), mis = noise(DirectLight::Mis);
  EXPECT_LT(ris, 0.8 * mis) << "RIS " << ris << ", MIS " << mis;
}

TEST(Render, ResampledDirectLightSameImageWhateverTheThreads) {
  RenderScene sc;
  sc.kind = PreviewScene::Cylinders;
  RenderLights l;
  l.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  l.points.push_back({Eigen::Vector3d(0, 2, 3), Eigen::Vector3d(5, 5, 5)});
  auto o = small(16, 8);
  o.direct = DirectLight::Ris;
  o.ris_light_candidates = 2;
  o.threads = 1;
  const auto a1 = render(sc, one(glossy_copper()), l, o);
  o.threads = 2;
  const auto a2 = render(sc, one(glossy_copper()), l, o);
  EXPECT_EQ(a1.rgb, a2.rgb);
  o.seed = 2;
  EXPECT_NE(a1.rgb, render(sc, one(glossy_copper()), l, o).rgb);
}

TEST(Render, ResampledDirectLightOptionsAreChecked) {
  RenderScene sc;
  RenderLights l;
  l.envmap_path = kEnvmaps + "/blender_courtyard.exr";
  auto o = small(8, 1);
  o.direct = DirectLight::Ris;
  for (auto [m, n] : {std::pair{0, 1}, {17, 1}, {4, 0}, {4, 5}}) {
    o.ris_brdf_candidates = m;
    o.ris_light_candidates = n;
    EXPECT_THROW(render(sc, one(glossy_copper()), l, o), InputError) << m << "," << n;
  }
  EXPECT_EQ(parse_direct_light("ris", "--direct"), DirectLight::Ris);
  EXPECT_EQ(parse_direct_light("mis", "--direct"), DirectLight::Mis);
  EXPECT_THROW(parse_direct_light("nee", "--direct"), InputError);
}

TEST(Render, LatticeCandidatesAreBrdfSamplesOfTheLatticePoints) {
  // The RIS candidates of lattice_directions (GGX: the stretched frame once, fixed rotations,
  // no normalisation) against sample_direction at the lattice points (u1 + j / M, u2 + j phi)
  // mod 1, and their density and target against ris_terms of the same direction; for GGX (the
  // fast loop) and Beckmann (the plain loop), and against ris_terms for a Lambertian (generic).
  auto cu = std::make_shared<ConductorFresnel>(metal("Cu"));
  std::vector<std::shared_ptr<const Brdf>> brdfs = {
      std::make_shared<MicrofacetBrdf>(std::make_shared<GgxDistribution>(0.08, 0.3, 0.4), cu),
      std::make_shared<MicrofacetBrdf>(std::make_shared<BeckmannDistribution>(0.2, 0.05), cu),
      std::make_shared<LambertianBrdf>(0.7)};
  const double lambda[4] = {380e-9, 480e-9, 600e-9, 790e-9};
  const double phi = 0.6180339887498949;
  for (const auto& b : brdfs) {
    const pt::SpectralMaterial m(std::make_shared<UniformSvbrdf>(b));
    pt::SpectralMaterial::Wavelengths w;
    m.prepare(lambda, 4, w);
    int compared = 0;
    for (int i = 0; i < 200; ++i) {
      const double tv = 1.5 * (i % 20) / 20, pv = 0.31 * i;
      const Vec3 wv(std::sin(tv) * std::cos(pv), std::sin(tv) * std::sin(pv), std::cos(tv));
      const auto view = m.view(wv);
      const double u1 = (i + 0.5) / 200, u2 = std::fmod(0.7548776662 * i, 1.0);
      const int M = 1 + i % 8, a = std::min(int(u1 * M), M - 1);
      Vec3 wl[16];
      double pdf[16], target[16];
      bool ok[16];
      m.lattice_directions(0, 0, view, u1, u2, w, M, a, wl, pdf, target, ok);
      for (int k = 0; k < M; ++k) {
        if (k == a) continue;
        const double o1 = double(k - a) / M, o2 = (k - a) * phi;
        double v1 = u1 + o1 - std::floor(o1), v2 = u2 + o2 - std::floor(o2);
        v1 -= std::floor(v1);
        v2 -= std::floor(v2);
        Vec3 ref;
        double ref_pdf = 0, ref_target = 0;
        const bool got = m.sample_direction(0, 0, view, v1, v2, w, ref, ref_pdf, ref_target);
        ASSERT_EQ(ok[k], got) << b->describe() << " i " << i << " k " << k;
        if (!got) continue;
        EXPECT_LT((wl[k] - ref).norm(), 1e-9) << b->describe() << " i " << i << " k " << k;
        EXPECT_NEAR(pdf[k], ref_pdf, 1e-9 * ref_pdf) << b->describe() << " i " << i;
        EXPECT_NEAR(target[k], ref_target, 1e-9 * ref_target) << b->describe() << " i " << i;
        double t_pdf = 0, t_target = 0;
        ASSERT_TRUE(m.ris_terms(0, 0, view, ref, w, t_pdf, t_target));
        EXPECT_NEAR(t_pdf, ref_pdf, 1e-8 * ref_pdf) << b->describe() << " i " << i;
        EXPECT_NEAR(t_target, ref_target, 1e-8 * ref_target) << b->describe() << " i " << i;
        ++compared;
      }
    }
    EXPECT_GT(compared, 300) << b->describe();
  }
}

// The preview renderer: furnace, mirror, MIS consistency, determinism, anisotropy.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "microbrdf/error.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/tabulated_distribution.hpp"
#include "render/envmap.hpp"
#include "render/scene.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

const std::string kShared = MICROBRDF_SHARED_DATA;

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

Eigen::Vector3d mean_rgb(const RenderImage& img) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < img.rgb.size() / 3; ++i)
    m += Eigen::Vector3d(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
  return m / double(img.rgb.size() / 3);
}

std::string temp_dir() {
  auto d = fs::temp_directory_path() / ("microbrdf_render_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d.string();
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
  sc.kind = PreviewScene::furnace_sphere;
  RenderLights l;
  l.uniform_white_env = true;
  for (MisMode mode : {MisMode::mis, MisMode::brdf_only, MisMode::light_only}) {
    // Light sampling alone wastes half its samples below the horizon: more samples.
    auto o = small(32, mode == MisMode::light_only ? 512 : 64);
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
  sc.kind = PreviewScene::furnace_sphere;
  RenderLights l;
  l.uniform_white_env = true;
  auto img = render(sc, one(std::make_shared<LambertianBrdf>(0.5)), l, small(32, 32));
  double m = 0;
  for (int y = 8; y < 24; ++y)
    for (int x = 8; x < 24; ++x) m += img.rgb[(y * 32 + x) * 3 + 1] / 256.0;
  EXPECT_NEAR(m, 0.5, 0.005);  // a convex object sees only the sky: one bounce
}

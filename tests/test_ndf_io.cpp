// NDF files (.npy + JSON sidecar, .exr) and previews.
#include <gtest/gtest.h>
#include <unistd.h>

#include <bit>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <string>
#include <vector>

#include "core/npy.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/tabulated_distribution.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  fs::path dir =
      fs::temp_directory_path() / ("microbrdf-test-ndf-io-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

std::vector<std::uint8_t> slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void spit(const fs::path& p, const std::vector<std::uint8_t>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
}

void fill_beckmann(TabulatedNdf& t, double alpha, double cx = 0, double cy = 0) {
  for (std::size_t iy = 0; iy < t.resolution(); ++iy)
    for (std::size_t ix = 0; ix < t.resolution(); ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
      if (r2 >= 1) continue;
      const double z2 = 1 - r2;
      const double dx = x - cx, dy = y - cy, tan2 = (dx * dx + dy * dy) / z2;
      t.at(ix, iy) = std::exp(-tan2 / (alpha * alpha)) / (M_PI * alpha * alpha * z2 * z2);
    }
  t.normalise();
}

// A table with awkward values (random mantissas, tiny and huge magnitudes) and metadata.
TabulatedNdf awkward_table(std::size_t n) {
  TabulatedNdf t(n);
  fill_beckmann(t, 0.3);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(0.5, 1.5);
  for (double& v : t.values()) v *= u(rng);
  t.at(n / 2, n / 2) = 1.0 / 3.0;
  t.at(1, 1) = 1e-30;
  t.meta.method = "filtered";
  t.meta.filter_sigma_m = 1.0e-6 / 3.0;
  t.meta.wavelength_m = 532.1e-9;
  t.meta.sources = {"scan a.x3p", "dir/\"quoted\".datx", "ünïcode.sur"};
  t.meta.samples_used = 123456789;
  t.meta.samples_skipped = 42;
  t.meta.projected_area_m2 = 1.0 / 7.0 * 1e-6;
  t.meta.leveling = "plane";
  t.meta.parameterisation = "orthographic-disk node-centred";
  t.meta.notes = "line 1\nline 2, tab\there";
  return t;
}

void expect_same_meta(const NdfMetadata& a, const NdfMetadata& b) {
  EXPECT_EQ(a.method, b.method);
  EXPECT_EQ(a.filter_sigma_m, b.filter_sigma_m);
  EXPECT_EQ(a.wavelength_m, b.wavelength_m);
  EXPECT_EQ(a.sources, b.sources);
  EXPECT_EQ(a.samples_used, b.samples_used);
  EXPECT_EQ(a.samples_skipped, b.samples_skipped);
  EXPECT_EQ(a.projected_area_m2, b.projected_area_m2);
  EXPECT_EQ(a.leveling, b.leveling);
  EXPECT_EQ(a.parameterisation, b.parameterisation);
  EXPECT_EQ(a.notes, b.notes);
}

template <class F>
void expect_file_error(const std::string& path, F&& f, const std::string& fragment = "") {
  try {
    f();
    ADD_FAILURE() << "no FileError for " << path;
  } catch (const FileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
    if (!fragment.empty()) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
    }
  }
}

std::uint32_t be32(const std::vector<std::uint8_t>& b, std::size_t at) {
  return (std::uint32_t(b[at]) << 24) | (std::uint32_t(b[at + 1]) << 16) |
         (std::uint32_t(b[at + 2]) << 8) | std::uint32_t(b[at + 3]);
}

int brightness(const RgbImage& img, std::size_t x, std::size_t y) {
  const auto* p = &img.pixels[(y * img.width + x) * 3];
  return p[0] + p[1] + p[2];
}

}  // namespace

TEST(ndf_io, NpyRoundTripIsBitExact) {
  const auto path = (temp_dir() / "rt.npy").string();
  TabulatedNdf t = awkward_table(65);
  write_ndf(t, path);
  EXPECT_TRUE(fs::exists(temp_dir() / "rt.json"));
  TabulatedNdf r = read_ndf(path);
  ASSERT_EQ(r.resolution(), 65u);
  ASSERT_EQ(r.values().size(), t.values().size());
  EXPECT_EQ(std::memcmp(r.values().data(), t.values().data(), 8 * t.values().size()), 0);
  expect_same_meta(r.meta, t.meta);
}

TEST(ndf_io, NpyHeaderIsWhatNumpyWrites) {
  const auto path = temp_dir() / "hdr.npy";
  TabulatedNdf t(33);
  fill_beckmann(t, 0.2);
  write_ndf(t, path.string());
  const auto b = slurp(path);
  ASSERT_GE(b.size(), 10u);
  const std::uint8_t magic[8] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  EXPECT_EQ(std::memcmp(b.data(), magic, 8), 0);
  const std::size_t hlen = b[8] | (std::size_t(b[9]) << 8);
  EXPECT_EQ((10 + hlen) % 64, 0u) << "numpy aligns the data to 64 bytes";
  const std::string header(b.begin() + 10, b.begin() + 10 + static_cast<std::ptrdiff_t>(hlen));
  const std::string dict = "{'descr': '<f8', 'fortran_order': False, 'shape': (33, 33), }";
  EXPECT_EQ(header.substr(0, dict.size()), dict);
  EXPECT_EQ(header.back(), '\n');
  EXPECT_EQ(header.find_first_not_of(' ', dict.size()), header.size() - 1);
  EXPECT_EQ(b.size(), 10 + hlen + 8 * 33 * 33);
  // Row iy, column ix, little-endian float64.
  double v;
  std::memcpy(&v, b.data() + 10 + hlen + 8 * (20 * 33 + 7), 8);
  EXPECT_EQ(v, t.at(7, 20));
}

TEST(ndf_io, SidecarStatesConventions) {
  const auto path = temp_dir() / "conv.npy";
  TabulatedNdf t(17);
  fill_beckmann(t, 0.5);
  t.meta.method = "naive";
  write_ndf(t, path.string());
  std::ifstream in(temp_dir() / "conv.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("resolution"), 17);
  EXPECT_EQ(j.at("method"), "naive");
  EXPECT_EQ(j.at("conventions").at("m_x"), "m_x = -1 + 2 ix/(N-1)");
  EXPECT_EQ(j.at("conventions").at("value"), "D per steradian");
  EXPECT_EQ(j.at("conventions").at("normalisation"), "integral of D(m)(m.n) = 1");
  for (const char* key :
       {"filter_sigma_m", "wavelength_m", "sources", "samples_used", "samples_skipped",
        "projected_area_m2", "leveling", "parameterisation", "notes"})
    EXPECT_TRUE(j.contains(key)) << key;
}

TEST(ndf_io, NpyWithoutSidecarReadsDefaults) {
  const auto dir = temp_dir();
  TabulatedNdf t(9);
  fill_beckmann(t, 0.4);
  t.meta.method = "beckmann";
  write_ndf(t, (dir / "nos.npy").string());
  fs::remove(dir / "nos.json");
  TabulatedNdf r = read_ndf((dir / "nos.npy").string());
  EXPECT_EQ(r.values(), t.values());
  EXPECT_EQ(r.meta.method, "");
}

TEST(ndf_io, ExrRoundTripToFloatPrecision) {
  const auto path = (temp_dir() / "rt.exr").string();
  TabulatedNdf t = awkward_table(65);
  t.meta.samples_used = 5'000'000'000ull;  // beyond int: stored as double
  write_ndf(t, path);
  TabulatedNdf r = read_ndf(path);
  ASSERT_EQ(r.resolution(), 65u);
  for (std::size_t i = 0; i < t.values().size(); ++i)
    ASSERT_EQ(r.values()[i], static_cast<double>(static_cast<float>(t.values()[i]))) << i;
  expect_same_meta(r.meta, t.meta);
  // The value layout matches the .npy one (row iy).
  EXPECT_EQ(r.at(32, 32), static_cast<double>(1.0f / 3.0f));
}

TEST(ndf_io, CorruptNpyGivesFileErrorWithPath) {
  const auto dir = temp_dir();
  TabulatedNdf t(17);
  fill_beckmann(t, 0.3);
  const auto good = dir / "good.npy";
  write_ndf(t, good.string());
  const auto bytes = slurp(good);

  const auto trunc = (dir / "trunc.npy").string();
  spit(trunc, std::vector<std::uint8_t>(bytes.begin(), bytes.end() - 100));
  expect_file_error(
      trunc, [&] { read_ndf(trunc); }, "truncated");

  const auto garbage = (dir / "garbage.npy").string();
  spit(garbage, {1, 2, 3, 4, 5});
  expect_file_error(garbage, [&] { read_ndf(garbage); });

  auto save = [&](const std::string& name, const std::vector<double>& v, std::size_t r,
                  std::size_t c) {
    const auto p = (dir / name).string();
    spit(p, detail::encode_npy_f64(v, r, c));
    return p;
  };
  const auto rect = save("rect.npy", std::vector<double>(4 * 5, 0.1), 4, 5);
  expect_file_error(
      rect, [&] { read_ndf(rect); }, "square");
  const auto tiny = save("tiny.npy", std::vector<double>(4, 0.1), 2, 2);
  expect_file_error(
      tiny, [&] { read_ndf(tiny); }, "< 3");
  std::vector<double> v(9, 0.1);
  v[4] = -1;
  const auto neg = save("neg.npy", v, 3, 3);
  expect_file_error(
      neg, [&] { read_ndf(neg); }, "negative");
  v[4] = std::numeric_limits<double>::infinity();  // NaN (unmeasured) is accepted, inf is not
  const auto inf = save("inf_read.npy", v, 3, 3);
  expect_file_error(
      inf, [&] { read_ndf(inf); }, "infinite");
  // NaN (unmeasured) is accepted where measured nodes remain inside the disk (a 3 x 3 table has
  // only its centre inside, so use 5 x 5).
  std::vector<double> w(25, 0.1);
  w[12] = std::nan("");
  EXPECT_TRUE(std::isnan(read_ndf(save("nan.npy", w, 5, 5)).at(2, 2)));

  const auto missing = (dir / "missing.npy").string();
  expect_file_error(missing, [&] { read_ndf(missing); });
  const auto txt = (dir / "table.txt").string();
  expect_file_error(
      txt, [&] { read_ndf(txt); }, "extension");
}

TEST(ndf_io, BadSidecarGivesFileErrorWithSidecarPath) {
  const auto dir = temp_dir();
  TabulatedNdf t(9);
  fill_beckmann(t, 0.3);
  const auto npy = (dir / "side.npy").string();
  const auto json = (dir / "side.json").string();
  write_ndf(t, npy);
  std::ofstream(json) << "{\"resolution\": 10}";
  expect_file_error(
      json, [&] { read_ndf(npy); }, "resolution");
  std::ofstream(json) << "{\"method\": ";
  expect_file_error(
      json, [&] { read_ndf(npy); }, "JSON");
  std::ofstream(json) << "{\"samples_used\": -3}";
  expect_file_error(
      json, [&] { read_ndf(npy); }, "samples_used");
}

TEST(ndf_io, CorruptExrGivesFileErrorWithPath) {
  const auto dir = temp_dir();
  TabulatedNdf t(33);
  fill_beckmann(t, 0.3);
  const auto good = dir / "good.exr";
  write_ndf(t, good.string());
  const auto bytes = slurp(good);
  const auto trunc = (dir / "trunc.exr").string();
  spit(trunc, std::vector<std::uint8_t>(
                  bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(bytes.size() / 2)));
  expect_file_error(trunc, [&] { read_ndf(trunc); });
  const auto garbage = (dir / "garbage.exr").string();
  spit(garbage, std::vector<std::uint8_t>(300, 0x5A));
  expect_file_error(garbage, [&] { read_ndf(garbage); });
}

TEST(ndf_io, FailedWriteLeavesNothing) {
  const auto dir = temp_dir() / "no-such-dir";
  TabulatedNdf t(9);
  fill_beckmann(t, 0.3);
  for (const char* name : {"x.npy", "x.exr", "x.png"}) {
    const auto p = (dir / name).string();
    if (std::string(name) == "x.png")
      expect_file_error(p, [&] { write_ndf_preview(t, p); });
    else
      expect_file_error(p, [&] { write_ndf(t, p); });
  }
  EXPECT_FALSE(fs::exists(dir));
  TabulatedNdf bad(9);  // NaN means "unmeasured" and is written; infinities are refused
  bad.at(4, 4) = std::numeric_limits<double>::infinity();
  const auto p = (temp_dir() / "inf.npy").string();
  expect_file_error(p, [&] { write_ndf(bad, p); });
  EXPECT_FALSE(fs::exists(p));
}

TEST(ndf_io, PreviewPngHasExpectedSize) {
  TabulatedNdf t(129);
  fill_beckmann(t, 0.3);
  const auto path = temp_dir() / "prev.png";
  NdfPreviewOptions opt;
  opt.size = 200;
  write_ndf_preview(t, path.string(), opt);
  const RgbImage img = render_ndf_preview(t, opt);
  const auto b = slurp(path);
  ASSERT_GT(b.size(), 24u);
  EXPECT_EQ(b[1], 'P');
  EXPECT_EQ(be32(b, 16), img.width);
  EXPECT_EQ(be32(b, 20), img.height);
  EXPECT_GE(img.width, 200u + 20u + 16u);
  EXPECT_GE(img.height, 200u + 20u);
}

TEST(ndf_io, PreviewPeakIsBrighterThanRimAndMyPointsUp) {
  TabulatedNdf t(129);
  fill_beckmann(t, 0.15, 0.0, 0.5);  // peak at m_y = +0.5: the upper half of the image
  NdfPreviewOptions opt;
  opt.size = 200;
  const RgbImage img = render_ndf_preview(t, opt);
  auto px = [&](double mx, double my) {
    return brightness(img, 10 + static_cast<std::size_t>((mx + 1) / 2 * 200),
                      10 + static_cast<std::size_t>((1 - my) / 2 * 200));
  };
  EXPECT_GT(px(0, 0.5), px(0.9, 0) + 100);
  EXPECT_GT(px(0, 0.5), px(0, -0.5) + 100);
  EXPECT_GT(px(0, 0.5), px(-0.5, 0.5) + 100);
  // Zero inside the disk is near black.
  EXPECT_LT(px(0, -0.9), 60);
}

TEST(ndf_io, PreviewZoomPanelWidensImageAndShowsPeak) {
  TabulatedNdf t(257);
  fill_beckmann(t, 0.02);
  NdfPreviewOptions opt;
  opt.size = 128;
  const RgbImage plain = render_ndf_preview(t, opt);
  opt.zoom = true;
  const RgbImage zoom = render_ndf_preview(t, opt);
  EXPECT_EQ(zoom.width, plain.width + 128 + 10);
  EXPECT_EQ(zoom.height, plain.height);
  // The zoom panel (origin x = 148) is bright over a large area around its centre; the full
  // view shows the narrow peak in a few pixels only.
  // Bright pixels (top of the colour scale; the grey lines of circle and zoom frame excluded)
  // in the central quarter of a panel.
  auto bright_pixels = [&](std::size_t x0) {
    int count = 0;
    for (std::size_t y = 10 + 32; y < 10 + 96; ++y)
      for (std::size_t x = x0 + 32; x < x0 + 96; ++x) {
        const auto* p = &zoom.pixels[(y * zoom.width + x) * 3];
        const bool grey = p[0] == p[1] && p[1] == p[2];
        count += brightness(zoom, x, y) > 400 && !grey;
      }
    return count;
  };
  EXPECT_GT(bright_pixels(10), 0);
  EXPECT_GT(bright_pixels(148), 20 * bright_pixels(10));
  // The zoom region is marked on the full view: grey frame pixels near the centre.
  int frame = 0;
  for (std::size_t y = 10 + 54; y < 10 + 74; ++y)
    for (std::size_t x = 10 + 54; x < 10 + 74; ++x) {
      const auto* p = &zoom.pixels[(y * zoom.width + x) * 3];
      frame += p[0] == 210 && p[1] == 210 && p[2] == 210;
    }
  EXPECT_GT(frame, 12);
}

TEST(ndf_io, PreviewIntoReadOnlyDirectoryThrowsAndLeavesNothing) {
  const auto dir = temp_dir() / "ro";
  fs::create_directories(dir);
  fs::permissions(dir, fs::perms::owner_read | fs::perms::owner_exec);
  const bool enforced = !std::ofstream(dir / "probe");  // root ignores permissions
  fs::remove(dir / "probe");
  TabulatedNdf t(33);
  fill_beckmann(t, 0.3);
  const auto p = (dir / "p.png").string();
  if (enforced) {
    expect_file_error(p, [&] { write_ndf_preview(t, p); });
    EXPECT_TRUE(fs::is_empty(dir));
  }
  fs::permissions(dir, fs::perms::owner_all);
  if (!enforced) GTEST_SKIP() << "permissions not enforced (running as root)";
}

// How the table was sampled and the zoom window travel through both formats; a sidecar from
// before the record (no "sampling", no "window") reads as an unrecorded sampling (inferred from
// the method) on the whole disk.
TEST(ndf_io, SamplingAndWindowRoundTrip) {
  const auto dir = temp_dir();
  const NdfWindow w = zoom_window(0.25, -0.5, 0.125);
  TabulatedNdf t(33, w);
  fill_beckmann(t, 0.02, 0.25, -0.5);
  t.meta.method = "filtered";
  t.meta.sampling = "cell";
  t.meta.window_mass = 0.875;
  for (const char* name : {"win.npy", "win.exr"}) {
    SCOPED_TRACE(name);
    const std::string path = (dir / name).string();
    write_ndf(t, path);
    const TabulatedNdf r = read_ndf(path);
    EXPECT_EQ(r.window(), w);
    EXPECT_EQ(r.meta.sampling, "cell");
    EXPECT_EQ(r.meta.window_mass, 0.875);
    EXPECT_DOUBLE_EQ(r.node_x(0), 0.125);
    EXPECT_DOUBLE_EQ(r.node_y(32), -0.375);
    // The same function: bilinear values inside the window, 0 outside it (inside the disk).
    EXPECT_NEAR(r.eval_disk(0.25, -0.5), t.eval_disk(0.25, -0.5), 1e-6 * t.eval_disk(0.25, -0.5));
    EXPECT_EQ(r.eval_disk(0.0, 0.0), 0.0);
  }
  std::ifstream in(dir / "win.json");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j.at("sampling"), "cell");
  EXPECT_EQ(j.at("window").at("x").at(0).get<double>(), 0.125);
  EXPECT_EQ(j.at("window").at("y").at(1).get<double>(), -0.375);
  EXPECT_EQ(j.at("conventions").at("m_x"), "m_x = 0.125 + 0.25 ix/(N-1)");
  // A whole-disk table writes its sampling (inferred when not set) and the window [-1, 1]^2.
  TabulatedNdf full(17);
  fill_beckmann(full, 0.5);
  full.meta.method = "ggx";
  write_ndf(full, (dir / "full.npy").string());
  std::ifstream fin(dir / "full.json");
  const auto jf = nlohmann::json::parse(fin);
  EXPECT_EQ(jf.at("sampling"), "point");
  EXPECT_EQ(jf.at("window").at("x").at(0).get<double>(), -1.0);
  // An old sidecar: no sampling, no window.
  nlohmann::json old = jf;
  old.erase("sampling");
  old.erase("window");
  old.erase("window_mass");
  std::ofstream(dir / "full.json") << old.dump();
  const TabulatedNdf r = read_ndf((dir / "full.npy").string());
  EXPECT_TRUE(r.window().full());
  EXPECT_TRUE(r.meta.sampling.empty());
  EXPECT_FALSE(ndf_sampling_recorded(r.meta));
  EXPECT_EQ(ndf_sampling(r.meta), "point");  // from the method "ggx"
}

TEST(ndf_io, BadWindowOrSamplingInSidecarIsAFileError) {
  const auto dir = temp_dir();
  TabulatedNdf t(17);
  fill_beckmann(t, 0.5);
  write_ndf(t, (dir / "badw.npy").string());
  const auto side = (dir / "badw.json").string();
  std::ifstream in(side);
  const auto good = nlohmann::json::parse(in);
  auto expect_bad = [&](const nlohmann::json& j, const std::string& fragment) {
    std::ofstream(side, std::ios::trunc) << j.dump();
    expect_file_error(
        side, [&] { read_ndf((dir / "badw.npy").string()); }, fragment);
  };
  nlohmann::json j = good;
  j["window"] = {{"x", {-0.5, 0.5}}, {"y", {-0.5, 0.25}}};  // not square
  expect_bad(j, "window");
  j["window"] = {{"x", {0.5, 1.5}}, {"y", {0, 1}}};  // outside [-1, 1]^2
  expect_bad(j, "window");
  j["window"] = "all";
  expect_bad(j, "window");
  j = good;
  j["sampling"] = "splat";
  expect_bad(j, "sampling");
  j = good;
  j["window_mass"] = 1.5;
  expect_bad(j, "window_mass");
}

// A zoomed table honours its window everywhere: the integral over its nodes, moments, slices
// (over the part of the line inside the window), resampling and splatting.
TEST(ndf_io, ZoomedTableHonoursItsWindow) {
  const NdfWindow w = zoom_window(0.1, 0.0, 0.05);
  TabulatedNdf t(101, w);
  fill_beckmann(t, 0.01, 0.1, 0.0);
  EXPECT_NEAR(t.integral(), 1.0, 1e-12);
  EXPECT_NEAR(t.spacing(), 0.001, 1e-15);
  const Eigen::Vector3d mn = t.mean_normal();
  EXPECT_NEAR(mn.x() / mn.z(), 0.1 / std::sqrt(1 - 0.01), 2e-3);
  EXPECT_NEAR(t.rms_slope(M_PI / 2), 0.01 / std::sqrt(2.0), 0.01 * 0.01 / std::sqrt(2.0) * 3);
  const NdfSlice s = t.slice(0, 201);
  EXPECT_NEAR(s.t.front(), 0.05, 1e-12);
  EXPECT_NEAR(s.t.back(), 0.15, 1e-12);
  double peak_t = 0, peak = 0;
  for (std::size_t i = 0; i < s.t.size(); ++i)
    if (s.value[i] > peak) peak = s.value[i], peak_t = s.t[i];
  EXPECT_NEAR(peak_t, 0.1, 1e-3);
  const NdfSlice miss = t.slice(M_PI / 2, 11);  // the y axis misses the window
  for (double v : miss.value) EXPECT_EQ(v, 0.0);
  const TabulatedNdf r = t.resampled(51);
  EXPECT_EQ(r.window(), w);
  EXPECT_NEAR(r.eval_disk(0.1, 0.0) / t.eval_disk(0.1, 0.0), 1.0, 1e-3);
  TabulatedNdf z(11, w);
  z.splat(0.1, 0.0, 1.0);  // the centre node
  z.splat(0.0, 0.0, 1.0);  // outside the window: ignored
  EXPECT_EQ(z.at(5, 5), 1.0);
  EXPECT_NEAR(z.integral() / (z.spacing() * z.spacing()), 1.0, 1e-12);
  EXPECT_THROW(TabulatedNdf(11, NdfWindow{0.9, 0, 0.2}), std::invalid_argument);
  EXPECT_THROW(t.add(TabulatedNdf(101)), std::invalid_argument);
  const NdfWindow c = zoom_window(0.99, -2, 0.1);  // clamped inside [-1, 1]^2
  EXPECT_NEAR(c.x1(), 1.0, 1e-15);
  EXPECT_NEAR(c.y0(), -1.0, 1e-15);
}

// A BRDF's microfacet distribution from a zoomed table (renders, `brdf --ndf`): samples stay in
// the window, and the sampling pdf is the density they are drawn from: E[D(m) m_z / pdf] = 1
// (the table's normalisation) within Monte Carlo error, off-centre so that the window's origin
// matters.
TEST(ndf_io, ZoomedTableSamplesInsideItsWindowWithItsPdf) {
  const NdfWindow w = zoom_window(0.2, 0.1, 0.15);
  TabulatedNdf t(129, w);
  fill_beckmann(t, 0.04, 0.2, 0.1);
  t.meta.method = "filtered";
  const TabulatedDistribution d(t);
  const Vec3 v(std::sin(0.5), 0, std::cos(0.5));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 20000;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const Vec3 m = d.sample_visible(v, u(rng), u(rng));
    const double x = m.x() / m.norm(), y = m.y() / m.norm();
    ASSERT_TRUE(x >= w.x0() - 1e-12 && x <= w.x1() + 1e-12 && y >= w.y0() - 1e-12 &&
                y <= w.y1() + 1e-12)
        << x << " " << y;
    const double pdf = d.sampling_pdf(v, m);
    ASSERT_GT(pdf, 0);
    sum += d.D(m) * (m.z() / m.norm()) / pdf;
  }
  EXPECT_NEAR(sum / n, 1.0, 0.03);
  EXPECT_EQ(d.D(Vec3(0, 0, 1)), 0.0);  // the pole is outside this window
}

TEST(ndf_io, StackOverLambdaQRoundTripsAndReadsItsPrimaryTable) {
  const auto path = (temp_dir() / "stack.npy").string();
  std::vector<TabulatedNdf> layers;
  const double lq[3] = {400e-9, 555e-9, 800e-9};
  for (int l = 0; l < 3; ++l) {
    TabulatedNdf t(33);
    fill_beckmann(t, 0.1 + 0.1 * l);
    t.meta.method = "kirchhoff";
    t.meta.wavelength_m = lq[l];
    t.meta.notes = "layer " + std::to_string(l);
    layers.push_back(t);
  }
  ASSERT_TRUE(write_ndf_stack(layers, 1, path));
  // numpy's layout: a C-order (3, 33, 33) float64 array, the layers one after another.
  const auto b = slurp(path);
  const std::string header(b.begin() + 10, b.begin() + 10 + (b[8] | (b[9] << 8)));
  EXPECT_NE(header.find("'shape': (3, 33, 33)"), std::string::npos) << header;
  ASSERT_EQ(b.size(), 10 + header.size() + 3 * 33 * 33 * 8);
  for (int l = 0; l < 3; ++l)
    EXPECT_EQ(std::memcmp(b.data() + 10 + header.size() + l * 33 * 33 * 8,
                          layers[l].values().data(), 33 * 33 * 8),
              0);
  const auto back = read_ndf_stack(path);
  ASSERT_EQ(back.size(), 3u);
  for (int l = 0; l < 3; ++l) {
    EXPECT_EQ(back[l].meta.wavelength_m, lq[l]);
    EXPECT_EQ(back[l].meta.notes, "layer " + std::to_string(l));
    EXPECT_EQ(back[l].values(), layers[l].values());
  }
  // A reader of one table gets the primary layer.
  const TabulatedNdf one = read_ndf(path);
  EXPECT_EQ(one.meta.wavelength_m, 555e-9);
  EXPECT_EQ(one.values(), layers[1].values());
  // Unsorted layers are refused; a stack without its sidecar's list is refused on reading.
  std::swap(layers[0], layers[2]);
  EXPECT_THROW(write_ndf_stack(layers, 0, (temp_dir() / "bad.npy").string()), FileError);
  fs::remove(temp_dir() / "stack.json");
  EXPECT_THROW(read_ndf_stack(path), FileError);
}

// A table built from node values takes them without a copy and checks their count.
TEST(ndf_io, TableFromValuesAdoptsThemAndChecksTheCount) {
  std::vector<double> v(17 * 17);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<double>(i % 7);
  const double* storage = v.data();
  TabulatedNdf t(17, std::move(v));
  EXPECT_EQ(t.resolution(), 17u);
  EXPECT_EQ(t.values().data(), storage);  // adopted, not copied
  EXPECT_EQ(t.at(3, 2), static_cast<double>((2 * 17 + 3) % 7));
  std::vector<double> short_values(17 * 17 - 1);
  EXPECT_THROW(TabulatedNdf(17, std::move(short_values)), std::invalid_argument);
  std::vector<double> two(4);
  EXPECT_THROW(TabulatedNdf(2, std::move(two)), std::invalid_argument);
}

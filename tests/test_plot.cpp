// Plots: PNG and SVG files of the asked-for size, text in the SVG, log axes, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "microbrdf/error.hpp"
#include "microbrdf/plot.hpp"
#include "plot/ticks.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

fs::path temp_dir() {
  auto d =
      fs::temp_directory_path() /
      ("microbrdf_test_plot_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
       "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Width and height from a PNG's IHDR chunk.
std::pair<std::uint32_t, std::uint32_t> png_size(const std::string& bytes) {
  auto be32 = [&](std::size_t o) {
    return (std::uint32_t(std::uint8_t(bytes[o])) << 24) |
           (std::uint32_t(std::uint8_t(bytes[o + 1])) << 16) |
           (std::uint32_t(std::uint8_t(bytes[o + 2])) << 8) |
           std::uint32_t(std::uint8_t(bytes[o + 3]));
  };
  EXPECT_GE(bytes.size(), 24u);
  EXPECT_EQ(bytes.substr(1, 3), "PNG");
  EXPECT_EQ(bytes.substr(12, 4), "IHDR");
  return {be32(16), be32(20)};
}

Plot sample_plot() {
  Plot p;
  p.title = "Free travel probability";
  p.x.label = "theta (deg)";
  p.y.label = "Gamma_0 (1)";
  PlotSeries a;
  PlotSeries b;
  for (int i = 0; i <= 90; i += 2) {
    double t = i * M_PI / 180;
    a.x.push_back(i);
    a.y.push_back(std::exp(-std::tan(t) / 3));
    b.x.push_back(i);
    b.y.push_back(std::exp(-std::tan(t) / 3) + 0.02 * std::sin(i));
    b.y_err.push_back(0.02);
  }
  a.label = "analytic";
  b.label = "simulated & <checked>";
  b.style = PlotStyle::Markers;
  PlotSeries c = a;
  c.label = "dashed";
  c.style = PlotStyle::Dashed;
  for (auto& v : c.y) v *= 0.9;
  c.band_lo = c.y;
  c.band_hi = c.y;
  for (auto& v : c.band_lo) v -= 0.05;
  for (auto& v : c.band_hi) v += 0.05;
  p.add(a);
  p.add(b);
  p.add(c);
  return p;
}

}  // namespace

TEST(plot, PngHasAskedSize) {
  auto d = temp_dir();
  auto p = sample_plot();
  p.write((d / "a.png").string(), 640, 480);
  auto [w, h] = png_size(slurp(d / "a.png"));
  EXPECT_EQ(w, 640u);
  EXPECT_EQ(h, 480u);
  // write_png ignores the extension.
  p.write_png((d / "b.img").string(), 300, 200);
  auto [w2, h2] = png_size(slurp(d / "b.img"));
  EXPECT_EQ(w2, 300u);
  EXPECT_EQ(h2, 200u);
  // No temporaries left behind.
  int n = 0;
  for (auto& e : fs::directory_iterator(d))
    n += e.path().string().find(".tmp-") != std::string::npos;
  EXPECT_EQ(n, 0);
  fs::remove_all(d);
}

TEST(plot, SvgHasSizeTitleAndLabels) {
  auto d = temp_dir();
  auto p = sample_plot();
  p.write((d / "a.svg").string(), 700, 500);
  auto svg = slurp(d / "a.svg");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("width=\"700"), std::string::npos);
  EXPECT_NE(svg.find("height=\"500"), std::string::npos);
  EXPECT_NE(svg.find("<title>Free travel probability</title>"), std::string::npos);
  EXPECT_NE(svg.find("theta (deg)"), std::string::npos);
  EXPECT_NE(svg.find("Gamma_0 (1)"), std::string::npos);
  EXPECT_NE(svg.find("simulated &amp; &lt;checked&gt;"), std::string::npos);  // escaped
  fs::remove_all(d);
}

TEST(plot, LogAxisDropsNonPositiveData) {
  auto d = temp_dir();
  Plot p;
  p.title = "log";
  p.x.label = "s (1)";
  p.y.label = "value (1)";
  p.y.scale = AxisScale::Log;
  p.x.scale = AxisScale::Log;
  PlotSeries s;
  s.x = {-1, 0, 0.1, 1, 10, 100, NAN, 1000};
  s.y = {1, 1, 1e-3, 0, 1e-1, -5, 1, 1e2};
  s.label = "mixed";
  s.y_err = {0, 0, 2e-3, 0, 0.5, 0, 0, 1};  // lower end <= 0: drawn to the frame
  p.add(s);
  EXPECT_NO_THROW(p.write((d / "log.png").string()));
  EXPECT_NO_THROW(p.write((d / "log.svg").string()));
  // Only non-positive data on the log axis: nothing to draw.
  Plot q = p;
  q.series[0].y = {0, -1, 0, 0, -2, 0, 0, 0};
  try {
    q.write((d / "none.png").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to draw"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("log axis"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(d / "none.png"));
  // Fixed non-positive limit on a log axis is an error.
  Plot r = p;
  r.y.min = 0.0;
  EXPECT_THROW(r.write((d / "bad.png").string()), InputError);
  fs::remove_all(d);
}

TEST(plot, EmptyPlotIsAClearError) {
  auto d = temp_dir();
  Plot p;
  p.title = "empty";
  try {
    p.write((d / "e.png").string());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("nothing to draw"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("empty"), std::string::npos);
  }
  PlotSeries s;
  s.x = {1, 2};
  s.y = {NAN, INFINITY};
  p.add(s);
  EXPECT_THROW(p.write((d / "e.svg").string()), InputError);
  EXPECT_TRUE(fs::is_empty(d));
  fs::remove_all(d);
}

TEST(plot, BadInputsAndUnwritablePaths) {
  auto d = temp_dir();
  auto p = sample_plot();
  p.series[0].y.pop_back();
  EXPECT_THROW(p.write((d / "a.png").string()), InputError);  // x, y lengths differ
  auto q = sample_plot();
  EXPECT_THROW(q.write((d / "a.jpg").string()), InputError);  // unknown format
  EXPECT_THROW(q.write((d / "no" / "such" / "dir.png").string()), FileError);
  EXPECT_THROW(q.write((d / "no" / "such" / "dir.svg").string()), FileError);
  fs::remove_all(d);
}

TEST(plot, SinglePointAndConstantData) {
  auto d = temp_dir();
  Plot p;
  p.add({{1.0}, {2.0}, "one", PlotStyle::Markers});
  EXPECT_NO_THROW(p.write((d / "one.png").string(), 200, 150));
  fs::remove_all(d);
}

TEST(plot, GridOfPlots) {
  auto d = temp_dir();
  std::vector<Plot> plots(5, sample_plot());
  plots[1].y.scale = AxisScale::Log;
  write_plot_grid(plots, 3, (d / "grid.png").string(), 320, 240);
  auto [w, h] = png_size(slurp(d / "grid.png"));
  EXPECT_EQ(w, 960u);
  EXPECT_EQ(h, 480u);
  write_plot_grid(plots, 2, (d / "grid.svg").string(), 320, 240);
  EXPECT_NE(slurp(d / "grid.svg").find("theta (deg)"), std::string::npos);
  EXPECT_THROW(write_plot_grid({}, 2, (d / "x.png").string()), InputError);
  fs::remove_all(d);
}

TEST(plot, Ticks) {
  auto t = detail::linear_ticks(0, 90, 9);
  ASSERT_FALSE(t.empty());
  EXPECT_EQ(t.front().label, "0");
  EXPECT_EQ(t.back().label, "90");
  auto u = detail::linear_ticks(-0.013, 0.021, 5);
  for (auto& k : u) EXPECT_LE(k.label.size(), 6u) << k.label;
  bool zero = false;
  for (auto& k : u) zero |= k.value == 0 && std::stod(k.label) == 0 && k.label[0] != '-';
  EXPECT_TRUE(zero);
  auto l = detail::log_ticks(1e-3, 1e2);
  int labelled = 0;
  for (auto& k : l) labelled += !k.label.empty();
  EXPECT_EQ(labelled, 6);  // 1e-3 .. 100
  EXPECT_EQ(detail::format_tick(1e-5, 1e-5), "1e-5");
  EXPECT_EQ(detail::format_tick(2.5, 0.5), "2.5");
  EXPECT_EQ(detail::format_tick(-75, 25), "-75");
  EXPECT_EQ(detail::format_tick(0.75, 0.25), "0.75");
  EXPECT_EQ(detail::format_tick(0.2, 0.1), "0.2");
  auto narrow = detail::log_ticks(2, 3);
  EXPECT_GE(narrow.size(), 2u);
}

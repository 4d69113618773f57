// Measured-BRDF file formats: RGL tensor container, MERL .binary, goniometer CSV (round trips,
// hostile headers, exact values at the tabulation nodes).
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "microbrdf/brdf_albedo.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/microfacet_brdf.hpp"
#include "microbrdf/tensor_file.hpp"
#include "test_microfacet_common.hpp"

using namespace microbrdf;

namespace {
constexpr double kDeg = 3.14159265358979323846 / 180.0;
Vec3 dir(double theta_deg, double phi_deg) { return mtest::direction(theta_deg, phi_deg); }
MicrofacetBrdf ggx_conductor(double ax, double ay) {
  return MicrofacetBrdf(std::make_shared<GgxDistribution>(ax, ay, 0),
                        std::make_shared<ConductorFresnel>(constant_index(1.2, 3.5)));
}
}  // namespace

TEST(TensorFile, RoundTripKeepsFieldsAndAlignsBlocks) {
  TensorFile f;
  const std::vector<double> a = {1.5, -2, 3.25, 4, 5, 6};
  const std::vector<std::uint8_t> d = {'h', 'i', '!'};
  f.fields.push_back(TensorField::uint8("description", {3}, d));
  f.fields.push_back(TensorField::float32("a", {2, 3}, std::span<const double>(a)));
  const auto bytes = encode_tensor_file(f);
  EXPECT_EQ(std::memcmp(bytes.data(), "tensor_file\0\1\0", 14), 0);
  EXPECT_EQ(bytes.size() % 8, 0u);
  const auto g = parse_tensor_file(bytes, "mem");
  ASSERT_EQ(g.fields.size(), 2u);
  const auto& ga = g.field("a", "mem");
  EXPECT_EQ(ga.shape, (std::vector<std::uint64_t>{2, 3}));
  const auto v = ga.as_float32("mem");
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(v[i], static_cast<float>(a[i]));
  EXPECT_EQ(g.field("description", "mem").data, d);
  // Every data block starts at a multiple of 8 bytes: the offset field follows name + ndim + dtype.
  std::size_t pos = 18;
  for (const auto& fld : f.fields) {
    pos += 2 + fld.name.size() + 2 + 1;
    std::uint64_t off;
    std::memcpy(&off, bytes.data() + pos, 8);
    EXPECT_EQ(off % 8, 0u) << fld.name;
    pos += 8 + 8 * fld.shape.size();
  }
  EXPECT_THROW(g.field("missing", "mem"), FileError);
}

TEST(TensorFile, HostileHeadersAreRejectedWithoutHugeAllocations) {
  TensorFile f;
  const std::vector<double> a = {1, 2, 3, 4};
  f.fields.push_back(TensorField::float32("a", {4}, std::span<const double>(a)));
  auto good = encode_tensor_file(f);
  // Field count far beyond what the bytes can hold.
  auto b = good;
  const std::uint32_t many = 0xffffffffu;
  std::memcpy(b.data() + 14, &many, 4);
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  // A shape of 2^62 elements.
  b = good;
  const std::uint64_t huge = std::uint64_t{1} << 62;
  std::memcpy(b.data() + 18 + 2 + 1 + 2 + 1 + 8, &huge, 8);
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  // Offset past the end.
  b = good;
  const std::uint64_t far = 1u << 30;
  std::memcpy(b.data() + 18 + 2 + 1 + 2 + 1, &far, 8);
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  // Wrong magic, wrong version, truncated.
  b = good;
  b[0] = 'T';
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  b = good;
  b[12] = 2;
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  b.assign(good.begin(), good.begin() + 30);
  EXPECT_THROW(parse_tensor_file(b, "x.bsdf"), FileError);
  try {
    parse_tensor_file(b, "x.bsdf");
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("x.bsdf"), std::string::npos);
  }
}

TEST(Merl, CoordinatesInvertDirections) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  for (int k = 0; k < 200; ++k) {
    const double th = u(rng) * 1.5, td = u(rng) * 1.5, pd = u(rng) * 3.14159;
    Vec3 wi, wo;
    merl_directions(th, td, pd, wi, wo);
    const auto c = merl_coordinates(wi, wo);
    EXPECT_NEAR(c[0], th, 1e-9);
    EXPECT_NEAR(c[1], td, 1e-9);
    EXPECT_NEAR(c[2], pd, 1e-9);
  }
}

TEST(Merl, WriteReadRoundTripIsExactAtBinCentresAndCloseBetween) {
  const auto g = ggx_conductor(0.3, 0.3);
  const MerlTable t = tabulate_merl(g);
  const auto bytes = encode_merl(t);
  EXPECT_EQ(bytes.size(), 12 + 3 * MerlTable::kBins * 8);
  const MerlBrdf m(parse_merl(bytes, "mem.binary"), "mem");
  const auto wl = merl_channel_wavelengths();
  // At bin centres: the written value exactly (up to the 1/1500 scaling round trip).
  Vec3 wi, wo;
  merl_directions(merl_theta_half(30), merl_theta_diff(20), merl_phi_diff(50), wi, wo);
  EXPECT_NEAR(m.eval(wi, wo, wl[1]), g.eval(wi, wo, wl[1]), 1e-12 * g.eval(wi, wo, wl[1]));
  // Between bins, trilinear interpolation stays within 2% on the lobe.
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  int n = 0;
  for (int k = 0; k < 400; ++k) {
    const Vec3 a = dir(60 * u(rng), 360 * u(rng)), b = dir(60 * u(rng), 360 * u(rng));
    const double ref = g.eval(a, b, wl[0]);
    if (ref < 0.2) continue;
    EXPECT_NEAR(m.eval(a, b, wl[0]), ref, 0.02 * ref);
    ++n;
  }
  EXPECT_GT(n, 20);
}

TEST(Merl, InvalidBinsAreUnmeasuredAndHostileFilesRejected) {
  MerlTable t;
  for (auto& v : t.rgb) v = std::numeric_limits<double>::quiet_NaN();
  const MerlBrdf m(parse_merl(encode_merl(t), "mem"));
  EXPECT_TRUE(std::isnan(m.eval(dir(10, 0), dir(10, 180), 550e-9)));
  auto bytes = encode_merl(MerlTable{});
  std::int32_t bad = 1 << 30;
  std::memcpy(bytes.data(), &bad, 4);
  EXPECT_THROW(parse_merl(bytes, "x.binary"), FileError);
  bytes = encode_merl(MerlTable{});
  bytes.resize(bytes.size() - 8);
  EXPECT_THROW(parse_merl(bytes, "x.binary"), FileError);
}

TEST(Gonio, CsvRoundTripAndErrorsNameTheLine) {
  GonioData d;
  d.has_sigma = true;
  d.points.push_back({10 * kDeg, 0, 20 * kDeg, 180 * kDeg, 550e-9, 1.25, 0.01});
  d.points.push_back({30 * kDeg, 45 * kDeg, 5 * kDeg, -90 * kDeg, 600e-9, 0.5, 0.02});
  const auto text = encode_gonio_csv(d);
  const auto e = parse_gonio_csv(text, "mem.csv");
  ASSERT_EQ(e.points.size(), 2u);
  EXPECT_TRUE(e.has_sigma);
  EXPECT_NEAR(e.points[1].phi_o, -90 * kDeg, 1e-15);
  EXPECT_NEAR(e.points[1].wavelength_m, 600e-9, 1e-20);
  EXPECT_NEAR(e.points[0].sigma, 0.01, 1e-15);
  // Columns in another order, extra columns ignored, comments skipped.
  const auto f = parse_gonio_csv(
      "# instrument "
      "X\nbrdf_per_sr,extra,wavelength_nm,phi_o_deg,theta_o_deg,phi_i_deg,theta_i_deg\n"
      "2.5,abc,550,180,10,0,10\n",
      "mem.csv");
  ASSERT_EQ(f.points.size(), 1u);
  EXPECT_FALSE(f.has_sigma);
  EXPECT_EQ(f.points[0].brdf, 2.5);
  EXPECT_TRUE(std::isnan(f.points[0].sigma));
  try {
    parse_gonio_csv(
        "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n"
        "10,0,10,180,550,1\n10,0,95,180,550,1\n",
        "g.csv");
    FAIL();
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("g.csv: line 3"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_gonio_csv("theta_i_deg,phi_i_deg\n1,2\n", "g.csv"), FileError);
  EXPECT_THROW(parse_gonio_csv("", "g.csv"), FileError);
  EXPECT_THROW(parse_gonio_csv("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,"
                               "brdf_per_sr\n10,0,10,180,nan,1\n",
                               "g.csv"),
               FileError);
}

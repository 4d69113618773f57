// OpenGPS .x3p reader and writer: real fixtures against independent reference values, the
// conventions (signed int16 + scaling, valid.bin bit order, +Inf), a bit-exact round trip, and
// hostile input (truncation, absurd sizes, size mismatches, missing members).
#include <gtest/gtest.h>
#include <unistd.h>
#include <zip.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "format_test_util.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/surface.hpp"

using namespace microbrdf;
using namespace microbrdf::test;
namespace fs = std::filesystem;

namespace {

const std::string kData = MICROBRDF_TEST_DATA;

// |a - b| <= rel * |b| (reference values are printed with ~6 significant digits).
#define EXPECT_REL(a, b, rel) EXPECT_NEAR((a), (b), std::abs(b) * (rel))

struct Ref {
  std::size_t nx, ny;
  double dx, dy;
  std::size_t invalid;
  double min, max, mean, sq, z00;  // z00 NaN = invalid
};

void check_fixture(const std::string& path, const Ref& ref, double mean_abs_tol) {
  Surface s = read_surface(path);
  s.check();
  EXPECT_EQ(s.nx, ref.nx);
  EXPECT_EQ(s.ny, ref.ny);
  EXPECT_REL(s.dx, ref.dx, 1e-6);
  EXPECT_REL(s.dy, ref.dy, 1e-6);
  Stats st = stats(s);
  EXPECT_EQ(st.invalid, ref.invalid);
  EXPECT_REL(st.min, ref.min, 1e-5);
  EXPECT_REL(st.max, ref.max, 1e-5);
  // The mean of a zero-centred surface is tiny: compare it against the roughness scale.
  EXPECT_NEAR(st.mean, ref.mean, std::max(std::abs(ref.mean) * 1e-5, mean_abs_tol));
  EXPECT_REL(st.sq, ref.sq, 1e-5);
  if (std::isnan(ref.z00)) {
    EXPECT_FALSE(s.is_valid(0));
    EXPECT_TRUE(std::isnan(s.z[0]));
  } else {
    ASSERT_TRUE(s.is_valid(0));
    EXPECT_REL(s.z[0], ref.z00, 1e-6);
  }
  EXPECT_EQ(s.meta.format, "x3p");
  EXPECT_EQ(s.meta.z_unit_in_file, "m");
  EXPECT_EQ(s.meta.get("md5_warning"), "");
}

std::vector<std::uint8_t> slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {});
}

std::string temp_path(const std::string& leaf) {
  return (fs::temp_directory_path() / ("microbrdf-x3p-" + std::to_string(::getpid()) + "-" + leaf))
      .string();
}

/// Builds a zip archive from (name, content) pairs, stored uncompressed or deflated.
std::string make_zip(const std::string& leaf,
                     const std::vector<std::pair<std::string, std::string>>& members) {
  std::string path = temp_path(leaf);
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  EXPECT_NE(z, nullptr);
  for (const auto& [name, content] : members) {
    zip_source_t* src = zip_source_buffer(z, content.data(), content.size(), 0);
    EXPECT_GE(zip_file_add(z, name.c_str(), src, 0), 0);
  }
  EXPECT_EQ(zip_close(z), 0);
  return path;
}

std::string main_xml(const std::string& sizes, const std::string& ztype,
                     const std::string& record3_data) {
  return R"(<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
 <Record1><Revision>ISO5436 - 2000</Revision><FeatureType>SUR</FeatureType>
  <Axes>
   <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-6</Increment><Offset>0</Offset></CX>
   <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>2e-6</Increment><Offset>0</Offset></CY>
   <CZ><AxisType>A</AxisType><DataType>)" +
         ztype + R"(</DataType></CZ>
  </Axes></Record1>
 <Record3><MatrixDimension>)" +
         sizes + "</MatrixDimension>" + record3_data + R"(</Record3>
 <Record4><ChecksumFile>md5checksum.hex</ChecksumFile></Record4>
</p:ISO5436_2>
)";
}

std::string dims(const std::string& x, const std::string& y) {
  return "<SizeX>" + x + "</SizeX><SizeY>" + y + "</SizeY><SizeZ>1</SizeZ>";
}

const std::string kLink = "<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>";

std::string doubles(std::size_t n) {
  std::string b(n * 8, '\0');
  for (std::size_t i = 0; i < n; ++i) {
    double v = 1e-6 * static_cast<double>(i);
    std::memcpy(&b[i * 8], &v, 8);
  }
  return b;
}

/// Expects reading `path` to throw FileError naming the file and containing `needle`.
void expect_x3p_error(const std::string& path, const std::string& needle) {
  try {
    read_surface(path);
    ADD_FAILURE() << "no FileError for " << path;
  } catch (const FileError& e) {
    std::string what = e.what();
    EXPECT_NE(what.find(fs::path(path).filename().string()), std::string::npos) << what;
    EXPECT_NE(what.find(needle), std::string::npos) << what;
  }
}

}  // namespace

// ------------------------------------------------------------------ real fixtures

TEST(x3p, SampleLandMatchesReference) {
  check_fixture(kData + "/sample-land.x3p",
                {918, 256, 2.58e-6, 2.58e-6, 25292, -7.94735e-05, 5.24986e-05, -5.35207e-07,
                 3.43343e-05, -5.421108e-05},
                1e-11);
  Surface s = read_surface(kData + "/sample-land.x3p");
  EXPECT_EQ(s.meta.instrument, "Sensofar Sneox1 350262016");
  EXPECT_EQ(s.meta.date, "2018-09-15T17:46:09");
  EXPECT_EQ(s.meta.get("creator"), "CSAFE, Connor Hegenreter");
  EXPECT_EQ(s.meta.get("x3p_main_xml"), "sample-land/main.xml");
  EXPECT_NE(s.meta.comment.find("Downsampled"), std::string::npos);
  EXPECT_EQ(s.x0, 0.0);
  EXPECT_EQ(s.y0, 0.0);
}

#ifdef MICROBRDF_EXTRA_DATA
// Two real files over the 2 MB fixture limit, read from the optional extra data folder.
TEST(x3p, MountainsMapX3p2MatchesReference) {
  std::string path = std::string(MICROBRDF_EXTRA_DATA) + "/x3p-2.x3p";
  if (!fs::exists(path)) GTEST_SKIP() << path << " not in the extra data folder";
  check_fixture(path,
                {650, 650, 0.127656509837346e-6, 0.314582113527746e-6, 0, -3.14421e-07, 2.39916e-07,
                 -2.49182e-09, 7.72803e-08, 6.579781e-08},
                1e-13);
  Surface s = read_surface(path);
  EXPECT_DOUBLE_EQ(s.x0, 7.65614218798151e-005);  // non-zero offsets kept
  EXPECT_DOUBLE_EQ(s.y0, 1.29451679506934e-005);
  EXPECT_EQ(s.meta.get("instrument_manufacturer"), "DIGITAL SURF");
}

TEST(x3p, AliconaSkiInfiniteMarksInfInvalid) {
  std::string path = std::string(MICROBRDF_EXTRA_DATA) + "/SkiInfiniteFocus.x3p";
  if (!fs::exists(path)) GTEST_SKIP() << path << " not in the extra data folder";
  check_fixture(path,
                {1197, 940, 3.678887926e-6, 3.680270397e-6, 4272, -5.19301e-05, 3.23063e-05,
                 5.00245e-10, 1.8155e-05, NAN},
                1e-11);
}
#endif

TEST(x3p, Sample1BinMatchesReferenceAndValidBitOrder) {
  check_fixture(kData + "/ISO5436-sample1_bin.x3p",
                {4, 4, 0.016016, 0.016016, 1, -0.808369, 1.0476, 0.291926, 0.610509, 0.486219},
                1e-6);
  Surface s = read_surface(kData + "/ISO5436-sample1_bin.x3p");
  // valid.bin = 7f ff: LSB first, so only point 7 (x = 3, y = 1) is invalid.
  for (std::size_t i = 0; i < s.size(); ++i) EXPECT_EQ(s.is_valid(i), i != 7) << i;
  EXPECT_EQ(s.meta.get("instrument_manufacturer"), "NanoFocus AG");
}

TEST(x3p, Sample4SignedInt16Scaling) {
  check_fixture(kData + "/ISO5436-sample4_bin.x3p",
                {4, 4, 0.016016, 0.016016, 1, -0.808, 1.048, 0.292, 0.610538, 0.486}, 1e-6);
  Surface s4 = read_surface(kData + "/ISO5436-sample4_bin.x3p");
  Surface s1 = read_surface(kData + "/ISO5436-sample1_bin.x3p");
  // Point 7 is invalid only through valid.bin (its raw value is 0, z would be -0.5).
  EXPECT_FALSE(s4.is_valid(7));
  EXPECT_EQ(s4.valid_count(), 15u);
  // z = -0.5 + 0.001 * raw with signed raw values: the heights below -0.5 need negative raw.
  std::size_t below = 0;
  for (std::size_t i = 0; i < s4.size(); ++i) {
    if (!s4.is_valid(i)) continue;
    below += s4.z[i] < -0.5;
    double raw = (s4.z[i] + 0.5) / 0.001;
    EXPECT_NEAR(raw, std::round(raw), 1e-6) << i;        // on the int16 grid
    EXPECT_NEAR(s4.z[i], s1.z[i], 0.0005 + 1e-12) << i;  // same heights, quantised
  }
  EXPECT_GT(below, 0u);
}

// ------------------------------------------------------------------ writer

TEST(x3p, RoundTripIsBitExact) {
  std::mt19937_64 rng(42);
  std::normal_distribution<double> g(0, 1e-6);
  Surface s(37, 23, 1.234567890123e-7, 3.1415926535897e-7);
  s.x0 = -12.3456789e-6;
  s.y0 = 98.7654321e-5;
  for (auto& v : s.z) v = g(rng);
  s.z[5] = -0.0;                                                   // sign of zero survives
  s.z[6] = 5e-324;                                                 // denormal survives
  for (std::size_t i : {0u, 7u, 8u, 100u, 850u}) s.invalidate(i);  // holes, incl. byte edges
  s.meta.date = "2024-01-02T03:04:05";
  s.meta.comment = "round <trip> & \"test\"";
  s.meta.set("instrument_manufacturer", "ACME");
  s.meta.set("instrument_model", "Profilo 3000");
  std::string path = temp_path("roundtrip.x3p");
  write_surface(s, path);
  Surface r = read_surface(path);
  fs::remove(path);
  ASSERT_EQ(r.nx, s.nx);
  ASSERT_EQ(r.ny, s.ny);
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.dx), std::bit_cast<std::uint64_t>(s.dx));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.dy), std::bit_cast<std::uint64_t>(s.dy));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.x0), std::bit_cast<std::uint64_t>(s.x0));
  EXPECT_EQ(std::bit_cast<std::uint64_t>(r.y0), std::bit_cast<std::uint64_t>(s.y0));
  EXPECT_EQ(r.valid, s.valid);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (s.is_valid(i))
      EXPECT_EQ(std::bit_cast<std::uint64_t>(r.z[i]), std::bit_cast<std::uint64_t>(s.z[i])) << i;
    else
      EXPECT_TRUE(std::isnan(r.z[i])) << i;
  }
  EXPECT_EQ(r.meta.date, s.meta.date);
  EXPECT_EQ(r.meta.comment, s.meta.comment);
  EXPECT_EQ(r.meta.instrument, "ACME Profilo 3000");
  EXPECT_EQ(r.meta.get("creator"), "microbrdf");
  EXPECT_EQ(r.meta.get("md5_warning"), "");  // the writer's checksums are right
}

TEST(x3p, WriterLayoutIsStandard) {
  Surface s(8, 6, 1e-6, 1e-6);
  s.invalidate(3);
  std::string path = temp_path("layout.x3p");
  write_surface(s, path);
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_RDONLY, &err);
  ASSERT_NE(z, nullptr);
  EXPECT_GE(zip_name_locate(z, "main.xml", 0), 0);
  EXPECT_GE(zip_name_locate(z, "md5checksum.hex", 0), 0);
  EXPECT_GE(zip_name_locate(z, "bindata/data.bin", 0), 0);
  EXPECT_GE(zip_name_locate(z, "bindata/valid.bin", 0), 0);
  zip_stat_t st;
  ASSERT_EQ(zip_stat(z, "bindata/data.bin", 0, &st), 0);
  EXPECT_EQ(st.size, 8u * 6u * 8u);
  ASSERT_EQ(zip_stat(z, "bindata/valid.bin", 0, &st), 0);
  EXPECT_EQ(st.size, 6u);
  ASSERT_EQ(zip_stat(z, "main.xml", 0, &st), 0);
  std::string xml(st.size, '\0');
  zip_file_t* f = zip_fopen(z, "main.xml", 0);
  ASSERT_NE(f, nullptr);
  EXPECT_EQ(zip_fread(f, xml.data(), xml.size()), static_cast<zip_int64_t>(xml.size()));
  zip_fclose(f);
  zip_discard(z);
  fs::remove(path);
  EXPECT_NE(xml.find("http://www.opengps.eu/2008/ISO5436_2"), std::string::npos);
  EXPECT_NE(xml.find("<FeatureType>SUR</FeatureType>"), std::string::npos);
  EXPECT_NE(xml.find("<Revision>ISO5436 - 2000</Revision>"), std::string::npos);
  EXPECT_NE(xml.find("<Creator>microbrdf</Creator>"), std::string::npos);
  EXPECT_NE(xml.find("<MD5ChecksumValidPoints>"), std::string::npos);
  EXPECT_NE(xml.find("<ChecksumFile>md5checksum.hex</ChecksumFile>"), std::string::npos);
}

TEST(x3p, RoundTripSampleLand) {
  Surface a = read_surface(kData + "/sample-land.x3p");
  std::string path = temp_path("land.x3p");
  write_surface(a, path);
  Surface b = read_surface(path);
  fs::remove(path);
  ASSERT_EQ(b.nx, a.nx);
  ASSERT_EQ(b.ny, a.ny);
  EXPECT_EQ(b.dx, a.dx);
  EXPECT_EQ(b.dy, a.dy);
  EXPECT_EQ(b.valid, a.valid);
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.is_valid(i)) {
      ASSERT_EQ(b.z[i], a.z[i]) << i;
    }
  EXPECT_EQ(b.meta.instrument, a.meta.instrument);
  EXPECT_EQ(b.meta.date, a.meta.date);
  EXPECT_EQ(b.meta.comment, a.meta.comment);
}

// ------------------------------------------------------------------ hostile input

TEST(x3p, TruncatedArchivesThrowFileError) {
  auto bytes = slurp(kData + "/ISO5436-sample1_bin.x3p");
  ASSERT_GT(bytes.size(), 1000u);
  std::size_t errors = 0;
  for (std::size_t len :
       {std::size_t{0}, std::size_t{3}, std::size_t{30}, std::size_t{200}, bytes.size() / 2,
        bytes.size() - 100, bytes.size() - 22, bytes.size() - 1}) {
    std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<long>(len));
    try {
      read_surface_bytes(cut, SurfaceFormat::X3p, "cut.x3p");
      ADD_FAILURE() << "truncated to " << len << " bytes was accepted";
    } catch (const FileError& e) {
      ++errors;
      EXPECT_NE(std::string(e.what()).find("cut.x3p"), std::string::npos);
    }
  }
  EXPECT_EQ(errors, 8u);
  // A big one too: cut inside data.bin's compressed stream.
  auto land = slurp(kData + "/sample-land.x3p");
  for (std::size_t len : {land.size() / 3, land.size() - 5000}) {
    std::vector<std::uint8_t> cut(land.begin(), land.begin() + static_cast<long>(len));
    EXPECT_THROW(read_surface_bytes(cut, SurfaceFormat::X3p, "cut.x3p"), FileError) << len;
  }
}

TEST(x3p, CorruptedDataBinBytesThrowFileError) {
  // Flip bytes inside the compressed stream of a real file: libzip's CRC or inflate must catch
  // it, and whatever it reports comes back as FileError.
  auto land = slurp(kData + "/sample-land.x3p");
  for (std::size_t at : {std::size_t{20000}, land.size() / 2}) {
    auto bad = land;
    for (std::size_t k = 0; k < 64; ++k) bad[at + k] ^= 0x5a;
    EXPECT_THROW(read_surface_bytes(bad, SurfaceFormat::X3p, "bad.x3p"), FileError) << at;
  }
}

TEST(x3p, DataSizeMismatchNamesFile) {
  std::string path =
      make_zip("mismatch.x3p", {{"main.xml", main_xml(dims("4", "3"), "D", kLink)},
                                {"bindata/data.bin", doubles(11)}});  // 11 of 12 points
  expect_x3p_error(path, "bindata/data.bin");
  expect_x3p_error(path, "96 bytes");
  fs::remove(path);
}

TEST(x3p, DataSizeMismatchForDataTypeNamesFile) {
  // Right count for float64, but the header says int16.
  std::string path = make_zip(
      "mismatch-type.x3p",
      {{"main.xml", main_xml(dims("4", "3"), "I", kLink)}, {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "int16");
  fs::remove(path);
}

TEST(x3p, AbsurdSizeXNamesFile) {
  std::string path =
      make_zip("absurd.x3p", {{"main.xml", main_xml(dims("4000000000", "3"), "D", kLink)},
                              {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "absurdly large");
  fs::remove(path);
  path = make_zip("negative.x3p", {{"main.xml", main_xml(dims("-4", "3"), "D", kLink)},
                                   {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "SizeX");
  fs::remove(path);
  path = make_zip("zero.x3p", {{"main.xml", main_xml(dims("0", "3"), "D", kLink)},
                               {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "empty grid");
  fs::remove(path);
}

TEST(x3p, MissingDataMemberNamesFile) {
  std::string path = make_zip("nodata.x3p", {{"main.xml", main_xml(dims("4", "3"), "D", kLink)}});
  expect_x3p_error(path, "not in the archive");
  fs::remove(path);
}

TEST(x3p, MissingMainXmlAndBadXml) {
  std::string path = make_zip("nomain.x3p", {{"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "no main.xml");
  fs::remove(path);
  path = make_zip("badxml.x3p", {{"main.xml", "<ISO5436_2><Record1>"}});
  expect_x3p_error(path, "not well-formed");
  fs::remove(path);
  path = make_zip("macosx.x3p", {{"__MACOSX/x/main.xml", main_xml(dims("4", "3"), "D", kLink)},
                                 {"__MACOSX/x/bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "no main.xml");
  fs::remove(path);
}

TEST(x3p, UnsupportedVariantsAreClear) {
  std::string xml = main_xml(dims("4", "3"), "D", kLink);
  std::string pcl = xml;
  pcl.replace(pcl.find("SUR"), 3, "PCL");
  std::string path = make_zip("pcl.x3p", {{"main.xml", pcl}, {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "PCL");
  fs::remove(path);
  path = make_zip(
      "sizez.x3p",
      {{"main.xml", main_xml("<SizeX>4</SizeX><SizeY>3</SizeY><SizeZ>2</SizeZ>", "D", kLink)},
       {"bindata/data.bin", doubles(24)}});
  expect_x3p_error(path, "SizeZ");
  fs::remove(path);
  path = make_zip("ztype.x3p", {{"main.xml", main_xml(dims("4", "3"), "Q", kLink)},
                                {"bindata/data.bin", doubles(12)}});
  expect_x3p_error(path, "DataType");
  fs::remove(path);
}

TEST(x3p, ValidBinSizeMismatch) {
  std::string link =
      "<DataLink><PointDataLink>bindata/data.bin</PointDataLink>"
      "<ValidPointsLink>bindata/valid.bin</ValidPointsLink></DataLink>";
  std::string path = make_zip("validsize.x3p", {{"main.xml", main_xml(dims("4", "3"), "D", link)},
                                                {"bindata/data.bin", doubles(12)},
                                                {"bindata/valid.bin", std::string(1, '\xff')}});
  expect_x3p_error(path, "bindata/valid.bin");
  fs::remove(path);
  // The right size (2 bytes for 12 points) is accepted; bit 9 cleared marks point 9 invalid.
  path = make_zip("validok.x3p", {{"main.xml", main_xml(dims("4", "3"), "D", link)},
                                  {"bindata/data.bin", doubles(12)},
                                  {"bindata/valid.bin", std::string("\xff\xfd", 2)}});
  Surface s = read_surface(path);
  fs::remove(path);
  EXPECT_EQ(s.valid_count(), 11u);
  EXPECT_FALSE(s.is_valid(9));
  EXPECT_DOUBLE_EQ(s.z[10], 10e-6);
  EXPECT_EQ(s.dy, 2e-6);
}

TEST(x3p, InlineDataList) {
  std::string list = "<DataList>";
  for (int i = 0; i < 6; ++i)
    list += i == 4 ? "<Datum/>" : "<Datum>" + std::to_string(i) + "e-6</Datum>";
  list += "</DataList>";
  std::string path = make_zip("inline.x3p", {{"main.xml", main_xml(dims("3", "2"), "D", list)}});
  Surface s = read_surface(path);
  fs::remove(path);
  ASSERT_EQ(s.size(), 6u);
  EXPECT_DOUBLE_EQ(s.z[5], 5e-6);
  EXPECT_FALSE(s.is_valid(4));  // empty Datum = missing point
  EXPECT_EQ(s.valid_count(), 5u);
  // A DataList whose count disagrees with the grid is refused.
  path = make_zip("inline-bad.x3p", {{"main.xml", main_xml(dims("4", "2"), "D", list)}});
  expect_x3p_error(path, "6 Datum");
  fs::remove(path);
}

TEST(x3p, Md5MismatchIsAWarningNotAnError) {
  std::string link =
      "<DataLink><PointDataLink>bindata/data.bin</PointDataLink>"
      "<MD5ChecksumPointData>00112233445566778899AABBCCDDEEFF</MD5ChecksumPointData>"
      "</DataLink>";
  std::string path = make_zip("md5.x3p", {{"main.xml", main_xml(dims("4", "3"), "D", link)},
                                          {"bindata/data.bin", doubles(12)}});
  Surface s = read_surface(path);
  fs::remove(path);
  EXPECT_NE(s.meta.get("md5_warning").find("bindata/data.bin"), std::string::npos);
}

TEST(x3p, ZipBombIsRefusedBeforeReading) {
  // 64 MiB of zeros deflate to ~64 KB: plausible for deflate, so it is read only if the grid
  // asks for exactly that many bytes. Here the grid asks for 12 doubles.
  std::string zeros(std::size_t{64} << 20, '\0');
  std::string path = temp_path("bomb.x3p");
  int err = 0;
  zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
  ASSERT_NE(z, nullptr);
  std::string xml = main_xml(dims("4", "3"), "D", kLink);
  zip_file_add(z, "main.xml", zip_source_buffer(z, xml.data(), xml.size(), 0), 0);
  zip_int64_t i =
      zip_file_add(z, "bindata/data.bin", zip_source_buffer(z, zeros.data(), zeros.size(), 0), 0);
  zip_set_file_compression(z, static_cast<zip_uint64_t>(i), ZIP_CM_DEFLATE, 9);
  ASSERT_EQ(zip_close(z), 0);
  expect_x3p_error(path, "bindata/data.bin");
  fs::remove(path);
}

TEST(x3p, ForgedHugeMemberSizeIsRefusedBeforeAllocating) {
  // A stored data.bin whose central-directory entry is patched to claim 2 GiB, with a grid that
  // asks for exactly 2 GiB: the claim is implausible for a tiny archive and must be refused
  // without allocating or inflating anything.
  std::string path = temp_path("forged.x3p");
  {
    int err = 0;
    zip_t* z = zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &err);
    ASSERT_NE(z, nullptr);
    std::string xml = main_xml(dims("16384", "16384"), "D", kLink);
    std::string data = doubles(12);
    zip_file_add(z, "main.xml", zip_source_buffer(z, xml.data(), xml.size(), 0), 0);
    zip_int64_t i =
        zip_file_add(z, "bindata/data.bin", zip_source_buffer(z, data.data(), data.size(), 0), 0);
    zip_set_file_compression(z, static_cast<zip_uint64_t>(i), ZIP_CM_STORE, 0);
    ASSERT_EQ(zip_close(z), 0);
  }
  auto bytes = slurp(path);
  fs::remove(path);
  const std::string name = "bindata/data.bin";
  bool patched = false;
  for (std::size_t p = 0; p + 46 + name.size() <= bytes.size(); ++p) {
    if (bytes[p] == 'P' && bytes[p + 1] == 'K' && bytes[p + 2] == 1 && bytes[p + 3] == 2 &&
        std::memcmp(&bytes[p + 46], name.data(), name.size()) == 0) {
      const std::uint32_t huge = 0x80000000u;  // uncompressed size field at offset 24
      std::memcpy(&bytes[p + 24], &huge, 4);
      patched = true;
    }
  }
  ASSERT_TRUE(patched);
  try {
    read_surface_bytes(bytes, SurfaceFormat::X3p, "forged.x3p");
    ADD_FAILURE() << "forged size accepted";
  } catch (const FileError& e) {
    EXPECT_NE(std::string(e.what()).find("implausible"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("forged.x3p"), std::string::npos) << e.what();
  }
}

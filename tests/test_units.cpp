#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "microbrdf/error.hpp"
#include "microbrdf/units.hpp"

using namespace microbrdf;

TEST(Units, Lengths) {
  EXPECT_DOUBLE_EQ(parse_length("110nm"), 110e-9);
  EXPECT_DOUBLE_EQ(parse_length("1um"), 1e-6);
  EXPECT_DOUBLE_EQ(parse_length("1 \xC2\xB5m"), 1e-6);
  EXPECT_DOUBLE_EQ(parse_length("0.5mm"), 0.5e-3);
  EXPECT_DOUBLE_EQ(parse_length("2e-6m"), 2e-6);
  EXPECT_THROW(parse_length("110"), InputError);  // a bare length is ambiguous
  EXPECT_THROW(parse_length("110 furlongs"), InputError);
  EXPECT_THROW(parse_length("nm"), InputError);
}

TEST(Units, Angles) {
  EXPECT_NEAR(parse_angle("30"), M_PI / 6, 1e-15);  // a bare angle means degrees
  EXPECT_NEAR(parse_angle("30deg"), M_PI / 6, 1e-15);
  EXPECT_DOUBLE_EQ(parse_angle("0.05rad"), 0.05);
  EXPECT_THROW(parse_angle("3 parsecs"), InputError);
}

TEST(Units, Pairs) {
  auto p = parse_length_pair("70x53um");
  EXPECT_DOUBLE_EQ(p.x, 70e-6);
  EXPECT_DOUBLE_EQ(p.y, 53e-6);
  p = parse_length_pair("1mm x 500um");
  EXPECT_DOUBLE_EQ(p.x, 1e-3);
  EXPECT_DOUBLE_EQ(p.y, 500e-6);
}

TEST(Units, Format) {
  EXPECT_EQ(format_length(110e-9), "110 nm");
  EXPECT_EQ(format_length(1.5e-6), "1.5 um");
  EXPECT_EQ(format_length(0.0), "0 m");
  EXPECT_EQ(format_length(1.4e-21), "0 m");
  EXPECT_EQ(format_length(-2e-12), "-2 pm");
  // Values that do not exist print as n/a, never "nan m" or "inf m".
  EXPECT_EQ(format_length(std::numeric_limits<double>::quiet_NaN()), "n/a");
  EXPECT_EQ(format_length(std::numeric_limits<double>::infinity()), "n/a");
}

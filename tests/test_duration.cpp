// Durations on the command line (--time, --mpi-timeout): values in seconds written out by hand.
#include <gtest/gtest.h>

#include <string>

#include "microbrdf/duration.hpp"
#include "microbrdf/error.hpp"

using microbrdf::InputError;
using microbrdf::parse_duration;

TEST(Duration, UnitsToSeconds) {
  EXPECT_DOUBLE_EQ(parse_duration("30s", "--t"), 30.0);
  EXPECT_DOUBLE_EQ(parse_duration("30", "--t"), 30.0);  // a bare number is seconds
  EXPECT_DOUBLE_EQ(parse_duration("10min", "--t"), 600.0);
  EXPECT_DOUBLE_EQ(parse_duration("10m", "--t"), 600.0);
  EXPECT_DOUBLE_EQ(parse_duration("2h", "--t"), 7200.0);
  EXPECT_DOUBLE_EQ(parse_duration("1.5 h", "--t"), 5400.0);
  EXPECT_DOUBLE_EQ(parse_duration("250ms", "--t"), 0.25);
  EXPECT_DOUBLE_EQ(parse_duration("0", "--t"), 0.0);
  EXPECT_DOUBLE_EQ(parse_duration("8760h", "--t"), 365.0 * 86400);  // a year: the largest
}

TEST(Duration, RefusedNamingTheFlag) {
  for (const char* bad :
       {"", "soon", "-1s", "nan", "inf", "1e300h", "8761h", "5 days", "10 parsecs"}) {
    try {
      parse_duration(bad, "--mpi-timeout");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const InputError& e) {
      EXPECT_EQ(std::string(e.what()).rfind("--mpi-timeout: ", 0), 0u) << e.what();
    }
  }
}

// detail::fast_atan2 (core/fast_atan2.hpp) against std::atan2: every octant and sign, the octant
// edges, tiny and huge magnitudes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "core/fast_atan2.hpp"

using microbrdf::detail::fast_atan2;

TEST(FastAtan2, WithinThreeTenthsOfAPicoradianEverywhere) {
  double worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const double a = -M_PI + 2 * M_PI * (i + 0.37) / 200000;
    for (double r : {1e-300, 1e-9, 0.7, 1.0, 3.5e4, 1e250}) {
      const double y = r * std::sin(a), x = r * std::cos(a);
      worst = std::max(worst, std::abs(fast_atan2(y, x) - std::atan2(y, x)));
    }
  }
  EXPECT_LT(worst, 3e-13);
  // Octant edges and axes.
  for (double y : {-2.0, -1.0, -0.0, 0.0, 1.0, 2.0})
    for (double x : {-2.0, -1.0, 1.0, 2.0}) EXPECT_NEAR(fast_atan2(y, x), std::atan2(y, x), 3e-13);
  EXPECT_NEAR(fast_atan2(1.0, 0.0), M_PI / 2, 1e-15);
  EXPECT_NEAR(fast_atan2(-1.0, 0.0), -M_PI / 2, 1e-15);
  EXPECT_NEAR(fast_atan2(std::tan(M_PI / 8), 1.0), M_PI / 8, 3e-13);
  EXPECT_EQ(fast_atan2(0.0, 0.0), 0.0);
  EXPECT_TRUE(std::isnan(fast_atan2(std::nan(""), 1.0)));
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(fast_atan2(inf, 1.0), std::atan2(inf, 1.0));
}

// KirchhoffOptions::progress: called with the fraction of the scan's patches done, from 0 to 1,
// once per patch, and the result does not depend on whether it is set.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "microbrdf/kirchhoff.hpp"

using namespace microbrdf;

TEST(kirchhoff_progress, ReportsEachPatchFromZeroToOne) {
  // A 64 x 48 tilted plane (0.11 um spacing) cut into 3 x 2 patches of 2.3 um.
  Surface s(64, 48, 0.11e-6, 0.11e-6);
  for (std::size_t y = 0; y < s.ny; ++y)
    for (std::size_t x = 0; x < s.nx; ++x) s.at(x, y) = 0.02 * static_cast<double>(x) * s.dx;
  KirchhoffOptions o;
  o.resolution = 33;
  o.patch_x = 64 * 0.11e-6 / 3;
  o.patch_y = 48 * 0.11e-6 / 2;
  std::vector<double> seen;
  o.progress = [&](double f) { seen.push_back(f); };
  KirchhoffAccumulator acc(o);
  acc.add(s);
  ASSERT_EQ(acc.patches(), 6u);
  ASSERT_EQ(seen.size(), 7u);  // 0, then once per patch
  EXPECT_EQ(seen.front(), 0.0);
  EXPECT_DOUBLE_EQ(seen.back(), 1.0);
  for (std::size_t i = 1; i < seen.size(); ++i)
    EXPECT_NEAR(seen[i], static_cast<double>(i) / 6, 1e-15);
  // Same table without the callback.
  KirchhoffOptions quiet = o;
  quiet.progress = nullptr;
  const TabulatedNdf a = acc.result(), b = estimate_kirchhoff(s, quiet);
  ASSERT_EQ(a.values().size(), b.values().size());
  for (std::size_t i = 0; i < a.values().size(); ++i) EXPECT_EQ(a.values()[i], b.values()[i]);
}

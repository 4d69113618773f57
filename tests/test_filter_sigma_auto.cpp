// --filter-sigma auto: the Hellinger distance between NDF tables and the sweep of the filter
// sigma against D_K (filter_sigma_auto.hpp).
#include <gtest/gtest.h>

#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/filter_sigma_auto.hpp"
#include "microbrdf/generate.hpp"

using namespace microbrdf;

namespace {

Surface gaussian(std::size_t n, double spacing, double sigma, double tau, std::uint64_t seed) {
  GaussianSurfaceParams p;
  p.nx = p.ny = n;
  p.dx = p.dy = spacing;
  p.sigma = sigma;
  p.tau_x = p.tau_y = tau;
  p.seed = seed;
  return generate_gaussian(p);
}

FilterSigmaAutoOptions small_sweep() {
  FilterSigmaAutoOptions o;
  o.resolution = 129;
  o.coarse_points = 9;
  o.refine_points = 4;
  o.kirchhoff.patch_x = o.kirchhoff.patch_y = 0;  // one tile per scan
  return o;
}

void expect_consistent(const FilterSigmaAuto& r) {
  ASSERT_GE(r.curve.size(), 9u);
  for (std::size_t i = 1; i < r.curve.size(); ++i)
    EXPECT_LT(r.curve[i - 1].sigma_m, r.curve[i].sigma_m);
  for (const auto& p : r.curve) EXPECT_GE(p.hellinger, r.hellinger);  // the chosen one is the min
  EXPECT_DOUBLE_EQ(r.curve.front().sigma_m, r.sigma_min_m);
  EXPECT_DOUBLE_EQ(r.curve.back().sigma_m, r.sigma_max_m);
  EXPECT_NEAR(hellinger_distance(r.filtered, r.kirchhoff), r.hellinger, 1e-12);
  const auto j = r.to_json();
  EXPECT_EQ(j.at("curve").size(), r.curve.size());
  EXPECT_DOUBLE_EQ(j.at("sigma_m").get<double>(), r.sigma_m);
}

}  // namespace

TEST(Hellinger, ZeroForEqualTablesOneForDisjointAndScaleFree) {
  TabulatedNdf a(33), b(33);
  a.at(16, 16) = 1;
  a.at(17, 16) = 3;
  b.at(10, 10) = 2;
  EXPECT_NEAR(hellinger_distance(a, a), 0, 1e-12);
  EXPECT_NEAR(hellinger_distance(a, b), 1, 1e-12);
  TabulatedNdf a3 = a;
  for (auto& v : a3.values()) v *= 3;  // normalisation does not matter
  EXPECT_NEAR(hellinger_distance(a, a3), 0, 1e-12);
  // p = (1/4, 3/4), q = (1, 0): H^2 = 1 - sqrt(1/4).
  TabulatedNdf q(33);
  q.at(16, 16) = 5;
  EXPECT_NEAR(hellinger_distance(a, q), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(hellinger_distance(q, a), hellinger_distance(a, q), 1e-15);
  EXPECT_THROW(hellinger_distance(a, TabulatedNdf(17)), std::invalid_argument);
  EXPECT_THROW(hellinger_distance(a, TabulatedNdf(33)), InputError);
}

// Two scales: a geometric-optics Gaussian (tau 3 um, 0.2 um rms: q h ~ 4.5) plus a fine roughness
// of 10 nm rms and 100 nm correlation length, far below lambda_q = 555 nm (q h ~ 0.2). D_K sees
// the large slopes only; the naive NDF sees the fine slopes (rms 0.14 per axis) too. A filter of
// about the fine scale removes them and keeps the large ones: the distance has an interior minimum.
TEST(FilterSigmaAuto, TwoScaleSurfaceHasAnInteriorMinimumBelowTheNaiveDistance) {
  Surface s = gaussian(512, 25e-9, 0.2e-6, 3e-6, 1);
  const Surface fine = gaussian(512, 25e-9, 10e-9, 0.1e-6, 2);
  for (std::size_t i = 0; i < s.z.size(); ++i) s.z[i] += fine.z[i];
  const FilterSigmaAuto r = choose_filter_sigma(std::vector<Surface>{s}, small_sweep());
  expect_consistent(r);
  EXPECT_FALSE(r.at_lower_end);
  EXPECT_FALSE(r.at_upper_end);
  EXPECT_LT(r.hellinger, r.curve.front().hellinger - 0.03);
  EXPECT_LT(r.hellinger, r.curve.back().hellinger - 0.03);
  EXPECT_LT(r.hellinger, r.hellinger_naive_kirchhoff - 0.03);
  // About the fine scale: well above the spacing, well below the large correlation length.
  EXPECT_GT(r.sigma_m, 50e-9);
  EXPECT_LT(r.sigma_m, 500e-9);
  // The filter removed the fine slopes (rms 0.14 per axis) and kept the large ones (0.094): the
  // naive NDF is much wider. (D_K's own rms slope is no yardstick: the fine roughness scatters a
  // faint halo over the whole disk, which dominates a second moment but not the distance.)
  EXPECT_GT(r.naive.rms_slope(0), 1.4 * r.filtered.rms_slope(0));
}

// One scale in the geometric-optics regime (q h ~ 3.4, curvature radius >> lambda): D_K is the
// slope distribution, so no filter helps and the minimum lies at the smallest sigma swept.
TEST(FilterSigmaAuto, GeometricGaussianPrefersTheSmallestSigma) {
  const Surface s = gaussian(512, 50e-9, 0.15e-6, 2e-6, 3);
  const FilterSigmaAuto r = choose_filter_sigma(std::vector<Surface>{s}, small_sweep());
  expect_consistent(r);
  EXPECT_TRUE(r.at_lower_end);
  EXPECT_DOUBLE_EQ(r.sigma_m, 50e-9);
  EXPECT_LT(r.hellinger, r.curve.back().hellinger - 0.3);
}

TEST(FilterSigmaAuto, TooSmallAFieldIsAnInputError) {
  const Surface s = gaussian(8, 50e-9, 0.1e-6, 0.2e-6, 1);
  EXPECT_THROW(choose_filter_sigma(std::vector<Surface>{s}, small_sweep()), InputError);
}

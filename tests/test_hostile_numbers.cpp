// Numbers that are valid but absurd for the data they apply to: the filtered-normal kernel
// against the scan (its bound, its exact clamping, its memory estimate), micro-scene geometry
// against the tile, goniometer rows against the budget, and the file-size limit reported like a
// full disk.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <string>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/surface.hpp"

using namespace microbrdf;
namespace fs = std::filesystem;

namespace {

// A smooth bumpy surface (no randomness: the reference values below depend on nothing else).
Surface bumps(std::size_t nx, std::size_t ny, double dx, double dy) {
  Surface s(nx, ny, dx, dy);
  for (std::size_t iy = 0; iy < ny; ++iy)
    for (std::size_t ix = 0; ix < nx; ++ix)
      s.z[iy * nx + ix] = 0.3 * dx * std::sin(0.7 * double(ix)) +
                          0.2 * dy * std::cos(0.45 * double(iy)) +
                          0.05 * dx * double(ix) * double(iy) / double(nx);
  s.sync_mask();
  return s;
}

// Restores the memory budget a test changed.
struct BudgetGuard {
  std::uint64_t saved = memory_budget();
  ~BudgetGuard() { set_memory_budget(saved); }
};

// Independent reference: the Gaussian-weighted least-squares plane over every sample of the
// scan (no truncation at all: with the filter as wide as the scan, the truncated kernel reaches
// every sample anyway), solved as a 3 x 3 system by Cramer's rule.
void plane_normal(const Surface& s, std::size_t cx, std::size_t cy, double sigma, double n[3]) {
  double A[3][3] = {}, b[3] = {};
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      const double u = (double(ix) - double(cx)) * s.dx, v = (double(iy) - double(cy)) * s.dy;
      const double w = std::exp(-0.5 * (u * u + v * v) / (sigma * sigma));
      const double f[3] = {1, u, v}, h = s.z[iy * s.nx + ix];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) A[r][c] += w * f[r] * f[c];
        b[r] += w * f[r] * h;
      }
    }
  auto det3 = [](const double m[3][3]) {
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
  };
  const double d = det3(A);
  double slope[2];
  for (int k = 1; k <= 2; ++k) {
    double m[3][3];
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) m[r][c] = c == k ? b[r] : A[r][c];
    slope[k - 1] = det3(m) / d;
  }
  const double inv = 1 / std::sqrt(1 + slope[0] * slope[0] + slope[1] * slope[1]);
  n[0] = -slope[0] * inv;
  n[1] = -slope[1] * inv;
  n[2] = inv;
}

}  // namespace

TEST(HostileNumbers, FilterSigmaLongerThanTheScanIsRefusedNamingTheFile) {
  Surface s = bumps(16, 16, 1e-6, 1e-6);
  EXPECT_THROW(filtered_normals(s, 17e-6), InputError);
  s.meta.source_path = "scan.npy";
  try {
    filtered_normals(s, 1000.0);
    FAIL() << "a 1000 m filter sigma on a 16 um scan was accepted";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "scan.npy");
    EXPECT_NE(std::string(e.what()).find("filter sigma 1000 m is longer than the scan"),
              std::string::npos)
        << e.what();
  }
  // 1e-30 m spacing with a 1 um sigma: once 1e25 taps (a crash); now refused the same way.
  Surface tiny = bumps(16, 16, 1e-30, 1e-30);
  EXPECT_THROW(filtered_normals(tiny, 1e-6), InputError);
  EXPECT_THROW(filtered_normals(s, 1e-6, 1e9), InputError);  // truncation beyond 40 sigma
  EXPECT_NO_THROW(filtered_normals(s, 16e-6));               // the scan's side itself is fine
}

TEST(HostileNumbers, KernelClampedToTheScanGivesTheExactPlaneFit) {
  // sigma = the scan's side, truncation 4: the kernel would reach 4 scan lengths; clamped to the
  // scan it must still give the plane fit over every sample (support rule off: at the corners
  // most of so wide a kernel lies outside the scan).
  const Surface s = bumps(24, 20, 1e-6, 1.3e-6);
  const double sigma = 24e-6;
  const NormalField f = filtered_normals(s, sigma, 4, 0.0);
  ASSERT_EQ(f.used, s.size());
  for (auto [ix, iy] : {std::pair<std::size_t, std::size_t>{0, 0}, {23, 19}, {11, 7}, {5, 18}}) {
    double n[3];
    plane_normal(s, ix, iy, sigma, n);
    const std::size_t i = iy * s.nx + ix;
    EXPECT_NEAR(f.mx[i], n[0], 1e-9) << ix << ", " << iy;
    EXPECT_NEAR(f.my[i], n[1], 1e-9) << ix << ", " << iy;
    EXPECT_NEAR(f.mz[i], n[2], 1e-9) << ix << ", " << iy;
  }
  // A kernel of 1.2e8 taps along x (x spacing a million times finer than y): its reference mass
  // comes from the Gaussian's integral, not a loop over the taps; every sample is accounted for.
  const Surface a = bumps(6, 40, 1e-12, 1e-6);
  const NormalField g = filtered_normals(a, 30e-6);
  EXPECT_EQ(g.used + g.skipped, a.size());
}

TEST(HostileNumbers, FilteredNormalWorkingMemoryIsCheckedAgainstTheBudget) {
  BudgetGuard guard;
  Surface s = bumps(2, 6000, 1e-6, 1e-6);
  s.meta.source_path = "strip.npy";
  set_memory_budget(8ull << 20);
  try {
    filtered_normals(s, 5e-3);  // the ring of x-filtered rows: 6000 rows x 5 x 128 doubles
    FAIL() << "the filtered normals' working buffers ignored an 8 MiB budget";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "strip.npy");
    EXPECT_NE(std::string(e.what()).find("over the memory budget of 8 MiB"), std::string::npos)
        << e.what();
  }
  set_memory_budget(1ull << 30);
  EXPECT_NO_THROW(filtered_normals(s, 5e-3));
}

TEST(HostileNumbers, SceneGeometryIsBoundedByTheTile) {
  MicroSceneDesc d;
  d.width = d.height = 100e-6;
  d.materials.push_back(MicroMaterial{});
  d.planes.push_back({0.0, 0});
  EXPECT_NO_THROW(check_scene_geometry(d));
  d.planes.push_back({1e6, 0});  // a plane a million metres up: once 150 rays/s
  try {
    check_scene_geometry(d);
    FAIL() << "a plane at z = 1e6 m was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("plane 2: z = 1e+06 m must lie within 10 mm"),
              std::string::npos)
        << e.what();
  }
  d.planes.pop_back();
  d.planes.push_back({9.9e-3, 0});  // just inside 100 sides
  EXPECT_NO_THROW(check_scene_geometry(d));
  d.capsules.push_back(Capsule{{50e-6, 50e-6, 1e300}, {50e-6, 50e-6, 1e300}, 1e300, 0});
  EXPECT_THROW(check_scene_geometry(d), InputError);
  d.capsules.back() = Capsule{{50e-6, 50e-6, 0}, {50e-6, 50e-6, 0}, NAN, 0};
  EXPECT_THROW(check_scene_geometry(d), InputError);
  d.capsules.back() = Capsule{{-1, 50e-6, 0}, {2, 50e-6, 0}, 1e-6, 0};  // a metres-long fibre
  EXPECT_THROW(check_scene_geometry(d), InputError);
  d.capsules.clear();
  d.width = 1e-300;  // a tile below 1 nm
  EXPECT_THROW(check_scene_geometry(d), InputError);
  // The constructor checks too (scenes built in code, e.g. from Python), before Embree sees them.
  d.width = 100e-6;
  d.planes.back().z = INFINITY;
  EXPECT_THROW(MicroScene{d}, InputError);
}

TEST(HostileNumbers, GoniometerRowsAreCheckedAgainstTheBudgetBeforeParsing) {
  BudgetGuard guard;
  std::string csv = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n";
  for (int i = 0; i < 100000; ++i) csv += "10,0,12,180,550,0.5\n";
  set_memory_budget(4ull << 20);
  try {
    parse_gonio_csv(csv, "many.csv");
    FAIL() << "100000 rows were parsed under a 4 MiB budget";
  } catch (const FileError& e) {
    EXPECT_EQ(e.path(), "many.csv");
    EXPECT_NE(std::string(e.what()).find("up to 100002 goniometer rows"), std::string::npos)
        << e.what();
  }
  set_memory_budget(1ull << 30);
  EXPECT_EQ(parse_gonio_csv(csv, "many.csv").points.size(), 100000u);
}

namespace {

// In a child process (the limit and the handler stay there): writes 256 KiB under a 64 KiB
// limit; 0 when the error names the file and the limit and the handler saw the signal.
int write_past_the_limit(const std::string& out) {
  install_file_size_limit_handler();
  const rlimit r{64 * 1024, 64 * 1024};
  setrlimit(RLIMIT_FSIZE, &r);
  int code = 3;  // no error at all
  try {
    write_file_atomic(out, std::string(256 * 1024, 'x'));
  } catch (const FileError& e) {
    const std::string m = e.what();
    code = m.find(out + ": the file size limit (ulimit -f: 64 KiB) was reached") == 0 ? 0 : 4;
  }
  return file_size_limit_reached() ? code : 5;
}

}  // namespace

TEST(HostileNumbers, FileSizeLimitIsReportedLikeAFullDiskWithNothingLeft) {
  const fs::path dir =
      fs::temp_directory_path() / ("microbrdf-fsize-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string out = (dir / "big.bin").string();
  EXPECT_EXIT(std::_Exit(write_past_the_limit(out)), ::testing::ExitedWithCode(0), "");
  // Nothing written, no temporary left.
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

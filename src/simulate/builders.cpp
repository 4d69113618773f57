// Procedural micro-geometry: cylinder arrays, sphere grids, velvet fibres, plain weave.
#include <algorithm>
#include <cmath>

#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/simulate.hpp"

namespace microbrdf {
namespace {

using Vec = Eigen::Vector3d;

// Whole number of periods in `length`, or InputError.
int periods(double length, double period, const char* what) {
  const double n = length / period;
  const long k = std::lround(n);
  if (k < 1 || std::abs(n - double(k)) > 1e-6 * n)
    throw InputError(std::string(what) + ": the tile must be a whole number of periods (" +
                     std::to_string(n) + ")");
  return static_cast<int>(k);
}

// Every builder asks before it grows the scene: `n` more capsules from a count in a file.
void reserve_objects(MicroSceneDesc& d, std::int64_t n, const char* what) {
  const auto total = static_cast<std::int64_t>(d.capsules.size()) + n;
  if (n < 0 || total > kMaxSceneObjects)
    throw InputError(std::string(what) + ": " + std::to_string(n) +
                     " objects; a scene holds at most " + std::to_string(kMaxSceneObjects));
  const std::uint64_t bytes = mul_sat(static_cast<std::uint64_t>(total), 256);
  if (bytes > memory_budget())
    throw InputError(std::string(what) + ": " + std::to_string(total) + " objects need " +
                     format_bytes(bytes) + ", over the memory budget of " +
                     format_bytes(memory_budget()) + " (--max-memory)");
  d.capsules.reserve(static_cast<std::size_t>(total));
}

}  // namespace

void add_cylinders(MicroSceneDesc& d, double radius, std::int64_t count, double z_axis,
                   double jitter, std::uint64_t seed, int material, bool along_y) {
  if (!(radius > 0) || count < 1) throw InputError("cylinders: radius > 0 and count >= 1");
  reserve_objects(d, count, "cylinders");
  const double across = along_y ? d.width : d.height, along = along_y ? d.height : d.width;
  const double pitch = across / count;
  SimRng rng(seed, 0x6379);
  // Ends well outside the tile: the tile clips them, so they act as infinite cylinders.
  const double s0 = -2 * radius - 1e-3 * along, s1 = along + 2 * radius + 1e-3 * along;
  for (std::int64_t k = 0; k < count; ++k) {
    const double c =
        (static_cast<double>(k) + 0.5) * pitch + jitter * pitch * (2 * rng.uniform() - 1);
    const Vec a = along_y ? Vec(c, s0, z_axis) : Vec(s0, c, z_axis);
    const Vec b = along_y ? Vec(c, s1, z_axis) : Vec(s1, c, z_axis);
    d.capsules.push_back(Capsule{a, b, radius, material});
  }
}

void add_spheres(MicroSceneDesc& d, double radius, double pitch, double z, double jitter,
                 std::uint64_t seed, int material) {
  if (!(radius > 0) || !(pitch > 0)) throw InputError("spheres: radius and pitch must be > 0");
  const int nx = periods(d.width, pitch, "spheres"), ny = periods(d.height, pitch, "spheres");
  reserve_objects(d, std::int64_t{nx} * ny, "spheres");
  SimRng rng(seed, 0x737068);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const double x = (i + 0.5) * pitch + jitter * pitch * (2 * rng.uniform() - 1);
      const double y = (j + 0.5) * pitch + jitter * pitch * (2 * rng.uniform() - 1);
      const Vec c(x, y, z);
      d.capsules.push_back(Capsule{c, c, radius, material});
    }
}

void add_fibers(MicroSceneDesc& d, const FiberParams& p) {
  if (!(p.radius > 0) || !(p.length > 0) || p.count < 1)
    throw InputError("fibers: radius, length and count must be positive");
  reserve_objects(d, p.count, "fibers");
  SimRng rng(p.seed, 0x66696272);
  for (std::int64_t k = 0; k < p.count; ++k) {
    const Vec a(rng.uniform() * d.width, rng.uniform() * d.height, 0);
    const double tilt = std::clamp(p.tilt + p.tilt_spread * (2 * rng.uniform() - 1), 0.0, 1.5);
    const double az = p.tilt_azimuth + p.azimuth_spread * (2 * rng.uniform() - 1);
    const Vec dir(std::sin(tilt) * std::cos(az), std::sin(tilt) * std::sin(az), std::cos(tilt));
    d.capsules.push_back(Capsule{a, a + p.length * dir, p.radius, p.material});
  }
}

void add_weave(MicroSceneDesc& d, const WeaveParams& p) {
  if (!(p.pitch > 0) || !(p.radius > 0) || p.segments_per_pitch < 2)
    throw InputError("weave: pitch, radius > 0 and segments >= 2");
  if (p.crimp < p.radius * 0.999)
    throw InputError("weave: crimp must be >= the thread radius or the threads intersect");
  const int nx = periods(d.width, p.pitch, "weave"), ny = periods(d.height, p.pitch, "weave");
  if (nx % 2 || ny % 2) throw InputError("weave: the tile must be an even number of pitches");
  if (p.segments_per_pitch > kMaxSceneObjects)
    throw InputError("weave: " + std::to_string(p.segments_per_pitch) + " segments per pitch");
  const std::int64_t seg = p.segments_per_pitch;
  reserve_objects(d, 2 * std::int64_t{nx} * ny * seg, "weave");
  const double P = p.pitch, A = p.crimp;
  // Warp j along x: z = A cos(pi (x - P/2) / P + pi j), over weft i where (-1)^(i+j) = 1.
  for (int j = 0; j < ny; ++j) {
    const double y = (j + 0.5) * P;
    auto z = [&](double x) { return A * std::cos(M_PI * (x - P / 2) / P + M_PI * j); };
    for (std::int64_t k = 0; k < nx * seg; ++k) {
      const double xa = double(k) * P / double(seg), xb = double(k + 1) * P / double(seg);
      d.capsules.push_back(
          Capsule{Vec(xa, y, z(xa)), Vec(xb, y, z(xb)), p.radius, p.warp_material});
    }
  }
  // Weft i along y: the opposite phase.
  for (int i = 0; i < nx; ++i) {
    const double x = (i + 0.5) * P;
    auto z = [&](double y) { return -A * std::cos(M_PI * (y - P / 2) / P + M_PI * i); };
    for (std::int64_t k = 0; k < ny * seg; ++k) {
      const double ya = double(k) * P / double(seg), yb = double(k + 1) * P / double(seg);
      d.capsules.push_back(
          Capsule{Vec(x, ya, z(ya)), Vec(x, yb, z(yb)), p.radius, p.weft_material});
    }
  }
}

Surface mirror_tile(const Surface& s) {
  Surface m(2 * s.nx, 2 * s.ny, s.dx, s.dy);
  m.meta = s.meta;
  for (std::size_t j = 0; j < m.ny; ++j)
    for (std::size_t i = 0; i < m.nx; ++i) {
      const std::size_t si = i < s.nx ? i : 2 * s.nx - 1 - i;
      const std::size_t sj = j < s.ny ? j : 2 * s.ny - 1 - j;
      m.at(i, j) = s.at(si, sj);
    }
  m.sync_mask();
  return m;
}

}  // namespace microbrdf

// MicroScene: the Embree 3 scene of one periodic tile and the tile-wrapping ray query.
#include "microbrdf/microscene.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/embree_device.hpp"
#include "core/embree_ray.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

using Vec = Eigen::Vector3d;
using Analytic = MicroScene::Analytic;

void embree_error(void*, RTCError code, const char* str) {
  // Errors surface as exceptions from the calls below (rtcGetDeviceError); nothing to do here
  // beyond keeping Embree from printing.
  (void)code;
  (void)str;
}

// Smallest root t of |w + t e|^2 = r^2 style quadratics in (tmin, tmax) that passes `accept`.
template <class Accept>
void quadratic_roots(double A, double B, double C, double tmin, double& best, Accept&& accept) {
  // A t^2 + 2 B t + C = 0
  if (!(A > 0)) return;
  const double disc = B * B - A * C;
  if (disc < 0) return;
  const double s = std::sqrt(disc);
  // Stable form: q = -(B + sign(B) s); roots q / A and C / q.
  const double q = -(B + std::copysign(s, B));
  double t1 = q / A, t2 = (q != 0) ? C / q : t1;
  if (t1 > t2) std::swap(t1, t2);
  for (double t : {t1, t2})
    if (t > tmin && t < best && accept(t)) {
      best = t;
      return;
    }
}

// Nearest intersection of the ray with a capsule or plane in (tmin, tmax); returns t or inf.
double intersect_analytic(const Analytic& c, const Vec& o, const Vec& d, double tmin, double tmax) {
  double best = tmax;
  if (c.plane) {
    if (d.z() == 0) return std::numeric_limits<double>::infinity();
    const double t = (c.a.z() - o.z()) / d.z();
    return (t > tmin && t < tmax) ? t : std::numeric_limits<double>::infinity();
  }
  const Vec oa = o - c.a;
  const double r2 = c.radius * c.radius;
  if (c.length > 0) {
    // Infinite cylinder about the axis, kept where the axial coordinate is inside [0, L].
    const double ou = oa.dot(c.u), du = d.dot(c.u);
    const Vec w = oa - ou * c.u, e = d - du * c.u;
    quadratic_roots(e.dot(e), w.dot(e), w.dot(w) - r2, tmin, best, [&](double t) {
      const double s = ou + t * du;
      return s >= 0 && s <= c.length;
    });
    // End spheres, kept beyond their end.
    for (int end = 0; end < 2; ++end) {
      const Vec oc = end == 0 ? oa : Vec(oa - c.length * c.u);
      quadratic_roots(1.0, oc.dot(d), oc.dot(oc) - r2, tmin, best, [&](double t) {
        const double s = ou + t * du;
        return end == 0 ? s < 0 : s > c.length;
      });
    }
  } else {
    quadratic_roots(1.0, oa.dot(d), oa.dot(oa) - r2, tmin, best, [](double) { return true; });
  }
  return best < tmax ? best : std::numeric_limits<double>::infinity();
}

Vec analytic_normal(const Analytic& c, const Vec& p) {
  if (c.plane) return Vec(0, 0, 1);
  const double s = std::clamp((p - c.a).dot(c.u), 0.0, c.length);
  const Vec n = p - (c.a + s * c.u);
  const double len = n.norm();
  return len > 0 ? Vec(n / len) : Vec(0, 0, 1);
}

struct UserData {
  const std::vector<Analytic>* prims;
  double width, height, zmin, zmax;
};

void user_bounds(const RTCBoundsFunctionArguments* args) {
  const auto* ud = static_cast<const UserData*>(args->geometryUserPtr);
  const Analytic& c = (*ud->prims)[args->primID];
  RTCBounds* b = args->bounds_o;
  if (c.plane) {
    const double pad = 1e-6 * std::max(ud->width, ud->height);
    b->lower_x = float(-pad);
    b->lower_y = float(-pad);
    b->upper_x = float(ud->width + pad);
    b->upper_y = float(ud->height + pad);
    b->lower_z = float(c.a.z() - pad);
    b->upper_z = float(c.a.z() + pad);
    return;
  }
  const Vec e = c.a + c.length * c.u;
  const Vec lo = c.a.cwiseMin(e).array() - c.radius * 1.0001;
  const Vec hi = c.a.cwiseMax(e).array() + c.radius * 1.0001;
  b->lower_x = std::nextafter(float(lo.x()), -INFINITY);
  b->lower_y = std::nextafter(float(lo.y()), -INFINITY);
  b->lower_z = std::nextafter(float(lo.z()), -INFINITY);
  b->upper_x = std::nextafter(float(hi.x()), INFINITY);
  b->upper_y = std::nextafter(float(hi.y()), INFINITY);
  b->upper_z = std::nextafter(float(hi.z()), INFINITY);
}

void user_intersect(const RTCIntersectFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* ud = static_cast<const UserData*>(args->geometryUserPtr);
  auto* rh = reinterpret_cast<RTCRayHit*>(args->rayhit);  // N == 1 (rtcIntersect1 only)
  const Vec o(rh->ray.org_x, rh->ray.org_y, rh->ray.org_z);
  const Vec d(rh->ray.dir_x, rh->ray.dir_y, rh->ray.dir_z);
  const double t =
      intersect_analytic((*ud->prims)[args->primID], o, d, rh->ray.tnear, rh->ray.tfar);
  if (!std::isfinite(t)) return;
  rh->ray.tfar = float(t);
  rh->hit.Ng_x = 0;
  rh->hit.Ng_y = 0;
  rh->hit.Ng_z = 1;
  rh->hit.u = rh->hit.v = 0;
  rh->hit.primID = args->primID;
  rh->hit.geomID = args->geomID;
  rh->hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

void user_occluded(const RTCOccludedFunctionNArguments* args) {
  if (!args->valid[0]) return;
  const auto* ud = static_cast<const UserData*>(args->geometryUserPtr);
  auto* ray = reinterpret_cast<RTCRay*>(args->ray);
  const Vec o(ray->org_x, ray->org_y, ray->org_z), d(ray->dir_x, ray->dir_y, ray->dir_z);
  if (std::isfinite(intersect_analytic((*ud->prims)[args->primID], o, d, ray->tnear, ray->tfar)))
    ray->tfar = -INFINITY;
}

// Replicas of a primitive across the tile edges (skipped in a direction it already spans).
void replicate(const Analytic& c, double W, double H, std::vector<Analytic>& out) {
  const Vec e = c.a + c.length * c.u;
  const double r = c.radius;
  const double x0 = std::min(c.a.x(), e.x()) - r, x1 = std::max(c.a.x(), e.x()) + r;
  const double y0 = std::min(c.a.y(), e.y()) - r, y1 = std::max(c.a.y(), e.y()) + r;
  const bool span_x = x0 <= 0 && x1 >= W, span_y = y0 <= 0 && y1 >= H;
  for (int sx = -1; sx <= 1; ++sx)
    for (int sy = -1; sy <= 1; ++sy) {
      if ((sx != 0 && span_x) || (sy != 0 && span_y)) continue;
      const double ox = sx * W, oy = sy * H;
      // Does the shifted box overlap the tile?
      if (x1 + ox < 0 || x0 + ox > W || y1 + oy < 0 || y0 + oy > H) continue;
      Analytic k = c;
      k.a += Vec(ox, oy, 0);
      out.push_back(k);
    }
}

}  // namespace

int MicroSceneDesc::material_index(const std::string& n) const {
  for (std::size_t i = 0; i < materials.size(); ++i)
    if (materials[i].name == n) return static_cast<int>(i);
  std::string names;
  for (const auto& m : materials) names += (names.empty() ? "" : ", ") + m.name;
  throw InputError("unknown material '" + n + "' (defined: " + names + ")");
}

struct MicroSceneUser {
  UserData data;
};

MicroScene::MicroScene(MicroSceneDesc desc) : desc_(std::move(desc)) {
  const double W = desc_.width, H = desc_.height;
  if (!(W > 0) || !(H > 0)) throw InputError("micro-scene: the tile needs a positive size");
  if (desc_.materials.empty()) throw InputError("micro-scene: no materials");
  try {
    check_scene_geometry(desc_);
  } catch (const InputError& e) {
    throw InputError(std::string("micro-scene: ") + e.what());
  }
  cos_rot_ = std::cos(desc_.rotation);
  sin_rot_ = std::sin(desc_.rotation);
  auto check_mat = [&](int m) {
    if (m < 0 || m >= static_cast<int>(desc_.materials.size()))
      throw InputError("micro-scene: material index out of range");
  };

  zmin_ = std::numeric_limits<double>::infinity();
  zmax_ = -zmin_;
  for (const auto& c : desc_.capsules) {
    check_mat(c.material);
    Analytic a;
    a.a = c.a;
    const Vec ab = c.b - c.a;
    a.length = ab.norm();
    a.u = a.length > 0 ? Vec(ab / a.length) : Vec(0, 0, 1);
    a.radius = c.radius;
    a.material = c.material;
    if (!(c.radius > 0)) throw InputError("micro-scene: capsule radius must be positive");
    zmin_ = std::min({zmin_, c.a.z() - c.radius, c.b.z() - c.radius});
    zmax_ = std::max({zmax_, c.a.z() + c.radius, c.b.z() + c.radius});
    replicate(a, W, H, capsules_);
  }
  for (const auto& p : desc_.planes) {
    check_mat(p.material);
    Analytic a;
    a.plane = true;
    a.a = Vec(0, 0, p.z);
    a.u = Vec(0, 0, 1);
    a.material = p.material;
    capsules_.push_back(a);
    zmin_ = std::min(zmin_, p.z);
    zmax_ = std::max(zmax_, p.z);
  }

  auto* device = detail::new_embree_device("verbose=0", "micro-scene");
  rtcSetDeviceErrorFunction(device, embree_error, nullptr);
  device_ = device;
  RTCScene scene = rtcNewScene(device);
  scene_ = scene;
  rtcSetSceneFlags(scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_HIGH);

  for (const auto& hf : desc_.heightfields) {
    check_mat(hf.material);
    const Surface& s = hf.surface;
    if (s.nx < 2 || s.ny < 2) throw InputError("micro-scene: height field needs >= 2x2 samples");
    if (std::abs(s.nx * s.dx - W) > 1e-9 * W || std::abs(s.ny * s.dy - H) > 1e-9 * H)
      throw InputError("micro-scene: height field extent " + std::to_string(s.nx * s.dx) + " x " +
                       std::to_string(s.ny * s.dy) + " m does not match the tile");
    for (double z : s.z)
      if (!std::isfinite(z))
        throw InputError("micro-scene: height field has invalid samples (fill them first)");
    // Vertices over the tile plus one cell all round, wrapped periodically: a ray that crosses
    // the surface right at a tile wall then never meets the mesh's own boundary edge (where
    // float round-off could let it slip through); hits in the margin are wrapped back.
    const std::size_t vx = s.nx + 3, vy = s.ny + 3;
    std::vector<float> v(3 * vx * vy + 1);  // +1: Embree reads 16 bytes at the last vertex
    const auto wrap = [](long i, std::size_t n) {
      return static_cast<std::size_t>((i % long(n) + long(n)) % long(n));
    };
    for (std::size_t j = 0; j < vy; ++j)
      for (std::size_t i = 0; i < vx; ++i) {
        const long ii = long(i) - 1, jj = long(j) - 1;
        const double z = s.z[wrap(jj, s.ny) * s.nx + wrap(ii, s.nx)];
        float* p = &v[3 * (j * vx + i)];
        p[0] = float(ii == long(s.nx) ? W : double(ii) * s.dx);
        p[1] = float(jj == long(s.ny) ? H : double(jj) * s.dy);
        p[2] = float(z);
        zmin_ = std::min(zmin_, z);
        zmax_ = std::max(zmax_, z);
      }
    RTCGeometry g;
    if (hf.grid) {
      if (vx > 32767 || vy > 32767) throw InputError("micro-scene: grid wider than 32767");
      g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_GRID);
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v.data(), 0,
                                 3 * sizeof(float), vx * vy);
      auto* grid = static_cast<RTCGrid*>(
          rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_GRID, 0, RTC_FORMAT_GRID, sizeof(RTCGrid), 1));
      grid->startVertexID = 0;
      grid->stride = static_cast<unsigned>(vx);
      grid->width = static_cast<unsigned short>(vx);
      grid->height = static_cast<unsigned short>(vy);
    } else {
      g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
      rtcSetSharedGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, v.data(), 0,
                                 3 * sizeof(float), vx * vy);
      const std::size_t cx = vx - 1, cy = vy - 1;
      auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
          g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), 2 * cx * cy));
      std::size_t k = 0;
      for (std::size_t j = 0; j < cy; ++j)
        for (std::size_t i = 0; i < cx; ++i) {
          const auto v00 = unsigned(j * vx + i), v10 = v00 + 1, v01 = unsigned(v00 + vx),
                     v11 = v01 + 1;
          // Counter-clockwise seen from above: normals point up.
          idx[k++] = v00, idx[k++] = v10, idx[k++] = v11;
          idx[k++] = v00, idx[k++] = v11, idx[k++] = v01;
        }
    }
    triangles_ += 2 * s.nx * s.ny;  // the tile's own (the margin repeats them)
    rtcCommitGeometry(g);
    const unsigned id = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    if (geom_material_.size() <= id) geom_material_.resize(id + 1, -1);
    geom_material_[id] = hf.material;
    if (hf_geom_ < 0) hf_geom_ = static_cast<int>(id);
    vertex_store_.push_back(std::move(v));
  }

  if (!std::isfinite(zmin_)) throw InputError("micro-scene: no geometry");
  if (desc_.heightfields.size() == 1 && capsules_.empty()) build_escape_bound();
  // A little room above and below so rays start and end clear of the geometry.
  const double span = std::max({W, H, zmax_ - zmin_});
  eps_ = 1e-5 * span;  // ~40 float ulps of the coordinates
  zmax_ += 4 * eps_;
  zmin_ -= 4 * eps_;

  if (!capsules_.empty()) {
    auto* ud = new MicroSceneUser{UserData{&capsules_, W, H, zmin_, zmax_}};
    RTCGeometry g = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_USER);
    rtcSetGeometryUserPrimitiveCount(g, static_cast<unsigned>(capsules_.size()));
    rtcSetGeometryUserData(g, &ud->data);
    rtcSetGeometryBoundsFunction(g, user_bounds, nullptr);
    rtcSetGeometryIntersectFunction(g, user_intersect);
    rtcSetGeometryOccludedFunction(g, user_occluded);
    rtcCommitGeometry(g);
    user_geom_ = rtcAttachGeometry(scene, g);
    rtcReleaseGeometry(g);
    user_data_owner_ = ud;
  }
  rtcCommitScene(scene);
  if (rtcGetDeviceError(device) != RTC_ERROR_NONE)
    throw InputError("micro-scene: Embree could not build the scene");
}

// Per-block bounds of the one height field for clears_upward(), from the float vertices Embree
// traces (x, y as placed in the vertex buffer, z rounded to float).
void MicroScene::build_escape_bound() {
  const Surface& s = desc_.heightfields[0].surface;
  const std::size_t nx = s.nx, ny = s.ny;
  constexpr std::size_t kCells = 8;
  esc_nbx_ = static_cast<int>((nx + kCells - 1) / kCells);
  esc_nby_ = static_cast<int>((ny + kCells - 1) / kCells);
  esc_bw_ = kCells * s.dx;
  esc_bh_ = kCells * s.dy;
  esc_hmax_.assign(std::size_t(esc_nbx_) * esc_nby_, -std::numeric_limits<double>::infinity());
  esc_grad_.resize(4 * esc_hmax_.size());
  for (std::size_t b = 0; b < esc_hmax_.size(); ++b) {
    esc_grad_[4 * b] = esc_grad_[4 * b + 2] = std::numeric_limits<double>::infinity();
    esc_grad_[4 * b + 1] = esc_grad_[4 * b + 3] = -std::numeric_limits<double>::infinity();
  }
  const double W = desc_.width, H = desc_.height;
  auto xf = [&](std::size_t i) { return double(float(i == nx ? W : double(i) * s.dx)); };
  auto yf = [&](std::size_t j) { return double(float(j == ny ? H : double(j) * s.dy)); };
  auto zf = [&](std::size_t i, std::size_t j) {
    return double(float(s.z[(j % ny) * nx + i % nx]));
  };
  for (std::size_t j = 0; j < ny; ++j)
    for (std::size_t i = 0; i < nx; ++i) {
      const double hx = xf(i + 1) - xf(i), hy = yf(j + 1) - yf(j);
      const double z00 = zf(i, j), z10 = zf(i + 1, j), z01 = zf(i, j + 1), z11 = zf(i + 1, j + 1);
      // The four triangles of the cell's two possible diagonals.
      // (gx, gy) of each is one of (gx0 or gx1, gy0 or gy1).
      const double gx0 = (z10 - z00) / hx, gx1 = (z11 - z01) / hx;
      const double gy0 = (z01 - z00) / hy, gy1 = (z11 - z10) / hy;
      const std::size_t b = (j / kCells) * esc_nbx_ + i / kCells;
      esc_hmax_[b] = std::max({esc_hmax_[b], z00, z10, z01, z11});
      double* g = &esc_grad_[4 * b];  // min gx, max gx, min gy, max gy
      g[0] = std::min({g[0], gx0, gx1});
      g[1] = std::max({g[1], gx0, gx1});
      g[2] = std::min({g[2], gy0, gy1});
      g[3] = std::max({g[3], gy0, gy1});
    }
  esc_top_ = *std::max_element(esc_hmax_.begin(), esc_hmax_.end());
}

namespace {

// The escape bound's walk, one axis: into the neighbouring block of `nb` (widths `bw`, the last
// the rest of the tile's `extent`) upwards or downwards, wrapping across the tile edge to the
// periodic copy; [lo, hi) follows the block.
inline void next_block(bool up, int& c, double& lo, double& hi, int nb, double bw, double extent) {
  const auto width = [&](int i) { return i == nb - 1 ? extent - i * bw : bw; };
  if (up) {
    c = c + 1 == nb ? 0 : c + 1;
    lo = hi;
    hi = lo + width(c);
  } else {
    c = c == 0 ? nb - 1 : c - 1;
    hi = lo;
    lo = hi - width(c);
  }
}

}  // namespace

bool MicroScene::clears_upward(const Vec& p, const Vec& n, const Vec& d) const {
  if (esc_hmax_.empty() || !(d.z() > 0)) return false;
  const double margin = 0.25 * eps_;
  const Vec o = p + eps_ * n;
  if (o.z() >= esc_top_ + margin) return true;
  const double W = desc_.width, H_tile = desc_.height;
  // Start block: the one holding p; both p and the origin must lie in it.
  const int bi = std::min(int(p.x() / esc_bw_), esc_nbx_ - 1);
  const int bj = std::min(int(p.y() / esc_bh_), esc_nby_ - 1);
  if (bi < 0 || bj < 0) return false;
  double x0 = bi * esc_bw_, x1 = bi == esc_nbx_ - 1 ? W : x0 + esc_bw_;
  double y0 = bj * esc_bh_, y1 = bj == esc_nby_ - 1 ? H_tile : y0 + esc_bh_;
  if (o.x() < x0 || o.x() > x1 || o.y() < y0 || o.y() > y1) return false;
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Ray parameter where it leaves the current block through an x or a y wall.
  const double ix = d.x() != 0 ? 1 / d.x() : 0, iy = d.y() != 0 ? 1 / d.y() : 0;
  auto exit_x = [&] { return d.x() > 0 ? (x1 - o.x()) * ix : d.x() < 0 ? (x0 - o.x()) * ix : inf; };
  auto exit_y = [&] { return d.y() > 0 ? (y1 - o.y()) * iy : d.y() < 0 ? (y0 - o.y()) * iy : inf; };
  // Over a block the mesh is continuous and the block convex, so along a horizontal path of
  // length r in direction e the height rises by at most S(e) r, S(e) the largest slope along e of
  // any triangle over the block (from the ranges of the gradients' components, with a relative
  // margin), and it never exceeds the block's highest vertex. H bounds the height of the surface
  // under the ray where it enters a block (first, under the origin: from p across the horizontal
  // offset eps n_xy); over the block the surface then stays below min(H + S t, hmax) while the
  // ray rises linearly: both bounds are checked where they matter (the ends of the stretch below
  // hmax). The walk ends when the ray is above the highest vertex of the tile.
  auto rise = [this](std::size_t b, double ex, double ey) {
    const double* g = &esc_grad_[4 * b];
    const double r = std::max(g[0] * ex, g[1] * ex) + std::max(g[2] * ey, g[3] * ey);
    return r + 1e-6 * std::abs(r) + 1e-9 * (std::abs(ex) + std::abs(ey));
  };
  int ci = bi, cj = bj;
  double t_in = 0, H = p.z() + eps_ * rise(std::size_t(bj) * esc_nbx_ + bi, n.x(), n.y());
  for (int step = 0; step < 32; ++step) {
    const std::size_t b = std::size_t(cj) * esc_nbx_ + ci;
    const double hmax = esc_hmax_[b], S = rise(b, d.x(), d.y());
    const double tx = exit_x(), ty = exit_y(), t_out = std::min(tx, ty);
    if (o.z() + t_in * d.z() < hmax + margin) {
      // Clearance over the Lipschitz bound, linear in t: checked at t_in and where the ray
      // passes hmax (or leaves the block first).
      auto clear = [&](double tt) { return o.z() + tt * d.z() - (H + S * (tt - t_in)) >= margin; };
      const double t_high = (hmax + margin - o.z()) / d.z();
      if (!clear(t_in) || !clear(std::min(t_high, t_out))) return false;
    }
    if (o.z() + t_out * d.z() >= esc_top_ + margin) return true;
    H = std::min(H + S * (t_out - t_in), hmax);
    t_in = t_out;
    // Into the next block (across the tile edge: the periodic copy).
    if (tx <= ty) next_block(d.x() > 0, ci, x0, x1, esc_nbx_, esc_bw_, W);
    if (ty <= tx) next_block(d.y() > 0, cj, y0, y1, esc_nby_, esc_bh_, H_tile);
  }
  return false;
}

MicroScene::~MicroScene() {
  if (scene_) rtcReleaseScene(static_cast<RTCScene>(scene_));
  if (device_) rtcReleaseDevice(static_cast<RTCDevice>(device_));
  delete static_cast<MicroSceneUser*>(user_data_owner_);
}

Eigen::Vector3d MicroScene::to_scene(const Eigen::Vector3d& w) const {
  return {cos_rot_ * w.x() + sin_rot_ * w.y(), -sin_rot_ * w.x() + cos_rot_ * w.y(), w.z()};
}
Eigen::Vector3d MicroScene::to_brdf(const Eigen::Vector3d& w) const {
  return {cos_rot_ * w.x() - sin_rot_ * w.y(), sin_rot_ * w.x() + cos_rot_ * w.y(), w.z()};
}

TraceEnd MicroScene::trace(Eigen::Vector3d o, const Eigen::Vector3d& d, MicroHit& hit,
                           std::size_t* segments, std::vector<MicroRay>* log, int kind) const {
  const double W = desc_.width, H = desc_.height;
  auto* scene = static_cast<RTCScene>(scene_);
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  double travelled = 0;
  constexpr double inf = std::numeric_limits<double>::infinity();
  // Origins offset from a hit next to a wall may lie just outside the tile: wrap them in.
  if (o.x() < 0) o.x() += W;
  if (o.x() >= W) o.x() -= W;
  if (o.y() < 0) o.y() += H;
  if (o.y() >= H) o.y() -= H;
  const double tx = d.x() > 0 ? 1 / d.x() : d.x() < 0 ? -1 / d.x() : inf;
  const double ty = d.y() > 0 ? 1 / d.y() : d.y() < 0 ? -1 / d.y() : inf;
  for (int seg = 0; seg < 100000; ++seg) {
    // Distance to the tile's side walls and to the top/bottom of the scene.
    const double t_x = d.x() > 0 ? (W - o.x()) * tx : d.x() < 0 ? o.x() * tx : inf;
    const double t_y = d.y() > 0 ? (H - o.y()) * ty : d.y() < 0 ? o.y() * ty : inf;
    const double t_z = d.z() > 0   ? (zmax_ - o.z()) / d.z()
                       : d.z() < 0 ? (zmin_ - o.z()) / d.z()
                                   : inf;
    const double t_side = std::min(t_x, t_y);
    const double t_far = std::min(t_side, t_z);
    RTCRayHit rh;
    // Slightly past the wall so hits exactly on it are not missed (the wrap re-tests them).
    detail::fill_rayhit(rh, o, d, 0, float(std::min(t_far * (1 + 1e-6) + eps_, 1e30)));
    if (log)
      log->push_back(MicroRay{{rh.ray.org_x, rh.ray.org_y, rh.ray.org_z},
                              {rh.ray.dir_x, rh.ray.dir_y, rh.ray.dir_z},
                              rh.ray.tfar,
                              seg == 0 ? kind : 2});
    rtcIntersect1(scene, &ctx, &rh);
    if (segments) ++*segments;
    if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
      const double t = rh.ray.tfar;
      hit.p = o + t * d;
      hit.path_length = travelled + t;
      if (rh.hit.geomID == user_geom_) {
        const Analytic& c = capsules_[rh.hit.primID];
        hit.n = analytic_normal(c, hit.p);
        hit.material = c.material;
        const Vec axis = (c.plane || c.length == 0) ? Vec(1, 0, 0) : c.u;
        Vec tan = axis - axis.dot(hit.n) * hit.n;
        if (tan.squaredNorm() < 1e-12) tan = Vec(0, 1, 0) - hit.n.y() * hit.n;
        hit.tangent = tan.normalized();
      } else {
        Vec n(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
        n.normalize();
        if (n.z() < 0) n = -n;  // height fields face up
        hit.n = n;
        hit.material = geom_material_[rh.hit.geomID];
        Vec tan = Vec(1, 0, 0) - n.x() * n;
        hit.tangent = tan.normalized();
      }
      // Keep the point in the tile (hits just past a wall belong to the next tile).
      if (hit.p.x() >= W) hit.p.x() -= W;
      if (hit.p.x() < 0) hit.p.x() += W;
      if (hit.p.y() >= H) hit.p.y() -= H;
      if (hit.p.y() < 0) hit.p.y() += H;
      return TraceEnd::Hit;
    }
    if (t_z <= t_side) return d.z() > 0 ? TraceEnd::EscapedUp : TraceEnd::EscapedDown;
    // Next tile: move to the wall and wrap.
    o += t_side * d;
    travelled += t_side;
    if (t_x <= t_y) o.x() = d.x() > 0 ? 0.0 : W;
    if (t_y <= t_x) o.y() = d.y() > 0 ? 0.0 : H;
  }
  return TraceEnd::Lost;
}

}  // namespace microbrdf

// A micro-scene drawn as geometry on the plate (micro_patch.hpp).
#include "render/micro_patch.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "microbrdf/error.hpp"

namespace microbrdf::pt {

using V3 = Eigen::Vector3d;

MicroPatch::MicroPatch(const MicroSceneDesc& desc, double tiles, double half,
                       double brush_angle_rad)
    : half_(half) {
  if (!(tiles > 0) || !std::isfinite(tiles))
    throw InputError("render: the micro-scene needs a positive number of tiles across the plate");
  scene_ = std::make_unique<MicroScene>(desc);
  mpu_ = tiles * scene_->width() / (2 * half);
  ymin_ = scene_->zmin() / mpu_;
  ymax_ = scene_->zmax() / mpu_;
  const double c = std::cos(brush_angle_rad), s = std::sin(brush_angle_rad);
  tz_ = V3(0, 1, 0);
  tx_ = c * V3(1, 0, 0) + s * tz_.cross(V3(1, 0, 0));  // as PreviewGeometry::shade turns t
  ty_ = tz_.cross(tx_);
}

V3 MicroPatch::to_scene(const V3& w) const {
  return scene_->to_scene(V3(w.dot(tx_), w.dot(ty_), w.dot(tz_)));
}

V3 MicroPatch::to_world(const V3& v) const {
  const V3 b = scene_->to_brdf(v);
  return b.x() * tx_ + b.y() * ty_ + b.z() * tz_;
}

bool MicroPatch::intersect(const V3& o, const V3& d, double tfar, MicroPatchHit& hit) const {
  // The box holding the patch: [-half, half] in x and z, the micro-scene's heights in y.
  double t0 = 0, t1 = tfar;
  const V3 lo(-half_, ymin_, -half_), hi(half_, ymax_, half_);
  for (int a = 0; a < 3; ++a) {
    if (d[a] == 0) {
      if (o[a] < lo[a] || o[a] > hi[a]) return false;
      continue;
    }
    double ta = (lo[a] - o[a]) / d[a], tb = (hi[a] - o[a]) / d[a];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (!(t0 < t1)) return false;
  // Into the micro-scene at the entry point: metres, wrapped into the tile (MicroScene::trace
  // follows the ray across the tiles; its path length gives the distance).
  V3 q = mpu_ * to_scene(o + t0 * d);
  q.z() = std::clamp(q.z(), scene_->zmin(), scene_->zmax());
  const double W = scene_->width(), H = scene_->height();
  q.x() -= W * std::floor(q.x() / W);
  q.y() -= H * std::floor(q.y() / H);
  q.x() = std::clamp(q.x(), 0.0, std::nextafter(W, 0.0));
  q.y() = std::clamp(q.y(), 0.0, std::nextafter(H, 0.0));
  MicroHit mh;
  if (scene_->trace(q, to_scene(d), mh) != TraceEnd::Hit) return false;
  const double t = t0 + mh.path_length / mpu_;
  if (!(t < t1)) return false;  // beyond the square's side or tfar: nothing there
  hit.t = t;
  hit.p = o + t * d;
  hit.n = to_world(mh.n).normalized();
  hit.t_dir = to_world(mh.tangent);
  hit.t_dir = (hit.t_dir - hit.t_dir.dot(hit.n) * hit.n).normalized();
  hit.material = mh.material;
  return true;
}

}  // namespace microbrdf::pt

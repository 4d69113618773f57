// Preview scenes on Embree 3 (see scene.hpp).
#include "render/scene.hpp"

#include <tiny_obj_loader.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <limits>

#include "core/embree_device.hpp"
#include "core/embree_ray.hpp"
#include "microbrdf/error.hpp"
#include "render/micro_patch.hpp"

namespace microbrdf::pt {
namespace {

Camera look_at(const V3& pos, const V3& target, const V3& world_up, double tan_half) {
  Camera c;
  c.position = pos;
  c.forward = (target - pos).normalized();
  c.right = c.forward.cross(world_up).normalized();
  c.up = c.right.cross(c.forward);
  c.tan_half_fov = tan_half;
  return c;
}

// Cylinder pair (Dong Fig. 10): radius, half height, centre offset in x.
constexpr double kCylR = 0.45, kCylHalf = 1.5, kCylX = 0.5;
}  // namespace
// Plate (Dong Fig. 13): the sample is 10 cm square and the camera 64 cm above it; in scene
// units the plate is 2 wide, so the camera stands 12.8 above.
constexpr double kPlateHalf = 1.0, kPlateCamera = 12.8;
namespace {

/// The vase profile r(y), y in [-1, 1], and dr/dy.
double vase_r(double y) { return 0.5 + 0.25 * std::cos(M_PI * (y + 0.3) / 1.3); }
double vase_dr(double y) { return -0.25 * M_PI / 1.3 * std::sin(M_PI * (y + 0.3) / 1.3); }

V3 any_perpendicular(const V3& n) {
  V3 a = std::abs(n.x()) < 0.9 ? V3(1, 0, 0) : V3(0, 1, 0);
  return (a - a.dot(n) * n).normalized();
}

}  // namespace

Camera preview_camera(PreviewScene s) {
  const V3 up(0, 1, 0);
  switch (s) {
    case PreviewScene::Cylinders:
      return look_at(V3(0, 0, 6), V3::Zero(), up, 1.2 / 6);
    case PreviewScene::Plate:
      return look_at(V3(0, kPlateCamera, 0), V3::Zero(), V3(0, 0, -1),
                     1.1 * kPlateHalf / kPlateCamera);
    case PreviewScene::Vase:
      return look_at(V3(0, 0.8, 4.5), V3(0, -0.05, 0), up, 0.26);
    case PreviewScene::Obj:
      return look_at(V3(0, 0, 4.5), V3::Zero(), up, 0.27);
    case PreviewScene::Sphere:
    case PreviewScene::FurnaceSphere:
      break;
  }
  return look_at(V3(0, 0, 4), V3::Zero(), up, 1.15 / 4);
}

PreviewGeometry::PreviewGeometry(const RenderScene& scene) : scene_(scene) {
  device_ = detail::new_embree_device("threads=1", "the preview renderer");
  try {
    rtc_ = rtcNewScene(device_);
    rtcSetSceneFlags(rtc_, RTC_SCENE_FLAG_ROBUST);
    camera_ = preview_camera(scene.kind);
    switch (scene.kind) {
      case PreviewScene::Cylinders:
        build_cylinder(V3(-kCylX, 0, 0), kCylR, kCylHalf, 0);
        build_cylinder(V3(kCylX, 0, 0), kCylR, kCylHalf, M_PI / 2);
        break;
      case PreviewScene::Plate:
        if (scene.micro_scene)
          build_micro_plate(kPlateHalf);
        else
          build_plate(kPlateHalf);
        break;
      case PreviewScene::Sphere:
      case PreviewScene::FurnaceSphere:
        add_sphere(V3::Zero(), 1);
        break;
      case PreviewScene::Vase:
        build_vase();
        break;
      case PreviewScene::Obj:
        build_obj(scene.obj_path);
        break;
    }
    if (scene.micro_scene && !micro_)
      throw InputError("render: a micro-scene is drawn on the plate only (--scene plate)");
    rtcCommitScene(rtc_);
    for (Object& o : objects_) {  // the turn of the brushing direction, per object
      const double turn = scene_.brush_angle_rad + o.tangent_turn;
      o.cos_turn = std::cos(turn);
      o.sin_turn = std::sin(turn);
    }
  } catch (...) {
    // The destructor does not run for a constructor that throws (an unreadable OBJ).
    if (rtc_) rtcReleaseScene(rtc_);
    rtcReleaseDevice(device_);
    throw;
  }
}

PreviewGeometry::~PreviewGeometry() {
  if (rtc_) rtcReleaseScene(rtc_);
  if (device_) rtcReleaseDevice(device_);
}

void PreviewGeometry::add_sphere(const V3& c, double r) {
  RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_SPHERE_POINT);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                        RTC_FORMAT_FLOAT4, 4 * sizeof(float), 1));
  v[0] = float(c.x());
  v[1] = float(c.y());
  v[2] = float(c.z());
  v[3] = float(r);
  rtcCommitGeometry(g);
  rtcAttachGeometry(rtc_, g);
  rtcReleaseGeometry(g);
  Object o;
  o.shape = Shape::Sphere;
  o.centre = c;
  o.radius = r;
  objects_.push_back(o);
}

void PreviewGeometry::add_mesh(Shape shape, const std::vector<float>& pos,
                               std::vector<unsigned> idx, std::vector<float> normals,
                               std::vector<float> uvs, const V3& centre, double radius,
                               double tangent_turn) {
  RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 3 * sizeof(float), pos.size() / 3));
  std::copy(pos.begin(), pos.end(), v);
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned), idx.size() / 3));
  std::copy(idx.begin(), idx.end(), ib);
  rtcCommitGeometry(g);
  rtcAttachGeometry(rtc_, g);
  rtcReleaseGeometry(g);
  Object o;
  o.shape = shape;
  o.centre = centre;
  o.radius = radius;
  o.tangent_turn = tangent_turn;
  o.normals = std::move(normals);
  o.uvs = std::move(uvs);
  o.indices = std::move(idx);
  objects_.push_back(std::move(o));
}

void PreviewGeometry::build_cylinder(const V3& c, double r, double half, double turn) {
  const int n = 512;
  std::vector<float> pos, nrm, uv;
  std::vector<unsigned> idx;
  for (int i = 0; i <= n; ++i) {
    const double phi = 2 * M_PI * i / n;
    const V3 radial(std::sin(phi), 0, std::cos(phi));
    for (int k = 0; k < 2; ++k) {
      const V3 p = c + r * radial + V3(0, k ? half : -half, 0);
      pos.insert(pos.end(), {float(p.x()), float(p.y()), float(p.z())});
      nrm.insert(nrm.end(), {float(radial.x()), float(radial.y()), float(radial.z())});
      uv.insert(uv.end(), {float(phi * r), float(k ? half : -half)});
    }
  }
  for (int i = 0; i < n; ++i) {
    const unsigned a = 2 * i, b = 2 * i + 1, c2 = 2 * i + 2, d = 2 * i + 3;
    idx.insert(idx.end(), {a, c2, b, b, c2, d});
  }
  add_mesh(Shape::Cylinder, pos, idx, nrm, uv, c, r, turn);
}

void PreviewGeometry::build_plate(double half) {
  std::vector<float> pos = {float(-half), 0, float(-half), float(half),  0, float(-half),
                            float(half),  0, float(half),  float(-half), 0, float(half)};
  std::vector<float> nrm = {0, 1, 0, 0, 1, 0, 0, 1, 0, 0, 1, 0};
  std::vector<float> uv = {float(-half), float(half),  float(half),  float(half),
                           float(half),  float(-half), float(-half), float(-half)};
  add_mesh(Shape::Plate, pos, {0, 2, 1, 0, 3, 2}, nrm, uv, V3::Zero(), half, 0);
}

void PreviewGeometry::build_vase() {
  const int nphi = 256, ny = 128;
  std::vector<float> pos, nrm, uv;
  std::vector<unsigned> idx;
  for (int i = 0; i <= nphi; ++i) {
    const double phi = 2 * M_PI * i / nphi;
    const V3 radial(std::sin(phi), 0, std::cos(phi));
    for (int k = 0; k <= ny; ++k) {
      const double y = -1 + 2.0 * k / ny, r = vase_r(y);
      const V3 p = r * radial + V3(0, y, 0);
      const V3 n = (radial - vase_dr(y) * V3(0, 1, 0)).normalized();
      pos.insert(pos.end(), {float(p.x()), float(p.y()), float(p.z())});
      nrm.insert(nrm.end(), {float(n.x()), float(n.y()), float(n.z())});
      uv.insert(uv.end(), {float(phi * 0.5), float(y)});
    }
  }
  for (int i = 0; i < nphi; ++i)
    for (int k = 0; k < ny; ++k) {
      const unsigned a = i * (ny + 1) + k, b = a + 1, c = a + ny + 1, d = c + 1;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
  add_mesh(Shape::Mesh, pos, idx, nrm, uv, V3::Zero(), 1, 0);
}

void PreviewGeometry::build_micro_plate(double half) {
  if (scene_.brushing != Brushing::Linear)
    throw InputError(
        "render: a micro-scene is laid out along one direction (--brush-angle); rotational "
        "brushing is not drawn");
  micro_ = std::make_unique<MicroPatch>(*scene_.micro_scene, scene_.micro_tiles, half,
                                        scene_.brush_angle_rad);
  micro_first_ = static_cast<int>(objects_.size());
  for (int m = 0; m < micro_->material_count(); ++m) {
    Object o;
    o.shape = Shape::Micro;
    objects_.push_back(o);
  }
}

void PreviewGeometry::build_obj(const std::string& path) {
  if (path.empty()) throw InputError("the obj scene needs a mesh file (--obj FILE.obj)");
  if (!std::filesystem::exists(path)) throw FileError::missing(path);
  tinyobj::ObjReaderConfig cfg;
  cfg.triangulate = true;
  cfg.vertex_color = false;
  cfg.mtl_search_path = "";
  tinyobj::ObjReader reader;
  if (!reader.ParseFromFile(path, cfg))
    throw FileError(path, "obj: " + (reader.Error().empty() ? "cannot parse" : reader.Error()));
  const auto& at = reader.GetAttrib();
  std::vector<tinyobj::index_t> corners;
  for (const auto& s : reader.GetShapes())
    corners.insert(corners.end(), s.mesh.indices.begin(), s.mesh.indices.end());
  if (corners.empty() || corners.size() % 3) throw FileError(path, "obj: no triangles");
  const std::size_t nv = at.vertices.size() / 3;
  for (const auto& c : corners)
    if (c.vertex_index < 0 || std::size_t(c.vertex_index) >= nv)
      throw FileError(path, "obj: vertex index out of range");
  // Bounding box -> centred, largest side 2.
  V3 lo = V3::Constant(std::numeric_limits<double>::max()), hi = -lo;
  for (const auto& c : corners) {
    const V3 p(at.vertices[3 * c.vertex_index], at.vertices[3 * c.vertex_index + 1],
               at.vertices[3 * c.vertex_index + 2]);
    if (!p.allFinite()) throw FileError(path, "obj: non-finite vertex");
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  const V3 mid = (lo + hi) / 2;
  const double size = (hi - lo).maxCoeff();
  if (!(size > 0)) throw FileError(path, "obj: degenerate mesh (zero size)");
  const double s = 2 / size;
  // Smooth normals where the file has none: area-weighted face normals summed per vertex.
  std::vector<V3> smooth(nv, V3::Zero());
  auto P = [&](int i) {
    return V3(at.vertices[3 * i], at.vertices[3 * i + 1], at.vertices[3 * i + 2]);
  };
  for (std::size_t f = 0; f < corners.size(); f += 3) {
    const int a = corners[f].vertex_index, b = corners[f + 1].vertex_index,
              c = corners[f + 2].vertex_index;
    const V3 fn = (P(b) - P(a)).cross(P(c) - P(a));
    smooth[a] += fn;
    smooth[b] += fn;
    smooth[c] += fn;
  }
  std::vector<float> pos, nrm, uv;
  std::vector<unsigned> idx;
  const std::size_t nn = at.normals.size() / 3, nt = at.texcoords.size() / 2;
  for (std::size_t i = 0; i < corners.size(); ++i) {
    const auto& c = corners[i];
    const V3 p = (P(c.vertex_index) - mid) * s;
    V3 n = smooth[c.vertex_index];
    if (c.normal_index >= 0 && std::size_t(c.normal_index) < nn)
      n = V3(at.normals[3 * c.normal_index], at.normals[3 * c.normal_index + 1],
             at.normals[3 * c.normal_index + 2]);
    n = n.norm() > 0 && n.allFinite() ? n.normalized() : V3(0, 1, 0);
    double u = p.x(), v = p.y();
    if (c.texcoord_index >= 0 && std::size_t(c.texcoord_index) < nt) {
      u = at.texcoords[2 * c.texcoord_index];
      v = at.texcoords[2 * c.texcoord_index + 1];
    }
    pos.insert(pos.end(), {float(p.x()), float(p.y()), float(p.z())});
    nrm.insert(nrm.end(), {float(n.x()), float(n.y()), float(n.z())});
    uv.insert(uv.end(), {float(u), float(v)});
    idx.push_back(unsigned(i));
  }
  add_mesh(Shape::Mesh, pos, idx, nrm, uv, V3::Zero(), 1, 0);
}

double PreviewGeometry::intersect(const V3& o, const V3& d, double tfar, ShadingPoint& sp) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  detail::fill_rayhit(rh, o, d, 0, float(std::min(tfar, 1e30)));
  rtcIntersect1(rtc_, &ctx, &rh);
  MicroPatchHit mh;
  const bool embree = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  if (micro_ && micro_->intersect(o, d, embree ? double(rh.ray.tfar) : tfar, mh)) {
    shade_micro(mh, d, sp);
    return mh.t;
  }
  if (!embree) return -1;
  const double t = rh.ray.tfar;
  shade(rh.hit.geomID, rh.hit.primID, rh.hit.u, rh.hit.v, o + t * d,
        V3(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z), d, sp);
  return t;
}

void PreviewGeometry::shade_micro(const MicroPatchHit& h, const V3& d, ShadingPoint& sp) const {
  sp.object = micro_first_ + h.material;
  sp.p = h.p;
  sp.eps = micro_->epsilon();
  // Two-sided, as every object: the normal faces the incoming ray.
  sp.ng = h.n.dot(d) > 0 ? V3(-h.n) : h.n;
  sp.n = sp.ng;
  sp.t = h.t_dir;
  sp.b = sp.n.cross(sp.t);
  sp.u = sp.v = 0;
}

double PreviewGeometry::intersect_bare(const V3& o, const V3& d) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh;
  detail::fill_rayhit(rh, o, d, 0, std::numeric_limits<float>::infinity());
  rtcIntersect1(rtc_, &ctx, &rh);
  MicroPatchHit mh;
  const bool embree = rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
  if (micro_ && micro_->intersect(o, d, embree ? double(rh.ray.tfar) : 1e30, mh)) return mh.t;
  return embree ? rh.ray.tfar : -1;
}

bool PreviewGeometry::occluded(const V3& o, const V3& d, double tfar) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRay r;
  detail::fill_ray(r, o, d, 0, float(std::min(tfar, 1e30)));
  rtcOccluded1(rtc_, &ctx, &r);
  if (r.tfar < 0) return true;
  MicroPatchHit mh;
  return micro_ && micro_->intersect(o, d, tfar, mh);
}

void PreviewGeometry::shade(unsigned geom, unsigned prim, float bu, float bv, const V3& p, V3 ng,
                            const V3& d, ShadingPoint& sp) const {
  const Object& o = objects_[geom];
  sp.object = int(geom);
  sp.p = p;
  sp.eps = epsilon();
  double u0 = 0, v0 = 0;
  V3 n = V3(0, 0, 1);
  switch (o.shape) {
    case Shape::Sphere: {
      n = (p - o.centre).normalized();
      ng = n;
      if (uv_) u0 = std::atan2(n.x(), n.z()) * o.radius;
      v0 = p.y() - o.centre.y();
      break;
    }
    case Shape::Cylinder: {
      V3 r = p - o.centre;
      r -= r.dot(o.axis) * o.axis;
      n = r.normalized();
      if (uv_) u0 = std::atan2(n.x(), n.z()) * o.radius;
      v0 = (p - o.centre).dot(o.axis);
      break;
    }
    case Shape::Plate:
      n = V3(0, 1, 0);
      u0 = p.x();
      v0 = -p.z();
      break;
    case Shape::Micro:  // (shade_micro)
      break;
    case Shape::Mesh: {
      const unsigned* ix = &o.indices[3 * prim];
      const double w0 = 1.0 - bu - bv;
      const float *n0 = &o.normals[3 * ix[0]], *n1 = &o.normals[3 * ix[1]],
                  *n2 = &o.normals[3 * ix[2]];
      n = V3(w0 * n0[0] + bu * n1[0] + bv * n2[0], w0 * n0[1] + bu * n1[1] + bv * n2[1],
             w0 * n0[2] + bu * n1[2] + bv * n2[2]);
      const float *t0 = &o.uvs[2 * ix[0]], *t1 = &o.uvs[2 * ix[1]], *t2 = &o.uvs[2 * ix[2]];
      u0 = w0 * t0[0] + bu * t1[0] + bv * t2[0];
      v0 = w0 * t0[1] + bu * t1[1] + bv * t2[1];
      n = n.norm() > 0 ? n.normalized() : ng.normalized();
      break;
    }
  }
  ng = ng.norm() > 0 ? ng.normalized() : n;
  // Two-sided: both normals face the incoming ray.
  if (ng.dot(d) > 0) ng = -ng;
  if (n.dot(ng) < 0) n = -n;
  sp.ng = ng;
  sp.n = n;
  // Brushing direction: a fixed direction (the camera's right turned by the brush angle) or
  // circles about the object's axis, projected into the tangent plane, then turned about n.
  V3 t0;
  if (scene_.brushing == Brushing::Rotational) {
    t0 = o.axis.cross(p - o.centre);
  } else {
    t0 = camera_.right;
  }
  t0 -= t0.dot(n) * n;
  t0 = t0.norm() > 1e-9 ? t0.normalized() : any_perpendicular(n);
  const double c = o.cos_turn, s = o.sin_turn;
  const V3 nt = n.cross(t0);
  sp.t = c * t0 + s * nt;
  sp.b = n.cross(sp.t);
  // Texture coordinates follow the tangent: u along t, v along b.
  if (!uv_) {
    sp.u = sp.v = 0;
    return;
  }
  sp.u = (c * u0 + s * v0) * scene_.uv_scale;
  sp.v = (-s * u0 + c * v0) * scene_.uv_scale;
}

}  // namespace microbrdf::pt

namespace microbrdf {

RenderLights::Disk dong_plate_light() {
  const double a = 23 * M_PI / 180, half = 4.5 * M_PI / 180;
  RenderLights::Disk d;
  const Eigen::Vector3d dir(-std::sin(a), std::cos(a), 0);  // the image's left is -x
  d.centre = pt::kPlateCamera * dir;
  d.normal = -dir;
  d.radius = pt::kPlateCamera * std::tan(half);
  d.rgb_radiance = Eigen::Vector3d::Constant(1 / (std::sin(half) * std::sin(half)));
  return d;
}

}  // namespace microbrdf

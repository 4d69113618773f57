#pragma once
// Preview scenes on Embree 3: geometry, camera and the shading frame (normal, brushing tangent,
// texture coordinates) at a hit.
//
// World frame: y up; cameras look along -z (front views) or -y (the plate, seen from above).
// Objects are about 2 units across. Spheres are Embree sphere primitives (exact); cylinders, the
// vase, the plate and OBJ meshes are triangles, shaded with analytic (cylinder, plate) or
// interpolated vertex normals (vase, OBJ).

#include <embree3/rtcore.h>

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "microbrdf/render.hpp"

namespace microbrdf::pt {

class MicroPatch;  // micro_patch.hpp
struct MicroPatchHit;

using V3 = Eigen::Vector3d;

struct Camera {
  V3 position, forward, right, up;  ///< orthonormal; right x up = -forward
  double tan_half_fov = 0.3;        ///< vertical
  /// Unit ray direction through image position (x, y) in pixels (row 0 at the top).
  V3 direction(double x, double y, int width, int height) const {
    const double aspect = double(width) / height;
    const double sx = (2 * x / width - 1) * tan_half_fov * aspect;
    const double sy = (1 - 2 * y / height) * tan_half_fov;
    return (forward + sx * right + sy * up).normalized();
  }
};
Camera preview_camera(PreviewScene s);

struct ShadingPoint {
  V3 p;                 ///< hit position
  V3 ng;                ///< geometric normal, facing the incoming ray
  V3 n;                 ///< shading normal, same side as ng
  V3 t, b;              ///< tangent (the BRDF's x axis) and bitangent n x t
  double u = 0, v = 0;  ///< texture coordinates (repeats)
  int object = 0;       ///< index into the scene's objects (material slot)
  double eps = 0;       ///< offset that takes a ray's origin off this surface (along ng)
  V3 to_local(const V3& w) const { return {w.dot(t), w.dot(b), w.dot(n)}; }
  V3 to_world(const V3& w) const { return w.x() * t + w.y() * b + w.z() * n; }
};

class PreviewGeometry {
 public:
  /// Builds the scene (throws InputError/FileError: unknown scene, unreadable OBJ).
  PreviewGeometry(const RenderScene& scene);
  ~PreviewGeometry();
  PreviewGeometry(const PreviewGeometry&) = delete;
  PreviewGeometry& operator=(const PreviewGeometry&) = delete;

  /// Closest hit along the ray within (tnear, tfar); fills sp, returns the distance or -1.
  double intersect(const V3& o, const V3& d, double tfar, ShadingPoint& sp) const;
  /// True when something blocks the segment o + t d, t in (0, tfar).
  bool occluded(const V3& o, const V3& d, double tfar) const;
  /// Bare Embree primary-ray query (the benchmark's reference): the hit distance or -1.
  double intersect_bare(const V3& o, const V3& d) const;

  int object_count() const { return int(objects_.size()); }
  /// Leaves the texture coordinates of shading points at 0 (for materials that ignore them:
  /// saves an atan2 per hit on spheres and cylinders).
  void set_texture_coordinates(bool on) { uv_ = on; }
  const Camera& camera() const { return camera_; }
  /// A length for ray offsets (1e-4 of the scene size); a micro-scene's hits carry their own
  /// (ShadingPoint::eps).
  double epsilon() const { return 1e-4 * extent_; }

 private:
  enum class Shape { Sphere, Cylinder, Plate, Mesh, Micro };
  struct Object {
    Shape shape;
    V3 centre = V3::Zero(), axis = V3(0, 1, 0);
    double radius = 1;
    double tangent_turn = 0;            // extra rotation of the brushing direction about n, rad
    double cos_turn = 1, sin_turn = 0;  // of the whole turn (with the scene's brush angle)
    // triangle meshes: per-vertex normals and texture coordinates
    std::vector<float> normals, uvs;
    std::vector<unsigned> indices;
  };
  void add_sphere(const V3& c, double r);
  void add_mesh(Shape shape, const std::vector<float>& pos, std::vector<unsigned> idx,
                std::vector<float> normals, std::vector<float> uvs, const V3& centre, double radius,
                double tangent_turn);
  void build_cylinder(const V3& c, double r, double h, double turn);
  void build_vase();
  void build_plate(double half);
  void build_obj(const std::string& path);
  void build_micro_plate(double half);
  void shade(unsigned geom, unsigned prim, float bu, float bv, const V3& p, V3 ng, const V3& d,
             ShadingPoint& sp) const;
  void shade_micro(const MicroPatchHit& h, const V3& d, ShadingPoint& sp) const;

  RenderScene scene_;
  RTCDevice device_ = nullptr;
  RTCScene rtc_ = nullptr;
  // index = Embree geometry id; a micro-scene's materials (no Embree geometry here) come after
  std::vector<Object> objects_;
  std::unique_ptr<MicroPatch> micro_;  // RenderScene::micro_scene
  int micro_first_ = 0;                // objects_ index of its first material
  Camera camera_;
  double extent_ = 2;
  bool uv_ = true;
};

}  // namespace microbrdf::pt

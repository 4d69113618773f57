#pragma once
// A micro-scene drawn as geometry (RenderScene::micro_scene): the periodic tile of
// include/microbrdf/microscene.hpp repeated over the plate's square, traced by MicroScene::trace
// (which follows a ray across the tiles of the infinite periodic surface) and clipped to the
// square. The tile is never copied, so any number of tiles costs the memory of one.
//
// Frames: world y up, the plate in y = 0 over [-half, half]^2. The micro-scene's BRDF frame has
// z = the plate's normal (world y), x = the plate's brushing direction (world x turned by the
// brush angle about y, as the plate's shading tangent), y = z x x; its scene frame is that turned
// by the scene's own "rotation" (MicroScene::to_scene). Lengths: one world unit is
// metres_per_unit() metres of the micro-scene.

#include <Eigen/Core>
#include <memory>

#include "microbrdf/microscene.hpp"

namespace microbrdf::pt {

struct MicroPatchHit {
  double t = 0;           ///< distance along the world ray
  Eigen::Vector3d p;      ///< world position
  Eigen::Vector3d n;      ///< world unit normal, out of the solid
  Eigen::Vector3d t_dir;  ///< world unit tangent (the local BRDF's x axis), orthogonal to n
  int material = 0;       ///< index into the micro-scene's materials
};

class MicroPatch {
 public:
  /// `tiles` tiles across the square's side 2 `half`; `brush_angle_rad` turns the micro-scene
  /// about the normal. Builds the MicroScene (throws InputError as its constructor does).
  MicroPatch(const MicroSceneDesc& desc, double tiles, double half, double brush_angle_rad);

  /// Nearest hit of the world ray o + t d (unit d), t in (0, tfar); false when there is none.
  bool intersect(const Eigen::Vector3d& o, const Eigen::Vector3d& d, double tfar,
                 MicroPatchHit& hit) const;
  /// Offset (world units) that takes a ray's origin off a micro-surface (MicroScene::epsilon).
  double epsilon() const { return scene_->epsilon() / mpu_; }
  double metres_per_unit() const { return mpu_; }
  int material_count() const { return static_cast<int>(scene_->desc().materials.size()); }

 private:
  Eigen::Vector3d to_scene(const Eigen::Vector3d& world_dir) const;
  Eigen::Vector3d to_world(const Eigen::Vector3d& scene_dir) const;
  std::unique_ptr<MicroScene> scene_;
  double half_ = 1, mpu_ = 1, ymin_ = 0, ymax_ = 0;
  Eigen::Vector3d tx_, ty_, tz_;  // world axes of the micro-scene's BRDF frame
};

}  // namespace microbrdf::pt

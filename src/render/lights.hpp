#pragma once
// The lights of a render: an optional environment map, point lights, sphere and disk area
// lights. One light is chosen uniformly per light sample; sample() and pdf() give densities per
// steradian at the shading point (point lights are delta lights: no pdf, never hit by rays).
// Area lights emit from one side (disks: the side their normal points to) and do not block
// light (they are not in the Embree scene; rays hit them analytically).

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>

#include "microbrdf/render.hpp"
#include "render/envmap.hpp"

namespace microbrdf::pt {

struct LightSample {
  Eigen::Vector3d dir;  ///< unit, from the shading point towards the light
  Eigen::Vector3d rgb;  ///< radiance arriving (point lights: intensity / distance^2)
  double distance = 0;  ///< to the light (infinity for the environment)
  double pdf = 0;       ///< per steradian, including the choice of the light
  bool delta = false;
};

struct LightHit {
  double t = -1;  ///< distance along the ray (-1: no area light hit)
  Eigen::Vector3d rgb = Eigen::Vector3d::Zero();
  double pdf = 0;  ///< light-sampling density of this direction (incl. choice)
};

class LightSet {
 public:
  explicit LightSet(const RenderLights& lights);
  int count() const { return count_; }
  const EnvironmentMap* env() const { return env_.get(); }
  /// Whether there are sphere or disk lights (hit_area can find something).
  bool has_area() const { return !l_.spheres.empty() || !l_.disks.empty(); }

  /// Samples one light from x with a 2D point: u1 chooses the light (uniformly) and, stretched
  /// back to [0,1), places the sample on it together with u2.
  std::optional<LightSample> sample(const Eigen::Vector3d& x, double u1, double u2) const;
  /// The nearest area light along x + t d, t in (0, tmax).
  LightHit hit_area(const Eigen::Vector3d& x, const Eigen::Vector3d& d, double tmax) const;
  /// Memory prefetches for a later sample(x, u1, u2) and env_rgb(d) (no effect on results).
  /// With `cells`, also the map record the draw's column walk starts at.
  void prefetch_sample(double u1, double u2, bool cells = false) const {
    if (!env_ || !(count_ > 0)) return;
    const int i = std::min(int(u1 * count_), count_ - 1);
    if (i == 0) env_->prefetch_sample(std::min(u1 * count_, std::nextafter(1.0, 0.0)), u2, cells);
  }
  /// Returns what env_rgb needs besides d (the map pixel).
  std::pair<int, int> prefetch_env(const Eigen::Vector3d& d) const {
    return env_ ? env_->prefetch_lookup(d) : std::pair<int, int>{-1, -1};
  }
  /// Environment radiance and its light-sampling pdf (incl. choice) for an escaping ray.
  Eigen::Vector3d env_rgb(const Eigen::Vector3d& d, double& pdf) const;
  /// The same with the pixel from prefetch_env(d).
  Eigen::Vector3d env_rgb(const Eigen::Vector3d& d, std::pair<int, int> pixel, double& pdf) const;

 private:
  RenderLights l_;
  std::unique_ptr<EnvironmentMap> env_;
  int count_ = 0;
};

}  // namespace microbrdf::pt

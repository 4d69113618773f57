// Filling Embree 3 rays from Eigen vectors: the one place that sets every field Embree reads
// (origin, direction, [tnear, tfar], all mask bits, no flags, time 0; hits invalid).
#pragma once

#include <embree3/rtcore.h>

#include <Eigen/Core>

namespace microbrdf::detail {

// Ray for rtcOccluded1 from origin o along d over [tnear, tfar] (units of |d|).
inline void fill_ray(RTCRay& r, const Eigen::Vector3d& o, const Eigen::Vector3d& d, float tnear,
                     float tfar) {
  r.org_x = float(o.x());
  r.org_y = float(o.y());
  r.org_z = float(o.z());
  r.dir_x = float(d.x());
  r.dir_y = float(d.y());
  r.dir_z = float(d.z());
  r.tnear = tnear;
  r.tfar = tfar;
  r.mask = 0xFFFFFFFFu;
  r.flags = 0;
  r.time = 0;
}

// Ray and empty hit for rtcIntersect1, as fill_ray.
inline void fill_rayhit(RTCRayHit& rh, const Eigen::Vector3d& o, const Eigen::Vector3d& d,
                        float tnear, float tfar) {
  fill_ray(rh.ray, o, d, tnear, tfar);
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
}

}  // namespace microbrdf::detail

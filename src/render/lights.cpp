// Light sampling and analytic light hits (see lights.hpp).
#include "render/lights.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "microbrdf/error.hpp"

namespace microbrdf::pt {
namespace {

using V3 = Eigen::Vector3d;
constexpr double kInf = std::numeric_limits<double>::infinity();

void frame(const V3& w, V3& a, V3& b) {
  V3 h = std::abs(w.x()) < 0.9 ? V3(1, 0, 0) : V3(0, 1, 0);
  a = (h - h.dot(w) * w).normalized();
  b = w.cross(a);
}

/// 1 - cos(theta_max) of the cone a sphere of radius r subtends at distance d > r, accurately.
double one_minus_cos_max(double r, double d) {
  const double s2 = (r * r) / (d * d);
  return s2 / (1 + std::sqrt(std::max(0.0, 1 - s2)));
}

/// Nearest t > 0 where x + t d meets the sphere, or -1.
double ray_sphere(const V3& x, const V3& d, const V3& c, double r) {
  const V3 oc = x - c;
  const double b = oc.dot(d), cc = oc.squaredNorm() - r * r, disc = b * b - cc;
  if (disc < 0) return -1;
  const double s = std::sqrt(disc);
  const double t0 = -b - s, t1 = -b + s;
  return t0 > 0 ? t0 : (t1 > 0 ? t1 : -1);
}

}  // namespace

LightSet::LightSet(const RenderLights& lights) : l_(lights) {
  if (!lights.envmap_path.empty() && lights.uniform_white_env)
    throw InputError("lights: give an environment map or the uniform white environment, not both");
  if (lights.uniform_white_env) {
    env_ = std::make_unique<EnvironmentMap>(
        EnvironmentMap::uniform(V3::Constant(lights.envmap_scale)));
  } else if (!lights.envmap_path.empty()) {
    env_ = std::make_unique<EnvironmentMap>(read_envmap_image(lights.envmap_path),
                                            lights.envmap_scale, lights.envmap_rotation_rad);
  }
  for (const auto& s : l_.spheres)
    if (!(s.radius > 0)) throw InputError("lights: a sphere light needs a radius > 0");
  for (auto& d : l_.disks) {
    if (!(d.radius > 0) || !(d.normal.norm() > 0))
      throw InputError("lights: a disk light needs a radius > 0 and a normal");
    d.normal.normalize();
  }
  count_ = (env_ ? 1 : 0) + int(l_.points.size() + l_.spheres.size() + l_.disks.size());
}

std::optional<LightSample> LightSet::sample(const V3& x, double u1, double u2) const {
  if (count_ == 0) return std::nullopt;
  // u1 chooses the light and is then stretched back to [0,1) for the light itself, so one
  // stratified 2D point serves both.
  int i = std::min(int(u1 * count_), count_ - 1);
  u1 = std::min(u1 * count_ - i, std::nextafter(1.0, 0.0));
  const double choose = 1.0 / count_;
  LightSample s;
  if (env_) {
    if (i == 0) {
      double pdf;
      s.dir = env_->sample(u1, u2, pdf, &s.rgb);
      if (!(pdf > 0)) return std::nullopt;
      s.pdf = pdf * choose;
      s.distance = kInf;
      return s;
    }
    --i;
  }
  if (i < int(l_.points.size())) {
    const auto& p = l_.points[i];
    const V3 v = p.position - x;
    const double d2 = v.squaredNorm();
    if (!(d2 > 0)) return std::nullopt;
    s.distance = std::sqrt(d2);
    s.dir = v / s.distance;
    s.rgb = p.rgb_intensity / d2;
    s.pdf = choose;  // a probability, not a density: delta light
    s.delta = true;
    return s;
  }
  i -= int(l_.points.size());
  if (i < int(l_.spheres.size())) {
    const auto& sp = l_.spheres[i];
    const V3 v = sp.centre - x;
    const double d = v.norm();
    if (d <= sp.radius) return std::nullopt;
    const V3 w = v / d;
    V3 a, b;
    frame(w, a, b);
    const double omc = one_minus_cos_max(sp.radius, d);
    const double one_minus_cos = u1 * omc, cos_t = 1 - one_minus_cos;
    const double sin_t = std::sqrt(std::max(0.0, one_minus_cos * (2 - one_minus_cos)));
    const double phi = 2 * M_PI * u2;
    s.dir = (cos_t * w + sin_t * (std::cos(phi) * a + std::sin(phi) * b)).normalized();
    const double t = ray_sphere(x, s.dir, sp.centre, sp.radius);
    s.distance = t > 0 ? t : d - sp.radius;
    s.rgb = sp.rgb_radiance;
    s.pdf = choose / (2 * M_PI * omc);
    return s;
  }
  i -= int(l_.spheres.size());
  const auto& dk = l_.disks[i];
  V3 a, b;
  frame(dk.normal, a, b);
  const double r = dk.radius * std::sqrt(u1), phi = 2 * M_PI * u2;
  const V3 y = dk.centre + r * (std::cos(phi) * a + std::sin(phi) * b);
  const V3 v = y - x;
  const double d2 = v.squaredNorm();
  if (!(d2 > 0)) return std::nullopt;
  s.distance = std::sqrt(d2);
  s.dir = v / s.distance;
  const double cos_l = -s.dir.dot(dk.normal);
  if (cos_l <= 0) return std::nullopt;
  s.rgb = dk.rgb_radiance;
  s.pdf = choose * d2 / (M_PI * dk.radius * dk.radius * cos_l);
  return s;
}

LightHit LightSet::hit_area(const V3& x, const V3& d, double tmax) const {
  LightHit h;
  if (count_ == 0) return h;
  const double choose = 1.0 / count_;
  double best = tmax;
  for (const auto& sp : l_.spheres) {
    const double t = ray_sphere(x, d, sp.centre, sp.radius);
    if (t > 0 && t < best) {
      const double dist = (sp.centre - x).norm();
      best = t;
      h.t = t;
      h.rgb = sp.rgb_radiance;
      h.pdf = dist > sp.radius ? choose / (2 * M_PI * one_minus_cos_max(sp.radius, dist)) : 0;
    }
  }
  for (const auto& dk : l_.disks) {
    const double dn = d.dot(dk.normal);
    if (dn >= 0) continue;  // back side or parallel: emits nothing this way
    const double t = (dk.centre - x).dot(dk.normal) / dn;
    if (!(t > 0 && t < best)) continue;
    if ((x + t * d - dk.centre).squaredNorm() > dk.radius * dk.radius) continue;
    best = t;
    h.t = t;
    h.rgb = dk.rgb_radiance;
    h.pdf = choose * t * t / (M_PI * dk.radius * dk.radius * (-dn));
  }
  return h;
}

V3 LightSet::env_rgb(const V3& d, double& pdf) const {
  if (!env_) {
    pdf = 0;
    return V3::Zero();
  }
  const V3 rgb = env_->rgb_and_pdf(d, pdf);
  pdf /= count_;
  return rgb;
}

V3 LightSet::env_rgb(const V3& d, std::pair<int, int> pixel, double& pdf) const {
  if (!env_) {
    pdf = 0;
    return V3::Zero();
  }
  const V3 rgb = env_->rgb_and_pdf_at(d, pixel, pdf);
  pdf /= count_;
  return rgb;
}

}  // namespace microbrdf::pt

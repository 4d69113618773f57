// Environment maps: lookup and importance sampling (see envmap.hpp for the conventions).
#include "render/envmap.hpp"

#include <algorithm>
#include <cmath>

#include "microbrdf/envmap_image.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

namespace microbrdf {

EnvmapImage read_envmap(const std::string& path) {
  pt::RgbFloatImage img = pt::read_envmap_image(path);
  return {img.width, img.height, std::move(img.rgb)};
}

}  // namespace microbrdf

namespace microbrdf::pt {

RgbFloatImage read_envmap_image(const std::string& path) {
  auto head = read_file_bytes(path, std::uint64_t{1} << 31);
  if (head.size() >= 4 && head[0] == 0x76 && head[1] == 0x2f && head[2] == 0x31 && head[3] == 0x01)
    return read_exr_rgb(path);
  if (head.size() >= 2 && head[0] == '#' && head[1] == '?')
    return read_radiance_hdr_bytes(head, path);
  throw FileError(path,
                  "not an environment map: expected OpenEXR (.exr) or Radiance RGBE (.hdr) data");
}

EnvironmentMap::EnvironmentMap(RgbFloatImage img, double scale, double rotation_rad)
    : img_(std::move(img)), rotation_u_(rotation_rad / (2 * M_PI)) {
  if (img_.width <= 0 || img_.height <= 0 ||
      img_.rgb.size() != std::size_t(img_.width) * img_.height * 3)
    throw InputError("environment map: empty or inconsistent image");
  if (!(scale >= 0) || !std::isfinite(scale))
    throw InputError("environment map: the scale must be finite and >= 0");
  for (auto& c : img_.rgb) c = std::isfinite(c) ? std::max(0.0f, c * float(scale)) : 0.0f;
  // Weights: largest channel times sin(theta) (the pixel's solid angle), so that every pixel
  // with any radiance can be drawn.
  const std::size_t w = img_.width, h = img_.height;
  std::vector<double> f(w * h);
  for (std::size_t r = 0; r < h; ++r) {
    const double s = std::sin(M_PI * (r + 0.5) / h);
    for (std::size_t c = 0; c < w; ++c) {
      const float* p = &img_.rgb[(r * w + c) * 3];
      f[r * w + c] = std::max({p[0], p[1], p[2]}) * s;
    }
  }
  // The radiance travels with the sampling tables (one record per pixel, see distribution2d.hpp):
  // every look-up reads it from there, and the image itself is not kept.
  dist_ = PiecewiseConstant2D(f, w, h, img_.rgb.data());
  std::vector<float>().swap(img_.rgb);
}

EnvironmentMap EnvironmentMap::uniform(const Eigen::Vector3d& rgb) {
  EnvironmentMap m;
  m.uniform_ = true;
  m.uniform_rgb_ = rgb;
  return m;
}

void EnvironmentMap::pixel_of(const Eigen::Vector3d& d, int& col, int& row) const {
  const double theta = std::acos(std::clamp(d.y(), -1.0, 1.0));
  double u = 0.5 + std::atan2(d.x(), -d.z()) / (2 * M_PI) + rotation_u_;
  u -= std::floor(u);
  col = std::min(int(u * img_.width), img_.width - 1);
  row = std::clamp(int(theta / M_PI * img_.height), 0, img_.height - 1);
}

Eigen::Vector3d EnvironmentMap::direction(double u, double v) const {
  const double phi = 2 * M_PI * (u - 0.5 - rotation_u_), theta = M_PI * v;
  const double st = std::sin(theta);
  return {st * std::sin(phi), std::cos(theta), -st * std::cos(phi)};
}

Eigen::Vector3d EnvironmentMap::rgb(const Eigen::Vector3d& d) const {
  if (uniform_) return uniform_rgb_;
  int c, r;
  pixel_of(d, c, r);
  const float* p = dist_.payload(c, r);
  return {p[0], p[1], p[2]};
}

Eigen::Vector3d EnvironmentMap::sample(double u1, double u2, double& pdf,
                                       Eigen::Vector3d* rgb) const {
  if (uniform_) {
    const double z = 1 - 2 * u2, r = std::sqrt(std::max(0.0, 1 - z * z)), phi = 2 * M_PI * u1;
    pdf = 1 / (4 * M_PI);
    if (rgb) *rgb = uniform_rgb_;
    return {r * std::cos(phi), z, r * std::sin(phi)};
  }
  double u, v, p;
  const std::size_t cell = dist_.sample(u1, u2, u, v, p);
  if (rgb) {
    // Cells index the stored image (the rotation acts in direction()).
    const float* q = dist_.payload(cell);
    *rgb = Eigen::Vector3d(q[0], q[1], q[2]);
  }
  const double st = std::sin(M_PI * v);
  pdf = st > 0 ? p / (2 * M_PI * M_PI * st) : 0;
  return direction(u, v);
}

double EnvironmentMap::pdf(const Eigen::Vector3d& d) const {
  if (uniform_) return 1 / (4 * M_PI);
  int c, r;
  pixel_of(d, c, r);
  const double st = std::hypot(d.x(), d.z()) / d.norm();  // sin theta, exact near the poles
  return st > 0 ? dist_.pdf(c, r) / (2 * M_PI * M_PI * st) : 0;
}

Eigen::Vector3d EnvironmentMap::rgb_and_pdf(const Eigen::Vector3d& d, double& pdf) const {
  if (uniform_) {
    pdf = 1 / (4 * M_PI);
    return uniform_rgb_;
  }
  int c, r;
  pixel_of(d, c, r);
  const double st = std::hypot(d.x(), d.z()) / d.norm();  // sin theta, exact near the poles
  pdf = st > 0 ? dist_.pdf(c, r) / (2 * M_PI * M_PI * st) : 0;
  const float* p = dist_.payload(c, r);
  return {p[0], p[1], p[2]};
}

}  // namespace microbrdf::pt

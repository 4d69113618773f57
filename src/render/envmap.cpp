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
  // The sampling tables index columns with 16 bits (distribution2d.hpp): 65535 columns is 8x
  // the width of an 8K panorama.
  if (img_.width > 65535)
    throw InputError("environment map: " + std::to_string(img_.width) +
                     " pixels wide; at most 65535 columns are supported (resample it)");
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
  // Edge tables (pixel_of, direction_in_pixel); the series inside a pixel need small pixels.
  tables_ = w >= 64 && h >= 32;
  row_scale_ = double(h) / M_PI;
  row_margin_ = 2e-4 * row_scale_;
  col_margin_ = 5e-5 * double(w) / (2 * M_PI);
  row_step_ = M_PI / double(h);
  col_step_ = 2 * M_PI / double(w);
  row_cos_.resize(h + 1);
  row_sin_.resize(h + 1);
  for (std::size_t r = 0; r <= h; ++r) {
    const double t = M_PI * double(r) / double(h);
    row_cos_[r] = std::cos(t);
    row_sin_[r] = std::sin(t);
  }
  row_cos_[0] = 1;
  row_cos_[h] = -1;
  row_sin_[0] = row_sin_[h] = 0;
  // Rows by y: cell i holds y in (1 - (i + 1) / y_scale_, 1 - i / y_scale_] (8 cells per row on
  // average); the row if the cell, widened by 1e-12, meets no row edge, else -1.
  row_by_y_.assign(8 * h, -1);
  y_scale_ = 0.5 * double(row_by_y_.size());
  int r_lo = 0;
  for (std::size_t i = 0; i < row_by_y_.size(); ++i) {
    const double y_hi = 1 - double(i) / y_scale_ + 1e-12,
                 y_lo = 1 - double(i + 1) / y_scale_ - 1e-12;
    while (r_lo + 1 < int(h) && y_hi <= row_cos_[r_lo + 1])
      ++r_lo;  // pixel_of's edge test, incrementally
    int r_hi = r_lo;
    while (r_hi + 1 < int(h) && y_lo <= row_cos_[r_hi + 1]) ++r_hi;
    if (r_hi == r_lo && r_lo < 32767) row_by_y_[i] = std::int16_t(r_lo);
  }
  col_sin_.resize(w + 1);
  col_cos_.resize(w + 1);
  for (std::size_t c = 0; c <= w; ++c) {
    const double phi = 2 * M_PI * (double(c) / double(w) - 0.5 - rotation_u_);
    col_sin_[c] = std::sin(phi);
    col_cos_[c] = std::cos(phi);
  }
}

EnvironmentMap EnvironmentMap::uniform(const Eigen::Vector3d& rgb) {
  EnvironmentMap m;
  m.uniform_ = true;
  m.uniform_rgb_ = rgb;
  return m;
}

namespace {

// acos to ~7e-5 rad (Abramowitz & Stegun 4.4.45): a first guess of the row only.
inline double acos_guess(double x) {
  const double a = std::abs(x);
  const double r = std::sqrt(std::max(0.0, 1 - a)) *
                   (1.5707288 + a * (-0.2121144 + a * (0.0742610 - 0.0187293 * a)));
  return x >= 0 ? r : M_PI - r;
}

// atan2(y, x) to ~1e-5 rad (A&S 4.4.49 on [0, 1] with octant reduction): a first guess only.
inline double atan2_guess(double y, double x) {
  const double ax = std::abs(x), ay = std::abs(y);
  const double mx = std::max(ax, ay), mn = std::min(ax, ay);
  if (!(mx > 0)) return 0;
  const double t = mn / mx, t2 = t * t;
  double a =
      t * (0.9998660 + t2 * (-0.3302995 + t2 * (0.1801410 + t2 * (-0.0851330 + t2 * 0.0208351))));
  if (ay > ax) a = M_PI_2 - a;
  if (x < 0) a = M_PI - a;
  return y < 0 ? -a : a;
}

// sin and cos of a small angle a (|a| <= 0.1) to ~1e-16 by their series.
inline void small_sincos(double a, double& s, double& c) {
  // (Horner with the reciprocal factorials: no divisions)
  const double a2 = a * a;
  s = a * (1 + a2 * (-1.0 / 6 + a2 * (1.0 / 120 + a2 * (-1.0 / 5040 + a2 * (1.0 / 362880)))));
  c = 1 + a2 * (-0.5 +
                a2 * (1.0 / 24 + a2 * (-1.0 / 720 + a2 * (1.0 / 40320 + a2 * (-1.0 / 3628800)))));
}

}  // namespace

void EnvironmentMap::pixel_of(const Eigen::Vector3d& d, int& col, int& row) const {
  if (!tables_) return pixel_of_exact(d, col, row);
  const int w = img_.width, h = img_.height;
  // Row: theta >= pi r / h  <=>  y <= cos(pi r / h).
  // The guesses decide alone when they fall further from a pixel edge than their error
  // (acos_guess 7e-5 rad, atan2_guess 1e-5 rad; margins 2e-4 and 5e-5 rad): the tests against
  // the edges are needed near the edges only.
  const double y = std::clamp(d.y(), -1.0, 1.0);
  // The row from the table over y where its cell holds no row edge (most of the sphere but the
  // poles), else from the guess.
  int r = row_by_y_[std::min(std::size_t((1 - y) * y_scale_), row_by_y_.size() - 1)];
  if (r < 0) {
    const double gr = acos_guess(y) * row_scale_;
    r = std::clamp(int(gr), 0, h - 1);
    if (!(gr - r > row_margin_ && gr - r < 1 - row_margin_)) {
      while (r > 0 && y > row_cos_[r]) --r;
      while (r + 1 < h && y <= row_cos_[r + 1]) ++r;
    }
  }
  // Column: the azimuth of p = (x, -z) lies at or past the left edge of column c when
  // sin(phi - phi_c) >= 0, i.e. p.x cos(phi_c) - p.z sin(phi_c) >= 0 (edges less than a half
  // turn apart: w >= 64).
  const double px = d.x(), pz = -d.z();
  double u = 0.5 + atan2_guess(px, pz) * (0.5 / M_PI) + rotation_u_;
  u -= std::floor(u);
  const double gc = u * w;
  int c = std::min(int(gc), w - 1);
  if (gc - c > col_margin_ && gc - c < 1 - col_margin_ && px * px + pz * pz > 1e-12) {
    col = c;
    row = r;
    return;
  }
  auto past = [&](int k) {  // p at or past the left edge of column k (mod w)
    const int kk = k == w ? 0 : k;
    return px * col_cos_[kk] - pz * col_sin_[kk] >= 0;
  };
  for (int step = 0; step < 3; ++step) {
    const bool a = past(c), b = past(c + 1);
    if (a && !b) {
      col = c;
      row = r;
      return;
    }
    if (!a)
      c = c == 0 ? w - 1 : c - 1;
    else
      c = c + 1 == w ? 0 : c + 1;
  }
  int rr;
  pixel_of_exact(d, col, rr);  // undecided (p = 0 at the poles): the definition
  row = r;
}

void EnvironmentMap::pixel_of_exact(const Eigen::Vector3d& d, int& col, int& row) const {
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

Eigen::Vector3d EnvironmentMap::direction_in_pixel(std::size_t col, double fu, std::size_t row,
                                                   double fv, double& sin_theta) const {
  const double w = img_.width, h = img_.height;
  if (!tables_) {
    const double v = (double(row) + fv) / h;
    sin_theta = std::sin(M_PI * v);
    return direction((double(col) + fu) / w, v);
  }
  double sa, ca, sb, cb;
  small_sincos(col_step_ * fu, sa, ca);
  small_sincos(row_step_ * fv, sb, cb);
  const double sp = col_sin_[col] * ca + col_cos_[col] * sa;
  const double cp = col_cos_[col] * ca - col_sin_[col] * sa;
  const double st = row_sin_[row] * cb + row_cos_[row] * sb;
  const double ct = row_cos_[row] * cb - row_sin_[row] * sb;
  sin_theta = st;
  return {st * sp, ct, -st * cp};
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
  std::size_t col, row;
  double fu, fv, p;
  const float* q = dist_.sample_cell(u1, u2, col, fu, row, fv, p);
  // Cells index the stored image (the rotation acts in the direction).
  if (rgb) *rgb = Eigen::Vector3d(q[0], q[1], q[2]);
  double st;
  const Eigen::Vector3d d = direction_in_pixel(col, fu, row, fv, st);
  pdf = st > 0 ? p / (2 * M_PI * M_PI * st) : 0;
  return d;
}

double EnvironmentMap::pdf(const Eigen::Vector3d& d) const {
  if (uniform_) return 1 / (4 * M_PI);
  int c, r;
  pixel_of(d, c, r);
  const double st = std::sqrt((d.x() * d.x() + d.z() * d.z()) / d.squaredNorm());  // sin theta
  return st > 0 ? dist_.pdf(c, r) / (2 * M_PI * M_PI * st) : 0;
}

Eigen::Vector3d EnvironmentMap::rgb_and_pdf(const Eigen::Vector3d& d, double& pdf) const {
  if (uniform_) {
    pdf = 1 / (4 * M_PI);
    return uniform_rgb_;
  }
  int c, r;
  pixel_of(d, c, r);
  return rgb_and_pdf_at(d, {c, r}, pdf);
}

Eigen::Vector3d EnvironmentMap::rgb_and_pdf_at(const Eigen::Vector3d& d, std::pair<int, int> pixel,
                                               double& pdf) const {
  if (uniform_) {
    pdf = 1 / (4 * M_PI);
    return uniform_rgb_;
  }
  const auto [c, r] = pixel;
  const double st = std::sqrt((d.x() * d.x() + d.z() * d.z()) / d.squaredNorm());  // sin theta
  pdf = st > 0 ? dist_.pdf(c, r) / (2 * M_PI * M_PI * st) : 0;
  const float* p = dist_.payload(c, r);
  return {p[0], p[1], p[2]};
}

}  // namespace microbrdf::pt

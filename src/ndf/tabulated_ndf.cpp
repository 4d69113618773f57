// TabulatedNdf: storage, bilinear evaluation, normalisation, moments, slices, splatting.
#include "microbrdf/tabulated_ndf.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "microbrdf/memory_budget.hpp"

namespace microbrdf {

NdfWindow zoom_window(double cx, double cy, double half) {
  NdfWindow w;
  w.half = std::isfinite(half) ? std::clamp(half, 1e-6, 1.0) : 1.0;
  const double lim = 1.0 - w.half;
  w.cx = std::isfinite(cx) ? std::clamp(cx, -lim, lim) : 0.0;
  w.cy = std::isfinite(cy) ? std::clamp(cy, -lim, lim) : 0.0;
  if (w.half == 1.0) w.cx = w.cy = 0.0;
  return w;
}

std::string ndf_sampling(const NdfMetadata& meta) {
  if (!meta.sampling.empty()) return meta.sampling;
  std::string m = meta.method;
  std::transform(m.begin(), m.end(), m.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  for (const char* point : {"beckmann", "ggx", "ellipsoid", "trowbridge-reitz", "gtr2", "kirchhoff",
                            "measured", "lobe"})
    if (m == point) return "point";
  return "cell";
}

TabulatedNdf::TabulatedNdf(std::size_t resolution, const NdfWindow& window)
    : n_(resolution), w_(window), d_() {
  if (resolution < 3) throw std::invalid_argument("TabulatedNdf: resolution must be >= 3");
  constexpr double kTol = 1e-12;
  if (!(w_.half > 0 && w_.half <= 1 + kTol) || !(std::abs(w_.cx) + w_.half <= 1 + kTol) ||
      !(std::abs(w_.cy) + w_.half <= 1 + kTol))
    throw std::invalid_argument("TabulatedNdf: the window must lie inside [-1, 1]^2");
  check_memory("an NDF table", mul_sat(mul_sat(resolution, resolution), sizeof(double)),
               std::to_string(resolution) + " x " + std::to_string(resolution) + " nodes");
  d_.assign(resolution * resolution, 0.0);
}

TabulatedNdf::TabulatedNdf(std::size_t resolution, std::vector<double>&& values,
                           const NdfWindow& window)
    : TabulatedNdf(3, window) {
  if (resolution < 3) throw std::invalid_argument("TabulatedNdf: resolution must be >= 3");
  if (values.size() != mul_sat(resolution, resolution))
    throw std::invalid_argument("TabulatedNdf: " + std::to_string(values.size()) + " values for " +
                                std::to_string(resolution) + " x " + std::to_string(resolution) +
                                " nodes");
  n_ = resolution;
  d_ = std::move(values);
}

double TabulatedNdf::eval_disk(double mx, double my) const {
  if (!(mx * mx + my * my <= 1.0)) return 0.0;  // also rejects NaN
  const double inv = 1.0 / spacing();
  double fx = (mx - w_.x0()) * inv, fy = (my - w_.y0()) * inv;
  if (!w_.full()) {
    const double last = static_cast<double>(n_ - 1);
    if (!(fx >= 0 && fx <= last && fy >= 0 && fy <= last)) return 0.0;  // outside the window
  }
  auto ix = static_cast<std::size_t>(std::clamp(std::floor(fx), 0.0, static_cast<double>(n_ - 2)));
  auto iy = static_cast<std::size_t>(std::clamp(std::floor(fy), 0.0, static_cast<double>(n_ - 2)));
  double tx = fx - static_cast<double>(ix), ty = fy - static_cast<double>(iy);
  const double* r0 = &d_[iy * n_ + ix];
  const double* r1 = r0 + n_;
  return (1 - ty) * ((1 - tx) * r0[0] + tx * r0[1]) + ty * ((1 - tx) * r1[0] + tx * r1[1]);
}

double TabulatedNdf::eval(const Eigen::Vector3d& m) const {
  double len = m.norm();
  if (!(len > 0) || m.z() <= 0) return 0.0;
  return eval_disk(m.x() / len, m.y() / len);
}

double TabulatedNdf::integral() const {
  double sum = 0;
  for (double v : d_) sum += v;
  return sum * spacing() * spacing();
}

void TabulatedNdf::normalise() {
  double i = integral();
  if (!(i > 0) || !std::isfinite(i))
    throw std::domain_error("TabulatedNdf: cannot normalise an empty table");
  for (double& v : d_) v /= i;
}

void TabulatedNdf::clear_outside_disk() {
  const double before = integral();
  for (std::size_t iy = 0; iy < n_; ++iy)
    for (std::size_t ix = 0; ix < n_; ++ix) {
      double x = node_x(ix), y = node_y(iy);
      if (x * x + y * y > 1.0) d_[iy * n_ + ix] = 0.0;
    }
  if (std::fabs(before - 1.0) < 1e-6 && integral() > 0) normalise();
}

namespace {

// Calls f(mx, my, mz, w) for every node inside the disk with mz > 0, w = D * Delta^2 (the
// node's share of integral D(m)(m.n) dw).
template <class F>
void for_each_node(const TabulatedNdf& t, F&& f) {
  const double a = t.spacing() * t.spacing();
  const std::size_t n = t.resolution();
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix) {
      double w = t.at(ix, iy);
      if (w == 0) continue;
      double x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
      if (r2 >= 1.0) continue;
      f(x, y, std::sqrt(1.0 - r2), w * a);
    }
}

}  // namespace

Eigen::Vector3d TabulatedNdf::mean_normal() const {
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for_each_node(*this,
                [&](double x, double y, double z, double w) { s += w * Eigen::Vector3d(x, y, z); });
  double len = s.norm();
  return len > 0 ? Eigen::Vector3d(s / len) : Eigen::Vector3d(0, 0, 1);
}

Eigen::Matrix2d TabulatedNdf::slope_covariance() const {
  double sw = 0;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
  for_each_node(*this, [&](double x, double y, double z, double w) {
    Eigen::Vector2d s(-x / z, -y / z);
    sw += w;
    mean += w * s;
    second += w * s * s.transpose();
  });
  if (sw <= 0) return Eigen::Matrix2d::Zero();
  mean /= sw;
  return second / sw - mean * mean.transpose();
}

double TabulatedNdf::rms_slope(double phi) const {
  Eigen::Vector2d u(std::cos(phi), std::sin(phi));
  return std::sqrt(std::max(0.0, u.dot(slope_covariance() * u)));
}

Eigen::Vector3d TabulatedNdf::peak() const {
  auto it = std::max_element(d_.begin(), d_.end());
  auto i = static_cast<std::size_t>(it - d_.begin());
  double x = node_x(i % n_), y = node_y(i / n_);
  return {x, y, std::sqrt(std::max(0.0, 1.0 - x * x - y * y))};
}

NdfSlice TabulatedNdf::slice(double phi, std::size_t samples) const {
  NdfSlice s;
  if (samples < 2) samples = 2;
  const double c = std::cos(phi), sn = std::sin(phi);
  // The part of the line t (cos phi, sin phi), t in [-1, 1], inside the window (slab clipping).
  double ta = -1.0, tb = 1.0;
  if (!w_.full()) {
    auto clip = [&](double dir, double lo, double hi) {
      if (std::abs(dir) < 1e-15) {
        if (lo > 0 || hi < 0) tb = ta - 1;  // parallel and outside
        return;
      }
      double a = lo / dir, b = hi / dir;
      if (a > b) std::swap(a, b);
      ta = std::max(ta, a);
      tb = std::min(tb, b);
    };
    clip(c, w_.x0(), w_.x1());
    clip(sn, w_.y0(), w_.y1());
    if (!(tb > ta)) ta = -1.0, tb = 1.0;  // the line misses the window: zeros over [-1, 1]
  }
  for (std::size_t k = 0; k < samples; ++k) {
    double t = ta + (tb - ta) * static_cast<double>(k) / static_cast<double>(samples - 1);
    s.t.push_back(t);
    s.theta.push_back(std::asin(std::clamp(t, -1.0, 1.0)));
    s.value.push_back(eval_disk(t * c, t * sn));
  }
  return s;
}

void TabulatedNdf::splat(double mx, double my, double weight) {
  const double inv = 1.0 / spacing();
  double fx = (mx - w_.x0()) * inv, fy = (my - w_.y0()) * inv;
  const double last = static_cast<double>(n_ - 1);
  if (!(fx >= 0 && fx <= last && fy >= 0 && fy <= last)) return;
  auto ix = static_cast<std::size_t>(std::min(std::floor(fx), last - 1));
  auto iy = static_cast<std::size_t>(std::min(std::floor(fy), last - 1));
  double tx = fx - static_cast<double>(ix), ty = fy - static_cast<double>(iy);
  double* r0 = &d_[iy * n_ + ix];
  double* r1 = r0 + n_;
  r0[0] += weight * (1 - tx) * (1 - ty);
  r0[1] += weight * tx * (1 - ty);
  r1[0] += weight * (1 - tx) * ty;
  r1[1] += weight * tx * ty;
}

void TabulatedNdf::add(const TabulatedNdf& other, double w) {
  if (other.n_ != n_) throw std::invalid_argument("TabulatedNdf::add: resolutions differ");
  if (!(other.w_ == w_)) throw std::invalid_argument("TabulatedNdf::add: windows differ");
  for (std::size_t i = 0; i < d_.size(); ++i) d_[i] += w * other.d_[i];
}

TabulatedNdf TabulatedNdf::resampled(std::size_t resolution) const {
  return resampled(resolution, w_);
}

TabulatedNdf TabulatedNdf::resampled(std::size_t resolution, const NdfWindow& window) const {
  TabulatedNdf out(resolution, window);
  for (std::size_t iy = 0; iy < resolution; ++iy)
    for (std::size_t ix = 0; ix < resolution; ++ix)
      out.at(ix, iy) = eval_disk(out.node_x(ix), out.node_y(iy));
  out.meta = meta;
  if (out.integral() > 0) out.normalise();
  return out;
}

}  // namespace microbrdf

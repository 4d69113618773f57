// Continuous marginal/conditional warp of a bilinear density (src/brdf/marginal2d.hpp).
#include "core/marginal2d.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace microbrdf::detail {
namespace {

// Largest i in [0, n-2] with pred(i) true (0 if none): the interval holding a value.
template <class Pred>
std::size_t find_interval(std::size_t n, Pred pred) {
  std::size_t lo = 0, hi = n - 1;  // invariant: answer in [lo, hi)
  if (n < 2) return 0;
  while (hi - lo > 1) {
    const std::size_t mid = (lo + hi) / 2;
    if (pred(mid))
      lo = mid;
    else
      hi = mid;
  }
  return lo;
}

double safe_sqrt(double x) { return std::sqrt(std::max(0.0, x)); }

}  // namespace

Marginal2D::Marginal2D(std::span<const float> data, std::size_t nx, std::size_t ny,
                       std::vector<std::vector<double>> params, bool sampling)
    : nx_(nx), ny_(ny), params_(std::move(params)), sampling_(sampling) {
  if (nx < 2 || ny < 2) throw std::invalid_argument("a 2-D table needs at least 2 x 2 nodes");
  if (params_.size() > 3) throw std::invalid_argument("at most three parameters");
  std::size_t slices = 1;
  strides_.assign(params_.size(), 0);
  for (std::size_t d = params_.size(); d-- > 0;) {
    const auto& p = params_[d];
    if (p.empty()) throw std::invalid_argument("a parameter has no nodes");
    for (std::size_t i = 0; i + 1 < p.size(); ++i)
      if (!(p[i + 1] > p[i])) throw std::invalid_argument("parameter nodes must increase");
    for (double v : p)
      if (!std::isfinite(v)) throw std::invalid_argument("parameter nodes must be finite");
    strides_[d] = slices;
    slices *= p.size();
  }
  const std::size_t size = nx * ny;
  if (data.size() != slices * size) throw std::invalid_argument("table size mismatch");
  data_.assign(data.begin(), data.end());
  for (double v : data_)
    if (!std::isfinite(v)) throw std::invalid_argument("non-finite value in a table");
  if (!sampling) return;
  cond_.assign(slices * size, 0.0);
  marg_.assign(slices * ny, 0.0);
  for (std::size_t s = 0; s < slices; ++s) {
    double* d = data_.data() + s * size;
    double* c = cond_.data() + s * size;
    double* m = marg_.data() + s * ny;
    for (std::size_t k = 0; k < size; ++k)
      if (d[k] < 0) throw std::invalid_argument("negative value in a sampling table");
    for (std::size_t y = 0; y < ny; ++y) {
      double sum = 0;
      c[y * nx] = 0;
      for (std::size_t x = 0; x + 1 < nx; ++x) {
        sum += 0.5 * (d[y * nx + x] + d[y * nx + x + 1]);
        c[y * nx + x + 1] = sum;
      }
    }
    double sum = 0;
    m[0] = 0;
    for (std::size_t y = 0; y + 1 < ny; ++y) {
      sum += 0.5 * (c[(y + 1) * nx - 1] + c[(y + 2) * nx - 1]);
      m[y + 1] = sum;
    }
    if (!(sum > 0) || !std::isfinite(sum))
      throw std::invalid_argument("a sampling table slice has no positive mass");
    const double norm = 1.0 / sum;
    for (std::size_t k = 0; k < size; ++k) {
      c[k] *= norm;
      d[k] *= norm;
    }
    for (std::size_t y = 0; y < ny; ++y) m[y] *= norm;
  }
}

Marginal2D::Weights Marginal2D::weights(const double* param) const {
  Weights w;
  w.n = 1;
  w.slice[0] = 0;
  w.w[0] = 1;
  for (std::size_t d = 0; d < params_.size(); ++d) {
    const auto& p = params_[d];
    if (p.size() == 1) continue;
    const double v = param[d];
    const std::size_t i = find_interval(p.size(), [&](std::size_t k) { return p[k] < v; });
    const double t = std::clamp((v - p[i]) / (p[i + 1] - p[i]), 0.0, 1.0);
    const int n = w.n;
    for (int k = 0; k < n; ++k) {
      w.slice[k + n] = w.slice[k] + (i + 1) * strides_[d];
      w.w[k + n] = w.w[k] * t;
      w.slice[k] += i * strides_[d];
      w.w[k] *= 1 - t;
    }
    w.n = 2 * n;
  }
  return w;
}

double Marginal2D::data_at(const Weights& w, std::size_t i) const {
  double v = 0;
  for (int k = 0; k < w.n; ++k) v += w.w[k] * data_[w.slice[k] * nx_ * ny_ + i];
  return v;
}
double Marginal2D::cond_at(const Weights& w, std::size_t i) const {
  double v = 0;
  for (int k = 0; k < w.n; ++k) v += w.w[k] * cond_[w.slice[k] * nx_ * ny_ + i];
  return v;
}
double Marginal2D::marg_at(const Weights& w, std::size_t j) const {
  double v = 0;
  for (int k = 0; k < w.n; ++k) v += w.w[k] * marg_[w.slice[k] * ny_ + j];
  return v;
}

double Marginal2D::eval(Vec2 pos, const double* param) const {
  const Weights w = weights(param);
  const double px = std::clamp(pos[0], 0.0, 1.0) * double(nx_ - 1);
  const double py = std::clamp(pos[1], 0.0, 1.0) * double(ny_ - 1);
  const std::size_t ix = std::min(static_cast<std::size_t>(px), nx_ - 2);
  const std::size_t iy = std::min(static_cast<std::size_t>(py), ny_ - 2);
  const double tx = px - double(ix), ty = py - double(iy);
  const std::size_t i = iy * nx_ + ix;
  const double v = (1 - ty) * ((1 - tx) * data_at(w, i) + tx * data_at(w, i + 1)) +
                   ty * ((1 - tx) * data_at(w, i + nx_) + tx * data_at(w, i + nx_ + 1));
  return sampling_ ? v * double(nx_ - 1) * double(ny_ - 1) : v;
}

std::pair<Marginal2D::Vec2, double> Marginal2D::sample(Vec2 u, const double* param) const {
  const Weights w = weights(param);
  constexpr double kEps = 1e-7;
  double ux = std::clamp(u[0], kEps, 1 - kEps), uy = std::clamp(u[1], kEps, 1 - kEps);
  // Row: the marginal CDF is quadratic inside a row interval.
  const std::size_t row = find_interval(ny_, [&](std::size_t j) { return marg_at(w, j) < uy; });
  uy -= marg_at(w, row);
  const double r0 = cond_at(w, (row + 1) * nx_ - 1), r1 = cond_at(w, (row + 2) * nx_ - 1);
  double t;
  if (std::abs(r0 - r1) < 1e-4 * (r0 + r1))
    t = 2 * uy / (r0 + r1);
  else
    t = (r0 - safe_sqrt(r0 * r0 - 2 * uy * (r0 - r1))) / (r0 - r1);
  t = std::clamp(t, 0.0, 1.0);
  // Column: the conditional CDF at the continuous row position t.
  ux *= (1 - t) * r0 + t * r1;
  auto cond = [&](std::size_t i) {
    return (1 - t) * cond_at(w, row * nx_ + i) + t * cond_at(w, (row + 1) * nx_ + i);
  };
  const std::size_t col = find_interval(nx_, [&](std::size_t i) { return cond(i) < ux; });
  ux -= cond(col);
  const std::size_t i = row * nx_ + col;
  const double c0 = (1 - t) * data_at(w, i) + t * data_at(w, i + nx_);
  const double c1 = (1 - t) * data_at(w, i + 1) + t * data_at(w, i + nx_ + 1);
  double s;
  if (std::abs(c0 - c1) < 1e-4 * (c0 + c1))
    s = (c0 + c1) > 0 ? 2 * ux / (c0 + c1) : 0.0;
  else
    s = (c0 - safe_sqrt(c0 * c0 - 2 * ux * (c0 - c1))) / (c0 - c1);
  s = std::clamp(s, 0.0, 1.0);
  const Vec2 pos{(double(col) + s) / double(nx_ - 1), (double(row) + t) / double(ny_ - 1)};
  const double pdf = ((1 - s) * c0 + s * c1) * double(nx_ - 1) * double(ny_ - 1);
  return {pos, pdf};
}

std::pair<Marginal2D::Vec2, double> Marginal2D::invert(Vec2 pos, const double* param) const {
  const Weights w = weights(param);
  const double px = std::clamp(pos[0], 0.0, 1.0) * double(nx_ - 1);
  const double py = std::clamp(pos[1], 0.0, 1.0) * double(ny_ - 1);
  const std::size_t ix = std::min(static_cast<std::size_t>(px), nx_ - 2);
  const std::size_t iy = std::min(static_cast<std::size_t>(py), ny_ - 2);
  const double s = px - double(ix), t = py - double(iy);
  const std::size_t i = iy * nx_ + ix;
  const double v00 = data_at(w, i), v10 = data_at(w, i + 1), v01 = data_at(w, i + nx_),
               v11 = data_at(w, i + nx_ + 1);
  const double c0 = (1 - t) * v00 + t * v01, c1 = (1 - t) * v10 + t * v11;
  const double pdf = (1 - s) * c0 + s * c1;
  double ux = s * (c0 + 0.5 * s * (c1 - c0));
  ux += (1 - t) * cond_at(w, i) + t * cond_at(w, i + nx_);
  const double r0 = cond_at(w, (iy + 1) * nx_ - 1), r1 = cond_at(w, (iy + 2) * nx_ - 1);
  const double rt = (1 - t) * r0 + t * r1;
  ux = rt > 0 ? ux / rt : 0.0;
  const double uy = t * (r0 + 0.5 * t * (r1 - r0)) + marg_at(w, iy);
  return {{ux, uy}, pdf * double(nx_ - 1) * double(ny_ - 1)};
}

}  // namespace microbrdf::detail

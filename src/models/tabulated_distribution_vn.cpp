// Approximate visible-normal sampling of a tabulated NDF with an exact pdf
// (tabulated_distribution_vn.hpp has the method).
#include "tabulated_distribution_vn.hpp"

#include <algorithm>
#include <cmath>

#include "core/bilinear_cell.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf::detail {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kMaxTries = 256;  // redraws inside one rim cell before giving up

template <class T>
bool non_decreasing(const T* a, std::size_t n) {
  for (std::size_t i = 1; i < n; ++i)
    if (!(a[i - 1] <= a[i])) return false;
  return true;
}

template <class T>
double width(const T* cdf, std::size_t i) {
  return static_cast<double>(cdf[i]) - (i ? static_cast<double>(cdf[i - 1]) : 0.0);
}

// Fills out[0, nc) with the inclusive row CDF of the nc x nc masses g (row-major) and, for
// each row r, out[nc + off[r], nc + off[r+1]) with the conditional CDF of the row's cells
// lo[r], lo[r] + 1, ... (the span of the row's cells that can have mass; g is 0 outside it);
// last entries exactly 1. Returns false if g has no mass.
template <class T>
bool cdf_2d(const std::vector<double>& g, std::size_t nc, const std::vector<std::uint32_t>& lo,
            const std::vector<std::uint32_t>& off, T* out) {
  double total = 0;
  for (std::size_t r = 0; r < nc; ++r) {
    const double* row = &g[r * nc];
    double run = 0;
    for (std::size_t c = 0; c < nc; ++c) run += row[c];
    const std::size_t len = off[r + 1] - off[r];
    T* cond = out + nc + off[r];
    double acc = 0;
    for (std::size_t c = 0; c < len; ++c)
      cond[c] = static_cast<T>(run > 0 ? (acc += row[lo[r] + c]) / run : 1.0);
    if (len) cond[len - 1] = 1;
    out[r] = static_cast<T>(total += run);  // unnormalised row CDF for now
  }
  if (!(total > 0) || !std::isfinite(total)) return false;
  double run = 0;
  for (std::size_t r = 0; r < nc; ++r) {
    for (std::size_t c = 0; c < nc; ++c) run += g[r * nc + c];
    out[r] = static_cast<T>(run / total);
  }
  out[nc - 1] = 1;
  return true;
}

}  // namespace

VisibleNormalTables::VisibleNormalTables(const TabulatedNdf& t, std::size_t coarse,
                                         std::size_t theta_steps, std::size_t phi_steps,
                                         double defensive)
    : t_(&t), nt_(theta_steps), np_(phi_steps), eps_(defensive) {
  if (coarse < 1 || theta_steps < 1 || phi_steps < 1)
    throw InputError("tabulated distribution: visible-normal tables need >= 1 node per axis");
  if (!(defensive > 0 && defensive <= 1))
    throw InputError("tabulated distribution: the defensive fraction must be in (0, 1]");
  const std::size_t n = t.resolution();
  cells_ = n - 1;
  nc_ = std::min(coarse, cells_);
  const std::size_t ns = std::min(2 * nc_, cells_);  // sub-blocks per side (moments)
  const double h = t.spacing();

  // Fine masses (inside the disk), their coarse cells, and the sub-block slope moments.
  std::vector<double> fm(cells_ * cells_, 0.0);
  std::vector<double> s0(ns * ns, 0.0), sx(ns * ns, 0.0), sy(ns * ns, 0.0);
  std::vector<std::uint32_t> count(nc_ * nc_ + 1, 0);
  for (std::size_t cy = 0; cy < cells_; ++cy) {
    const double y0 = t.node_y(cy), y1 = y0 + h;
    const double ny = std::clamp(0.0, y0, y1), fy = std::max(std::fabs(y0), std::fabs(y1));
    for (std::size_t cx = 0; cx < cells_; ++cx) {
      const double x0 = t.node_x(cx), x1 = x0 + h;
      const double nx = std::clamp(0.0, x0, x1), fx = std::max(std::fabs(x0), std::fabs(x1));
      if (nx * nx + ny * ny >= 1) continue;
      const double a = t.at(cx, cy), b = t.at(cx + 1, cy), c = t.at(cx, cy + 1),
                   d = t.at(cx + 1, cy + 1);
      const double m =
          fx * fx + fy * fy <= 1 ? 0.25 * (a + b + c + d) * h * h : rim_mass(x0, y0, h, a, b, c, d);
      if (!(m > 0)) continue;  // (cells with negative values are never drawn)
      fm[cy * cells_ + cx] = m;
      ++count[(cy * nc_ / cells_) * nc_ + cx * nc_ / cells_];
      // Slope at the cell centre (pulled inside the disk for rim cells): only shapes the
      // proposal, never the pdf.
      double xc = x0 + 0.5 * h, yc = y0 + 0.5 * h;
      const double r = std::hypot(xc, yc), rmax = 1 - 1e-3;
      if (r > rmax) {
        xc *= rmax / r;
        yc *= rmax / r;
      }
      const double inv_z = 1 / std::sqrt(1 - xc * xc - yc * yc);
      const std::size_t s = (cy * ns / cells_) * ns + cx * ns / cells_;
      s0[s] += m;
      sx[s] += m * xc * inv_z;
      sy[s] += m * yc * inv_z;
    }
  }

  // Fine cells grouped by coarse cell (counting sort), CDF per coarse cell.
  const std::size_t ncc = nc_ * nc_;
  offset_.assign(ncc + 1, 0);
  for (std::size_t c = 0; c < ncc; ++c) offset_[c + 1] = offset_[c] + count[c];
  fine_id_.assign(offset_[ncc], 0);
  fine_cdf_.assign(offset_[ncc], 0.0);
  std::vector<std::uint32_t> fill(offset_.begin(), offset_.end() - 1);
  for (std::size_t cy = 0; cy < cells_; ++cy)
    for (std::size_t cx = 0; cx < cells_; ++cx) {
      const double m = fm[cy * cells_ + cx];
      if (!(m > 0)) continue;
      const std::size_t c = (cy * nc_ / cells_) * nc_ + cx * nc_ / cells_;
      fine_id_[fill[c]] = static_cast<std::uint32_t>(cy * cells_ + cx);
      fine_cdf_[fill[c]++] = m;
    }
  mass_.assign(ncc, 0.0);
  double total = 0;
  for (std::size_t c = 0; c < ncc; ++c) {
    double run = 0;
    for (std::uint32_t i = offset_[c]; i < offset_[c + 1]; ++i) fine_cdf_[i] = run += fine_cdf_[i];
    for (std::uint32_t i = offset_[c]; i < offset_[c + 1]; ++i) fine_cdf_[i] /= run;
    if (offset_[c + 1] > offset_[c]) fine_cdf_[offset_[c + 1] - 1] = 1.0;
    mass_[c] = run;
    total += run;
  }
  // Each row's span of cells with mass (the same for every table: a view table gives mass only
  // to coarse cells with mass).
  row_lo_.assign(nc_, 0);
  row_off_.assign(nc_ + 1, 0);
  for (std::size_t r = 0; r < nc_; ++r) {
    std::size_t lo = nc_, hi = 0;
    for (std::size_t c = 0; c < nc_; ++c)
      if (mass_[r * nc_ + c] > 0) {
        lo = std::min(lo, c);
        hi = c + 1;
      }
    row_lo_[r] = static_cast<std::uint32_t>(hi > lo ? lo : 0);
    row_off_[r + 1] = row_off_[r] + static_cast<std::uint32_t>(hi > lo ? hi - lo : 0);
  }
  block_ = nc_ + row_off_[nc_];
  q_cdf_.assign(block_, 0.0);
  if (!cdf_2d(mass_, nc_, row_lo_, row_off_, q_cdf_.data()))
    throw InputError("tabulated NDF: no positive mass inside the unit disk");
  total_ = total;

  // Sub-blocks with mass: coarse cell, mass, mean slope (coarse of a sub-block = coarse of
  // each of its fine cells, since ns is 2 nc or the cell count).
  std::vector<std::uint32_t> sub_c;
  std::vector<double> sub_m, sub_p, sub_q;
  for (std::size_t by = 0; by < ns; ++by)
    for (std::size_t bx = 0; bx < ns; ++bx) {
      const std::size_t s = by * ns + bx;
      if (!(s0[s] > 0)) continue;
      sub_c.push_back(static_cast<std::uint32_t>((by * nc_ / ns) * nc_ + bx * nc_ / ns));
      sub_m.push_back(s0[s]);
      sub_p.push_back(sx[s] / s0[s]);
      sub_q.push_back(sy[s] / s0[s]);
    }

  // View tables: P_k(C) proportional to sum over its sub-blocks of M_s <v_k.z + v_k.x p + v_k.y q>+
  // (= integral_C D <v_k.m>+ dw where the horizon of v_k crosses no sub-block).
  const std::size_t tables = (nt_ + 1) * np_, block = block_;
  view_cdf_.assign(tables * block, 0.0f);
  const auto nsub = sub_c.size();
#pragma omp parallel
  {
    std::vector<double> g(ncc);
#pragma omp for schedule(dynamic, 4)
    for (long k = 0; k < static_cast<long>(tables); ++k) {
      const auto it = static_cast<std::size_t>(k) / np_, ip = static_cast<std::size_t>(k) % np_;
      const double th = 0.5 * kPi * static_cast<double>(it) / static_cast<double>(nt_),
                   ph = 2 * kPi * static_cast<double>(ip) / static_cast<double>(np_);
      const double vx = std::sin(th) * std::cos(ph), vy = std::sin(th) * std::sin(ph),
                   vz = std::cos(th);
      std::fill(g.begin(), g.end(), 0.0);
      for (std::size_t s = 0; s < nsub; ++s)
        g[sub_c[s]] += sub_m[s] * std::max(0.0, vz + vx * sub_p[s] + vy * sub_q[s]);
      float* out = &view_cdf_[static_cast<std::size_t>(k) * block];
      if (!cdf_2d(g, nc_, row_lo_, row_off_,
                  out))  // nothing visible from v_k (not for a positive table): Q
        for (std::size_t i = 0; i < block; ++i) out[i] = static_cast<float>(q_cdf_[i]);
    }
  }

  // The samplers' searches count entries (pick_counted), which equals the binary search's
  // answer for non-decreasing CDFs; they are by construction (running sums, rounded
  // monotonically), and this keeps the binary search should one not be.
  auto segments_sorted = [&](const auto* cdf) {
    if (!non_decreasing(cdf, nc_)) return false;
    for (std::size_t r = 0; r < nc_; ++r)
      if (!non_decreasing(cdf + nc_ + row_off_[r], row_off_[r + 1] - row_off_[r])) return false;
    return true;
  };
  sorted_ = segments_sorted(q_cdf_.data());
  for (std::size_t k = 0; sorted_ && k < tables; ++k)
    sorted_ = segments_sorted(view_cdf_.data() + k * block);
  for (std::size_t c = 0; sorted_ && c < ncc; ++c)
    sorted_ = non_decreasing(fine_cdf_.data() + offset_[c], offset_[c + 1] - offset_[c]);
}

std::size_t VisibleNormalTables::memory_bytes() const {
  return fine_cdf_.size() * sizeof(double) + fine_id_.size() * sizeof(std::uint32_t) +
         offset_.size() * sizeof(std::uint32_t) + (mass_.size() + q_cdf_.size()) * sizeof(double) +
         view_cdf_.size() * sizeof(float) +
         (row_lo_.size() + row_off_.size()) * sizeof(std::uint32_t);
}

VisibleNormalTables::Mix VisibleNormalTables::mix(const Vec3& v) const {
  // A path tracer asks for the sample and the densities of one view direction several times in
  // a row (light sample, BRDF sample): the last view of each thread is remembered (a pure
  // function of v and the tables, so the result is the same).
  struct Memo {
    std::uint64_t owner = 0;  // id_ (not the address: another object may reuse it)
    double x = 0, y = 0, z = 0;
    Mix mix{};
  };
  thread_local Memo memo;
  if (memo.owner == id_ && memo.x == v.x() && memo.y == v.y() && memo.z == v.z()) return memo.mix;
  const Mix x = mix_uncached(v);
  memo.owner = id_;
  memo.x = v.x();
  memo.y = v.y();
  memo.z = v.z();
  memo.mix = x;
  return x;
}

VisibleNormalTables::Mix VisibleNormalTables::mix_uncached(const Vec3& v) const {
  // theta in [0, 90] deg (v below the horizon: treated as grazing), phi periodic.
  const double st = std::hypot(v.x(), v.y());
  double ft = std::atan2(st, std::max(0.0, v.z())) * (static_cast<double>(nt_) / (0.5 * kPi));
  ft = std::clamp(ft, 0.0, static_cast<double>(nt_));
  const auto it = std::min(static_cast<std::size_t>(ft), nt_ - 1);
  const double a = ft - static_cast<double>(it);
  double p = std::atan2(v.y(), v.x());
  if (!(p >= 0)) p = p < 0 ? p + 2 * kPi : 0.0;
  const double fp =
      std::clamp(p * (static_cast<double>(np_) / (2 * kPi)), 0.0, static_cast<double>(np_));
  const auto ip = std::min(static_cast<std::size_t>(fp), np_ - 1);
  const double b = fp - static_cast<double>(ip);
  const std::size_t ip1 = ip + 1 == np_ ? 0 : ip + 1;
  const double keep = 1 - eps_;
  Mix x{};
  x.table[0] = it * np_ + ip;
  x.table[1] = it * np_ + ip1;
  x.table[2] = (it + 1) * np_ + ip;
  x.table[3] = (it + 1) * np_ + ip1;
  x.w[0] = keep * (1 - a) * (1 - b);
  x.w[1] = keep * (1 - a) * b;
  x.w[2] = keep * a * (1 - b);
  x.w[3] = keep * a * b;
  return x;
}

double VisibleNormalTables::coarse_probability(const Mix& x, std::size_t c) const {
  const std::size_t r = c / nc_, lo = row_lo_[r];
  if (c % nc_ < lo) return 0.0;
  const std::size_t col = c % nc_ - lo, cond = nc_ + row_off_[r];
  if (cond + col >= nc_ + row_off_[r + 1]) return 0.0;  // right of the row's span
  const double* q = q_cdf_.data();
  double p = eps_ * width(q, r) * width(q + cond, col);
  for (int k = 0; k < 4; ++k)
    if (x.w[k] > 0) {
      const float* t = &view_cdf_[x.table[k] * block_];
      p += x.w[k] * width(t, r) * width(t + cond, col);
    }
  return p;
}

Vec3 VisibleNormalTables::sample(const Mix& x, double u1, double u2) const {
  const std::size_t block = block_;
  // Component: view table k with probability w_k, else (probability eps) the plain Q.
  const float* cdf_k = nullptr;
  double lo = 0;
  for (int k = 0; k < 4; ++k) {
    if (x.w[k] > 0 && u1 < lo + x.w[k]) {
      cdf_k = &view_cdf_[x.table[k] * block];
      u1 = std::clamp((u1 - lo) / x.w[k], 0.0, std::nextafter(1.0, 0.0));
      break;
    }
    lo += x.w[k];
  }
  if (!cdf_k) u1 = std::clamp((u1 - lo) / (1 - lo), 0.0, std::nextafter(1.0, 0.0));
  // Coarse cell: row from u1, cell of the row from u2.
  double r1 = 0, r2 = 0;
  std::size_t row = 0, col = 0;
  if (cdf_k) {
    row = pick_counted(cdf_k, nc_, u1, r1, sorted_);
  } else {
    row = pick_counted(q_cdf_.data(), nc_, u1, r1, sorted_);
  }
  // (the row drawn has mass, so its span is not empty)
  const std::size_t cond = nc_ + row_off_[row], len = row_off_[row + 1] - row_off_[row];
  col = row_lo_[row] + (cdf_k ? pick_counted(cdf_k + cond, len, u2, r2, sorted_)
                              : pick_counted(&q_cdf_[cond], len, u2, r2, sorted_));
  const std::size_t c = row * nc_ + col;
  u2 = r2;
  const std::uint32_t b = offset_[c], e = offset_[c + 1];
  // The fine cell's corners are read right after the fine search: ask for the table's nodes of
  // the whole coarse cell now, together with the fine CDF and ids (one memory latency, not two).
  __builtin_prefetch(fine_id_.data() + b);
  {
    const std::size_t n = cells_ + 1, x_lo = (col * cells_ + nc_ - 1) / nc_,
                      x_hi = ((col + 1) * cells_ + nc_ - 1) / nc_,
                      y_lo = (row * cells_ + nc_ - 1) / nc_,
                      y_hi = ((row + 1) * cells_ + nc_ - 1) / nc_;
    const double* d = t_->values().data();
    for (std::size_t y = y_lo; y <= y_hi && y < n; ++y) {
      const char* p = reinterpret_cast<const char*>(d + y * n + x_lo);
      const char* end = reinterpret_cast<const char*>(d + y * n + std::min(x_hi, n - 1));
      for (; p <= end; p += 64) __builtin_prefetch(p);
      __builtin_prefetch(end);
    }
  }
  const std::size_t j =
      b + pick_counted(fine_cdf_.data() + b, e - b, u2, r2, sorted_);  // (e > b: C has mass)
  const std::size_t f = fine_id_[j], cx = f % cells_, cy = f / cells_;
  const TabulatedNdf& t = *t_;
  const double h = t.spacing(), a = t.at(cx, cy), bb = t.at(cx + 1, cy), cc = t.at(cx, cy + 1),
               d = t.at(cx + 1, cy + 1), x0 = t.node_x(cx), y0 = t.node_y(cy);
  for (int attempt = 0; attempt < kMaxTries; ++attempt) {
    double tx = 0, ty = 0;
    sample_bilinear(r1, r2, a, bb, cc, d, tx, ty);
    const double px = x0 + tx * h, py = y0 + ty * h, rr = px * px + py * py;
    if (rr < 1) return {px, py, std::sqrt(1 - rr)};
    // Outside the disk (a rim cell): redraw inside the same cell from numbers derived from
    // the inputs (sample stays a deterministic function of (v, u1, u2)).
    redraw_uniforms(r1, r2, attempt, 52);
  }
  // Practically unreachable (a cell with almost all of its mass outside the disk is drawn
  // with probability ~ its inside mass): the cell centre pulled inside the disk.
  return cell_centre_in_disk(x0, y0, h);
}

void VisibleNormalTables::prefetch(const Mix& x, std::size_t cx, std::size_t cy) const {
  const std::size_t c = coarse_of(cx, cy), r = c / nc_, cond = nc_ + row_off_[r];
  const std::size_t col = c % nc_ >= row_lo_[r] ? c % nc_ - row_lo_[r] : 0;
  __builtin_prefetch(&mass_[c]);
  for (int k = 0; k < 4; ++k)
    if (x.w[k] > 0) {
      const float* t = &view_cdf_[x.table[k] * block_];
      __builtin_prefetch(t + r);
      __builtin_prefetch(t + std::min(cond + col, block_ - 1));
    }
}

double VisibleNormalTables::pdf(const Vec3& v, const Vec3& m) const {
  const double len = m.norm();
  if (!(len > 0) || !(m.z() > 0)) return 0.0;
  const double px = m.x() / len, py = m.y() / len;
  const double e = t_->eval_disk(px, py);
  if (!(e > 0)) return 0.0;
  // The cell eval_disk used (same floor and clamp).
  const double inv = 1 / t_->spacing(), top = static_cast<double>(cells_ - 1);
  const double ox = t_->window().x0(), oy = t_->window().y0();  // the first node
  const auto cx = static_cast<std::size_t>(std::clamp(std::floor((px - ox) * inv), 0.0, top));
  const auto cy = static_cast<std::size_t>(std::clamp(std::floor((py - oy) * inv), 0.0, top));
  const std::size_t c = (cy * nc_ / cells_) * nc_ + cx * nc_ / cells_;
  if (!(mass_[c] > 0)) return 0.0;
  return coarse_probability(mix(v), c) * e / mass_[c] * (m.z() / len);
}

}  // namespace microbrdf::detail

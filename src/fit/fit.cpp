// Parametric NDF fits with Ceres (see include/microbrdf/fit.hpp and docs/fitting.md).
#include "microbrdf/fit.hpp"

#include <ceres/ceres.h>
#include <omp.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "core/helper_pool.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kThetaTiltMax = 1.2;  // rad, bound on theta_x, theta_y
constexpr double kAlphaMax = 4.0;
constexpr double kLogAmpMax = 3.0;

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

int shape_size(FitModel m) { return m == FitModel::Ellipsoid ? 5 : 3; }

// Shape parameter vector: (log alpha_x, log alpha_y, theta_x, theta_y, theta_z) for the
// ellipsoid, (log alpha_x, log alpha_y, theta_z) for Beckmann/GGX.
std::array<double, 5> to_shape(FitModel m, const EllipsoidParams& p) {
  if (m == FitModel::Ellipsoid)
    return {std::log(p.alpha_x), std::log(p.alpha_y), p.theta_x, p.theta_y, p.theta_z};
  return {std::log(p.alpha_x), std::log(p.alpha_y), p.theta_z, 0, 0};
}
EllipsoidParams from_shape(FitModel m, const double* s) {
  EllipsoidParams p;
  p.alpha_x = std::exp(s[0]);
  p.alpha_y = std::exp(s[1]);
  if (m == FitModel::Ellipsoid) {
    p.theta_x = s[2];
    p.theta_y = s[3];
    p.theta_z = s[4];
  } else {
    p.theta_z = s[2];
  }
  return p;
}

// Where a fit ended on a bound of its box ("" inside it): alphas (log) against [la_lo, la_hi],
// the ellipsoid's tilts against +-kThetaTiltMax, the node amplitude against +-kLogAmpMax.
std::string bound_note(FitModel m, const std::array<double, 5>& s, double la_lo, double la_hi,
                       bool amplitude_free, double log_amp) {
  constexpr double kTol = 1e-6;
  auto value = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.3g", v);
    return std::string(b);
  };
  auto which = [](bool x, bool y, const char* a, const char* b) {
    return std::string(" (") + (x && y ? std::string(a) + ", " + b : (x ? a : b)) + ")";
  };
  std::vector<std::string> notes;
  const bool lx = s[0] <= la_lo + kTol, ly = s[1] <= la_lo + kTol;
  if (lx || ly)
    notes.push_back("the lower alpha bound " + value(std::exp(la_lo)) +
                    which(lx, ly, "alpha_x", "alpha_y"));
  const bool hx = s[0] >= la_hi - kTol, hy = s[1] >= la_hi - kTol;
  if (hx || hy)
    notes.push_back("the upper alpha bound " + value(std::exp(la_hi)) +
                    which(hx, hy, "alpha_x", "alpha_y"));
  if (m == FitModel::Ellipsoid) {
    const bool tx = std::abs(s[2]) >= kThetaTiltMax - kTol,
               ty = std::abs(s[3]) >= kThetaTiltMax - kTol;
    if (tx || ty)
      notes.push_back("the tilt bound " + value(kThetaTiltMax) + " rad" +
                      which(tx, ty, "theta_x", "theta_y"));
  }
  if (amplitude_free && std::abs(log_amp) >= kLogAmpMax - kTol)
    notes.push_back("the amplitude bound exp(" + std::string(log_amp < 0 ? "-" : "") +
                    value(kLogAmpMax) + ")");
  std::string out;
  for (const auto& n : notes) out += (out.empty() ? "" : "; ") + n;
  return out;
}

// The three models as templates (T = double or a Ceres Jet), identical to microfacet.cpp's
// double versions (tested against them).
template <typename T>
struct ModelEval {
  FitModel kind;
  T m[3][3];  // ellipsoid: S^-1 R; Beckmann/GGX: rows 0, 1 = in-plane rotation Rz(theta_z)
  T norm;     // 1 / (pi ax ay ||A n||) (ellipsoid), 1 / (pi ax ay) otherwise
  T iax2, iay2;

  ModelEval(FitModel k, const T* s) : kind(k) {
    using std::cos;
    using std::exp;
    using std::sin;
    using std::sqrt;
    const T ax = exp(s[0]), ay = exp(s[1]);
    iax2 = T(1) / (ax * ax);
    iay2 = T(1) / (ay * ay);
    if (k == FitModel::Ellipsoid) {
      const T cx = cos(s[2]), sx = sin(s[2]), cy = cos(s[3]), sy = sin(s[3]), cz = cos(s[4]),
              sz = sin(s[4]);
      // R = Rx Ry Rz (active, right-handed), written out.
      T r[3][3];
      r[0][0] = cy * cz;
      r[0][1] = -cy * sz;
      r[0][2] = sy;
      r[1][0] = sx * sy * cz + cx * sz;
      r[1][1] = -sx * sy * sz + cx * cz;
      r[1][2] = -sx * cy;
      r[2][0] = -cx * sy * cz + sx * sz;
      r[2][1] = cx * sy * sz + sx * cz;
      r[2][2] = cx * cy;
      for (int j = 0; j < 3; ++j) {
        m[0][j] = r[0][j] / ax;
        m[1][j] = r[1][j] / ay;
        m[2][j] = r[2][j];
      }
      const T an =
          sqrt(ax * ax * r[0][2] * r[0][2] + ay * ay * r[1][2] * r[1][2] + r[2][2] * r[2][2]);
      norm = T(1) / (T(kPi) * ax * ay * an);
    } else {
      const T c = cos(s[2]), sn = sin(s[2]);
      m[0][0] = c;
      m[0][1] = -sn;
      m[1][0] = sn;
      m[1][1] = c;
      m[0][2] = m[1][2] = m[2][0] = m[2][1] = T(0);
      m[2][2] = T(1);
      norm = T(1) / (T(kPi) * ax * ay);
    }
  }

  // D(m) for a unit m with z > 0.
  T D(double x, double y, double z) const {
    using std::exp;
    if (kind == FitModel::Ellipsoid) {
      const T a = m[0][0] * x + m[0][1] * y + m[0][2] * z;
      const T b = m[1][0] * x + m[1][1] * y + m[1][2] * z;
      const T c = m[2][0] * x + m[2][1] * y + m[2][2] * z;
      const T q = a * a + b * b + c * c;
      return norm / (q * q);
    }
    const T u = m[0][0] * x + m[0][1] * y, v = m[1][0] * x + m[1][1] * y;
    if (kind == FitModel::Ggx) {
      const T q = u * u * iax2 + v * v * iay2 + T(z * z);
      return norm / (q * q);
    }
    const double z2 = z * z;
    return norm * exp(-(u * u * iax2 + v * v * iay2) / z2) / (z2 * z2);
  }
  T D_disk(double x, double y) const {
    const double r2 = x * x + y * y;
    return r2 < 1 ? D(x, y, std::sqrt(1 - r2)) : T(0);
  }
};

// Everything a residual needs: the region of interest, the transformed table, the forward
// operator.
struct FitContext {
  FitModel model = FitModel::Ellipsoid;
  FitObjective objective = FitObjective::Sqrt;
  bool tent = false;
  int s = 1;        // tent subsamples
  int threads = 1;  // for the solver's sums
  std::size_t n = 0;
  double delta = 0, eps = 0, lin_scale = 1;
  std::size_t ix0 = 0, ix1 = 0, iy0 = 0, iy1 = 0;
  std::vector<double> gt;  // g(T) on the ROI, row-major

  std::size_t cols() const { return ix1 - ix0 + 1; }
  std::size_t rows() const { return iy1 - iy0 + 1; }
  double ox = -1, oy = -1;  // the table's first node (its window's corner)
  double node_x(std::size_t i) const { return ox + delta * static_cast<double>(i); }
  double node_y(std::size_t i) const { return oy + delta * static_cast<double>(i); }

  template <typename T>
  T g(const T& d) const {
    using std::log;
    using std::sqrt;
    switch (objective) {
      case FitObjective::Sqrt:
        return sqrt(d + T(eps));
      case FitObjective::Log:
        return log(d + T(eps));
      case FitObjective::Linear:
        break;
    }
    return d * T(lin_scale);
  }
  double g0(double d) const { return g<double>(d); }

  // Model values of ROI row iy (absolute node index) into out[cols()].
  template <typename T>
  void row_values(const ModelEval<T>& me, std::size_t iy, T* out) const {
    const std::size_t nc = cols();
    const double y = node_y(iy);
    if (!tent) {
      for (std::size_t c = 0; c < nc; ++c) out[c] = me.D_disk(node_x(ix0 + c), y);
      return;
    }
    // Midpoint rule on the tent: 2s points per axis at offsets ((a + 1/2)/s - 1) Delta with
    // weights (1 - |offset|/Delta)/s (they sum to 1); sub-columns are shared by neighbours.
    const std::size_t ss = static_cast<std::size_t>(s);
    std::vector<double> w(2 * ss);
    for (std::size_t a = 0; a < 2 * ss; ++a) {
      const double u = (static_cast<double>(a) + 0.5) / s - 1.0;
      w[a] = (1.0 - std::abs(u)) / s;
    }
    const std::size_t nsub = ss * (nc + 1);
    std::vector<T> sub(nsub);
    const double h = delta / s, x0 = node_x(ix0) - delta + 0.5 * h;
    for (std::size_t c = 0; c < nc; ++c) out[c] = T(0);
    for (std::size_t b = 0; b < 2 * ss; ++b) {
      const double yb = y + ((static_cast<double>(b) + 0.5) / s - 1.0) * delta;
      for (std::size_t j = 0; j < nsub; ++j)
        sub[j] = me.D_disk(x0 + static_cast<double>(j) * h, yb);
      for (std::size_t c = 0; c < nc; ++c) {
        T acc = T(0);
        for (std::size_t a = 0; a < 2 * ss; ++a) acc += w[a] * sub[c * ss + a];
        out[c] += w[b] * acc;
      }
    }
  }

  template <typename T>
  void residuals(const T* shape, const T& amp, std::size_t iy, T* r) const {
    ModelEval<T> me(model, shape);
    const std::size_t nc = cols();
    std::vector<T> v(nc);
    row_values(me, iy, v.data());
    const double* gt_row = &gt[(iy - iy0) * nc];
    // NaN marks an unmeasured node (effective NDFs from measured BRDFs): no residual.
    for (std::size_t c = 0; c < nc; ++c)
      r[c] = std::isnan(gt_row[c]) ? T(0) : (g(v[c] * amp) - T(gt_row[c])) * T(delta);
  }

  // 1/2 sum r^2 in double; rows summed in order (the same number for any thread count).
  double cost(const double* shape, double amp) const {
    std::vector<double> per_row(rows(), 0.0);
    auto band = [&](std::size_t b) {
      std::vector<double> r(cols());
      for (std::size_t iy = iy0 + b * 8; iy <= iy1 && iy < iy0 + (b + 1) * 8; ++iy) {
        residuals<double>(shape, amp, iy, r.data());
        double t = 0;
        for (double x : r) t += x * x;
        per_row[iy - iy0] = t;
      }
    };
    const std::size_t bands = (rows() + 7) / 8;
    detail::HelperPool::instance().run(bands, rows() * cols() > 50000 ? threads : 1, band);
    double total = 0;
    for (double t : per_row) total += t;
    return 0.5 * total;
  }
  // Node mode: the amplitude that renormalises the point samples on the ROI.
  double node_amplitude(const double* shape) const {
    ModelEval<double> me(model, shape);
    double sum = 0;
    for (std::size_t iy = iy0; iy <= iy1; ++iy)
      for (std::size_t ix = ix0; ix <= ix1; ++ix) sum += me.D_disk(node_x(ix), node_y(iy));
    sum *= delta * delta;
    return sum > 0 ? 1.0 / sum : 1.0;
  }
};

// D(m) and its derivatives with respect to the shape parameters (log alpha_x, log alpha_y,
// [theta_x, theta_y,] theta_z) in closed form: the same model as ModelEval, for the solver's
// Jacobians (no automatic differentiation in the hot loop).
struct ModelGrad {
  FitModel kind = FitModel::Ellipsoid;
  int k = 5;                // shape parameters
  double m[3][3] = {};      // as ModelEval
  double dm[3][3][3] = {};  // ellipsoid: d m / d theta_{x,y,z}
  double norm = 0, iax2 = 0, iay2 = 0;
  double dln[5] = {};  // ellipsoid: d log(norm) / d shape

  ModelGrad(FitModel kd, const double* s) : kind(kd), k(shape_size(kd)) {
    const double ax = std::exp(s[0]), ay = std::exp(s[1]);
    iax2 = 1 / (ax * ax);
    iay2 = 1 / (ay * ay);
    if (kd != FitModel::Ellipsoid) {
      const double c = std::cos(s[2]), sn = std::sin(s[2]);
      m[0][0] = c;
      m[0][1] = -sn;
      m[1][0] = sn;
      m[1][1] = c;
      m[2][2] = 1;
      norm = 1 / (kPi * ax * ay);
      return;
    }
    const double cx = std::cos(s[2]), sx = std::sin(s[2]), cy = std::cos(s[3]), sy = std::sin(s[3]),
                 cz = std::cos(s[4]), sz = std::sin(s[4]);
    const double r[3][3] = {{cy * cz, -cy * sz, sy},
                            {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy},
                            {-cx * sy * cz + sx * sz, cx * sy * sz + sx * cz, cx * cy}};
    const double dr[3][3][3] = {// d/d theta_x
                                {{0, 0, 0},
                                 {cx * sy * cz - sx * sz, -cx * sy * sz - sx * cz, -cx * cy},
                                 {sx * sy * cz + cx * sz, -sx * sy * sz + cx * cz, -sx * cy}},
                                // d/d theta_y
                                {{-sy * cz, sy * sz, cy},
                                 {sx * cy * cz, -sx * cy * sz, sx * sy},
                                 {-cx * cy * cz, cx * cy * sz, -cx * sy}},
                                // d/d theta_z
                                {{-cy * sz, -cy * cz, 0},
                                 {-sx * sy * sz + cx * cz, -sx * sy * cz - cx * sz, 0},
                                 {cx * sy * sz + sx * cz, cx * sy * cz - sx * sz, 0}}};
    const double sc[3] = {1 / ax, 1 / ay, 1};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) {
        m[i][j] = r[i][j] * sc[i];
        for (int t = 0; t < 3; ++t) dm[t][i][j] = dr[t][i][j] * sc[i];
      }
    const double an2 =
        ax * ax * r[0][2] * r[0][2] + ay * ay * r[1][2] * r[1][2] + r[2][2] * r[2][2];
    norm = 1 / (kPi * ax * ay * std::sqrt(an2));
    dln[0] = -1 - ax * ax * r[0][2] * r[0][2] / an2;
    dln[1] = -1 - ay * ay * r[1][2] * r[1][2] / an2;
    for (int t = 0; t < 3; ++t)
      dln[2 + t] = -(ax * ax * r[0][2] * dr[t][0][2] + ay * ay * r[1][2] * dr[t][1][2] +
                     r[2][2] * dr[t][2][2]) /
                   an2;
  }

  // D at the unit vector (x, y, z), z > 0, and g[0..k-1] = dD / d shape.
  double eval(double x, double y, double z, double* g) const {
    switch (kind) {
      case FitModel::Ellipsoid:
        return eval_model<FitModel::Ellipsoid>(x, y, z, g);
      case FitModel::Beckmann:
        return eval_model<FitModel::Beckmann>(x, y, z, g);
      case FitModel::Ggx:
        break;
    }
    return eval_model<FitModel::Ggx>(x, y, z, g);
  }
  template <FitModel M>
  double eval_model(double x, double y, double z, double* g) const {
    if constexpr (M == FitModel::Ellipsoid) {
      const double a = m[0][0] * x + m[0][1] * y + m[0][2] * z;
      const double b = m[1][0] * x + m[1][1] * y + m[1][2] * z;
      const double c = m[2][0] * x + m[2][1] * y + m[2][2] * z;
      const double q = a * a + b * b + c * c;
      const double d = norm / (q * q), iq = 1 / q;
      g[0] = d * (dln[0] + 4 * a * a * iq);
      g[1] = d * (dln[1] + 4 * b * b * iq);
      for (int t = 0; t < 3; ++t) {
        const double da = dm[t][0][0] * x + dm[t][0][1] * y + dm[t][0][2] * z;
        const double db = dm[t][1][0] * x + dm[t][1][1] * y + dm[t][1][2] * z;
        const double dc = dm[t][2][0] * x + dm[t][2][1] * y + dm[t][2][2] * z;
        g[2 + t] = d * (dln[2 + t] - 4 * (a * da + b * db + c * dc) * iq);
      }
      return d;
    }
    const double u = m[0][0] * x + m[0][1] * y, v = m[1][0] * x + m[1][1] * y;
    const double uu = u * u * iax2, vv = v * v * iay2, uv = u * v * (iay2 - iax2);
    if constexpr (M == FitModel::Ggx) {
      const double q = uu + vv + z * z;
      const double d = norm / (q * q), iq = 1 / q;
      g[0] = d * (4 * uu * iq - 1);
      g[1] = d * (4 * vv * iq - 1);
      g[2] = -4 * d * uv * iq;
      return d;
    }
    const double z2 = z * z, iz2 = 1 / z2;
    const double d = norm * std::exp(-(uu + vv) * iz2) / (z2 * z2);
    g[0] = d * (2 * uu * iz2 - 1);
    g[1] = d * (2 * vv * iz2 - 1);
    g[2] = -2 * d * uv * iz2;
    return d;
  }
  double eval_disk(double x, double y, double* g) const {
    const double r2 = x * x + y * y;
    if (r2 < 1) return eval(x, y, std::sqrt(1 - r2), g);
    for (int i = 0; i < k; ++i) g[i] = 0;
    return 0;
  }
};

// Normal equations of the Gauss-Newton model at one point: J^T J, J^T r (columns: the shape
// parameters, then log amplitude) and the cost 1/2 r^T r.
struct NormalEq {
  int n = 0;
  double jtj[6][6] = {}, jtr[6] = {}, cost = 0;
  void add(const NormalEq& o) {
    for (int i = 0; i < n; ++i) {
      jtr[i] += o.jtr[i];
      for (int j = 0; j < n; ++j) jtj[i][j] += o.jtj[i][j];
    }
    cost += o.cost;
  }
};

// Residuals r = (g(amp v) - g(T)) Delta of the fit context, with their Jacobian, summed into
// normal equations row by row (each row's sums in a fixed order, rows folded in order: the same
// numbers whatever the thread count). v: the model as compared (node value or tent average).
template <int K, FitModel M>
NormalEq normal_equations_k(const FitContext& c, const double* shape, double log_amp) {
  const ModelGrad mg(M, shape);
  constexpr int k = K, np = K + 1;
  const double amp = std::exp(log_amp);
  const std::size_t nc = c.cols(), nr = c.rows();
  const std::size_t ss = c.tent ? static_cast<std::size_t>(c.s) : 1;
  // Tent mode: row iy averages the 2s sub-rows at y + ((b + 1/2)/s - 1) Delta, b < 2s; the
  // last s of them are the first s of the next row, so each sub-row (global index j, its y
  // computed from j alone) is evaluated once per band of rows. Node mode: one sub-row per row,
  // at the nodes.
  const std::size_t nsub = c.tent ? ss * (nc + 1) : nc;
  const std::size_t ring = c.tent ? 2 * ss : 1;
  const double h = c.delta / static_cast<double>(ss);
  const double x0 = c.tent ? c.node_x(c.ix0) - c.delta + 0.5 * h : c.node_x(c.ix0);
  const double y0 = c.tent ? c.node_y(c.iy0) - c.delta + 0.5 * h : c.node_y(c.iy0);
  std::vector<double> w(2 * ss, 1.0);
  if (c.tent)
    for (std::size_t a = 0; a < 2 * ss; ++a) {
      const double u = (static_cast<double>(a) + 0.5) / c.s - 1.0;
      w[a] = (1.0 - std::abs(u)) / c.s;
    }
  std::vector<NormalEq> rows(nr);
  // Bands of contiguous rows (neighbouring rows share their sub-rows) on the helper pool.
  const std::size_t bands = std::max<std::size_t>(
      1, std::min<std::size_t>(nr, 4 * static_cast<std::size_t>(std::max(1, c.threads))));
  auto band = [&](std::size_t bi) {
    // Ring of sub-rows: value then the K derivatives, nsub each.
    std::vector<double> buf(ring * nsub * (K + 1));
    std::vector<long> held(ring, -1);
    std::vector<double> val(nc), grad(nc * K);
    auto sub_row = [&](std::size_t j) -> const double* {
      double* out = &buf[(j % ring) * nsub * (K + 1)];
      if (held[j % ring] == static_cast<long>(j)) return out;
      held[j % ring] = static_cast<long>(j);
      const double y = y0 + static_cast<double>(j) * h;
      double g[5];
      for (std::size_t i = 0; i < nsub; ++i) {
        const double x = x0 + static_cast<double>(i) * h;
        const double r2 = x * x + y * y;
        double d = 0;
        if (r2 < 1) {
          d = mg.eval_model<M>(x, y, std::sqrt(1 - r2), g);
        } else {
          for (int p = 0; p < K; ++p) g[p] = 0;
        }
        out[i] = d;
        for (int p = 0; p < K; ++p) out[(static_cast<std::size_t>(p) + 1) * nsub + i] = g[p];
      }
      return out;
    };
    const std::size_t r0 = nr * bi / bands, r1 = nr * (bi + 1) / bands;
    for (std::size_t ri = r0; ri < r1; ++ri) {
      if (!c.tent) {
        const double* sr = sub_row(ri);
        for (std::size_t col = 0; col < nc; ++col) {
          val[col] = sr[col];
          for (int p = 0; p < K; ++p)
            grad[col * K + static_cast<std::size_t>(p)] =
                sr[(static_cast<std::size_t>(p) + 1) * nsub + col];
        }
      } else {
        std::fill(val.begin(), val.end(), 0.0);
        std::fill(grad.begin(), grad.end(), 0.0);
        for (std::size_t b = 0; b < 2 * ss; ++b) {
          const double* sr = sub_row(ri * ss + b);
          for (std::size_t col = 0; col < nc; ++col) {
            double acc = 0, ga[K] = {};
            for (std::size_t a = 0; a < 2 * ss; ++a) {
              const std::size_t i = col * ss + a;
              acc += w[a] * sr[i];
              for (int p = 0; p < K; ++p)
                ga[p] += w[a] * sr[(static_cast<std::size_t>(p) + 1) * nsub + i];
            }
            val[col] += w[b] * acc;
            for (int p = 0; p < K; ++p) grad[col * K + static_cast<std::size_t>(p)] += w[b] * ga[p];
          }
        }
      }
      NormalEq e;
      e.n = np;
      const double* gt_row = &c.gt[ri * nc];
      for (std::size_t col = 0; col < nc; ++col) {
        if (std::isnan(gt_row[col])) continue;  // unmeasured node: no residual
        const double d = val[col] * amp;
        double gv = 0, dg = 0;  // g(d) and g'(d)
        switch (c.objective) {
          case FitObjective::Sqrt:
            gv = std::sqrt(d + c.eps);
            dg = 0.5 / gv;
            break;
          case FitObjective::Log:
            gv = std::log(d + c.eps);
            dg = 1 / (d + c.eps);
            break;
          case FitObjective::Linear:
            gv = d * c.lin_scale;
            dg = c.lin_scale;
            break;
        }
        const double r = (gv - gt_row[col]) * c.delta;
        double j[np];
        const double f = dg * amp * c.delta;
        for (int p = 0; p < k; ++p) j[p] = f * grad[col * K + static_cast<std::size_t>(p)];
        j[k] = dg * d * c.delta;
        for (int p = 0; p < np; ++p) {
          e.jtr[p] += j[p] * r;
          for (int q = 0; q <= p; ++q) e.jtj[p][q] += j[p] * j[q];
        }
        e.cost += r * r;
      }
      rows[ri] = e;
    }
  };
  detail::HelperPool::instance().run(bands, c.threads, band);
  NormalEq total;
  total.n = np;
  for (const auto& e : rows) total.add(e);
  for (int p = 0; p < np; ++p)
    for (int q = 0; q < p; ++q) total.jtj[q][p] = total.jtj[p][q];
  total.cost *= 0.5;
  return total;
}
NormalEq normal_equations(const FitContext& c, const double* shape, double log_amp) {
  switch (c.model) {
    case FitModel::Ellipsoid:
      return normal_equations_k<5, FitModel::Ellipsoid>(c, shape, log_amp);
    case FitModel::Beckmann:
      return normal_equations_k<3, FitModel::Beckmann>(c, shape, log_amp);
    case FitModel::Ggx:
      break;
  }
  return normal_equations_k<3, FitModel::Ggx>(c, shape, log_amp);
}

// Levenberg-Marquardt on the normal equations above, with box bounds by projection: the
// solver's stopping rules are those given to Ceres before (relative cost change 1e-13,
// gradient 1e-14, relative step 1e-11). x: shape then log amplitude (fixed when !amp_free).
struct LmResult {
  int iterations = 0;
  bool converged = false;
  std::string message;
  double cost = 0, initial_cost = 0;
};
LmResult levenberg_marquardt(const FitContext& c, double* x, bool amp_free, const double* lo,
                             const double* hi, int max_iterations) {
  const int k = shape_size(c.model), np = k + 1, nf = amp_free ? np : k;
  LmResult out;
  NormalEq e = normal_equations(c, x, x[k]);
  out.initial_cost = e.cost;
  double lambda = 1e-4;
  // The histogram residuals do not vanish at the optimum, so Gauss-Newton alone converges only
  // linearly there. S approximates the rest of the Hessian, sum r_i grad^2 r_i, by the
  // structured secant update of Dennis, Gay and Welsch (NL2SOL): after each accepted step s,
  // S s = y#, y# = (J+^T r+ - J^T r) - J+^T J+ s. Steps solve (J^T J + tau S + lambda D) d = -g.
  Eigen::MatrixXd sm = Eigen::MatrixXd::Zero(nf, nf);
  int rejected_in_row = 0;
  out.message = "no iterations";
  for (int it = 0; it < max_iterations; ++it) {
    ++out.iterations;
    Eigen::MatrixXd jtj(nf, nf);
    Eigen::VectorXd g(nf);
    double gmax = 0;
    for (int p = 0; p < nf; ++p) {
      g(p) = e.jtr[p];
      // Projected gradient: a bound that blocks the descent direction does not count.
      const bool blocked = (x[p] <= lo[p] && e.jtr[p] > 0) || (x[p] >= hi[p] && e.jtr[p] < 0);
      if (!blocked) gmax = std::max(gmax, std::abs(e.jtr[p]));
      for (int q = 0; q < nf; ++q) jtj(p, q) = e.jtj[p][q];
    }
    if (gmax <= 1e-14) {
      out.converged = true;
      out.message = "Gradient tolerance reached.";
      break;
    }
    // Active set: a parameter on a bound whose descent direction leaves the box is held there
    // for this step (the reduced system is solved for the others).
    std::vector<int> fr;
    for (int p = 0; p < nf; ++p) {
      const bool blocked = (x[p] <= lo[p] && e.jtr[p] > 0) || (x[p] >= hi[p] && e.jtr[p] < 0);
      if (!blocked) fr.push_back(p);
    }
    const int nr = static_cast<int>(fr.size());
    Eigen::MatrixXd a(nr, nr), ag(nr, nr);
    Eigen::VectorXd gr(nr);
    for (int i = 0; i < nr; ++i) {
      gr(i) = g(fr[static_cast<std::size_t>(i)]);
      for (int j = 0; j < nr; ++j) {
        const int p = fr[static_cast<std::size_t>(i)], q = fr[static_cast<std::size_t>(j)];
        ag(i, j) = jtj(p, q);
        a(i, j) = jtj(p, q) + sm(p, q);
      }
      const int p = fr[static_cast<std::size_t>(i)];
      a(i, i) += lambda * std::max(e.jtj[p][p], 1e-30);
      ag(i, i) += lambda * std::max(e.jtj[p][p], 1e-30);
    }
    Eigen::LDLT<Eigen::MatrixXd> ldlt(a);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0)) {
      sm.setZero();  // the secant term made the model indefinite: Gauss-Newton again
      ldlt.compute(ag);
    }
    const Eigen::VectorXd sr = ldlt.solve(-gr);
    Eigen::VectorXd step = Eigen::VectorXd::Zero(nf);
    for (int i = 0; i < nr; ++i) step(fr[static_cast<std::size_t>(i)]) = sr(i);
    double xn[6];
    double step_norm = 0, x_norm = 0;
    for (int p = 0; p < np; ++p) {
      xn[p] = x[p];
      if (p < nf) xn[p] = std::clamp(x[p] + step(p), lo[p], hi[p]);
      step_norm += (xn[p] - x[p]) * (xn[p] - x[p]);
      x_norm += x[p] * x[p];
    }
    if (std::sqrt(step_norm) <= 1e-11 * (std::sqrt(x_norm) + 1e-11)) {
      out.converged = true;
      out.message = "Parameter tolerance reached.";
      break;
    }
    const NormalEq en = normal_equations(c, xn, xn[k]);
    if (std::isfinite(en.cost) && en.cost < e.cost) {
      const double change = (e.cost - en.cost) / e.cost;
      // Secant update of S (symmetric; skipped when the curvature along s is not positive).
      Eigen::VectorXd sv(nf), y(nf), jn_s(nf);
      for (int p = 0; p < nf; ++p) {
        sv(p) = xn[p] - x[p];
        y(p) = en.jtr[p] - e.jtr[p];
      }
      for (int p = 0; p < nf; ++p) {
        jn_s(p) = 0;
        for (int q = 0; q < nf; ++q) jn_s(p) += en.jtj[p][q] * sv(q);
      }
      const double ys = y.dot(sv);
      if (ys > 0) {
        // Size S down when it overstates the curvature along s (NL2SOL's tau).
        const double sss = sv.dot(sm * sv);
        const Eigen::VectorXd ysharp = y - jn_s;
        if (sss > 0) sm *= std::min(1.0, std::abs(sv.dot(ysharp)) / sss);
        const Eigen::VectorXd rr = ysharp - sm * sv;
        sm += (rr * y.transpose() + y * rr.transpose()) / ys -
              (rr.dot(sv) / (ys * ys)) * (y * y.transpose());
      }
      std::copy(xn, xn + np, x);
      e = en;
      lambda = std::max(lambda / 3, 1e-12);
      rejected_in_row = 0;
      if (change <= 1e-13) {
        out.converged = true;
        out.message = "Function tolerance reached.";
        break;
      }
    } else {
      lambda *= 4;
      if (++rejected_in_row >= 2) sm.setZero();
      if (lambda > 1e16) {
        out.converged = true;
        out.message = "No further decrease of the cost.";
        break;
      }
    }
    if (it + 1 == max_iterations) out.message = "Maximum number of iterations reached.";
  }
  out.cost = e.cost;
  return out;
}

template <int K>
struct RowCost {
  const FitContext* ctx;
  std::size_t iy;
  template <typename T>
  bool operator()(const T* shape, const T* log_amp, T* r) const {
    using std::exp;
    T s5[5] = {T(0), T(0), T(0), T(0), T(0)};  // ModelEval reads five entries
    for (int i = 0; i < K; ++i) s5[i] = shape[i];
    ctx->residuals(s5, T(exp(log_amp[0])), iy, r);
    return true;
  }
};

// Effective NDFs inferred from measured BRDFs (Dong eq. 9): absolute, not renormalised, NaN where
// nothing was measured.
bool measured_table(const TabulatedNdf& t) {
  if (lower(t.meta.method) == "measured") return true;
  for (double v : t.values())
    if (std::isnan(v)) return true;
  return false;
}

// Point samples (analytic models, Kirchhoff, measured): the sampling the table records, or the
// one inferred from its method when the file predates the record.
bool point_sampled(const TabulatedNdf& t) { return ndf_sampling(t.meta) == "point"; }

FitContext make_context(const TabulatedNdf& t, const FitOptions& o, const EllipsoidParams& start) {
  FitContext c;
  c.model = o.model;
  c.objective = o.objective;
  c.threads = o.threads > 0 ? o.threads : omp_get_max_threads();
  c.n = t.resolution();
  c.delta = t.spacing();
  c.ox = t.window().x0();
  c.oy = t.window().y0();
  FitSampling smp = o.sampling;
  const bool measured = measured_table(t);
  if (smp == FitSampling::Auto)
    smp = point_sampled(t) || measured ? FitSampling::Node : FitSampling::Tent;
  c.tent = smp == FitSampling::Tent;
  if (c.tent) {
    int s = o.tent_subsamples;
    if (s <= 0) {
      const double amin = std::min(start.alpha_x, start.alpha_y);
      s = static_cast<int>(std::ceil(4 * c.delta / std::max(amin, 1e-12)));
    }
    c.s = std::clamp(s, 1, 8);
  }
  const auto& v = t.values();
  double vmax = 0;
  for (double x : v) vmax = std::max(vmax, x);
  if (!(vmax > 0) || !std::isfinite(vmax))
    throw InputError("the NDF table is empty (no positive finite value); nothing to fit");
  c.eps = o.floor * vmax;
  // (On a zoomed table one sample's value is 1 / (samples inside the window Delta^2).)
  if (t.meta.samples_used > 0 && !point_sampled(t) && !measured)
    c.eps =
        std::max(c.eps, 0.375 / (static_cast<double>(t.meta.samples_used) *
                                 std::clamp(t.meta.window_mass, 1e-6, 1.0) * c.delta * c.delta));
  c.lin_scale = 1.0 / std::sqrt(vmax);
  // Region of interest: the box of nodes above roi_threshold * max, widened.
  const double thr = o.roi_threshold * vmax;
  std::size_t x0 = c.n, x1 = 0, y0 = c.n, y1 = 0;
  for (std::size_t iy = 0; iy < c.n; ++iy)
    for (std::size_t ix = 0; ix < c.n; ++ix)
      if (t.at(ix, iy) > thr) {
        x0 = std::min(x0, ix);
        x1 = std::max(x1, ix);
        y0 = std::min(y0, iy);
        y1 = std::max(y1, iy);
      }
  const std::size_t margin = 6;
  c.ix0 = x0 > margin ? x0 - margin : 0;
  c.iy0 = y0 > margin ? y0 - margin : 0;
  c.ix1 = std::min(c.n - 1, x1 + margin);
  c.iy1 = std::min(c.n - 1, y1 + margin);
  c.gt.resize(c.rows() * c.cols());
  for (std::size_t iy = c.iy0; iy <= c.iy1; ++iy)
    for (std::size_t ix = c.ix0; ix <= c.ix1; ++ix)
      c.gt[(iy - c.iy0) * c.cols() + (ix - c.ix0)] =
          std::isnan(t.at(ix, iy)) ? t.at(ix, iy) : c.g0(std::max(0.0, t.at(ix, iy)));
  return c;
}

void canonicalise(FitModel m, EllipsoidParams& p) {
  // A spheroid (alpha_x == alpha_y) depends on its axis R^T z only: A^T A = a^2 I + (1 - a^2)
  // (R^T z)(R^T z)^T, so theta_z is free; report theta_z = 0 and the tilt of that axis.
  if (m == FitModel::Ellipsoid &&
      std::abs(p.alpha_x - p.alpha_y) <= 1e-6 * std::max(p.alpha_x, p.alpha_y)) {
    const Eigen::Vector3d axis =
        (rotation_x(p.theta_x) * rotation_y(p.theta_y) * rotation_z(p.theta_z)).transpose() *
        Eigen::Vector3d(0, 0, 1);
    const Eigen::Vector3d w = axis.z() < 0 ? Eigen::Vector3d(-axis) : axis;
    p.theta_x = std::asin(std::clamp(w.y(), -1.0, 1.0));
    p.theta_y = std::atan2(-w.x(), w.z());
    p.theta_z = 0;
    return;
  }
  // theta_z into (-pi/2, pi/2]; for the ellipsoid (tx, ty, tz) == (-tx, -ty, tz + pi).
  const double k = std::ceil((p.theta_z - kPi / 2) / kPi);
  p.theta_z -= k * kPi;
  if (p.theta_z <= -kPi / 2) p.theta_z += kPi;
  if (m == FitModel::Ellipsoid && static_cast<long long>(std::llround(k)) % 2 != 0) {
    p.theta_x = -p.theta_x;
    p.theta_y = -p.theta_y;
  }
  if (m != FitModel::Ellipsoid) p.theta_x = p.theta_y = 0;
}

// Nelder-Mead on the same objective (reference solver; bounds by clamping).
int nelder_mead(const std::function<double(const std::vector<double>&)>& f, std::vector<double>& x,
                const std::vector<double>& step, int max_evals, double& fbest, bool& converged) {
  converged = false;
  const std::size_t n = x.size();
  std::vector<std::vector<double>> pts(n + 1, x);
  std::vector<double> fv(n + 1);
  for (std::size_t i = 0; i < n; ++i) pts[i + 1][i] += step[i];
  int evals = 0;
  for (std::size_t i = 0; i <= n; ++i) {
    fv[i] = f(pts[i]);
    ++evals;
  }
  int iter = 0;
  while (evals < max_evals) {
    ++iter;
    std::vector<std::size_t> idx(n + 1);
    for (std::size_t i = 0; i <= n; ++i) idx[i] = i;
    std::sort(idx.begin(), idx.end(), [&](std::size_t a, std::size_t b) { return fv[a] < fv[b]; });
    const std::size_t best = idx[0], worst = idx[n], second = idx[n - 1];
    double spread = 0;  // simplex size in parameter units (log alpha, rad)
    for (std::size_t i = 0; i <= n; ++i)
      for (std::size_t j = 0; j < n; ++j)
        spread = std::max(spread, std::abs(pts[i][j] - pts[best][j]));
    if (spread < 1e-8) {
      converged = true;
      break;
    }
    std::vector<double> cen(n, 0.0);
    for (std::size_t i = 0; i <= n; ++i)
      if (i != worst)
        for (std::size_t j = 0; j < n; ++j) cen[j] += pts[i][j] / static_cast<double>(n);
    auto along = [&](double t) {
      std::vector<double> p(n);
      for (std::size_t j = 0; j < n; ++j) p[j] = cen[j] + t * (pts[worst][j] - cen[j]);
      return p;
    };
    auto xr = along(-1);
    const double fr = f(xr);
    ++evals;
    if (fr < fv[best]) {
      auto xe = along(-2);
      const double fe = f(xe);
      ++evals;
      if (fe < fr) {
        pts[worst] = xe;
        fv[worst] = fe;
      } else {
        pts[worst] = xr;
        fv[worst] = fr;
      }
    } else if (fr < fv[second]) {
      pts[worst] = xr;
      fv[worst] = fr;
    } else {
      auto xc = fr < fv[worst] ? along(-0.5) : along(0.5);
      const double fc = f(xc);
      ++evals;
      if (fc < std::min(fr, fv[worst])) {
        pts[worst] = xc;
        fv[worst] = fc;
      } else {
        for (std::size_t i = 0; i <= n; ++i)
          if (i != best) {
            for (std::size_t j = 0; j < n; ++j)
              pts[i][j] = pts[best][j] + 0.5 * (pts[i][j] - pts[best][j]);
            fv[i] = f(pts[i]);
            ++evals;
          }
      }
    }
  }
  const std::size_t b =
      static_cast<std::size_t>(std::min_element(fv.begin(), fv.end()) - fv.begin());
  x = pts[b];
  fbest = fv[b];
  return iter;
}

}  // namespace

FitModel parse_fit_model(const std::string& name) {
  const std::string m = lower(name);
  if (m == "ellipsoid") return FitModel::Ellipsoid;
  if (m == "beckmann") return FitModel::Beckmann;
  if (m == "ggx" || m == "trowbridge-reitz" || m == "gtr2") return FitModel::Ggx;
  throw InputError("unknown model '" + name + "' (ellipsoid | beckmann | ggx)");
}
std::string fit_model_name(FitModel m) {
  switch (m) {
    case FitModel::Ellipsoid:
      return "ellipsoid";
    case FitModel::Beckmann:
      return "beckmann";
    case FitModel::Ggx:
      break;
  }
  return "ggx";
}
FitObjective parse_fit_objective(const std::string& name) {
  const std::string m = lower(name);
  if (m == "sqrt") return FitObjective::Sqrt;
  if (m == "linear") return FitObjective::Linear;
  if (m == "log") return FitObjective::Log;
  throw InputError("unknown objective '" + name + "' (sqrt | linear | log)");
}
std::string fit_objective_name(FitObjective o) {
  return o == FitObjective::Sqrt ? "sqrt" : o == FitObjective::Linear ? "linear" : "log";
}
FitSampling parse_fit_sampling(const std::string& name) {
  const std::string m = lower(name);
  if (m == "auto") return FitSampling::Auto;
  if (m == "node") return FitSampling::Node;
  if (m == "tent") return FitSampling::Tent;
  throw InputError("unknown sampling '" + name + "' (auto | node | tent)");
}
std::string fit_sampling_name(FitSampling s) {
  return s == FitSampling::Auto ? "auto" : s == FitSampling::Node ? "node" : "tent";
}

EllipsoidParams initial_guess(const TabulatedNdf& ndf, FitModel model) {
  const Eigen::Matrix2d c = ndf.slope_covariance();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(c);
  const Eigen::Vector2d ev = es.eigenvalues();
  const Eigen::Matrix2d vec = es.eigenvectors();
  // The alpha_x axis: the eigenvector nearer +x.
  const int ix = std::abs(vec(0, 0)) >= std::abs(vec(0, 1)) ? 0 : 1;
  const Eigen::Vector2d ax = vec.col(ix);
  double phi = std::atan2(ax.y(), ax.x());
  if (phi > kPi / 2) phi -= kPi;
  if (phi <= -kPi / 2) phi += kPi;
  EllipsoidParams p;
  auto width = [&](double lambda) {
    return std::clamp(std::sqrt(2 * std::max(lambda, 0.0)), 0.25 * ndf.spacing(), kAlphaMax);
  };
  p.alpha_x = width(ev(ix));
  p.alpha_y = width(ev(1 - ix));
  p.theta_z = -phi;
  if (model == FitModel::Ellipsoid) {
    const Eigen::Vector3d mu = ndf.mean_normal();
    const Eigen::Vector3d w = rotation_z(p.theta_z) * mu;
    p.theta_x = std::asin(std::clamp(w.y(), -1.0, 1.0));
    p.theta_y = std::atan2(-w.x(), w.z());
  }
  return p;
}

double fit_objective(const TabulatedNdf& ndf, const FitOptions& o, const EllipsoidParams& p,
                     double amplitude) {
  const FitContext c = make_context(ndf, o, p);
  const auto s = to_shape(o.model, p);
  return c.cost(s.data(), c.tent ? 1.0 : amplitude);
}

namespace {

FitResult fit_ndf_single(const TabulatedNdf& ndf, const FitOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  if (ndf.resolution() < 5) throw InputError("NDF table too small to fit");
  // Moments for the starting point come from the measured nodes only (NaN -> 0).
  EllipsoidParams start;
  if (o.initial) {
    start = *o.initial;
  } else if (measured_table(ndf)) {
    TabulatedNdf filled = ndf;
    for (double& v : filled.values())
      if (!(v > 0)) v = 0;
    start = initial_guess(filled, o.model);
  } else {
    start = initial_guess(ndf, o.model);
  }
  if (o.model != FitModel::Ellipsoid) start.theta_x = start.theta_y = 0;
  const double alpha_min = std::max(1e-5, ndf.spacing() / 20);
  start.alpha_x = std::clamp(start.alpha_x, alpha_min, kAlphaMax);
  start.alpha_y = std::clamp(start.alpha_y, alpha_min, kAlphaMax);

  FitContext ctx = make_context(ndf, o, start);
  const int k = shape_size(o.model);
  std::array<double, 5> shape = to_shape(o.model, start);
  double log_amp = 0;
  // Multi-start on the scale of both alphas (moments of heavy-tailed tables overestimate).
  if (!o.initial) {
    double best = std::numeric_limits<double>::infinity();
    std::array<double, 5> best_shape = shape;
    for (double f : {1.0, 0.7, 0.5, 0.35, 0.25, 0.18, 0.125}) {
      std::array<double, 5> s = shape;
      s[0] = std::max(std::log(alpha_min), s[0] + std::log(f));
      s[1] = std::max(std::log(alpha_min), s[1] + std::log(f));
      const double amp = ctx.tent ? 1.0 : ctx.node_amplitude(s.data());
      const double cst = ctx.cost(s.data(), amp);
      if (cst < best) {
        best = cst;
        best_shape = s;
      }
    }
    shape = best_shape;
    start = from_shape(o.model, shape.data());
    if (ctx.tent && o.tent_subsamples <= 0) ctx = make_context(ndf, o, start);  // subsamples
  }
  if (!ctx.tent) log_amp = std::log(ctx.node_amplitude(shape.data()));

  FitResult r;
  r.model = o.model;
  r.initial = start;
  r.objective = o.objective;
  r.sampling = ctx.tent ? FitSampling::Tent : FitSampling::Node;
  r.window = ndf.window();
  r.table_sampling = ndf_sampling(ndf.meta);
  r.table_sampling_recorded = ndf_sampling_recorded(ndf.meta);
  r.tent_subsamples = ctx.tent ? ctx.s : 1;
  r.floor = ctx.eps;
  r.residuals = ctx.rows() * ctx.cols();
  r.roi[0] = ctx.ix0;
  r.roi[1] = ctx.ix1;
  r.roi[2] = ctx.iy0;
  r.roi[3] = ctx.iy1;
  // (The library's solver reports the cost of its first evaluation instead: the same number.)
  if (o.solver != FitSolver::LevenbergMarquardt)
    r.initial_cost = ctx.cost(shape.data(), std::exp(log_amp));

  const double la_hi = std::log(kAlphaMax);
  double la_final = std::log(alpha_min);  // the lower alpha bound of the last pass
  // Tent mode resolves lobes down to ~2 quadrature steps: alpha >= 2 Delta / s. A fit that ends
  // on that bound is repeated with twice the subsamples (up to 8).
  for (int pass = 0;; ++pass) {
    const double la_lo =
        std::log(ctx.tent ? std::max(alpha_min, 2 * ctx.delta / ctx.s) : alpha_min);
    la_final = la_lo;
    shape[0] = std::max(shape[0], la_lo);
    shape[1] = std::max(shape[1], la_lo);
    if (o.solver == FitSolver::LevenbergMarquardt) {
      double x[6], lo[6], hi[6];
      for (int i = 0; i < k; ++i) {
        x[i] = shape[static_cast<std::size_t>(i)];
        lo[i] = i < 2 ? la_lo : -kThetaTiltMax;
        hi[i] = i < 2 ? la_hi : kThetaTiltMax;
      }
      if (k == 3 || k == 5) {  // theta_z: free
        lo[k - 1] = -std::numeric_limits<double>::infinity();
        hi[k - 1] = std::numeric_limits<double>::infinity();
      }
      x[k] = log_amp;
      lo[k] = -kLogAmpMax;
      hi[k] = kLogAmpMax;
      const LmResult lm = levenberg_marquardt(ctx, x, !ctx.tent, lo, hi, o.max_iterations);
      if (pass == 0) r.initial_cost = lm.initial_cost;
      for (int i = 0; i < k; ++i) shape[static_cast<std::size_t>(i)] = x[i];
      log_amp = x[k];
      r.iterations = lm.iterations;
      r.converged = lm.converged;
      r.termination = lm.message;
      r.final_cost = lm.cost;
    } else if (o.solver == FitSolver::CeresAutodiff) {
      ceres::Problem::Options po;
      ceres::Problem problem(po);
      for (std::size_t iy = ctx.iy0; iy <= ctx.iy1; ++iy) {
        const int nres = static_cast<int>(ctx.cols());
        ceres::CostFunction* cf = nullptr;
        if (k == 5)
          cf = new ceres::AutoDiffCostFunction<RowCost<5>, ceres::DYNAMIC, 5, 1>(
              new RowCost<5>{&ctx, iy}, nres);
        else
          cf = new ceres::AutoDiffCostFunction<RowCost<3>, ceres::DYNAMIC, 3, 1>(
              new RowCost<3>{&ctx, iy}, nres);
        problem.AddResidualBlock(cf, nullptr, shape.data(), &log_amp);
      }
      if (ctx.tent)
        problem.SetParameterBlockConstant(&log_amp);
      else {
        problem.SetParameterLowerBound(&log_amp, 0, -kLogAmpMax);
        problem.SetParameterUpperBound(&log_amp, 0, kLogAmpMax);
      }
      for (int i = 0; i < 2; ++i) {
        problem.SetParameterLowerBound(shape.data(), i, la_lo);
        problem.SetParameterUpperBound(shape.data(), i, la_hi);
      }
      if (k == 5)
        for (int i = 2; i < 4; ++i) {
          problem.SetParameterLowerBound(shape.data(), i, -kThetaTiltMax);
          problem.SetParameterUpperBound(shape.data(), i, kThetaTiltMax);
        }
      ceres::Solver::Options so;
      so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
      so.max_num_iterations = o.max_iterations;
      so.function_tolerance = 1e-13;
      so.gradient_tolerance = 1e-14;
      so.parameter_tolerance = 1e-11;
      so.num_threads = o.threads > 0 ? o.threads : omp_get_max_threads();
      so.logging_type = ceres::SILENT;
      so.minimizer_progress_to_stdout = false;
      ceres::Solver::Summary sum;
      ceres::Solve(so, &problem, &sum);
      r.iterations = sum.num_successful_steps + sum.num_unsuccessful_steps;
      r.converged = sum.termination_type == ceres::CONVERGENCE;
      r.termination = sum.message;
      r.final_cost = sum.final_cost;
    } else {
      std::vector<double> x(shape.begin(), shape.begin() + k);
      if (!ctx.tent) x.push_back(log_amp);
      std::vector<double> step(x.size(), 0.02);
      step[0] = step[1] = 0.1;
      auto f = [&](const std::vector<double>& v) {
        std::array<double, 5> s{};
        for (int i = 0; i < k; ++i) s[static_cast<std::size_t>(i)] = v[static_cast<std::size_t>(i)];
        s[0] = std::clamp(s[0], la_lo, la_hi);
        s[1] = std::clamp(s[1], la_lo, la_hi);
        if (k == 5) {
          s[2] = std::clamp(s[2], -kThetaTiltMax, kThetaTiltMax);
          s[3] = std::clamp(s[3], -kThetaTiltMax, kThetaTiltMax);
        }
        const double amp = ctx.tent ? 1.0 : std::exp(std::clamp(v.back(), -kLogAmpMax, kLogAmpMax));
        return ctx.cost(s.data(), amp);
      };
      double fb = 0;
      bool conv = false;
      r.iterations = nelder_mead(f, x, step, 200 * o.max_iterations, fb, conv);
      for (int i = 0; i < k; ++i)
        shape[static_cast<std::size_t>(i)] = x[static_cast<std::size_t>(i)];
      shape[0] = std::clamp(shape[0], la_lo, la_hi);
      shape[1] = std::clamp(shape[1], la_lo, la_hi);
      if (!ctx.tent) log_amp = std::clamp(x.back(), -kLogAmpMax, kLogAmpMax);
      r.final_cost = fb;
      r.converged = conv;
      r.termination = "Nelder-Mead";
    }
    const bool at_bound = std::min(shape[0], shape[1]) <= la_lo + 1e-6;
    if (!(ctx.tent && at_bound && ctx.s < 8 && pass < 3)) break;
    ctx.s = std::min(8, 2 * ctx.s);
    r.tent_subsamples = ctx.s;
  }
  r.solver_converged = r.converged;
  r.at_bound = bound_note(o.model, shape, la_final, la_hi, !ctx.tent, log_amp);
  if (!r.at_bound.empty()) r.converged = false;
  r.params = from_shape(o.model, shape.data());
  r.amplitude = std::exp(log_amp);
  canonicalise(o.model, r.params);
  r.phi = o.model == FitModel::Ellipsoid ? 0.0 : -r.params.theta_z;

  // Errors over the whole disk.
  const TabulatedNdf m = fit_table(r, ndf.resolution());
  double se = 0, st = 0, sh = 0;
  std::size_t count = 0;
  for (std::size_t iy = 0; iy < ndf.resolution(); ++iy)
    for (std::size_t ix = 0; ix < ndf.resolution(); ++ix) {
      const double x = ndf.node_x(ix), y = ndf.node_y(iy);
      if (x * x + y * y >= 1 || std::isnan(ndf.at(ix, iy))) continue;  // unmeasured
      const double tv = std::max(0.0, ndf.at(ix, iy)), mv = m.at(ix, iy);
      se += (tv - mv) * (tv - mv);
      st += tv * tv;
      const double dh = std::sqrt(tv) - std::sqrt(mv);
      sh += dh * dh;
      ++count;
    }
  r.rms_error = std::sqrt(se / static_cast<double>(std::max<std::size_t>(count, 1)));
  r.relative_l2_error = st > 0 ? std::sqrt(se / st) : 0.0;
  r.hellinger = std::sqrt(0.5 * sh * ndf.spacing() * ndf.spacing());
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

// The table at (N - 1) / 4 + 1 nodes, as the estimator would have made it there: tent tables
// (histograms) are restricted with the tent weights (1 - |a|/4)/4, a = -3..3 per axis (the
// coarse hat functions are these sums of fine ones, so mass and shape are kept exactly); node
// tables (point samples of a model) keep every fourth node.
TabulatedNdf coarsened(const TabulatedNdf& t, bool tent) {
  const std::size_t n = t.resolution(), nc = (n - 1) / 4 + 1;
  TabulatedNdf c(nc, t.window());
  c.meta = t.meta;
  const double w[7] = {0.0625, 0.125, 0.1875, 0.25, 0.1875, 0.125, 0.0625};
#pragma omp parallel for schedule(static)
  for (std::size_t iy = 0; iy < nc; ++iy)
    for (std::size_t ix = 0; ix < nc; ++ix) {
      if (!tent) {
        c.at(ix, iy) = t.at(4 * ix, 4 * iy);
        continue;
      }
      double acc = 0;
      for (int b = -3; b <= 3; ++b) {
        const long y = 4 * static_cast<long>(iy) + b;
        if (y < 0 || y >= static_cast<long>(n)) continue;
        for (int a = -3; a <= 3; ++a) {
          const long x = 4 * static_cast<long>(ix) + a;
          if (x < 0 || x >= static_cast<long>(n)) continue;
          acc +=
              w[b + 3] * w[a + 3] * t.at(static_cast<std::size_t>(x), static_cast<std::size_t>(y));
        }
      }
      c.at(ix, iy) = acc;
    }
  return c;
}

}  // namespace

FitResult fit_ndf(const TabulatedNdf& ndf, const FitOptions& o) {
  // Coarse to fine: on large tables whose lobe the quarter-resolution table still resolves (the
  // moment guess at least three coarse spacings wide), the multi-start and the first iterations
  // run on the coarse table; its optimum starts the fit on the full table, which converges to
  // the full table's own optimum.
  const std::size_t n = ndf.resolution();
  if (o.solver == FitSolver::LevenbergMarquardt && !o.initial && n >= 513 && (n - 1) % 4 == 0 &&
      !measured_table(ndf)) {
    const auto t0 = std::chrono::steady_clock::now();
    const EllipsoidParams g = initial_guess(ndf, o.model);
    const double coarse_spacing = 4 * ndf.spacing();
    if (std::min(g.alpha_x, g.alpha_y) >= 3 * coarse_spacing) {
      FitSampling smp = o.sampling;
      if (smp == FitSampling::Auto)
        smp = point_sampled(ndf) ? FitSampling::Node : FitSampling::Tent;
      const TabulatedNdf coarse = coarsened(ndf, smp == FitSampling::Tent);
      FitOptions co = o;
      co.sampling = smp;
      const FitResult c = fit_ndf_single(coarse, co);
      FitOptions fo = o;
      fo.initial = c.params;
      FitResult r = fit_ndf_single(ndf, fo);
      r.initial = c.initial;
      r.iterations += c.iterations;
      r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return r;
    }
  }
  return fit_ndf_single(ndf, o);
}

std::shared_ptr<MicrofacetDistribution> fitted_distribution(const FitResult& r) {
  const auto& p = r.params;
  switch (r.model) {
    case FitModel::Ellipsoid:
      return std::make_shared<EllipsoidDistribution>(p);
    case FitModel::Beckmann:
      return std::make_shared<BeckmannDistribution>(p.alpha_x, p.alpha_y, r.phi);
    case FitModel::Ggx:
      break;
  }
  return std::make_shared<GgxDistribution>(p.alpha_x, p.alpha_y, r.phi);
}

TabulatedNdf tabulate_tent(const MicrofacetDistribution& d, const std::string& model,
                           std::size_t resolution, int subsamples, const NdfWindow& window) {
  if (resolution < 3) throw InputError("NDF table resolution must be at least 3");
  const int s = std::max(1, subsamples);
  const auto ss = static_cast<std::size_t>(s);
  TabulatedNdf t(resolution, window);
  const double delta = t.spacing(), h = delta / s;
  std::vector<double> w(2 * ss);
  for (std::size_t a = 0; a < w.size(); ++a)
    w[a] = (1.0 - std::abs((static_cast<double>(a) + 0.5) / s - 1.0)) / s;
  // The midpoint samples of neighbouring tent cells coincide: D is evaluated once per point of
  // the sub-grid (s (N + 1))^2 (each sub-row's y and sub-column's x from its own index), rows in
  // contiguous bands per thread so that a row reuses the previous row's last s sub-rows.
  const std::size_t nsub = ss * (resolution + 1);
  const double x0 = t.node_x(0) - delta + 0.5 * h, y0 = t.node_y(0) - delta + 0.5 * h;
#pragma omp parallel
  {
    std::vector<double> buf(2 * ss * nsub);
    std::vector<long> held(2 * ss, -1);
    auto sub_row = [&](std::size_t j) -> const double* {
      double* out = &buf[(j % (2 * ss)) * nsub];
      if (held[j % (2 * ss)] == static_cast<long>(j)) return out;
      held[j % (2 * ss)] = static_cast<long>(j);
      const double y = y0 + static_cast<double>(j) * h;
      for (std::size_t i = 0; i < nsub; ++i) {
        const double x = x0 + static_cast<double>(i) * h, r2 = x * x + y * y;
        out[i] = r2 < 1 ? d.D(Vec3(x, y, std::sqrt(1 - r2))) : 0.0;
      }
      return out;
    };
#pragma omp for schedule(static)
    for (std::size_t iy = 0; iy < resolution; ++iy) {
      double* row = &t.at(0, iy);
      for (std::size_t b = 0; b < 2 * ss; ++b) {
        const double* sr = sub_row(iy * ss + b);
        for (std::size_t ix = 0; ix < resolution; ++ix) {
          double acc = 0;
          for (std::size_t a = 0; a < 2 * ss; ++a) acc += w[a] * sr[ix * ss + a];
          row[ix] += w[b] * acc;
        }
      }
    }
  }
  t.meta.method = model + "-tent";
  t.meta.sampling = "cell";
  t.meta.notes = d.describe() + "; tent-cell averages, " + std::to_string(s) + " subsamples";
  return t;
}

TabulatedNdf fit_table(const FitResult& r, std::size_t resolution) {
  const auto d = fitted_distribution(r);
  if (r.sampling == FitSampling::Tent) {
    TabulatedNdf t =
        tabulate_tent(*d, fit_model_name(r.model), resolution, r.tent_subsamples, r.window);
    t.meta.method = fit_model_name(r.model) + " fit";
    return t;
  }
  TabulatedNdf t(resolution, r.window);
  t.meta.sampling = "point";
  for (std::size_t iy = 0; iy < resolution; ++iy)
    for (std::size_t ix = 0; ix < resolution; ++ix) {
      const double x = t.node_x(ix), y = t.node_y(iy), r2 = x * x + y * y;
      t.at(ix, iy) = r2 < 1 ? r.amplitude * d->D(Vec3(x, y, std::sqrt(1 - r2))) : 0.0;
    }
  t.meta.method = fit_model_name(r.model) + " fit";
  t.meta.notes = d->describe();
  return t;
}

nlohmann::json fit_result_json(const FitResult& r) {
  const auto& p = r.params;
  auto params = [](const EllipsoidParams& q) {
    return nlohmann::json{{"alpha_x", q.alpha_x},
                          {"alpha_y", q.alpha_y},
                          {"theta_x", q.theta_x},
                          {"theta_y", q.theta_y},
                          {"theta_z", q.theta_z}};
  };
  return {
      {"model", fit_model_name(r.model)},
      {"params", params(p)},
      {"params_deg",
       {{"theta_x", p.theta_x * 180 / kPi},
        {"theta_y", p.theta_y * 180 / kPi},
        {"theta_z", p.theta_z * 180 / kPi}}},
      {"phi", r.phi},
      {"rms_error", r.rms_error},
      {"relative_l2_error", r.relative_l2_error},
      {"hellinger", r.hellinger},
      {"amplitude", r.amplitude},
      {"objective", fit_objective_name(r.objective)},
      {"sampling", fit_sampling_name(r.sampling)},
      {"table_sampling", r.table_sampling},
      {"table_sampling_recorded", r.table_sampling_recorded},
      {"window", {{"x", {r.window.x0(), r.window.x1()}}, {"y", {r.window.y0(), r.window.y1()}}}},
      {"tent_subsamples", r.tent_subsamples},
      {"floor", r.floor},
      {"initial_params", params(r.initial)},
      {"initial_cost", r.initial_cost},
      {"final_cost", r.final_cost},
      {"iterations", r.iterations},
      {"converged", r.converged},
      {"solver_converged", r.solver_converged},
      {"at_bound", r.at_bound.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.at_bound)},
      {"termination", r.termination},
      {"residuals", r.residuals},
      {"roi", {r.roi[0], r.roi[1], r.roi[2], r.roi[3]}},
      {"seconds", r.seconds}};
}

}  // namespace microbrdf

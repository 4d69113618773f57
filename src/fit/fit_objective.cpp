// The fit's objective, forward operator and normal equations (fit_context.hpp).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "core/helper_pool.hpp"
#include "fit/fit_context.hpp"
#include "microbrdf/error.hpp"

namespace microbrdf::fit_detail {
namespace {

// Tent weights: 2s midpoints per axis at offsets ((a + 1/2)/s - 1) Delta with weights
// (1 - |offset|/Delta)/s (they sum to 1).
std::vector<double> tent_weights(std::size_t ss) {
  std::vector<double> w(2 * ss);
  for (std::size_t a = 0; a < 2 * ss; ++a) {
    const double u = (static_cast<double>(a) + 0.5) / static_cast<double>(ss) - 1.0;
    w[a] = (1.0 - std::abs(u)) / static_cast<double>(ss);
  }
  return w;
}

}  // namespace

void FitContext::row_model(const NdfEvaluator& ev, std::size_t iy, double* out,
                           double* grad) const {
  const std::size_t nc = cols();
  const double y = node_y(iy);
  if (!tent) {
    ev.row(node_x(ix0), delta, nc, y, out, grad, nc);
    return;
  }
  // Midpoint rule on the tent; sub-columns are shared by neighbours.
  const std::size_t ss = static_cast<std::size_t>(s), kk = grad ? static_cast<std::size_t>(k) : 0;
  const std::vector<double> w = tent_weights(ss);
  const std::size_t nsub = ss * (nc + 1);
  std::vector<double> sub(nsub), sg(kk * nsub);
  const double h = delta / s, x0 = node_x(ix0) - delta + 0.5 * h;
  std::fill(out, out + nc, 0.0);
  if (grad) std::fill(grad, grad + kk * nc, 0.0);
  for (std::size_t b = 0; b < 2 * ss; ++b) {
    const double yb = y + ((static_cast<double>(b) + 0.5) / s - 1.0) * delta;
    ev.row(x0, h, nsub, yb, sub.data(), grad ? sg.data() : nullptr, nsub);
    for (std::size_t c = 0; c < nc; ++c) {
      double acc = 0;
      for (std::size_t a = 0; a < 2 * ss; ++a) acc += w[a] * sub[c * ss + a];
      out[c] += w[b] * acc;
      for (std::size_t p = 0; p < kk; ++p) {
        double ga = 0;
        for (std::size_t a = 0; a < 2 * ss; ++a) ga += w[a] * sg[p * nsub + c * ss + a];
        grad[p * nc + c] += w[b] * ga;
      }
    }
  }
}

double FitContext::cost(const double* shape, double amp) const {
  const auto ev = model->evaluator(shape, false);
  std::vector<double> per_row(rows(), 0.0);
  auto band = [&](std::size_t b) {
    std::vector<double> v(cols());
    for (std::size_t iy = iy0 + b * 8; iy <= iy1 && iy < iy0 + (b + 1) * 8; ++iy) {
      row_model(*ev, iy, v.data(), nullptr);
      const double* gt_row = &gt[(iy - iy0) * cols()];
      double t = 0;
      // NaN marks an unmeasured node (effective NDFs from measured BRDFs): no residual.
      for (std::size_t c = 0; c < cols(); ++c) {
        if (std::isnan(gt_row[c])) continue;
        const double r = (g0(v[c] * amp) - gt_row[c]) * delta;
        t += r * r;
      }
      per_row[iy - iy0] = t;
    }
  };
  const std::size_t bands = (rows() + 7) / 8;
  detail::HelperPool::instance().run(bands, rows() * cols() > 50000 ? threads : 1, band);
  double total = 0;
  for (double t : per_row) total += t;
  return 0.5 * total;
}

double FitContext::node_amplitude(const double* shape) const {
  const auto ev = model->evaluator(shape, false);
  std::vector<double> v(cols());
  double sum = 0;
  for (std::size_t iy = iy0; iy <= iy1; ++iy) {
    ev->row(node_x(ix0), delta, cols(), node_y(iy), v.data(), nullptr, 0);
    for (double x : v) sum += x;
  }
  sum *= delta * delta;
  return sum > 0 ? 1.0 / sum : 1.0;
}

bool measured_table(const TabulatedNdf& t) {
  std::string m = t.meta.method;
  std::transform(m.begin(), m.end(), m.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (m == "measured") return true;
  for (double v : t.values())
    if (std::isnan(v)) return true;
  return false;
}

bool point_sampled(const TabulatedNdf& t) { return ndf_sampling(t.meta) == "point"; }

FitContext make_context(const TabulatedNdf& t, const FitOptions& o, const NdfModel& model,
                        const std::vector<double>& start) {
  FitContext c;
  c.model = &model;
  c.k = static_cast<int>(model.params().size());
  if (c.k > kMaxParams)
    throw InputError("the model " + model.name() + " has more than " + std::to_string(kMaxParams) +
                     " parameters; the fit takes at most that many");
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
      double amin = 1e300;
      for (std::size_t i = 0; i < start.size(); ++i)
        if (model.params()[i].kind == NdfParam::Kind::Alpha) amin = std::min(amin, start[i]);
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

// Residuals r = (g(amp v) - g(T)) Delta of the fit context, with their Jacobian, summed into
// normal equations row by row (each row's sums in a fixed order, rows folded in order: the same
// numbers whatever the thread count). v: the model as compared (node value or tent average).
template <int K>
NormalEq normal_equations_k(const FitContext& c, const double* shape, double log_amp) {
  const auto ev = c.model->evaluator(shape, false);
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
  const std::vector<double> w = c.tent ? tent_weights(ss) : std::vector<double>(2, 1.0);
  // Per row, sized for this model (a kMaxParams-sized NormalEq per row would be 2 KB to clear
  // and fold per row and iteration).
  struct RowEq {
    double jtj[K + 1][K + 1] = {}, jtr[K + 1] = {}, cost = 0;
  };
  std::vector<RowEq> rows(nr);
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
      ev->row(x0, h, nsub, y, out, out + nsub, nsub);
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
      RowEq e;
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
  for (const auto& e : rows) {
    for (int p = 0; p < np; ++p) {
      total.jtr[p] += e.jtr[p];
      for (int q = 0; q < np; ++q) total.jtj[p][q] += e.jtj[p][q];
    }
    total.cost += e.cost;
  }
  for (int p = 0; p < np; ++p)
    for (int q = 0; q < p; ++q) total.jtj[q][p] = total.jtj[p][q];
  total.cost *= 0.5;
  return total;
}

namespace {
template <int... Ks>
NormalEq dispatch(const FitContext& c, const double* shape, double log_amp,
                  std::integer_sequence<int, Ks...>) {
  NormalEq out;
  const bool found =
      ((c.k == Ks + 1 ? (out = normal_equations_k<Ks + 1>(c, shape, log_amp), true) : false) ||
       ...);
  if (!found) throw InputError("the fit takes 1 to " + std::to_string(kMaxParams) + " parameters");
  return out;
}
}  // namespace

NormalEq normal_equations(const FitContext& c, const double* shape, double log_amp) {
  return dispatch(c, shape, log_amp, std::make_integer_sequence<int, kMaxParams>{});
}

}  // namespace microbrdf::fit_detail

// Per-texel filtered NDFs and ellipsoid fits (Dong 2015 section 9): each scan is cut into square
// texels, the Gaussian-filtered normals of the whole scan (so texels near each other share
// neighbours, as on the real surface) are binned per texel, and the ellipsoid NDF is fitted.
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>

#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf {
namespace {

struct Cut {
  std::size_t count = 0;            // whole texels along the axis
  std::vector<std::size_t> bounds;  // sample index of every texel edge (count + 1)
};

// Texel edges along one axis: texel k covers samples [round(k T/d), round((k+1) T/d)), the last
// one clipped to the scan; a texel at the end counts when at least min_area of it is inside.
Cut cut_axis(std::size_t n, double d, double texel, double min_area) {
  Cut c;
  const double per = texel / d;  // samples per texel
  c.count = static_cast<std::size_t>(std::floor(static_cast<double>(n) / per + (1 - min_area)));
  for (std::size_t k = 0; k <= c.count; ++k)
    c.bounds.push_back(
        std::min(n, static_cast<std::size_t>(std::llround(static_cast<double>(k) * per))));
  return c;
}

// Range check of a fit; empty when fine. Alphas below alpha_min are lifted to it first (and
// counted): a brushed texel's lobe along the scratches can be narrower than the table resolves
// (a node is 2/(N-1)), and "narrower than we can tell" is not a failed fit.
std::string out_of_range(EllipsoidParams& p, bool& lifted) {
  char buf[128];
  lifted = false;
  for (double* a : {&p.alpha_x, &p.alpha_y})
    if (*a > 0 && *a < ParamRange::alpha_min) {
      *a = ParamRange::alpha_min;
      lifted = true;
    }
  for (double a : {p.alpha_x, p.alpha_y})
    if (!(a >= ParamRange::alpha_min && a <= ParamRange::alpha_max)) {
      std::snprintf(buf, sizeof buf, "alpha %.4g outside [%g, %g]", a, ParamRange::alpha_min,
                    ParamRange::alpha_max);
      return buf;
    }
  for (double t : {p.theta_x, p.theta_y})
    if (!(std::fabs(t) <= ParamRange::tilt_max)) {
      std::snprintf(buf, sizeof buf, "tilt %.4g rad beyond %g", t, ParamRange::tilt_max);
      return buf;
    }
  return {};
}

// The texel's filtered normals (those the filter kept), for lobes below a node.
std::vector<Vec3> texel_normals(const NormalField& nf, std::size_t nx, std::size_t x0,
                                std::size_t x1, std::size_t y0, std::size_t y1) {
  std::vector<Vec3> out;
  out.reserve((x1 - x0) * (y1 - y0));
  for (std::size_t y = y0; y < y1; ++y)
    for (std::size_t x = x0; x < x1; ++x) {
      const std::size_t j = y * nx + x;
      if (nf.mz[j] > 0) out.emplace_back(nf.mx[j], nf.my[j], nf.mz[j]);
    }
  return out;
}

struct ScanResult {
  std::size_t tx = 0, ty = 0;  // texels along x and y
  std::vector<EllipsoidParams> p;
  std::vector<std::uint8_t> ok;
  std::vector<std::string> why;
  nlohmann::json info;
  std::atomic<std::size_t> lifted{0};  // texels whose alpha was lifted to alpha_min
  std::atomic<std::size_t> zoomed{0};  // texels refitted on a zoomed table
  ScanResult() = default;
  ScanResult(const ScanResult& o)
      : tx(o.tx),
        ty(o.ty),
        p(o.p),
        ok(o.ok),
        why(o.why),
        info(o.info),
        lifted(o.lifted.load()),
        zoomed(o.zoomed.load()) {}
};

// The ellipsoid fit of one texel's splatted table (normalised here), single-threaded: the texels
// themselves are the parallel work.
FitResult fit_texel_table(TabulatedNdf& t, std::size_t used, const TexelFitOptions& o) {
  t.normalise();
  t.meta.method = "filtered";
  t.meta.filter_sigma_m = o.filter_sigma_m;
  t.meta.samples_used = used;
  FitOptions fo;
  fo.model = "ellipsoid";
  fo.threads = 1;
  fo.sampling = o.sampling;
  fo.max_iterations = o.max_iterations;
  return fit_ndf(t, fo);
}

ScanResult fit_scan(const Surface& s, const TexelFitOptions& o) {
  if (!(o.texel_m > 0)) throw InputError("texel size must be positive");
  if (o.ndf_resolution < 17) throw InputError("texel NDF resolution must be at least 17");
  const Cut cx = cut_axis(s.nx, s.dx, o.texel_m, o.min_area_fraction);
  const Cut cy = cut_axis(s.ny, s.dy, o.texel_m, o.min_area_fraction);
  ScanResult r;
  r.tx = cx.count;
  r.ty = cy.count;
  const std::size_t n = r.tx * r.ty;
  r.p.assign(n, EllipsoidParams{});
  r.ok.assign(n, 0);
  r.why.assign(n, "");
  const std::size_t used_x = r.tx ? cx.bounds.back() : 0, used_y = r.ty ? cy.bounds.back() : 0;
  r.info = {{"texels_x", r.tx},
            {"texels_y", r.ty},
            {"samples_per_texel_x", o.texel_m / s.dx},
            {"samples_per_texel_y", o.texel_m / s.dy},
            {"samples_dropped", s.size() - used_x * used_y}};
  if (n == 0) return r;
  struct Lifted {  // reports the count into info when the scan is done
    ScanResult& r;
    ~Lifted() {
      r.info["alpha_lifted_to_min"] = r.lifted.load();
      r.info["alpha_zoomed"] = r.zoomed.load();
    }
  } report{r};
  const NormalField nf = filtered_normals(s, o.filter_sigma_m);
  const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (long k = 0; k < static_cast<long>(n); ++k) {
    const std::size_t i = static_cast<std::size_t>(k), kx = i % r.tx, ky = i / r.tx;
    const std::size_t x0 = cx.bounds[kx], x1 = cx.bounds[kx + 1];
    const std::size_t y0 = cy.bounds[ky], y1 = cy.bounds[ky + 1];
    try {
      TabulatedNdf t(o.ndf_resolution);
      std::size_t used = 0;
      for (std::size_t y = y0; y < y1; ++y)
        for (std::size_t x = x0; x < x1; ++x) {
          const std::size_t j = y * s.nx + x;
          if (nf.mz[j] <= 0) continue;  // skipped by the filter (hole, border)
          t.splat(nf.mx[j], nf.my[j], 1.0);
          ++used;
        }
      const std::size_t samples = (x1 - x0) * (y1 - y0);
      if (static_cast<double>(used) < o.min_valid_fraction * static_cast<double>(samples)) {
        char buf[128];
        std::snprintf(buf, sizeof buf, "too few filtered normals: %zu of %zu samples (< %.0f%%)",
                      used, samples, 100 * o.min_valid_fraction);
        r.why[i] = buf;
        continue;
      }
      const FitResult fr = fit_texel_table(t, used, o);
      r.p[i] = ellipsoid_params(fr.params);
      // A width below the table's resolution: refitted on a table zoomed along that axis.
      const double below = o.zoom_below_nodes * t.spacing();
      bool zoomed = false;
      if (fr.solver_converged && (r.p[i].alpha_x < below || r.p[i].alpha_y < below)) {
        r.p[i] = refit_narrow_lobe(texel_normals(nf, s.nx, x0, x1, y0, y1), r.p[i], o);
        zoomed = true;
      }
      bool lifted = false;
      if (!fr.solver_converged) {  // a texel at the alpha floor is lifted below, not dropped
        r.why[i] = "fit did not converge: " + fr.termination;
      } else if (auto bad = out_of_range(r.p[i], lifted); !bad.empty()) {
        r.why[i] = bad;
      } else {
        r.ok[i] = 1;
        if (lifted) r.lifted.fetch_add(1);
        if (zoomed) r.zoomed.fetch_add(1);
      }
    } catch (const std::exception& e) {
      r.p[i] = EllipsoidParams{NAN, NAN, NAN, NAN, NAN};
      r.why[i] = std::string("fit failed: ") + e.what();
    }
  }
  return r;
}

// A scan's fits as sent between ranks: 5 parameters and the flag per texel as exact doubles (NaN
// included), reasons and counters as JSON.
WorkResult pack(const ScanResult& r) {
  WorkResult w;
  w.values.reserve(r.p.size() * 6);
  for (std::size_t i = 0; i < r.p.size(); ++i) {
    const EllipsoidParams& p = r.p[i];
    w.values.insert(w.values.end(),
                    {p.alpha_x, p.alpha_y, p.theta_x, p.theta_y, p.theta_z, double(r.ok[i])});
  }
  w.text = nlohmann::json{{"tx", r.tx},
                          {"ty", r.ty},
                          {"why", r.why},
                          {"info", r.info},
                          {"lifted", r.lifted.load()},
                          {"zoomed", r.zoomed.load()}}
               .dump();
  return w;
}

ScanResult unpack(const WorkResult& w) {
  const auto j = nlohmann::json::parse(w.text);
  ScanResult r;
  r.tx = j.at("tx");
  r.ty = j.at("ty");
  r.why = j.at("why").get<std::vector<std::string>>();
  r.info = j.at("info");
  r.lifted = j.at("lifted").get<std::size_t>();
  r.zoomed = j.at("zoomed").get<std::size_t>();
  const std::size_t n = r.tx * r.ty;
  if (w.values.size() != 6 * n || r.why.size() != n)
    throw std::runtime_error("texel fits: a scan's result does not match its texel count");
  for (std::size_t i = 0; i < n; ++i) {
    const double* v = w.values.data() + 6 * i;
    r.p.push_back(EllipsoidParams{v[0], v[1], v[2], v[3], v[4]});
    r.ok.push_back(static_cast<std::uint8_t>(v[5]));
  }
  return r;
}

nlohmann::json options_json(const TexelFitOptions& o) {
  return {{"texel_m", o.texel_m},
          {"filter_sigma_m", o.filter_sigma_m},
          {"ndf_resolution", o.ndf_resolution},
          {"leveling", o.leveling.name()},
          {"min_valid_fraction", o.min_valid_fraction},
          {"min_area_fraction", o.min_area_fraction},
          {"model", "ellipsoid"},
          {"sampling", fit_sampling_name(o.sampling)},
          {"stacking", o.stack_along_y ? "y" : "x"},
          {"zoom_below_nodes", o.zoom_below_nodes},
          {"zoom_nodes", o.zoom_nodes}};
}

// Lays the scans' texel grids side by side (along x, or along y when stacking along y).
class Assembler {
 public:
  explicit Assembler(const TexelFitOptions& o) : o_(o) {}
  void add(const ScanResult& r, const std::string& source) {
    scans_.push_back(r);
    nlohmann::json info = r.info;
    info["path"] = source;
    info["offset"] = o_.stack_along_y ? total_y() - r.ty : total_x() - r.tx;
    meta_scans_.push_back(info);
  }
  ParamTexture finish() const {
    const std::size_t nx = total_x(), ny = total_y();
    if (nx == 0 || ny == 0)
      throw InputError("no whole texel of " + std::to_string(o_.texel_m * 1e6) +
                       " um fits in the scans (make --texel smaller than the scan)");
    ParamTexture t = ParamTexture::empty(nx, ny, o_.texel_m, "no scan covers this texel");
    std::size_t off = 0;
    for (const auto& r : scans_) {
      for (std::size_t ky = 0; ky < r.ty; ++ky)
        for (std::size_t kx = 0; kx < r.tx; ++kx) {
          const std::size_t src = kx + r.tx * ky;
          const std::size_t dst = o_.stack_along_y ? kx + nx * (ky + off) : (kx + off) + nx * ky;
          const EllipsoidParams& p = r.p[src];
          const double v[5] = {p.alpha_x, p.alpha_y, p.theta_x, p.theta_y, p.theta_z};
          for (int c = 0; c < 5; ++c)
            t.channel[static_cast<std::size_t>(c)][dst] = static_cast<float>(v[c]);
          t.valid[dst] = r.ok[src];
          t.why_invalid[dst] = r.ok[src] ? "" : r.why[src];
        }
      off += o_.stack_along_y ? r.ty : r.tx;
    }
    t.meta = {{"kind", "fitted"},
              {"fit", options_json(o_)},
              {"scans", meta_scans_},
              {"texels", nx * ny},
              {"failed", nx * ny - t.valid_count()},
              {"alpha_lifted_to_min", lifted()},
              {"alpha_zoomed", zoomed()}};
    nlohmann::json sources = nlohmann::json::array();
    for (const auto& s : meta_scans_) sources.push_back(s.at("path"));
    t.meta["sources"] = sources;
    return t;
  }

 private:
  std::size_t lifted() const {
    std::size_t v = 0;
    for (const auto& r : scans_) v += r.lifted.load();
    return v;
  }
  std::size_t zoomed() const {
    std::size_t v = 0;
    for (const auto& r : scans_) v += r.zoomed.load();
    return v;
  }
  std::size_t total_x() const {
    std::size_t v = 0;
    for (const auto& r : scans_) v = o_.stack_along_y ? std::max(v, r.tx) : v + r.tx;
    return v;
  }
  std::size_t total_y() const {
    std::size_t v = 0;
    for (const auto& r : scans_) v = o_.stack_along_y ? v + r.ty : std::max(v, r.ty);
    return v;
  }
  const TexelFitOptions& o_;
  std::vector<ScanResult> scans_;  // parameters only: a few hundred bytes per texel
  nlohmann::json meta_scans_ = nlohmann::json::array();
};

}  // namespace

std::array<double, 2> ellipsoid_widths_from_normals(const std::vector<Vec3>& normals,
                                                    const EllipsoidParams& p) {
  const EllipsoidDistribution d(p);
  std::vector<double> sx, sy;
  sx.reserve(normals.size());
  sy.reserve(normals.size());
  for (const Vec3& m : normals) {
    const Vec3 q = d.R() * m;
    if (!(q.z() > 0)) continue;
    sx.push_back(q.x() / q.z());
    sy.push_back(q.y() / q.z());
  }
  if (sx.size() < 2) throw InputError("widths from normals: fewer than two normals");
  auto median = [](std::vector<double>& v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  std::array<double, 2> w{};
  for (int axis = 0; axis < 2; ++axis) {
    std::vector<double>& v = axis == 0 ? sx : sy;
    const double centre = median(v);
    for (double& x : v) x = std::fabs(x - centre);
    w[static_cast<std::size_t>(axis)] = std::sqrt(3.0) * median(v);
  }
  return w;
}

EllipsoidParams refit_narrow_lobe(const std::vector<Vec3>& normals, const EllipsoidParams& first,
                                  const TexelFitOptions& o) {
  const double node = 2.0 / static_cast<double>(o.ndf_resolution - 1);
  const double below = o.zoom_below_nodes * node;
  const bool zx = first.alpha_x < below, zy = first.alpha_y < below;
  if (!zx && !zy) return first;
  // The lobe's scale from the normals (median rule), then the zoom that spreads it over
  // zoom_nodes nodes; at most 1e5 (a width of 1e-6 at N = 129).
  const auto guess = ellipsoid_widths_from_normals(normals, first);
  auto zoom = [&](bool narrow, double w) {
    return narrow ? std::clamp(o.zoom_nodes * node / std::max(w, 1e-12), 1.0, 1e5) : 1.0;
  };
  const double kx = zoom(zx, guess[0]), ky = zoom(zy, guess[1]);
  // The zoom is centred on the lobe (median slope along the zoomed axis), so the stretched lobe
  // stays near the disk centre, where slopes and disk coordinates agree.
  std::vector<double> sx, sy;
  for (const Vec3& m : normals)
    if (m.z() > 0) {
      sx.push_back(m.x() / m.z());
      sy.push_back(m.y() / m.z());
    }
  if (sx.empty()) return first;
  auto median = [](std::vector<double> v) {
    const auto mid = v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2);
    std::nth_element(v.begin(), mid, v.end());
    return *mid;
  };
  const double cx = zx ? median(sx) : 0.0, cy = zy ? median(sy) : 0.0;
  TabulatedNdf t(o.ndf_resolution);
  std::size_t used = 0;
  for (std::size_t i = 0; i < sx.size(); ++i) {
    // Slopes stretched k-fold along the zoomed axis: a table node there is 1/k of a slope node.
    const Vec3 q = Vec3(kx * (sx[i] - cx), ky * (sy[i] - cy), 1.0).normalized();
    t.splat(q.x(), q.y(), 1.0);
    ++used;
  }
  const FitResult fr = fit_texel_table(t, used, o);
  if (!fr.solver_converged) return first;
  // Back to unstretched slopes: the width along a zoomed axis shrinks by k, and so does the
  // peak's slope along it about the centre (theta_y > 0 puts the peak at slope -tan theta_y
  // along x, theta_x > 0 at +tan theta_x along y); small-slope forms.
  EllipsoidParams p = first;
  if (zx) {
    p.alpha_x = fr.params.at("alpha_x") / kx;
    p.theta_y = std::atan(std::tan(fr.params.at("theta_y")) / kx - cx);
  }
  if (zy) {
    p.alpha_y = fr.params.at("alpha_y") / ky;
    p.theta_x = std::atan(std::tan(fr.params.at("theta_x")) / ky + cy);
  }
  return p;
}

ParamTexture fit_texels(const Surface& s, const TexelFitOptions& options) {
  Surface lv = s;
  level_surface(lv, options.leveling);
  Assembler a(options);
  a.add(fit_scan(lv, options), s.meta.source_path.empty() ? "(memory)" : s.meta.source_path);
  ParamTexture t = a.finish();
  if (options.progress) options.progress(1.0);
  return t;
}

ParamTexture fit_texels(const std::vector<std::string>& scans, const ReadOptions& read,
                        const TexelFitOptions& options, WorkStats* stats) {
  if (scans.empty()) throw InputError("no scans given");
  Assembler a(options);
  WorkStats st = distribute_scans(
      scans, read,
      [&](std::size_t, const std::string&, Surface& s) {
        level_surface(s, options.leveling);
        return pack(fit_scan(s, options));
      },
      [&](std::size_t i, WorkResult&& r) {
        a.add(unpack(r), scans[i]);
        if (options.progress)
          options.progress(static_cast<double>(i + 1) / static_cast<double>(scans.size()));
      });
  if (!mpi_is_root()) return ParamTexture{};
  if (stats) *stats = st;
  return a.finish();
}

}  // namespace microbrdf

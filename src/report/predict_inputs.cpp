// predict stages 1-2: read, level and describe every scan (one in memory at a time, per rank and
// thread), accumulate the naive, filtered and (when asked) Kirchhoff NDFs over all MPI ranks
// (distribute.hpp), write the tables and their previews.
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"
#include "microbrdf/ndf_scanset.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/statistics.hpp"
#include "microbrdf/units.hpp"
#include "report/predict_stages.hpp"

namespace microbrdf::report {
namespace {

nlohmann::json stats_record(const Surface& s, const SurfaceStats& st) {
  nlohmann::json j = stats_json(st);
  j["width_m"] = s.width();
  j["height_m"] = s.height();
  return j;
}

std::string file_name(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

/// rms slope magnitude sqrt(<z_x^2 + z_y^2>) by central differences where both neighbours along
/// an axis are valid (each axis averaged over its own samples).
double rms_slope(const Surface& s) {
  double sx = 0, sy = 0;
  std::size_t nx = 0, ny = 0;
  for (std::size_t iy = 0; iy < s.ny; ++iy)
    for (std::size_t ix = 0; ix < s.nx; ++ix) {
      if (ix > 0 && ix + 1 < s.nx && s.is_valid(s.index(ix - 1, iy)) &&
          s.is_valid(s.index(ix + 1, iy))) {
        const double g = (s.at(ix + 1, iy) - s.at(ix - 1, iy)) / (2 * s.dx);
        sx += g * g;
        ++nx;
      }
      if (iy > 0 && iy + 1 < s.ny && s.is_valid(s.index(ix, iy - 1)) &&
          s.is_valid(s.index(ix, iy + 1))) {
        const double g = (s.at(ix, iy + 1) - s.at(ix, iy - 1)) / (2 * s.dy);
        sy += g * g;
        ++ny;
      }
    }
  return std::sqrt((nx ? sx / static_cast<double>(nx) : 0) +
                   (ny ? sy / static_cast<double>(ny) : 0));
}

// A low-order form left by the chosen levelling (a cylinder under plane levelling): the scan
// levelled again with poly3 loses more than a third of its slope variance or half its height
// variance. Warned by the caller.
constexpr double kFormSlopeShare = 1.0 / 3, kFormHeightShare = 0.5;
constexpr double kInvalidWarn = 0.1;       // warn above this fraction of invalid samples
constexpr double kLobeNodes = 10;          // a lobe should span at least this many nodes
constexpr double kRawIntegralWarn = 0.02;  // D_K raw integral further from 1 warns

void warn_scan(const Context& c, const std::string& path, const nlohmann::json& rec) {
  const double valid = rec.at("stats").value("valid_fraction", 1.0);
  if (valid < 1 - kInvalidWarn) {
    char pct[32];
    std::snprintf(pct, sizeof pct, "%.1f%%", 100 * (1 - valid));
    c.warn("invalid_samples",
           std::string(pct) + " of the samples of " + path +
               " are invalid (unmeasured); statistics and NDFs describe the valid part only",
           "check the scan (dropouts on steep or dark areas, a mask, a crop beyond the part); "
           "remeasure or crop to the valid area if the invalid part is not random");
  }
  const auto& f = rec.at("form_check");
  if (!f.is_object()) return;
  const double s = f.at("slope_rms").get<double>(), s3 = f.at("slope_rms_poly3").get<double>();
  const double q = f.at("sq_m").get<double>(), q3 = f.at("sq_poly3_m").get<double>();
  if (!(s3 * s3 < (1 - kFormSlopeShare) * s * s || q3 * q3 < (1 - kFormHeightShare) * q * q))
    return;
  const bool slopes = s3 * s3 < (1 - kFormSlopeShare) * s * s;
  char nums[200];
  std::snprintf(nums, sizeof nums, "Sq %s vs %s, rms slope %.4g vs %.4g after poly3 levelling",
                format_length(q).c_str(), format_length(q3).c_str(), s, s3);
  c.warn("form_dominates",
         "a low-order form dominates the " + std::string(slopes ? "slopes" : "heights") + " of " +
             path + " after " + rec.value("leveling", "") + " levelling (" + nums + "): " +
             (slopes ? "the NDF and the fits describe the form, not the roughness"
                     : "the height statistics (Sq, Sa, correlation lengths) describe the form; "
                       "the slopes, hence the NDF, change little"),
         "level with --level poly3 (or a higher order) unless the form belongs to the surface "
         "you want to predict");
}

// A lobe this narrow is not resolved by the table: rms slope s_min over the node spacing.
void warn_table(const Context& c, const std::string& name, const TabulatedNdf& t, double s_min,
                const TabulatedNdf* zoom = nullptr) {
  const double span = 4 * s_min / t.spacing();  // nodes across +-2 rms slopes
  if (!(span < kLobeNodes)) return;
  char b[200];
  std::snprintf(b, sizeof b,
                "the %s NDF's lobe (smallest rms slope %.3g) spans %.1f nodes of the %zu x %zu "
                "table (node spacing %.3g)",
                name.c_str(), s_min, span, t.resolution(), t.resolution(), t.spacing());
  const double need = std::ceil(kLobeNodes / 2 / std::max(s_min, 1e-12)) + 1;
  std::string todo;
  if (need <= 4097) {
    todo = "raise --resolution to at least " + std::to_string(static_cast<long>(need)) +
           " (the lobe then spans " + std::to_string(static_cast<int>(kLobeNodes)) +
           " nodes); until then read the rms slopes of summary.json's ndf." + name +
           " rather than the fitted widths";
  } else {
    todo =
        "the lobe is narrower than the largest table (4097) resolves: take the roughness from "
        "the rms slopes of summary.json's ndf." +
        name + " (slope_rms_x/y), not from the fits or the table's shape";
  }
  if (zoom) {
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(zoom->slope_covariance());
    const double zs = std::sqrt(std::max(es.eigenvalues()(0), 0.0));
    char z[480];
    std::snprintf(z, sizeof z,
                  "%sndf_%s_zoom.npy holds the same estimator on a window of half-width %.3g "
                  "around the lobe (node spacing %.3g; the lobe, smallest rms slope %.3g, spans "
                  "%.0f nodes; %.4g%% of the normals fall inside it), with its rms slopes in "
                  "summary.json's ndf.%s.zoom; ",
                  name == "filtered" ? "the fits use the zoomed table: " : "", name.c_str(),
                  zoom->window().half, zoom->spacing(), zs, 4 * zs / zoom->spacing(),
                  100 * zoom->meta.window_mass, name.c_str());
    // The whole-disk table's rms slopes are blurred by the splat (Delta^2 / 6 per axis): the
    // zoomed table's are the ones to read.
    todo = z + std::string("the whole-disk table (renders, previews) and its rms slopes are ") +
           "blurred by its node spacing" +
           (need <= 4097
                ? "; --resolution " + std::to_string(static_cast<long>(need)) + " would resolve it"
                : std::string());
  }
  c.warn("table_too_coarse", b, todo);
}

}  // namespace

nlohmann::json stage_inputs(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs,
                            WorkStats* stats) {
  const auto& o = c.opt;
  NdfEstimateOptions no;
  no.method = NdfMethod::Naive;
  no.resolution = o.ndf_resolution;
  NdfEstimateOptions fo = no;
  fo.method = NdfMethod::Filtered;
  fo.filter_sigma_m = o.filter_sigma_m;
  NdfAccumulator naive(no), filtered(fo);
  std::unique_ptr<KirchhoffAccumulator> kirchhoff;
  const KirchhoffOptions ko = dk_options(o);
  if (o.kirchhoff) kirchhoff = std::make_unique<KirchhoffAccumulator>(ko);
  // D_K is the slowest step (tens of seconds on a 2048 x 1024 scan): report it in 10 % steps,
  // when one rank does every scan in order.
  const bool local = mpi_size() == 1 || mpi_solo();
  auto dk_progress = c.decile_log("inputs: kirchhoff D_K");
  // Per scan, on whichever rank takes it: read, level, statistics, height preview and the
  // scan's share of every NDF; rank 0 folds the shares in scan order (docs/scale.md).
  auto compute = [&](std::size_t i, const std::string& path, Surface& s) {
    const LevelingResult lev = about_file(path, [&] { return level_surface(s, o.leveling); });
    const SurfaceStats st = compute_stats(s);
    // What poly3 levelling would leave (only when the levelling is of lower order).
    nlohmann::json form = nullptr;
    if (o.leveling.mode != Leveling::Polynomial || o.leveling.degree < 3) {
      Surface p3 = s;
      const LevelingResult l3 = level_surface(p3, LevelingSpec{Leveling::Polynomial, 3});
      form = {{"sq_m", lev.rms_after},
              {"sq_poly3_m", l3.rms_after},
              {"slope_rms", rms_slope(s)},
              {"slope_rms_poly3", rms_slope(p3)}};
    }
    const RgbImage preview = render_height_preview(s, 480);
    const nlohmann::json scan = {{"nx", s.nx}, {"ny", s.ny}, {"dx_m", s.dx}, {"dy_m", s.dy}};
    nlohmann::json rec = {{"path", path},
                          {"name", file_name(path)},
                          {"format", s.meta.format},
                          {"instrument", s.meta.instrument},
                          {"date", s.meta.date},
                          {"comment", s.meta.comment},
                          {"z_unit_in_file", s.meta.z_unit_in_file},
                          {"leveling", s.meta.leveling},
                          {"leveling_description", lev.description},
                          {"rms_before_leveling_m", lev.rms_before},
                          {"rms_after_leveling_m", lev.rms_after},
                          {"stats", stats_record(s, st)},
                          {"form_check", form}};
    std::vector<WorkResult> shares;
    about_file(path, [&] {
      shares.push_back(pack_partial(naive.estimate(s), scan));
      shares.push_back(pack_partial(filtered.estimate(s), scan));
      if (kirchhoff) {
        KirchhoffOptions k = ko;
        if (local)
          k.progress = [&, i](double f) {
            dk_progress((static_cast<double>(i) + f) / static_cast<double>(paths.size()));
          };
        shares.push_back(pack_partial(KirchhoffAccumulator(k).estimate(s), scan));
      }
    });
    // One message: the shares' numbers one after another (each preceded by its length), a JSON
    // line (record, the shares' texts), then the preview's bytes.
    WorkResult r;
    nlohmann::json texts = nlohmann::json::array();
    for (auto& sh : shares) {
      r.values.push_back(static_cast<double>(sh.values.size()));
      r.values.insert(r.values.end(), sh.values.begin(), sh.values.end());
      texts.push_back(std::move(sh.text));
    }
    r.text = nlohmann::json{{"record", rec},
                            {"scan", scan},
                            {"shares", texts},
                            {"preview", {preview.width, preview.height}}}
                 .dump();  // one line: dump() escapes control characters
    r.text += '\n';
    r.text.append(preview.pixels.begin(), preview.pixels.end());
    return r;
  };
  nlohmann::json inputs = nlohmann::json::array();
  auto consume = [&](std::size_t i, WorkResult&& r) {
    const auto eol = r.text.find('\n');
    if (eol == std::string::npos) throw std::runtime_error("predict: short scan message");
    const auto head = nlohmann::json::parse(r.text.substr(0, eol));
    const std::string& path = paths[i];
    const auto& scan = head.at("scan");
    const double dx = scan.at("dx_m").get<double>(), dy = scan.at("dy_m").get<double>();
    c.log("inputs: [" + std::to_string(i + 1) + "/" + std::to_string(paths.size()) + "] " + path +
          " (" + std::to_string(scan.at("nx").get<std::size_t>()) + " x " +
          std::to_string(scan.at("ny").get<std::size_t>()) + ")" +
          (kirchhoff ? ": naive, filtered, D_K" : ": naive, filtered"));
    if (o.filter_sigma_m < std::max(dx, dy))
      c.warn("filter_sigma_below_spacing",
             "filter sigma " + format_length(o.filter_sigma_m) + " is below the sample spacing " +
                 format_length(std::max(dx, dy)) + " of " + path +
                 ": the grid does not resolve the filter, so the filtered NDF depends on the "
                 "sampling more than on the chosen sigma",
             "give --filter-sigma of a few sample spacings (at least " +
                 format_length(2 * std::max(dx, dy)) +
                 "), or compare with the naive NDF (its rms slopes are in the NDF table)");
    warn_scan(c, path, head.at("record"));
    RgbImage preview(head.at("preview").at(0).get<std::size_t>(),
                     head.at("preview").at(1).get<std::size_t>());
    if (r.text.size() - eol - 1 != preview.pixels.size())
      throw std::runtime_error("predict: preview size does not match");
    std::copy(r.text.begin() + static_cast<std::ptrdiff_t>(eol + 1), r.text.end(),
              preview.pixels.begin());
    char name[64];
    std::snprintf(name, sizeof name, "img/height_%02zu.png", i + 1);
    write_png(c.path(name), preview);
    // The shares, in the order they were packed.
    std::size_t at = 0, k = 0;
    auto next_share = [&] {
      if (at >= r.values.size() || k >= head.at("shares").size())
        throw std::runtime_error("predict: short scan message");
      const auto len = static_cast<std::size_t>(r.values[at]);
      if (at + 1 + len > r.values.size()) throw std::runtime_error("predict: short scan message");
      WorkResult sh;
      sh.values.assign(r.values.begin() + static_cast<std::ptrdiff_t>(at + 1),
                       r.values.begin() + static_cast<std::ptrdiff_t>(at + 1 + len));
      sh.text = head.at("shares").at(k).get<std::string>();
      at += 1 + len;
      ++k;
      return sh;
    };
    naive.merge(unpack_ndf_partial(next_share(), o.ndf_resolution));
    filtered.merge(unpack_ndf_partial(next_share(), o.ndf_resolution));
    if (kirchhoff) kirchhoff->merge(unpack_kirchhoff_partial(next_share(), o.ndf_resolution));
    nlohmann::json rec = head.at("record");
    rec["preview"] = name;
    inputs.push_back(std::move(rec));
  };
  const WorkStats st = distribute_scans(paths, o.read, compute, consume);
  if (!mpi_is_root()) return inputs;  // rank 0 has the NDFs
  if (stats) *stats = st;
  ndfs.naive = std::make_unique<TabulatedNdf>(naive.result());
  ndfs.filtered = std::make_unique<TabulatedNdf>(filtered.result());
  if (kirchhoff) take_kirchhoff(*kirchhoff, ndfs);
  return inputs;
}

KirchhoffOptions dk_options(const PredictOptions& o) {
  KirchhoffOptions ko = o.kirchhoff_options;
  ko.wavelength_q = o.wavelength_m;
  ko.resolution = o.ndf_resolution;
  return ko;
}

void take_kirchhoff(const KirchhoffAccumulator& acc, NdfSet& ndfs) {
  ndfs.kirchhoff = std::make_unique<TabulatedNdf>(acc.result());
  ndfs.kirchhoff_stack = acc.stack_result();
  ndfs.kirchhoff_raw_integral = acc.raw_integral();
  ndfs.kirchhoff_aliased_fraction = acc.aliased_fraction();
  ndfs.kirchhoff_patches = acc.patches();
  ndfs.kirchhoff_supersample = acc.supersample();
}

namespace {

// Smallest and largest rms slope of a table (principal axes of the slope covariance).
std::pair<double, double> rms_slope_range(const TabulatedNdf& t) {
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(t.slope_covariance());
  return {std::sqrt(std::max(es.eigenvalues()(0), 0.0)),
          std::sqrt(std::max(es.eigenvalues()(1), 0.0))};
}

constexpr double kZoomSigmas = 12;  // zoom window half-width in rms slopes of the widest axis

}  // namespace

void stage_zoom(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs) {
  const auto& o = c.opt;
  const std::size_t n = o.ndf_resolution;
  auto zoom = [&](const TabulatedNdf* from, NdfMethod method, std::unique_ptr<TabulatedNdf>& out) {
    // A lobe a few nodes wide also has its rms slopes inflated by the bilinear splat (variance
    // Delta^2 / 6 per axis), so the window is set from an upper bound and refined until the
    // lobe spans kLobeNodes (at most three passes).
    for (int pass = 0; from && pass < 3; ++pass) {
      const auto [s_min, s_max] = rms_slope_range(*from);
      if (!(4 * s_min / from->spacing() < kLobeNodes)) break;  // resolved
      const Eigen::Vector3d mn = from->mean_normal();
      const double half_fit = 0.2 * std::max(s_min, 1e-9) * static_cast<double>(n - 1);
      const double half =
          std::min({kZoomSigmas * std::max(s_max, 1e-9), half_fit, from->window().half / 2});
      // A square window cannot hold a lobe far more elongated than it is wide (a grating's or a
      // brushed surface's line of normals): then no zoom, and the table warning stands.
      if (half < 3 * s_max) {
        c.log(std::string("inputs: no zoomed ") +
              (method == NdfMethod::Naive ? "naive" : "filtered") +
              " NDF: the lobe is too elongated for a square window at this resolution");
        break;
      }
      NdfEstimateOptions eo;
      eo.method = method;
      eo.resolution = n;
      eo.filter_sigma_m = o.filter_sigma_m;
      eo.window = zoom_window(mn.x(), mn.y(), half);
      char b[200];
      std::snprintf(b, sizeof b,
                    "inputs: %s NDF on a zoomed window (centre %.4g, %.4g, half-width %.4g; "
                    "node spacing %.3g)",
                    method == NdfMethod::Naive ? "naive" : "filtered", eo.window.cx, eo.window.cy,
                    eo.window.half, 2 * eo.window.half / double(n - 1));
      c.log(b);
      NdfAccumulator acc(eo);
      auto compute = [&](std::size_t, const std::string& path, Surface& s) {
        about_file(path, [&] { level_surface(s, o.leveling); });
        return pack_partial(acc.estimate(s), nlohmann::json::object());
      };
      auto consume = [&](std::size_t, WorkResult&& r) { acc.merge(unpack_ndf_partial(r, n)); };
      distribute_scans(paths, o.read, compute, consume);
      try {
        out = std::make_unique<TabulatedNdf>(acc.result());
      } catch (const InputError&) {
        break;  // nothing fell inside the window: keep what there is (the warning stands)
      }
      from = out.get();
    }
  };
  zoom(ndfs.naive.get(), NdfMethod::Naive, ndfs.naive_zoom);
  zoom(ndfs.filtered.get(), NdfMethod::Filtered, ndfs.filtered_zoom);
}

nlohmann::json stage_ndfs(const Context& c, const NdfSet& ndfs) {
  nlohmann::json out = nlohmann::json::object();
  const std::pair<const char*, const TabulatedNdf*> list[] = {{"naive", ndfs.naive.get()},
                                                              {"filtered", ndfs.filtered.get()},
                                                              {"kirchhoff", ndfs.kirchhoff.get()}};
  for (const auto& [name, ndf] : list) {
    if (!ndf) continue;
    c.log(std::string("NDFs: writing ") + name);
    const std::string table = std::string("ndf_") + name + ".npy";
    const std::string preview = std::string("img/ndf_") + name + ".png";
    if (ndf == ndfs.kirchhoff.get() && ndfs.kirchhoff_stack.size() > 1) {
      std::size_t primary = 0;
      while (ndfs.kirchhoff_stack[primary].meta.wavelength_m != ndf->meta.wavelength_m) ++primary;
      write_ndf_stack(ndfs.kirchhoff_stack, primary, c.path(table));
    } else {
      write_ndf(*ndf, c.path(table));
    }
    NdfPreviewOptions po;
    po.size = 300;
    po.zoom = true;
    write_ndf_preview(*ndf, c.path(preview), po);
    const auto mn = ndf->mean_normal();
    const auto pk = ndf->peak();
    const Eigen::Matrix2d cov = ndf->slope_covariance();
    // Principal slope axes: the axis of the smaller rms slope is the one scratches run along.
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(cov);
    const Eigen::Vector2d along = es.eigenvectors().col(0);  // smaller eigenvalue first
    double angle = std::atan2(along.y(), along.x());
    if (angle > M_PI / 2) angle -= M_PI;
    if (angle <= -M_PI / 2) angle += M_PI;
    const double s_min = std::sqrt(std::max(es.eigenvalues()(0), 0.0));
    const double s_max = std::sqrt(std::max(es.eigenvalues()(1), 0.0));
    const double sx = ndf->rms_slope(0), sy = ndf->rms_slope(M_PI / 2);
    const TabulatedNdf* zoom = ndf == ndfs.filtered.get() ? ndfs.filtered_zoom.get()
                               : ndf == ndfs.naive.get()  ? ndfs.naive_zoom.get()
                                                          : nullptr;
    warn_table(c, name, *ndf, s_min, zoom);
    nlohmann::json j = {{"method", ndf->meta.method},
                        {"file", table},
                        {"preview", preview},
                        {"resolution", ndf->resolution()},
                        {"integral", ndf->integral()},
                        {"mean_normal", {mn.x(), mn.y(), mn.z()}},
                        {"mean_normal_tilt_rad", std::acos(std::clamp(mn.z(), -1.0, 1.0))},
                        {"peak", {pk.x(), pk.y(), pk.z()}},
                        {"slope_rms_x", sx},
                        {"slope_rms_y", sy},
                        {"beckmann_alpha_x", std::sqrt(2.0) * sx},
                        {"beckmann_alpha_y", std::sqrt(2.0) * sy},
                        {"slope_rms_min", s_min},
                        {"slope_rms_max", s_max},
                        {"anisotropy", s_min > 0 ? s_max / s_min : 1.0},
                        {"smooth_axis_angle_rad", angle},
                        {"samples_used", ndf->meta.samples_used},
                        {"samples_skipped", ndf->meta.samples_skipped},
                        {"projected_area_m2", ndf->meta.projected_area_m2},
                        {"filter_sigma_m", ndf->meta.filter_sigma_m},
                        {"wavelength_m", ndf->meta.wavelength_m},
                        {"notes", ndf->meta.notes}};
    if (zoom) {
      // The zoomed table the fits use: its window, the share of the normals inside it and its
      // own rms slopes (the whole-disk table's are inflated by the splat when the lobe spans a
      // few nodes).
      const std::string zt = std::string("ndf_") + name + "_zoom.npy";
      write_ndf(*zoom, c.path(zt));
      const auto& w = zoom->window();
      j["zoom"] = {{"file", zt},
                   {"window", {{"x", {w.x0(), w.x1()}}, {"y", {w.y0(), w.y1()}}}},
                   {"node_spacing", zoom->spacing()},
                   {"window_mass", zoom->meta.window_mass},
                   {"slope_rms_x", zoom->rms_slope(0)},
                   {"slope_rms_y", zoom->rms_slope(M_PI / 2)}};
    }
    if (ndf == ndfs.kirchhoff.get()) {
      j["raw_integral"] = ndfs.kirchhoff_raw_integral;
      j["aliased_fraction"] = ndfs.kirchhoff_aliased_fraction;
      j["patches"] = ndfs.kirchhoff_patches;
      j["patch_m"] = {c.opt.kirchhoff_options.patch_x, c.opt.kirchhoff_options.patch_y};
      j["integration"] = to_string(c.opt.kirchhoff_options.integration);
      j["window"] = to_string(c.opt.kirchhoff_options.window);
      j["supersample"] = ndfs.kirchhoff_supersample;
      const double raw = ndfs.kirchhoff_raw_integral;
      if (std::abs(raw - 1) > kRawIntegralWarn) {
        char b[96];
        std::snprintf(b, sizeof b, "%.4g (%+.1f%%)", raw, 100 * (raw - 1));
        c.warn("kirchhoff_integral",
               std::string("the Kirchhoff D_K integrated to ") + b +
                   " before it was normalised to 1: the discretisation misses part of the "
                   "scattered power",
               "treat D_K's shape as approximate; a larger --patch or a finer --resolution "
               "brings the raw integral nearer 1");
      }
    }
    out[name] = std::move(j);
  }
  return out;
}

}  // namespace microbrdf::report

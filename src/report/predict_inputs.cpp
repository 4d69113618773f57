// predict stages 1-2: read, level and describe every scan (one in memory at a time), accumulate
// the naive, filtered and (when asked) Kirchhoff NDFs, write the tables and their previews.
#include <Eigen/Eigenvalues>
#include <cmath>
#include <cstdio>

#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/ndf_preview.hpp"
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

}  // namespace

nlohmann::json stage_inputs(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs) {
  const auto& o = c.opt;
  NdfEstimateOptions no;
  no.method = NdfMethod::Naive;
  no.resolution = o.ndf_resolution;
  NdfEstimateOptions fo = no;
  fo.method = NdfMethod::Filtered;
  fo.filter_sigma_m = o.filter_sigma_m;
  NdfAccumulator naive(no), filtered(fo);
  std::unique_ptr<KirchhoffAccumulator> kirchhoff;
  if (o.kirchhoff) {
    KirchhoffOptions ko;
    ko.wavelength_q = o.wavelength_m;
    ko.resolution = o.ndf_resolution;
    ko.patch_x = o.kirchhoff_patch_x_m;
    ko.patch_y = o.kirchhoff_patch_y_m;
    // D_K is the slowest step (tens of seconds on a 2048 x 1024 scan): report it in 10 % steps.
    ko.progress = [&c, last = -1](double f) mutable {
      const int step = static_cast<int>(f * 10);
      if (step == last) return;
      last = step;
      c.log("inputs: kirchhoff D_K " + std::to_string(step * 10) + "%");
    };
    kirchhoff = std::make_unique<KirchhoffAccumulator>(ko);
  }
  nlohmann::json inputs = nlohmann::json::array();
  for_each_scan(paths, o.read, [&](std::size_t i, const std::string& path, Surface& s) {
    c.log("inputs: [" + std::to_string(i + 1) + "/" + std::to_string(paths.size()) + "] " + path +
          " (" + std::to_string(s.nx) + " x " + std::to_string(s.ny) + ")");
    if (o.filter_sigma_m < std::max(s.dx, s.dy))
      c.log("inputs: warning: filter sigma " + format_length(o.filter_sigma_m) +
            " is below the sample spacing " + format_length(std::max(s.dx, s.dy)) + " of " + path +
            ": the filtered NDF approaches the naive one");
    const LevelingResult lev = level_surface(s, o.leveling);
    const SurfaceStats st = compute_stats(s);
    char preview[64];
    std::snprintf(preview, sizeof preview, "img/height_%02zu.png", i + 1);
    write_png(c.path(preview), render_height_preview(s, 480));
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
                          {"preview", preview}};
    c.log("inputs: NDFs of " + file_name(path) + (kirchhoff ? " (naive, filtered, D_K)" : ""));
    naive.add(s);
    filtered.add(s);
    if (kirchhoff) kirchhoff->add(s);
    inputs.push_back(std::move(rec));
  });
  ndfs.naive = std::make_unique<TabulatedNdf>(naive.result());
  ndfs.filtered = std::make_unique<TabulatedNdf>(filtered.result());
  if (kirchhoff) {
    ndfs.kirchhoff = std::make_unique<TabulatedNdf>(kirchhoff->result());
    ndfs.kirchhoff_raw_integral = kirchhoff->raw_integral();
    ndfs.kirchhoff_aliased_fraction = kirchhoff->aliased_fraction();
    ndfs.kirchhoff_patches = kirchhoff->patches();
  }
  return inputs;
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
    write_ndf(*ndf, c.path(table));
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
    if (ndf == ndfs.kirchhoff.get()) {
      j["raw_integral"] = ndfs.kirchhoff_raw_integral;
      j["aliased_fraction"] = ndfs.kirchhoff_aliased_fraction;
      j["patches"] = ndfs.kirchhoff_patches;
      j["patch_m"] = {c.opt.kirchhoff_patch_x_m, c.opt.kirchhoff_patch_y_m};
    }
    out[name] = std::move(j);
  }
  return out;
}

}  // namespace microbrdf::report

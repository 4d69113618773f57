// `predict`: options check, the staging folder (nothing half-written is ever left), the order of
// the stages, summary.json and report.html.
#include "microbrdf/predict.hpp"

#include <ceres/version.h>
#include <embree3/rtcore_config.h>
#include <fftw3.h>
#include <sys/resource.h>
#include <unistd.h>

#include <Eigen/Core>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/cairo_runtime.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/interrupt.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/run_inputs.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"
#include "microbrdf/version.hpp"
#include "report/predict_measured.hpp"
#include "report/predict_multiple_scattering.hpp"
#include "report/predict_ndf_compare.hpp"
#include "report/predict_stages.hpp"

namespace fs = std::filesystem;

namespace microbrdf {
namespace {

using Clock = std::chrono::steady_clock;
// CPU seconds of the whole process (all threads, user + system): what a stage costs whatever
// share of a loaded machine it got (wall times alone mislead there).
double process_cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         1e-6 * static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// True when `dir` holds nothing, or what an earlier predict wrote (summary.json is there).
bool replaceable(const fs::path& dir) {
  if (!fs::exists(dir)) return true;
  if (!fs::is_directory(dir)) return false;
  if (fs::is_empty(dir)) return true;
  return fs::exists(dir / "summary.json") && fs::exists(dir / "report.html");
}

/// The staging folder beside the target: removed unless committed; commit() swaps it in.
class Staging {
 public:
  explicit Staging(fs::path target) : target_(std::move(target)) {
    const fs::path parent = target_.has_parent_path() ? target_.parent_path() : fs::path(".");
    std::error_code ec;
    fs::create_directories(parent, ec);
    if (ec) throw FileError(parent.string(), "cannot create the folder: " + ec.message());
    const std::string stem = target_.filename().string();
    tmp_ = parent / ("." + stem + ".partial-" + std::to_string(::getpid()));
    register_temporary(tmp_.string());  // removed on SIGINT / SIGTERM too
    fs::remove_all(tmp_, ec);
    fs::create_directories(tmp_ / "img", ec);
    if (ec) throw FileError(tmp_.string(), "cannot create the staging folder: " + ec.message());
  }
  ~Staging() {
    if (!committed_) {
      std::error_code ec;
      fs::remove_all(tmp_, ec);
      unregister_temporary(tmp_.string());
    }
  }
  Staging(const Staging&) = delete;
  Staging& operator=(const Staging&) = delete;
  const fs::path& dir() const { return tmp_; }
  // The swap runs with interrupts held off: an interrupt never leaves the target moved aside.
  void commit() {
    without_interrupts([&] { swap_in(); });
  }

 private:
  void swap_in() {
    std::error_code ec;
    if (!replaceable(target_))
      throw FileError(target_.string(), "exists and is not a predict output; not replaced");
    refuse_replacing_inputs_under(target_.string());  // an earlier report holding a scan read now
    fs::path old;
    if (fs::exists(target_)) {
      old = target_;
      old += ".old-" + std::to_string(::getpid());
      fs::rename(target_, old, ec);
      if (ec)
        throw FileError(target_.string(), "cannot move the earlier output aside: " + ec.message());
    }
    fs::rename(tmp_, target_, ec);
    if (ec) {
      if (!old.empty()) fs::rename(old, target_, ec);
      throw FileError(target_.string(), "cannot rename the staging folder: " + ec.message());
    }
    committed_ = true;
    unregister_temporary(tmp_.string());
    if (!old.empty()) fs::remove_all(old, ec);
  }

  fs::path target_, tmp_;
  bool committed_ = false;
};

void check_inputs_exist(const std::vector<std::string>& paths, const char* what) {
  for (const auto& p : paths) {
    if (!fs::exists(p)) throw FileError::missing(p, what);
    if (fs::is_directory(p)) throw FileError(p, std::string("is a folder (") + what + ")");
  }
}

nlohmann::json settings_json(const PredictOptions& o, const OpticalConstants& m) {
  nlohmann::json ti = nlohmann::json::array();
  for (double t : o.slice_theta_i_rad) ti.push_back(t);
  return {{"inputs", o.inputs},
          {"spacing_override_m",
           {o.read.dx ? nlohmann::json(*o.read.dx) : nlohmann::json("from the file"),
            o.read.dy ? nlohmann::json(*o.read.dy) : nlohmann::json("from the file")}},
          {"leveling", o.leveling.name()},
          {"metal",
           o.material.form == MaterialSpec::Form::Metal ? o.material.metal : o.material.describe()},
          {"optical_constants", {{"name", m.name}, {"source", m.source}}},
          {"filter_sigma_m", o.filter_sigma_m},
          {"filter_sigma_auto", o.filter_sigma_auto},
          {"filter_sigma_sweep_resolution", o.filter_sigma_sweep_resolution},
          {"render_ndf", o.render_ndf},
          {"theory", o.theory},
          {"multiple_scattering", o.multiple_scattering},
          {"ndf_resolution", o.ndf_resolution},
          {"kirchhoff", o.kirchhoff},
          {"wavelength_m", o.wavelength_m},
          {"kirchhoff_patch_m", {o.kirchhoff_options.patch_x, o.kirchhoff_options.patch_y}},
          {"kirchhoff_integration", to_string(o.kirchhoff_options.integration)},
          {"kirchhoff_window", to_string(o.kirchhoff_options.window)},
          {"kirchhoff_supersample", o.kirchhoff_options.supersample == 0
                                        ? std::string("auto")
                                        : std::to_string(o.kirchhoff_options.supersample)},
          {"slice_theta_i_rad", ti},
          {"instrument_fwhm_rad", o.instrument_fwhm_rad},
          {"instrument", o.instrument_path.empty() ? "none" : o.instrument_path},
          {"slice_samples", o.slice_samples},
          {"render", o.render},
          {"envmap", o.envmap_path.empty() ? "none (built-in area lights)" : o.envmap_path},
          {"envmap_scale", o.envmap_scale},
          {"render_width", o.render_width},
          {"render_spp", o.render_spp},
          {"renders", !o.render         ? "none"
                      : o.render_models ? "all"
                                        : "measured"},
          {"strips_along", o.strips_along},
          {"strips_across", o.strips_across},
          {"texel_m", o.texel_m},
          {"texture_size", o.texture_size},
          {"texel_ndf_resolution", o.texel_resolution},
          {"seed", o.seed}};
}

nlohmann::json material_json(const OpticalConstants& m) {
  const Spectrum r0 = m.normal_reflectance_spectrum();
  const Eigen::Vector3d xyz = reflectance_to_xyz(r0);
  const Eigen::Vector3d rgb = xyz_to_linear_srgb(xyz);
  const auto c8 = linear_srgb_to_srgb8(rgb);
  return {{"name", m.name},
          {"source", m.source},
          {"n_555nm", m.n(555e-9)},
          {"k_555nm", m.k(555e-9)},
          {"r0_555nm", r0(555e-9)},
          {"xyz_d65", {xyz[0], xyz[1], xyz[2]}},
          {"linear_srgb", {rgb[0], rgb[1], rgb[2]}},
          {"srgb_hex", srgb8_hex(c8)}};
}

/// Non-finite numbers become null, so the summary in memory is what summary.json holds (JSON has
/// no NaN; nlohmann would write null anyway).
void nulls_for_nonfinite(nlohmann::json& j) {
  if (j.is_number_float() && !std::isfinite(j.get<double>())) {
    j = nullptr;
  } else if (j.is_structured()) {
    for (auto& e : j) nulls_for_nonfinite(e);
  }
}

}  // namespace

namespace report {
nlohmann::json versions() {
  detail::load_cairo();  // (its version string; the report's plots load it anyway)
  char eigen[32];
  std::snprintf(eigen, sizeof eigen, "%d.%d.%d", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION,
                EIGEN_MINOR_VERSION);
  return {{"microbrdf", version()},
          {"compiler", std::string("gcc/clang ") + __VERSION__},
          {"eigen", eigen},
          {"ceres", CERES_VERSION_STRING},
          {"embree", RTC_VERSION_STRING},
          {"fftw", std::string(fftw_version)},
          {"cairo", std::string(cairo_version_string())},
          {"nlohmann_json", std::to_string(NLOHMANN_JSON_VERSION_MAJOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_MINOR) + "." +
                                std::to_string(NLOHMANN_JSON_VERSION_PATCH)}};
}
}  // namespace report

void check_predict_options(const PredictOptions& o) {
  if (o.inputs.empty()) throw InputError("no scans given");
  if (!(o.filter_sigma_m > 0)) throw InputError("filter sigma must be > 0");
  if (o.filter_sigma_sweep_resolution < 17 || o.filter_sigma_sweep_resolution > 8193)
    throw InputError("filter sigma sweep resolution must lie in 17..8193");
  if (o.render_ndf != "naive" && o.render_ndf != "filtered" && o.render_ndf != "kirchhoff")
    throw InputError("render NDF '" + o.render_ndf + "': naive | filtered | kirchhoff");
  if (o.theory != "auto" && o.theory != "geometric" && o.theory != "kirchhoff" &&
      o.theory != "rayleigh-rice")
    throw InputError("theory '" + o.theory + "': auto | geometric | kirchhoff | rayleigh-rice");
  if (o.multiple_scattering != "auto" && o.multiple_scattering != "on" &&
      o.multiple_scattering != "off")
    throw InputError("multiple scattering '" + o.multiple_scattering + "': auto | on | off");
  if (o.render_ndf == "kirchhoff" && o.theory != "auto" && o.theory != "kirchhoff")
    throw InputError("--render-ndf kirchhoff contradicts --theory " + o.theory);
  if (o.ndf_resolution < 65 || o.ndf_resolution > 4097)
    throw InputError("NDF resolution must lie in 65..4097");
  if (!(o.wavelength_m > 100e-9 && o.wavelength_m < 20e-6))
    throw InputError("wavelength must lie in 100 nm .. 20 um");
  if (o.slice_theta_i_rad.empty()) throw InputError("give at least one slice angle");
  for (double t : o.slice_theta_i_rad)
    if (!(t >= 0 && t < M_PI / 2)) throw InputError("slice angles must lie in [0, 90) deg");
  if (o.slice_samples < 11 || o.slice_samples > 100001)
    throw InputError("slice samples must lie in 11..100001");
  if (o.render_width < 16 || o.render_width > 4096)
    throw InputError("render width must lie in 16..4096 pixels");
  if (o.render_spp < 1 || o.render_spp > 65536) throw InputError("render spp must lie in 1..65536");
  if (!(o.envmap_scale > 0)) throw InputError("environment map scale must be > 0");
  if (!o.envmap_path.empty()) check_inputs_exist({o.envmap_path}, "environment map");
  if (o.strips_along.empty() != o.strips_across.empty())
    throw InputError("texture synthesis needs both strips: --strips ALONG ACROSS");
  if (!o.strips_along.empty()) {
    check_inputs_exist(expand_scan_inputs(o.strips_along), "strip along the brushing");
    check_inputs_exist(expand_scan_inputs(o.strips_across), "strip across the brushing");
    if (!(o.texel_m > 0)) throw InputError("texel size must be > 0");
    if (o.texture_size < 8 || o.texture_size > 8192)
      throw InputError("texture size must lie in 8..8192 texels");
  }
  report::check_measured_option(o);
  (void)optical_constants(o.material);  // an unknown metal or unreadable CSV fails here
  const auto paths = expand_scan_inputs(o.inputs);
  check_inputs_exist(paths, "scan");
}

namespace {

// --filter-sigma auto: every rank runs the sweep (the same numbers everywhere) and goes on with
// the chosen sigma.
PredictOptions with_sigma(const PredictOptions& o, const std::optional<FilterSigmaAuto>& sweep) {
  PredictOptions r = o;
  if (sweep) r.filter_sigma_m = sweep->sigma_m;
  return r;
}

// Ranks other than 0 under mpirun: the per-scan stage only (rank 0 does everything else).
PredictResult predict_worker(const PredictOptions& given) {
  const auto paths = expand_scan_inputs(given.inputs);
  const PredictOptions o = with_sigma(given, report::filter_sigma_sweep(given, paths, nullptr));
  report::Context c{o, {}};
  report::NdfSet ndfs;
  report::stage_inputs(c, paths, ndfs);
  return {};
}

// Keeps library calls on this rank (texel fits of the strips) after the distributed stage.
struct SoloAfterwards {
  bool before = mpi_solo();
  ~SoloAfterwards() { mpi_set_solo(before); }
};

PredictResult predict_staged(const PredictOptions& given, const std::string& out_dir_given) {
  const auto t_start = Clock::now();
  const double cpu_start = process_cpu_seconds();
  check_predict_options(given);
  if (!mpi_is_root()) return predict_worker(given);
  // "out/" names the folder "out": the staging folder goes beside it, not into it.
  std::string out_dir = out_dir_given;
  while (out_dir.size() > 1 && out_dir.back() == '/') out_dir.pop_back();
  if (out_dir.empty()) throw InputError("no output folder given");
  const std::string leaf = fs::path(out_dir).filename().string();
  if (leaf == "." || leaf == ".." || out_dir == "/")
    throw InputError("output folder '" + out_dir_given +
                     "': give the folder a name (e.g. -o report)");
  if (!replaceable(out_dir))
    throw FileError(out_dir,
                    "exists and is not a predict output (no summary.json/report.html); "
                    "choose another folder or remove it");
  const auto t_sweep = Clock::now();
  if (given.filter_sigma_auto && given.log)
    given.log("[0/6] --filter-sigma auto: filtered NDFs against D_K over a sweep of sigma");
  const auto sweep = report::filter_sigma_sweep(given, expand_scan_inputs(given.inputs), given.log);
  const double sweep_s = seconds_since(t_sweep);
  const PredictOptions o = with_sigma(given, sweep);
  const OpticalConstants material = optical_constants(o.material);
  const auto fresnel = make_fresnel(o.material);
  const auto paths = expand_scan_inputs(o.inputs);

  Staging staging{fs::path(out_dir)};
  const OutputGroup::Bypass whole_folder;  // the staging folder is the commit unit
  report::Context c{o, staging.dir()};
  nlohmann::json timing = nlohmann::json::object();
  if (sweep) timing["filter_sigma_auto_s"] = sweep_s;
  nlohmann::json summary;
  summary["microbrdf"] = {{"command", "predict"}, {"report_format", 1}};
  summary["versions"] = report::versions();
  summary["settings"] = settings_json(o, material);
  summary["material"] = material_json(material);

  // Wall time as "<stage>_s" and process CPU time (all threads) as "<stage>_cpu_s".
  auto timed = [&](const char* name, auto&& fn) {
    const auto t0 = Clock::now();
    const double c0 = process_cpu_seconds();
    fn();
    timing[std::string(name) + "_s"] = seconds_since(t0);
    timing[std::string(name) + "_cpu_s"] = process_cpu_seconds() - c0;
  };
  report::NdfSet ndfs;
  std::vector<FitResult> fits;
  c.log("[1/6] inputs and NDFs (" + std::to_string(paths.size()) + " scan(s))");
  WorkStats work;
  timed("inputs", [&] { summary["inputs"] = report::stage_inputs(c, paths, ndfs, &work); });
  // How the per-scan stage was shared over MPI ranks (like "timing", it varies between runs).
  summary["mpi"] = work.to_json("scans_per_rank");
  summary["regime"] = report::stage_regime(c, summary["inputs"]);
  const SoloAfterwards solo;
  mpi_set_solo(true);
  timed("theory", [&] { report::stage_theory(c, paths, ndfs, summary["regime"]); });
  timed("ndf_zoom", [&] { report::stage_zoom(c, paths, ndfs); });
  timed("ndf_write", [&] { summary["ndf"] = report::stage_ndfs(c, ndfs); });
  timed("ndf_comparison", [&] {
    summary["ndf_comparison"] = report::stage_ndf_comparison(c, ndfs, sweep ? &*sweep : nullptr);
  });
  c.log("[2/6] fits");
  timed("fits", [&] { summary["fits"] = report::stage_fits(c, ndfs, fits, timing); });
  timed("ndf_cuts", [&] { summary["ndf_cuts"] = report::stage_ndf_slices(c, ndfs, fits); });
  timed("exports", [&] { summary["exports"] = report::stage_exports(c, fits); });
  timed("energy_loss",
        [&] { summary["multiple_scattering"] = report::stage_energy_loss(c, ndfs); });
  ndfs.multiple_scattering = summary["multiple_scattering"].value("in_comparison_strip", false);
  c.log("[3/6] BRDF slices");
  const auto measured = report::measured_brdf(ndfs, fresnel, material, fits);
  timed("brdf", [&] { summary["brdf"] = report::stage_brdf(c, ndfs, fits, fresnel, measured); });
  c.log("[4/6] renders");
  std::vector<report::ReferenceRender> references;
  const std::vector<report::NamedBrdf> models = report::model_brdfs(ndfs, fits, fresnel);
  timed("renders", [&] {
    summary["renders"] = report::stage_render(c, measured, models, timing, &references);
  });
  if (o.render && o.render_models)
    timed("render_comparison", [&] {
      summary["render_comparison"] = report::stage_compare_renders(c, models, references);
    });
  c.log("[5/6] texture");
  timed("texture", [&] { summary["texture"] = report::stage_texture(c, fresnel, timing); });
  if (!o.measured_path.empty())
    timed("measured", [&] { summary["measured"] = report::stage_measured(c, ndfs); });
  c.log("[6/6] report");
  summary["warnings"] = *c.warnings;  // every warning the run printed, in order

  nlohmann::json files = nlohmann::json::array();
  for (const auto& e : fs::recursive_directory_iterator(staging.dir()))
    if (e.is_regular_file()) files.push_back(fs::relative(e.path(), staging.dir()).string());
  std::sort(files.begin(), files.end());
  files.push_back("report.html");
  files.push_back("summary.json");
  summary["outputs"] = files;
  timing["total_s"] = seconds_since(t_start);
  timing["total_cpu_s"] = process_cpu_seconds() - cpu_start;
  summary["timing"] = timing;

  nulls_for_nonfinite(summary);
  const std::string html = render_report_html(summary, staging.dir().string());
  write_file_atomic(c.path("summary.json"), summary.dump(2) + "\n");
  write_file_atomic(c.path("report.html"), html);
  staging.commit();

  PredictResult r;
  r.dir = out_dir;
  r.report_path = (fs::path(out_dir) / "report.html").string();
  r.summary_path = (fs::path(out_dir) / "summary.json").string();
  r.summary = std::move(summary);
  return r;
}

}  // namespace

PredictResult predict(const PredictOptions& o, const std::string& out_dir) {
  try {
    return predict_staged(o, out_dir);
  } catch (const FileError& e) {
    // A failed write names the user's folder, not the hidden staging folder.
    std::string t = out_dir;
    while (t.size() > 1 && t.back() == '/') t.pop_back();
    const fs::path target(t);
    const std::string staged =
        ((target.has_parent_path() ? target.parent_path() : fs::path(".")) /
         ("." + target.filename().string() + ".partial-" + std::to_string(::getpid())))
            .string();
    if (!e.path().starts_with(staged)) throw;
    throw FileError(t + e.path().substr(staged.size()), e.problem());
  }
}

}  // namespace microbrdf

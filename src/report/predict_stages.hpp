#pragma once
// The stages of `predict` (predict.hpp). Each writes its files into the staging folder and
// returns its part of summary.json; paths in the JSON are relative to the output folder.
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/brdf.hpp"
#include "microbrdf/brdf_spec.hpp"
#include "microbrdf/distribute.hpp"
#include "microbrdf/fit.hpp"
#include "microbrdf/fresnel.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/predict.hpp"
#include "microbrdf/psd.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf::report {

struct Context {
  const PredictOptions& opt;
  std::filesystem::path dir;  ///< staging folder (becomes the output folder)
  void log(const std::string& line) const {
    if (opt.log) opt.log(line);
  }
  std::string path(const std::string& rel) const { return (dir / rel).string(); }
  /// The run's warnings, in the order they were raised: summary.json "warnings", the box at the
  /// top of the report (docs/report.md lists the codes).
  std::shared_ptr<nlohmann::json> warnings =
      std::make_shared<nlohmann::json>(nlohmann::json::array());
  /// Records a warning ({code, message, what_to_do}) and prints it as a progress line.
  void warn(const std::string& code, const std::string& message,
            const std::string& what_to_do) const {
    log("warning: " + message + " -- " + what_to_do);
    warnings->push_back({{"code", code}, {"message", message}, {"what_to_do", what_to_do}});
  }
  /// A progress callback for a fraction 0..1 of long work: logs "<what> N%" in 10 % steps, once
  /// per step.
  std::function<void(double)> decile_log(const std::string& what) const {
    return [this, what, last = -1](double f) mutable {
      const int step = static_cast<int>(f * 10);
      if (step == last) return;
      last = step;
      log(what + " " + std::to_string(step * 10) + "%");
    };
  }
};

/// What the input stage hands on: the NDFs of all scans together.
struct NdfSet {
  std::unique_ptr<TabulatedNdf> naive, filtered, kirchhoff;
  /// The naive and filtered NDFs on a zoomed window around their lobes, when the whole-disk
  /// tables do not resolve them (stage_zoom); the fits use filtered_zoom.
  std::unique_ptr<TabulatedNdf> naive_zoom, filtered_zoom;
  /// D_K over lambda_q (sorted; `kirchhoff` is the layer at the slices' wavelength): the
  /// Kirchhoff BRDF interpolates it at each direction's lambda_q.
  std::vector<TabulatedNdf> kirchhoff_stack;
  double kirchhoff_raw_integral = 0, kirchhoff_aliased_fraction = 0;
  std::size_t kirchhoff_patches = 0;
  std::size_t kirchhoff_supersample = 1;  ///< S of the node cell averages (1: point samples)
  /// The table of the "measured" BRDF (PredictOptions::render_ndf): naive, filtered or kirchhoff.
  std::string render = "filtered";
  /// The scattering theory of the "measured" BRDF (stage_theory): "geometric" (the `render`
  /// table), "kirchhoff" (the D_K stack) or "rayleigh-rice" (`psd`).
  std::string theory = "geometric";
  /// The scans' mean PSD (those sharing the first scan's grid) when theory is Rayleigh-Rice.
  std::shared_ptr<const AreaPsd> psd;
  /// The comparison strip shows the multiple-scattering BRDF of the geometric NDF
  /// (stage_energy_loss decides).
  bool multiple_scattering = false;
  const TabulatedNdf& for_render() const {
    if (render == "naive" && naive) return *naive;
    if (render == "kirchhoff" && kirchhoff) return *kirchhoff;
    return *filtered;
  }
};

/// Reads, levels and describes every scan; accumulates the NDFs. Spread over the MPI ranks (every
/// rank calls it; on ranks other than 0 it returns nothing and leaves `ndfs` empty). Returns
/// the "inputs" array; `stats` (rank 0): scans and seconds per rank.
nlohmann::json stage_inputs(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs,
                            WorkStats* stats = nullptr);
/// D_K's options in a predict run: PredictOptions::kirchhoff_options at the slices' wavelength on
/// the run's table resolution.
KirchhoffOptions dk_options(const PredictOptions& o);
/// Moves an accumulator's tables (the layer at the slices' wavelength, the stack) and its
/// diagnostics into `ndfs`.
void take_kirchhoff(const KirchhoffAccumulator& acc, NdfSet& ndfs);
/// Picks the scattering theory of the "measured" BRDF (PredictOptions::theory; "auto": the one
/// valid at normal incidence by `regime`), computes what it needs on this rank that the input
/// stage did not (D_K over lambda_q, or the scans' PSD; call after mpi_set_solo), records the
/// choice and its reason in `regime` ("theory", "used", per-incidence "used_is_valid") and warns
/// (method_outside_validity) where the theory used is outside its validity.
void stage_theory(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs,
                  nlohmann::json& regime);
/// For the naive and the filtered NDF whose lobe spans fewer than 10 nodes of its table
/// (smallest rms slope s: 4 s / Delta < 10): reads and levels the scans again on this rank and
/// tabulates the same estimator on a window around the mean normal, half-width 12 x the largest
/// rms slope (at most what keeps the lobe 10 nodes wide), refined up to three times, into
/// ndfs.naive_zoom / filtered_zoom. Call on rank 0 after the distributed stage (mpi_set_solo).
void stage_zoom(const Context& c, const std::vector<std::string>& paths, NdfSet& ndfs);
/// The scattering regime (Rayleigh-Rice, Kirchhoff, geometric) of the scans' mean statistics at
/// the slices' wavelength, at normal incidence and each slice's theta_i, with the numbers that
/// decided; warns (method_outside_validity) when the slices and renders use the geometric NDF on
/// a smooth surface. Returns the "regime" object (null without statistics).
nlohmann::json stage_regime(const Context& c, const nlohmann::json& inputs);
/// Writes the tables and previews; returns the "ndf" object.
nlohmann::json stage_ndfs(const Context& c, const NdfSet& ndfs);
/// Fits ellipsoid, Beckmann, GGX to the filtered NDF; returns the "fits" array (seconds of each
/// fit go into `timing`).
nlohmann::json stage_fits(const Context& c, const NdfSet& ndfs, std::vector<FitResult>& fits,
                          nlohmann::json& timing);
/// NDF cuts (measured vs fits) along the principal axes; returns the "ndf_slices" object.
nlohmann::json stage_ndf_slices(const Context& c, const NdfSet& ndfs,
                                const std::vector<FitResult>& fits);
/// A BRDF of the report with its summary key and its label.
struct NamedBrdf {
  std::string key, label;
  std::shared_ptr<const Brdf> brdf;
};
/// The predicted ("measured") BRDF of the scans in the run's theory (ndfs.theory): the
/// tabulated NDF with Smith shadowing and `fresnel` (geometric), the Kirchhoff BRDF over the D_K
/// stack shadowed by the ellipsoid fit (kirchhoff) or first-order Rayleigh-Rice of the scans' PSD
/// with `material`'s complex index (rayleigh-rice). Built once per run and shared by the slices,
/// the renders and the comparison strip.
std::shared_ptr<const Brdf> measured_brdf(const NdfSet& ndfs,
                                          const std::shared_ptr<const Fresnel>& fresnel,
                                          const OpticalConstants& material,
                                          const std::vector<FitResult>& fits);
/// Its label in the report ("measured (filtered NDF)", "measured (D_K over lambda_q)", ...).
std::string measured_label(const NdfSet& ndfs);
/// The BRDFs of the three fitted NDFs closest to the table (Hellinger distance; in the order of
/// `fits`) and of D_K when it was computed (whose
/// sampling proposal is the ellipsoid fit), with `fresnel`: what the slices, albedos and the
/// comparison strip compare with the measured NDF.
std::vector<NamedBrdf> model_brdfs(const NdfSet& ndfs, const std::vector<FitResult>& fits,
                                   const std::shared_ptr<const Fresnel>& fresnel);
/// BRDF slices and albedos of every model; returns the "brdf" object.
nlohmann::json stage_brdf(const Context& c, const NdfSet& ndfs, const std::vector<FitResult>& fits,
                          const std::shared_ptr<const Fresnel>& fresnel,
                          const std::shared_ptr<const Brdf>& measured);
/// A scene of the renders and of the comparison strip: geometry, lights, words for the report.
struct PredictScene {
  std::string name;  ///< "cylinders", "sphere", "plate" (file and summary key)
  RenderScene geometry;
  RenderLights lights;
  std::string lights_text, caption;
};
/// The compared scenes: the cylinder pair and the sphere under predict_lights(), the plate under
/// the small light of Dong 2015 Fig. 13.
std::vector<PredictScene> predict_scenes(const PredictOptions& o);
/// A measured-NDF render of stage_render that the comparison strip compares each model with.
struct ReferenceRender {
  PredictScene scene;
  std::string file;  ///< img/render_<scene>.png, relative to the output folder
  double exposure_stops = 0;
  RenderImage image;
  /// One realisation of the image's Monte Carlo noise in linear luminance, with the variance of
  /// the image's own noise (see stage_render): what a second, independent render of the same
  /// samples would add or take per pixel.
  std::vector<double> noise_luminance;
  std::uint64_t noise_seed = 0;  ///< the seed of the halves (or of the second render at 1 spp)
  /// The compared models' images (the `models` of stage_render, in order), rendered along the
  /// same paths as `image` (render_variants): their differences from it carry little noise.
  std::vector<RenderImage> model_images;
};
/// The exposure (stops, half-stop steps within +-10) at which the image's 99th-percentile
/// luminance shows at about full white; 0 for a black image.
double auto_exposure_stops(const RenderImage& img);
/// Renders of `scene` at `options.spp` samples per pixel, one per variant along shared paths
/// (render_variants; one variant: the same as render() gives), and in `noise` one realisation
/// of the first variant's own Monte Carlo noise in linear luminance, k (Y_A - Y_B) with Y_A,
/// Y_B its images of the first floor(spp/2) and the remaining samples and
/// k = sqrt(nA nB) / spp (at spp = 1: a second render with seed + 1, and (Y_2 - Y_1) / sqrt 2).
/// With `extra_lights`, the first variant also under those light sets along the same paths
/// (render_light_sets): their images follow the variants', one per set.
std::vector<RenderImage> render_split(
    const PredictScene& scene,
    const std::vector<std::vector<std::shared_ptr<const Svbrdf> > >& variants,
    const RenderOptions& options, std::vector<double>& noise,
    const std::vector<RenderLights>& extra_lights = {});
/// The image at half the size, each pixel the mean of a 2 x 2 block (width and height even):
/// a render at twice the size with N samples per pixel gives the half-size render with 4N.
RenderImage half_size(const RenderImage& img);
/// Renders; returns the "renders" array (or a "skipped" reason); seconds into `timing`. The
/// renders of predict_scenes() (the references of the comparison strip) go into `references`
/// when given, each with its noise from the two halves of its samples (render_split), so that
/// the noise is known without a second render, and with the images of `models` rendered along
/// the same paths (ReferenceRender::model_images).
nlohmann::json stage_render(const Context& c, const std::shared_ptr<const Brdf>& measured,
                            const std::vector<NamedBrdf>& models, nlohmann::json& timing,
                            std::vector<ReferenceRender>* references = nullptr);
/// The comparison strip: each reference scene's images of the fits (and D_K), rendered by
/// stage_render along the paths of its measured-NDF render (same lights, size, samples, seed,
/// exposure), their SSIM and RMS relative error against it, difference images, and the render
/// noise (from the two halves of the reference's samples, see
/// ReferenceRender::noise_luminance); returns the "render_comparison" object (the cylinder
/// pair's keys at the top level, every scene in "scenes").
nlohmann::json stage_compare_renders(const Context& c, const std::vector<NamedBrdf>& models,
                                     const std::vector<ReferenceRender>& references);
/// The lights of every predict render: the environment map if given, else a dim uniform sky
/// and two disk softboxes.
RenderLights predict_lights(const PredictOptions& o);
/// What predict_lights gives, in words for the report.
std::string predict_lights_description(const PredictOptions& o);
/// Render options of a predict render of width x height pixels (spp, seed, threads from `o`).
RenderOptions predict_render_options(const PredictOptions& o, int width, int height);
/// The fits as Mitsuba 3 and pbrt-v4 rough-conductor materials (each with a sphere scene) in
/// export/ of the output folder; returns the "exports" object.
nlohmann::json stage_exports(const Context& c, const std::vector<FitResult>& fits);
/// The glTF 2.0 .glb of a BRDF spec with the run's material at `rel` (inside export/), with
/// `uv_scale` texture repeats per scene unit: {"file": rel, "warnings": [what glTF cannot hold]}.
nlohmann::json write_glb(const Context& c, const BrdfSpec& spec, const std::string& rel,
                         double uv_scale);
/// Texture synthesis from strips; returns the "texture" object.
nlohmann::json stage_texture(const Context& c, const std::shared_ptr<const Fresnel>& fresnel,
                             nlohmann::json& timing);

/// Versions of the library and what it is built with.
nlohmann::json versions();

}  // namespace microbrdf::report

#pragma once
// `microbrdf predict`: the main job, from scans to a report a person reads in a browser.
//
// One call runs every stage that applies, streaming the scans one at a time:
//   1. inputs      read, level (plane by default), statistics, height previews;
//   2. NDFs        naive and filtered (Dong 2015 section 5.1), D_K when asked (section 6);
//   3. fits        ellipsoid, Beckmann and GGX fits of the filtered NDF (section 8);
//   4. BRDF slices in-plane and out-of-plane cuts of the microfacet BRDF (Dong eq. 1) with the
//                  measured (tabulated) NDF, the fitted models and D_K, for several theta_i;
//   5. renders     the cylinder pair of Dong Fig. 10 and a sphere under an environment map, a
//                  plate under a small light, and the comparison strip: each of the three with
//                  each fit (and D_K), SSIM and RMS relative error against the measured-NDF
//                  render, and the render noise; the fits as Mitsuba 3 / pbrt-v4 materials;
//   6. texture     when exemplar strips are given: per-texel ellipsoid fits and a synthesised
//                  parameter texture (Dong section 9), and a render of it.
// and writes into DIR:
//   report.html    self-contained (inline SVG plots, images as data: URIs, no external file);
//   summary.json   every number of the report, in SI units (docs/report.md lists every field);
//   ndf_*.npy      the tables (+ JSON sidecars), img/*.png the images, texture.exr, renders.
//
// Determinism: the same inputs, options and seed give a byte-identical summary.json apart from
// the "timing" object (wall-clock seconds live only there).
// Atomicity: everything is written into a temporary folder beside DIR, renamed to DIR at the
// end; an error leaves no DIR behind (an existing DIR from an earlier run is replaced only on
// success).

#include <cstdint>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "microbrdf/io.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/level.hpp"
#include "microbrdf/material_spec.hpp"

namespace microbrdf {

struct PredictOptions {
  std::vector<std::string> inputs;  ///< files, directories, globs, @manifests (scanset.hpp)
  ReadOptions read;                 ///< spacing overrides for formats without one
  LevelingSpec leveling;            ///< applied to every scan and strip (default: plane)

  /// The material of every BRDF (material_spec.hpp: a metal, n/k, an n,k CSV, R0 or a colour;
  /// exact or Schlick Fresnel).
  MaterialSpec material = MaterialSpec::named_metal("Fe");
  double filter_sigma_m = 1e-6;  ///< filtered NDF: Gaussian std of the local plane fit, m
  /// Choose filter_sigma_m instead: the sigma whose filtered NDF is nearest D_K at wavelength_m
  /// by Hellinger distance (filter_sigma_auto.hpp), on tables of filter_sigma_sweep_resolution.
  bool filter_sigma_auto = false;
  std::size_t filter_sigma_sweep_resolution = 257;
  /// The NDF of the "measured" BRDF (slices, renders, the comparison strip's reference):
  /// "naive", "filtered" or "kirchhoff" (needs kirchhoff = true). The fits are of the filtered
  /// NDF whatever this says.
  std::string render_ndf = "filtered";
  /// The scattering theory of the predicted ("measured") BRDF of the slices, renders and the
  /// comparison strip's reference: "auto" (default) picks the one valid for the scans at
  /// normal incidence and wavelength_m (regime.hpp, docs/regime.md): "rayleigh-rice" (the scans'
  /// own PSD; smooth metals), "kirchhoff" (D_K over lambda_q; computed for it even without
  /// `kirchhoff`) or "geometric" (the render_ndf table). Forcing one outside its validity warns
  /// (method_outside_validity). render_ndf "kirchhoff" means "kirchhoff" here.
  std::string theory = "auto";
  std::size_t ndf_resolution = 1025;
  bool kirchhoff = false;        ///< also compute D_K (slow: ~20 s per 2 M samples)
  double wavelength_m = 555e-9;  ///< lambda_q of D_K and the wavelength of the BRDF slices, m
  /// D_K's tiles (coherence area, Dong App. A; default 70 x 53 um), window, accuracy, Nyquist
  /// mask, integration rule (midpoint by default: fast, approximate; exact: the triangles of
  /// the piecewise-linear surface, 20-60x slower) and node supersampling (kirchhoff.hpp).
  /// Its wavelength_q and resolution are ignored: D_K is taken at wavelength_m on the
  /// ndf_resolution table. The --filter-sigma auto sweep uses these settings with the midpoint
  /// rule at its own resolution.
  KirchhoffOptions kirchhoff_options;
  std::vector<double> slice_theta_i_rad = {0.3490658503988659, 0.7853981633974483,
                                           1.2217304763960306};  ///< 20, 45, 70 deg
  /// Angles per slice, spread over the range where some model exceeds 1e-5 of the highest peak
  /// (plus 1 deg each side): brushed lobes are a fraction of a degree wide along the brushing.
  std::size_t slice_samples = 401;

  bool render = true;
  /// false: only the measured NDF's renders of the three scenes, each alone (no comparison strip,
  /// studio renders or swatch): a quick look, what `predict` rendered before the report compared
  /// the models in images (`--renders measured`).
  bool render_models = true;
  std::string envmap_path;  ///< equirectangular EXR/HDR; empty = a built-in set of area lights
  double envmap_scale = 1;
  int render_width = 256;  ///< pixels of each (square) render
  int render_spp = 32;     ///< samples per pixel

  /// Exemplar strips for texture synthesis (both or neither): scans along and across the
  /// brushing direction.
  std::vector<std::string> strips_along, strips_across;
  double texel_m = 53e-6;          ///< texel size of the per-texel fits, m
  std::size_t texture_size = 128;  ///< synthesised texture, texels per side
  std::size_t texel_resolution = 129;

  /// A measurement to compare the prediction with (docs/measured.md): a goniometer .csv, a MERL
  /// .binary, an RGL .bsdf or an effective NDF table; "" = none. The report gains a section.
  std::string measured_path;
  double instrument_fwhm_rad = 0;  ///< Gaussian instrument signature applied to the prediction
  std::string instrument_path;     ///< or a measured signature (an NDF table); "" = none

  std::uint64_t seed = 1;  ///< renders and texture synthesis
  /// 0 = all cores. Renders and NDFs do not depend on it; the fits (parallel sums in Ceres)
  /// agree across thread counts to ~1e-14 relative, bit for bit at the same count.
  int threads = 0;
  /// Progress lines ("[2/5] NDFs: filtered ..."); the CLI prints them on stderr.
  std::function<void(const std::string&)> log;
};

struct PredictResult {
  std::string dir;           ///< the output folder
  std::string report_path;   ///< DIR/report.html
  std::string summary_path;  ///< DIR/summary.json
  nlohmann::json summary;    ///< what summary.json holds
};

/// Checks the options and that every input exists and names a readable format, without reading
/// the scans. Throws InputError (bad option) or FileError (missing input). predict() calls it
/// first.
void check_predict_options(const PredictOptions& options);

/// Runs the pipeline into `out_dir` (created; an earlier predict output there is replaced).
/// Throws InputError / FileError naming the file and the problem; nothing is left behind then.
/// Refuses (FileError) to replace an existing non-empty folder that is not a predict output.
/// Under mpirun every rank calls it: the per-scan stage (reading, statistics, NDF shares) runs
/// over all ranks (distribute.hpp), rank 0 does the rest and returns the result; other ranks
/// return an empty PredictResult.
PredictResult predict(const PredictOptions& options, const std::string& out_dir);

/// The report page for a summary (as predict() writes it); images and SVG plots are read from
/// `dir` (the paths in the summary are relative to it) and embedded. Throws FileError when one
/// is missing.
std::string render_report_html(const nlohmann::json& summary, const std::string& dir);

}  // namespace microbrdf

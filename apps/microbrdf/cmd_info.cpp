// `microbrdf info FILE... [--json]`: grid, spacing, validity and the statistics the papers use.
#include <cmath>
#include <cstdio>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/preview.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct InfoArgs {
  std::vector<std::string> inputs;
  ReadFlags read;
  bool json = false, keep_going = false;
  std::string preview;
  std::string psd;
};

std::string deg(double slope) {
  return std::isfinite(slope) ? number_or_na(std::atan(slope) * 180 / M_PI, "%.3g deg") : "n/a";
}

void print_human(const std::string& path, const Surface& s, const SurfaceStats& st,
                 const std::string& lev) {
  std::printf("%s  [%s]\n", path.c_str(), s.meta.format.c_str());
  if (!s.meta.instrument.empty()) std::printf("  instrument     %s\n", s.meta.instrument.c_str());
  if (!s.meta.date.empty()) std::printf("  date           %s\n", s.meta.date.c_str());
  std::printf("  grid           %zu x %zu samples, spacing %s x %s, field %s x %s\n", st.nx, st.ny,
              format_length(st.dx).c_str(), format_length(st.dy).c_str(),
              format_length(s.width()).c_str(), format_length(s.height()).c_str());
  std::printf("  valid          %.2f%% (%zu invalid)\n", 100 * st.valid_fraction,
              s.size() - st.valid_count);
  std::printf("  levelling      %s\n", lev.c_str());
  std::printf("  heights        min %s, max %s, mean %s\n", format_length(st.min).c_str(),
              format_length(st.max).c_str(), format_length(st.mean).c_str());
  std::printf("  Sq (sigma)     %s    Sa %s\n", format_length(st.sq).c_str(),
              format_length(st.sa).c_str());
  std::printf("  skew / kurt    %s / %s (Gaussian: 0 / 3)\n", number_or_na(st.skewness).c_str(),
              number_or_na(st.kurtosis).c_str());
  std::printf("  rms slope      x %s (%s), y %s (%s)\n", number_or_na(st.slope_rms_x).c_str(),
              deg(st.slope_rms_x).c_str(), number_or_na(st.slope_rms_y).c_str(),
              deg(st.slope_rms_y).c_str());
  auto len = [](double v) {
    return std::isfinite(v) ? format_length(v) : std::string("longer than the scan");
  };
  std::printf("  corr. length   x %s, y %s, radial %s (1/e of the ACF = tau)\n",
              len(st.corr_length_x).c_str(), len(st.corr_length_y).c_str(),
              len(st.corr_length).c_str());
}

void write_psd_csv(const std::string& path, const Surface& s) {
  auto psd = power_spectrum(s);
  std::string text =
      "# radially averaged PSD, S(k) = integral C(r) exp(-i k.r) d^2r\nk_rad_per_m,s_m4\n";
  char line[64];
  for (std::size_t i = 0; i < psd.k.size(); ++i) {
    std::snprintf(line, sizeof line, "%.9g,%.9g\n", psd.k[i], psd.s[i]);
    text += line;
  }
  write_file_atomic(path, text);
}

void run(const InfoArgs& a) {
  auto paths = expand_scan_inputs(a.inputs);
  if ((!a.preview.empty() || !a.psd.empty()) && paths.size() != 1)
    throw InputError("--preview and --psd take exactly one input file (got " +
                     std::to_string(paths.size()) + ")");
  // Without --keep-going a file that is not there is a usage error, found before any reading.
  if (!a.keep_going) scan_inputs(a.inputs);
  nlohmann::json all = nlohmann::json::array(), failed = nlohmann::json::array();
  Progress progress("info");
  for (std::size_t i = 0; i < paths.size(); ++i) {
    progress.item(i, paths.size(), paths[i]);
    std::string lev;
    Surface s;
    try {
      s = load_surface(paths[i], a.read, &lev);
    } catch (const std::exception& e) {
      if (!a.keep_going) throw;
      // --keep-going: say which file failed and why, go on, and fail at the end.
      std::fprintf(stderr, "microbrdf info: error: %s (skipped)\n", e.what());
      failed.push_back({{"path", paths[i]}, {"error", e.what()}});
      continue;
    }
    auto st = compute_stats(s);
    if (a.json) {
      auto j = stats_json(paths[i], s, st);
      j["leveling_report"] = lev;
      all.push_back(j);
    } else {
      print_human(paths[i], s, st, lev);
    }
    if (!a.preview.empty()) write_png(a.preview, render_height_preview(s));
    if (!a.psd.empty()) write_psd_csv(a.psd, s);
  }
  if (a.json) print_json({{"surfaces", all}, {"failed", failed}});
  if (!failed.empty())
    throw FileError(
        std::to_string(failed.size()) + " of " + std::to_string(paths.size()) + " files",
        "could not be read (see above)");
}

}  // namespace

void register_info(CLI::App& app) {
  auto args = std::make_shared<InfoArgs>();
  auto* cmd =
      app.add_subcommand("info", "Grid, spacing, validity and surface statistics of height maps");
  cmd->footer(
      "Statistics: Sq = rms height (sigma), Sa, skewness, kurtosis (3 for Gaussian), rms slopes "
      "by\n"
      "central differences, correlation lengths where the normalised autocorrelation falls to 1/e\n"
      "(tau in C(r) = sigma^2 exp(-r^2/tau^2)). Invalid samples are excluded, never filled.\n\n"
      "Inputs: files, directories, glob patterns ('scans/*.x3p') or @manifest.txt.\n\n"
      "Examples:\n"
      "  microbrdf info scan.x3p\n"
      "  microbrdf info --json --level none data/*.dat\n"
      "  microbrdf info image.exr --spacing 110nm --preview heights.png\n"
      "  microbrdf info --keep-going --json scans/ >stats.json");
  cmd->add_option("files", args->inputs, "Height maps to describe")->required();
  add_read_flags(cmd, args->read, "plane");
  cmd->add_flag("--json", args->json,
                "Print one JSON object {\"surfaces\": [...]} (SI units) on stdout");
  cmd->add_option("--preview", args->preview,
                  "Write a false-colour height-map PNG (one input only)");
  cmd->add_option("--psd", args->psd, "Write the radially averaged PSD as CSV (one input only)");
  cmd->add_flag("--keep-going", args->keep_going,
                "Go on past files that cannot be read (each is reported on stderr and in the "
                "JSON's \"failed\" list); the exit code is still 1 if any failed");
  cmd->callback([args] { run_guarded("info", [&] { run(*args); }); });
}

}  // namespace microbrdf::cli

// `microbrdf info FILE... [--json]`: grid, spacing, validity and the statistics the papers use.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/material_spec.hpp"
#include "microbrdf/rayleigh_rice.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/units.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct InfoArgs {
  std::vector<std::string> inputs;
  ReadFlags read;
  bool json = false, keep_going = false;
  std::string preview;
  std::string psd;
  SpecFlags material;                            // for the TIS
  std::vector<std::string> wavelengths, angles;  // of the TIS table (default: the standard)
};

// The scan's PSD (psd.hpp) and its total integrated scatter at each wavelength and angle of
// incidence: with a material the Rayleigh-Rice TIS, else the material-free numbers only.
void add_psd_and_tis(const InfoArgs& a, const std::string& path, const Surface& s,
                     nlohmann::json& j) {
  std::vector<double> wl, th;
  for (const auto& w : a.wavelengths) wl.push_back(parse_length(w));
  for (const auto& t : a.angles) th.push_back(parse_angle(t));
  std::optional<OpticalConstants> m;
  if (has_material(a.material.keys()))
    m = optical_constants(material_spec(a.material, std::nullopt));
  add_psd_and_tis_json(j, s, path, m ? &*m : nullptr, wl, th);
}

std::string deg(double slope) {
  return std::isfinite(slope) ? number_or_na(std::atan(slope) * 180 / M_PI, "%.3g deg") : "n/a";
}

void print_human(std::FILE* out, const std::string& path, const Surface& s, const SurfaceStats& st,
                 const std::string& lev) {
  std::fprintf(out, "%s  [%s]\n", path.c_str(), s.meta.format.c_str());
  if (!s.meta.instrument.empty())
    std::fprintf(out, "  instrument     %s\n", s.meta.instrument.c_str());
  if (!s.meta.date.empty()) std::fprintf(out, "  date           %s\n", s.meta.date.c_str());
  std::fprintf(out, "  grid           %zu x %zu samples, spacing %s x %s, field %s x %s\n", st.nx,
               st.ny, format_length(st.dx).c_str(), format_length(st.dy).c_str(),
               format_length(s.width()).c_str(), format_length(s.height()).c_str());
  std::fprintf(out, "  valid          %.2f%% (%zu invalid)\n", 100 * st.valid_fraction,
               s.size() - st.valid_count);
  std::fprintf(out, "  levelling      %s\n", lev.c_str());
  std::fprintf(out, "  heights        min %s, max %s, mean %s\n", format_length(st.min).c_str(),
               format_length(st.max).c_str(), format_length(st.mean).c_str());
  std::fprintf(out, "  Sq (sigma)     %s    Sa %s\n", format_length(st.sq).c_str(),
               format_length(st.sa).c_str());
  std::fprintf(out, "  skew / kurt    %s / %s (Gaussian: 0 / 3)\n",
               number_or_na(st.skewness).c_str(), number_or_na(st.kurtosis).c_str());
  std::fprintf(out, "  rms slope      x %s (%s), y %s (%s)\n", number_or_na(st.slope_rms_x).c_str(),
               deg(st.slope_rms_x).c_str(), number_or_na(st.slope_rms_y).c_str(),
               deg(st.slope_rms_y).c_str());
  auto len = [](double v) {
    return std::isfinite(v) ? format_length(v) : std::string("longer than the scan");
  };
  std::fprintf(out, "  corr. length   x %s, y %s, radial %s (1/e of the ACF = tau)\n",
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

// One scan's record: the JSON of `info --json` or the text of the human listing.
WorkResult describe(const InfoArgs& a, const std::string& path, Surface& s, bool with_files) {
  const auto spec = LevelingSpec::parse(a.read.level);
  warn_if_sparse(path, s);
  std::string lev = about_file(path, [&] { return level_surface(s, spec); }).description;
  auto st = compute_stats(s);
  WorkResult r;
  if (a.json) {
    auto j = stats_json(path, s, st);
    j["leveling_report"] = lev;
    add_psd_and_tis(a, path, s, j);
    r.text = j.dump();
  } else {
    char* buf = nullptr;
    std::size_t len = 0;
    std::FILE* mem = open_memstream(&buf, &len);
    if (!mem) throw std::runtime_error("out of memory");
    print_human(mem, path, s, st, lev);
    std::fclose(mem);
    r.text.assign(buf, len);
    std::free(buf);
  }
  if (with_files && !a.preview.empty()) write_png(a.preview, render_height_preview(s));
  if (with_files && !a.psd.empty()) write_psd_csv(a.psd, s);
  return r;
}

void run(const InfoArgs& a) {
  auto paths = expand_scan_inputs(a.inputs);
  const bool files = !a.preview.empty() || !a.psd.empty();
  if (files && paths.size() != 1)
    throw InputError("--preview and --psd take exactly one input file (got " +
                     std::to_string(paths.size()) + ")");
  // Without --keep-going a file that is not there is a usage error, found before any reading.
  if (!a.keep_going) scan_inputs(a.inputs);
  LevelingSpec::parse(a.read.level);  // validate before the (maybe long) reads
  // The scans over the MPI ranks (docs/scale.md), listed by rank 0 in input order; with
  // --preview / --psd (one scan) rank 0 alone reads it and writes the files.
  nlohmann::json all = nlohmann::json::array();
  auto list = [&](std::size_t i, WorkResult&& r) {
    progress("info", i, paths.size(), paths[i]);
    if (a.json)
      all.push_back(nlohmann::json::parse(r.text));
    else
      std::fputs(r.text.c_str(), stdout);
  };
  WorkStats stats;
  nlohmann::json failed = nlohmann::json::array();
  if (files || a.keep_going) {
    // One scan with its files, or --keep-going (an interactive listing): rank 0 alone, in order.
    if (!mpi_is_root()) return;
    for (std::size_t i = 0; i < paths.size(); ++i) {
      Surface s;
      try {
        s = read_surface(paths[i], read_options(a.read));
      } catch (const std::exception& e) {
        if (!a.keep_going) throw;
        // --keep-going: say which file failed and why, go on, and fail at the end.
        std::fprintf(stderr, "microbrdf info: error: %s (skipped)\n", e.what());
        failed.push_back({{"path", paths[i]}, {"error", e.what()}});
        continue;
      }
      list(i, describe(a, paths[i], s, files));
    }
  } else {
    stats = distribute_scans(
        paths, read_options(a.read),
        [&](std::size_t, const std::string& path, Surface& s) {
          return describe(a, path, s, false);
        },
        list);
    if (!mpi_is_root()) return;
  }
  if (a.json)
    print_json({{"surfaces", all}, {"failed", failed}, {"mpi", stats.to_json("scans_per_rank")}});
  if (!failed.empty()) {
    std::fprintf(stderr, "microbrdf info: error: %zu of %zu files could not be read (see above)\n",
                 failed.size(), paths.size());
    set_exit_code(1);
  }
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
      "  microbrdf info polished.x3p --json --metal Al --wavelength 633nm --theta-i 0,45deg\n\n"
      "JSON: \"psd\" describes the scan's areal PSD (cycles/m, m^4, integral = Sq^2; Hann\n"
      "window, docs/rayleigh_rice.md); \"tis\" lists per wavelength and angle of incidence the\n"
      "Rayleigh factor (4 pi Sq cos theta / lambda)^2 and, with a material, the total\n"
      "integrated scatter in closed form and integrated from the Rayleigh-Rice BRDF.");
  cmd->add_option("files", args->inputs, "Height maps to describe")->required();
  add_read_flags(cmd, args->read, "plane");
  cmd->add_flag("--json", args->json,
                "Print one JSON object {\"surfaces\": [...]} (SI units) on stdout");
  cmd->add_option("--preview", args->preview,
                  "Write a false-colour height-map PNG (one input only)");
  cmd->add_option("--psd", args->psd, "Write the radially averaged PSD as CSV (one input only)");
  add_material_flags(cmd, args->material,
                     "with --json: the total integrated scatter of the first-order "
                     "Rayleigh-Rice BRDF beside (4 pi Sq cos theta / lambda)^2 R");
  cmd->add_option("--wavelength", args->wavelengths,
                  "With --json: wavelengths of the TIS table (default 405,555,633,1064nm)")
      ->delimiter(',')
      ->check(wavelength());
  cmd->add_option("--theta-i", args->angles,
                  "With --json: angles of incidence of the TIS table (default 0,20,45,70deg)")
      ->delimiter(',')
      ->check(angle_in(0, 89.9 * M_PI / 180));
  cmd->add_flag("--keep-going", args->keep_going,
                "Go on past files that cannot be read (each is reported on stderr and in the "
                "JSON's \"failed\" list); the exit code is still 1 if any failed");
  cmd->callback([args] { run_guarded("info", [&] { run(*args); }); });
}

}  // namespace microbrdf::cli

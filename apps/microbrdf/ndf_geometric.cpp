// `microbrdf ndf --method naive|filtered`: the geometric NDF of one scan or of a scan set (each
// scan estimated on its own, averaged by projected area; Dong 2015 section 5.1), with the filter
// sigma given or chosen against D_K (--filter-sigma auto, filter_sigma_auto.hpp).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>

#include "microbrdf/error.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/units.hpp"
#include "ndf_args.hpp"

namespace microbrdf::cli {
namespace {

// --filter-sigma auto: the sweep against D_K (filter_sigma_auto.hpp) with the Kirchhoff flags.
FilterSigmaAuto auto_filter_sigma(const NdfArgs& a, const std::vector<std::string>& paths,
                                  const ScanSetOptions& set) {
  if (a.sweep_resolution < 17 || a.sweep_resolution > 8193)
    throw InputError("--sweep-resolution must be in 17..8193");
  FilterSigmaAutoOptions fo;
  fo.resolution = a.sweep_resolution;
  fo.min_support = a.min_support;
  // The sweep's D_K takes the midpoint rule whatever --dk-integration says (the sweep compares
  // shapes; docs/guide.md).
  fo.kirchhoff = kirchhoff_options(a.dk, a.wavelength);
  fo.kirchhoff.integration = KirchhoffIntegration::Midpoint;
  if (!a.json)
    fo.log = [](const std::string& line) {
      std::fprintf(stderr, "microbrdf ndf: %s\n", line.c_str());
    };
  // Every rank runs the (deterministic) sweep on its own, so that all agree on the sigma.
  return choose_filter_sigma(paths, set.read, set.leveling, fo);
}

// Where the curve goes: beside the table, "<stem>_filter_sigma.csv".
std::string curve_path(const std::string& output) {
  std::filesystem::path p(output);
  return (p.parent_path() / (p.stem().string() + "_filter_sigma.csv")).string();
}

}  // namespace

void run_geometric(const NdfArgs& a) {
  NdfEstimateOptions o;
  if (a.method == "naive")
    o.method = NdfMethod::Naive;
  else if (a.method == "filtered")
    o.method = NdfMethod::Filtered;
  else
    throw InputError("unknown --method '" + a.method + "' (naive | filtered | kirchhoff)");
  const bool auto_sigma = a.filter_sigma == "auto";
  if (auto_sigma && o.method != NdfMethod::Filtered)
    throw InputError("--filter-sigma auto applies to --method filtered");
  o.filter_sigma_m = auto_sigma ? 1e-6 : parse_length(a.filter_sigma);
  o.resolution = a.resolution;
  o.min_support = a.min_support;
  if (a.resolution < 17 || a.resolution > 8193)
    throw InputError("--resolution must be in 17..8193");
  auto paths = scan_inputs(a.inputs);
  bool warned = false;
  SampleTally tally;
  ScanSetOptions set = scan_set_options(a, paths.size());
  std::optional<FilterSigmaAuto> sweep;
  if (auto_sigma) {
    sweep = auto_filter_sigma(a, paths, set);
    o.filter_sigma_m = sweep->sigma_m;
    if (sweep->kirchhoff_aliased_fraction > 0.5)
      std::fprintf(stderr,
                   "microbrdf ndf: warning: --filter-sigma auto: %.1f%% of D_K's mass lies beyond "
                   "the scan's Nyquist band (sample spacing above lambda_q/4 = %s) and was "
                   "removed; the chosen sigma rests on a small band about the pole\n",
                   100 * sweep->kirchhoff_aliased_fraction,
                   format_length(sweep->wavelength_q_m / 4).c_str());
  }
  set.on_scan = [&](std::size_t i, const std::string& path, const nlohmann::json& scan) {
    progress("ndf", i, paths.size(), path);
    tally.add(path, scan);
    const double d = std::max(scan.at("dx_m").get<double>(), scan.at("dy_m").get<double>());
    if (o.method == NdfMethod::Filtered && !warned && o.filter_sigma_m < d) {
      std::fprintf(stderr,
                   "microbrdf ndf: warning: filter sigma %s is below the sample spacing %s of %s: "
                   "the fit sees few neighbours and approaches the naive estimate\n",
                   format_length(o.filter_sigma_m).c_str(), format_length(d).c_str(), path.c_str());
      warned = true;
    }
  };
  WorkStats stats;
  auto acc = accumulate_ndf_scans(paths, o, set, &stats);
  if (!acc) return;  // rank 0 writes the outputs
  TabulatedNdf ndf = std::move(*acc).result();
  if (sweep) {
    char b[160];
    std::snprintf(b, sizeof b,
                  "%sfilter sigma chosen by --filter-sigma auto (Hellinger distance %.4g to D_K "
                  "at lambda_q %s, sweep at %zu^2)",
                  ndf.meta.notes.empty() ? "" : "; ", sweep->hellinger,
                  format_length(sweep->wavelength_q_m).c_str(), sweep->resolution);
    ndf.meta.notes += b;
  }
  write_outputs(ndf, a);
  if (sweep) write_filter_sigma_curve_csv(*sweep, curve_path(a.output));
  if (a.json) {
    auto j = ndf_json(ndf, a);
    if (sweep) {
      j["filter_sigma_auto"] = sweep->to_json();
      j["filter_sigma_auto"]["curve_file"] = curve_path(a.output);
    }
    j["samples_invalid"] = tally.invalid;  // height samples the scans mark invalid
    j["mpi"] = stats.to_json("scans_per_rank");
    print_json(j);
  } else {
    tally.print("ndf");
    if (sweep)
      std::fprintf(stderr,
                   "microbrdf ndf: --filter-sigma auto: %s (Hellinger distance to D_K %.4g; naive "
                   "NDF %.4g%s); curve of %zu sigmas from %s to %s -> %s\n",
                   format_length(sweep->sigma_m).c_str(), sweep->hellinger,
                   sweep->hellinger_naive_kirchhoff,
                   sweep->at_lower_end   ? "; minimum at the smallest sigma swept"
                   : sweep->at_upper_end ? "; minimum at the largest sigma swept"
                                         : "",
                   sweep->curve.size(), format_length(sweep->sigma_min_m).c_str(),
                   format_length(sweep->sigma_max_m).c_str(), curve_path(a.output).c_str());
    const Eigen::Matrix2d cov = ndf.slope_covariance();  // one pass over the table
    const double sx = std::sqrt(std::max(0.0, cov(0, 0))), sy = std::sqrt(std::max(0.0, cov(1, 1)));
    std::fprintf(stderr,
                 "microbrdf ndf: %s NDF of %zu scan(s) -> %s (%zu x %zu); %zu elements used, %zu "
                 "skipped; rms slope x "
                 "%.4g, y %.4g (Beckmann alpha %.4g, %.4g)\n",
                 ndf.meta.method.c_str(), paths.size(), a.output.c_str(), ndf.resolution(),
                 ndf.resolution(), ndf.meta.samples_used, ndf.meta.samples_skipped, sx, sy,
                 std::sqrt(2.0) * sx, std::sqrt(2.0) * sy);
  }
}

}  // namespace microbrdf::cli

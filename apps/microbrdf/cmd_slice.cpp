// `microbrdf slice NDF... -o plot.png`: 1-D cuts through tabulated NDFs along in-plane
// directions (the cross-brush and along-brush plots of Dong 2015 Fig. 9), several NDFs overlaid.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <sstream>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/plot.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct SliceArgs {
  std::vector<std::string> inputs, labels, azimuths{"0", "90"};
  std::string output, csv, theta_max = "90deg";
  bool log = false;
  std::size_t samples = 2049;
};

void run(const SliceArgs& a) {
  if (!a.labels.empty() && a.labels.size() != a.inputs.size())
    throw InputError("--label must be given once per input (" + std::to_string(a.inputs.size()) +
                     ")");
  double tmax = parse_angle(a.theta_max) * 180 / M_PI;
  std::vector<TabulatedNdf> ndfs;
  for (const auto& p : a.inputs) ndfs.push_back(read_ndf(p));
  // Zoomed tables only (and no --theta-max given): the axis spans their windows.
  bool all_zoomed = a.theta_max == "90deg";
  double reach = 0;
  for (const auto& t : ndfs) {
    const NdfWindow& w = t.window();
    all_zoomed = all_zoomed && !w.full();
    reach =
        std::max({reach, std::abs(w.x0()), std::abs(w.x1()), std::abs(w.y0()), std::abs(w.y1())});
  }
  if (all_zoomed) tmax = std::asin(std::min(1.0, reach)) * 180 / M_PI;
  std::vector<Plot> plots;
  std::ostringstream csv;
  csv << "# D (1/sr) along in-plane directions; theta = signed polar angle of "
         "m\nndf,azimuth_deg,theta_deg,d_per_sr\n";
  for (const auto& az_text : a.azimuths) {
    const double az = parse_angle(az_text);
    Plot plot;
    char title[96];
    std::snprintf(title, sizeof title, "NDF slice, azimuth %.4g deg", az * 180 / M_PI);
    plot.title = title;
    plot.x.label = "signed polar angle of m (deg)";
    plot.y.label = "D (1/sr)";
    plot.y.scale = a.log ? AxisScale::Log : AxisScale::Linear;
    plot.x.min = -tmax;
    plot.x.max = tmax;
    for (std::size_t i = 0; i < ndfs.size(); ++i) {
      auto s = ndfs[i].slice(az, a.samples);
      std::vector<double> x, y;
      std::string name =
          a.labels.empty() ? std::filesystem::path(a.inputs[i]).stem().string() : a.labels[i];
      for (std::size_t k = 0; k < s.t.size(); ++k) {
        double th = s.theta[k] * 180 / M_PI;
        if (std::fabs(th) > tmax) continue;
        x.push_back(th);
        y.push_back(s.value[k]);
        csv << name << ',' << az * 180 / M_PI << ',' << th << ',' << s.value[k] << '\n';
      }
      plot.add(PlotSeries(x, y, name));
    }
    plots.push_back(std::move(plot));
  }
  if (plots.size() == 1)
    plots[0].write(a.output);
  else
    write_plot_grid(plots, std::min<std::size_t>(plots.size(), 2), a.output);
  if (!a.csv.empty()) write_file_atomic(a.csv, csv.str());
  std::fprintf(stderr, "microbrdf slice: %zu NDF(s), %zu direction(s) -> %s\n", ndfs.size(),
               plots.size(), a.output.c_str());
}

}  // namespace

void register_slice(CLI::App& app) {
  auto a = std::make_shared<SliceArgs>();
  auto* cmd =
      app.add_subcommand("slice", "Plot 1-D cuts through tabulated NDFs (Dong 2015 Fig. 9)");
  cmd->footer(
      "Cuts run through the disk centre at the given azimuths (0 = along x, 90 = along y); the\n"
      "abscissa is the signed polar angle of the microfacet normal. Zoomed tables (a window of "
      "the\n"
      "disk, see docs/formats.md) are cut over their window only; when every table is zoomed and "
      "no\n"
      "--theta-max is given, the axis spans the windows.\n\n"
      "Examples:\n"
      "  microbrdf slice naive.npy filtered.npy --azimuth 0,90 --log -o slices.png\n"
      "  microbrdf slice ndf.npy --azimuth 90 --theta-max 15deg -o cross.svg --csv cross.csv");
  cmd->add_option("ndfs", a->inputs, "Tabulated NDFs (.npy or .exr)")->required();
  cmd->add_option("-o,--output", a->output, "Plot (.png or .svg)")->required();
  cmd->add_option("--azimuth", a->azimuths,
                  "In-plane directions (deg unless marked), comma separated")
      ->delimiter(',')
      ->capture_default_str()
      ->check(direction());
  cmd->add_option("--label", a->labels, "Legend names, one per NDF (default: file stems)")
      ->delimiter(',');
  cmd->add_option("--theta-max", a->theta_max, "Largest |polar angle| shown")
      ->capture_default_str()
      ->check(angle_in(0.001 * M_PI / 180, M_PI / 2));
  cmd->add_flag("--log", a->log, "Logarithmic D axis");
  cmd->add_option("--csv", a->csv, "Also write the slices as CSV");
  cmd->callback([a] { run_guarded("slice", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

#pragma once
// What the `simulate` modes share: the flags, the angle list, the trace options.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "microbrdf/microscene.hpp"
#include "microbrdf/simulate.hpp"

namespace microbrdf::cli::simulate_cli {

constexpr double kDeg = M_PI / 180;

struct SimArgs {
  std::string scene, output, time = "", in_plane, cone = "4deg", he_sigma, he_tau, sh, plot, csv;
  std::string phi_i = "0deg";
  bool isotropic = false, visibility = false;
  std::uint64_t vis_samples = 40000;
  int lmax = 15, points = 16, branches = 1, max_depth = 100, threads = 0;
  std::uint64_t rays = 2000000, seed = 1, gonio_rays = 1000000;
  bool json = false, quiet = false, single = false, independent = false;
};

/// "0,30,45" -> radians, each in [0, 90) deg (InputError naming --in-plane otherwise).
std::vector<double> angle_list(const std::string& text);
/// --branches, --max-depth (InputError when < 1).
TraceOptions trace_options(const SimArgs& a);

/// --in-plane: the virtual goniometer (goniometer.hpp), as CSV, JSON and a figure.
void run_in_plane(const SimArgs& a, const MicroScene& scene);
/// --visibility: ray-traced G1 and free travel probability against Smith and Sun 2002.
void run_visibility(const SimArgs& a, const MicroScene& scene);

}  // namespace microbrdf::cli::simulate_cli

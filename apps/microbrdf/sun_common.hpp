#pragma once
// What the `sun` subcommands share: their flags, the angle grid and number formatting.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "spec_flags.hpp"

namespace microbrdf::cli::sun_cli {

constexpr double kDeg = M_PI / 180;

struct SunArgs {
  std::vector<double> s;
  std::string theta_step = "1deg", theta_max = "90deg", theta_i = "30deg";
  std::string output, plot, plot_grid;
  bool json = false, log_y = false;
  double k_tau = 1;
  std::size_t samples = 100000;
  std::uint64_t seed = 1;
  double samples_per_tau = 16;
  std::size_t profile_length = 65536;
  SpecFlags material;
};

/// Radians to degrees for printing, rounded to 1e-9 deg (29.999999999999996 -> 30).
double deg(double rad);
/// "%.8g"
std::string num(double v);
/// "s = 0.5"
std::string s_label(double s);
/// 0, step, 2 step, ... up to --theta-max (rad); InputError for a bad step or maximum.
std::vector<double> theta_grid(const SunArgs& a);
/// At least one --s, each positive.
void check_s_list(const std::vector<double>& s);
/// --s (a list when `list`).
void add_s(CLI::App* c, SunArgs& a, bool list);

void run_simulate(const SunArgs& a);

}  // namespace microbrdf::cli::sun_cli

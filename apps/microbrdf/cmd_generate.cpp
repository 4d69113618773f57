// `microbrdf generate gaussian|profile|brushed|cylinders|grating -o FILE`: synthetic surfaces with
// known statistics, reproducible with --seed.
#include <cmath>
#include <cstdio>
#include <memory>
#include <utility>

#include "cli_checks.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/generate.hpp"
#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct GenArgs {
  std::string output, preview;
  std::size_t nx = 0, ny = 0;
  std::string spacing = "110nm";
  std::uint64_t seed = 1;
  bool json = false;
  // gaussian / profile / brushed
  std::string sigma = "0.1um", tau = "2um", tau_y, angle = "0";
  bool process = false;
  std::size_t rows = 1;
  std::string preset, tau_across = "2um", scratch_spacing, scratch_depth, scratch_width;
  std::string alpha_along, alpha_across, filter_sigma = "1um";
  // cylinders / grating
  std::string radius = "5um", pitch = "12um", amplitude = "0.1um", period = "5um";
  double jitter = 0;
  bool grooves = false;
};

std::pair<double, double> spacing_of(const GenArgs& a) {
  const LengthPair p = parse_length_or_pair(a.spacing);
  return {p.x, p.y};
}

// The outputs before the heights are made (a large grid takes seconds).
void check_outputs(const GenArgs& a) {
  Preflight pre;
  if (!a.preview.empty()) pre.output("--preview", a.preview, {".png"});
  pre.height_map_output("-o", a.output).done();
}

template <class P>
void set_grid(P& p, const GenArgs& a) {
  check_outputs(a);
  if (a.nx) p.nx = a.nx;
  if (a.ny) p.ny = a.ny;
  // The generators' own limit (2^28 samples, 2 GiB of heights), said with the flags and the
  // memory the grid would take.
  if (double(p.nx) * double(p.ny) > double(std::size_t{1} << 28))
    throw InputError("--nx x --ny: " + std::to_string(p.nx) + " x " + std::to_string(p.ny) +
                     " samples is more than 2^28 (268 million samples, 2 GiB of heights)");
  check_memory("--nx x --ny", mul_sat(mul_sat(p.nx, p.ny), 3 * sizeof(double)),
               "the heights and their spectrum");
  std::tie(p.dx, p.dy) = spacing_of(a);
}

void finish(const std::string& kind, const GenArgs& a, const Surface& s, nlohmann::json params) {
  write_surface(s, a.output);
  if (!a.preview.empty()) write_png(a.preview, render_height_preview(s));
  auto st = compute_stats(s);
  if (a.json) {
    auto j = stats_json(a.output, s, st);
    j["generator"] = kind;
    j["params"] = params;
    print_json(j);
  } else {
    std::fprintf(stderr,
                 "microbrdf generate %s: wrote %s (%zu x %zu, spacing %s); measured Sq %s, rms "
                 "slope x %s y %s, "
                 "corr. length x %s y %s\n",
                 kind.c_str(), a.output.c_str(), s.nx, s.ny, format_length(s.dx).c_str(),
                 format_length(st.sq).c_str(), number_or_na(st.slope_rms_x).c_str(),
                 number_or_na(st.slope_rms_y).c_str(), format_length(st.corr_length_x).c_str(),
                 format_length(st.corr_length_y).c_str());
  }
}

void add_common(CLI::App* c, GenArgs& a, const char* default_size) {
  c->add_option("-o,--output", a.output, "Output height map (.x3p .gwy .npy .xyz .txt)")
      ->required();
  c->add_option("--nx", a.nx, std::string("Samples along x (default ") + default_size + ")")
      ->check(count_in(1, 1 << 28));
  c->add_option("--ny", a.ny, "Samples along y (rows)")->check(count_in(1, 1 << 28));
  c->add_option("--spacing", a.spacing, "Sample spacing, e.g. 110nm, or 110x130nm for dx x dy")
      ->capture_default_str()
      ->check(length_or_pair_in(kMinLength, kMaxLength));
  c->add_option("--seed", a.seed, "Random seed (same seed, same surface)")->capture_default_str();
  c->add_option("--preview", a.preview, "Also write a false-colour PNG of the heights");
  c->add_flag("--json", a.json, "Print parameters and measured statistics as JSON on stdout");
}

}  // namespace

void register_generate(CLI::App& app) {
  auto a = std::make_shared<GenArgs>();
  auto* gen = app.add_subcommand("generate", "Synthetic surfaces with known statistics");
  gen->require_subcommand(1);
  gen->footer(
      "Kinds: gaussian, profile, brushed, cylinders, grating (each has --help).\n\n"
      "Examples:\n"
      "  microbrdf generate gaussian --sigma 0.2um --tau 2um -o g.x3p\n"
      "  microbrdf generate gaussian --sigma 0.2um --tau 5um --tau-y 1um --angle 30 -o aniso.x3p\n"
      "  microbrdf generate brushed --preset stainless4 -o brushed.x3p --preview brushed.png\n"
      "  microbrdf generate grating --amplitude 50nm --period 4um -o grating.x3p");

  auto* g = gen->add_subcommand(
      "gaussian", "Gaussian random surface, ACF sigma^2 exp(-(u/tau)^2 - (v/tau_y)^2)");
  add_common(g, *a, "1024");
  g->add_option("--sigma", a->sigma, "rms height")->capture_default_str()->check(height());
  g->add_option("--tau", a->tau, "Correlation length (along --angle)")
      ->capture_default_str()
      ->check(distance());
  g->add_option("--tau-y", a->tau_y,
                "Correlation length across --angle (default: = --tau, isotropic)")
      ->check(distance());
  g->add_option("--angle", a->angle, "Direction of --tau from the x axis (deg unless marked)")
      ->capture_default_str()
      ->check(direction());
  g->add_flag(
      "--process", a->process,
      "True Gaussian process (random amplitudes): statistics scatter between seeds. Default: exact "
      "spectrum (random phases), so every realisation has the asked-for ACF");
  g->callback([a] {
    run_guarded("generate", [&] {
      GaussianSurfaceParams p;
      set_grid(p, *a);
      p.sigma = parse_length(a->sigma);
      p.tau_x = parse_length(a->tau);
      p.tau_y = a->tau_y.empty() ? p.tau_x : parse_length(a->tau_y);
      p.angle = parse_angle(a->angle);
      p.seed = a->seed;
      p.exact_spectrum = !a->process;
      finish("gaussian", *a, generate_gaussian(p),
             {{"sigma_m", p.sigma},
              {"tau_x_m", p.tau_x},
              {"tau_y_m", p.tau_y},
              {"angle_rad", p.angle},
              {"seed", p.seed},
              {"exact_spectrum", p.exact_spectrum},
              {"expected_slope_rms_x", std::sqrt(2.0) * p.sigma / p.tau_x}});
    });
  });

  auto* pr = gen->add_subcommand("profile",
                                 "1-D Gaussian profiles by moving average (Sun 2002 section 4)");
  add_common(pr, *a, "65536");
  pr->add_option("--sigma", a->sigma, "rms height")->capture_default_str()->check(height());
  pr->add_option("--tau", a->tau, "Correlation length")->capture_default_str()->check(distance());
  pr->add_option("--rows", a->rows, "Number of independent profiles (rows)")->capture_default_str();
  pr->callback([a] {
    run_guarded("generate", [&] {
      check_outputs(*a);
      ProfileParams p;
      if (a->nx) p.n = a->nx;
      p.rows = a->rows;
      p.dx = spacing_of(*a).first;
      p.sigma = parse_length(a->sigma);
      p.tau = parse_length(a->tau);
      p.seed = a->seed;
      finish("profile", *a, generate_profiles(p),
             {{"sigma_m", p.sigma}, {"tau_m", p.tau}, {"seed", p.seed}});
    });
  });

  auto* b =
      gen->add_subcommand("brushed", "Brushed metal: anisotropic Gaussian base plus scratches");
  add_common(b, *a, "2048 x 1024");
  b->add_option("--preset", a->preset,
                "stainless4 (alpha ~0.007 along / 0.14 across) or aluminium4 (0.02 / 0.47)");
  b->add_option("--alpha-along", a->alpha_along,
                "Target width along the brushing. With --preset: of the ellipsoid fitted to the "
                "filtered NDF (the preset's depth modulation is kept and the base's rms width set "
                "to 1.6x this, the presets' own calibration); without: the rms width of the "
                "filtered Gaussian base")
      ->check(positive_number(10));
  b->add_option("--alpha-across", a->alpha_across,
                "Target width across (with --preset: base rms width 1.8x this)")
      ->check(positive_number(10));
  b->add_option("--filter-sigma", a->filter_sigma, "Filter the target widths refer to")
      ->capture_default_str()
      ->check(distance());
  b->add_option("--tau-across", a->tau_across, "Base correlation length across")
      ->capture_default_str()
      ->check(distance());
  b->add_option("--angle", a->angle, "Brushing direction from the x axis")
      ->capture_default_str()
      ->check(direction());
  b->add_option("--scratch-spacing", a->scratch_spacing,
                "Mean distance between scratches across the brushing "
                "(0 = no scratches)")
      ->check(length_in(0, kMaxLength));
  b->add_option("--scratch-depth", a->scratch_depth,
                "Mean scratch depth (exponentially distributed)")
      ->check(height());
  b->add_option("--scratch-width", a->scratch_width,
                "Mean Gaussian sigma of a scratch's cross-section")
      ->check(distance());
  b->callback([a] {
    run_guarded("generate", [&] {
      BrushedParams p = a->preset.empty() ? BrushedParams{} : brushed_preset(a->preset);
      set_grid(p, *a);
      p.angle = parse_angle(a->angle);
      p.seed = a->seed;
      if (!a->alpha_along.empty() || !a->alpha_across.empty()) {
        if (a->alpha_along.empty() || a->alpha_across.empty())
          throw InputError("--alpha-along and --alpha-across go together");
        p.tau_across = parse_length(a->tau_across);
        const auto [k_along, k_across] = brushed_modulation_calibration(p);
        solve_brushed_base(p, k_along * std::stod(a->alpha_along),
                           k_across * std::stod(a->alpha_across), parse_length(a->filter_sigma));
      }
      if (!a->scratch_spacing.empty()) {
        double d = parse_length(a->scratch_spacing);
        p.scratch_density = d > 0 ? 1.0 / d : 0.0;
      }
      if (!a->scratch_depth.empty()) p.scratch_depth = parse_length(a->scratch_depth);
      if (!a->scratch_width.empty()) p.scratch_width = parse_length(a->scratch_width);
      double s = parse_length(a->filter_sigma);
      finish("brushed", *a, generate_brushed(p),
             {{"preset", a->preset},
              {"sigma_m", p.sigma},
              {"tau_along_m", p.tau_along},
              {"tau_across_m", p.tau_across},
              {"angle_rad", p.angle},
              {"scratch_density_per_m", p.scratch_density},
              {"scratch_depth_m", p.scratch_depth},
              {"scratch_width_m", p.scratch_width},
              {"seed", p.seed},
              {"predicted_base_alpha_along_filtered",
               predicted_filtered_alpha(p.sigma, p.tau_along, p.tau_across, s)},
              {"predicted_base_alpha_across_filtered",
               predicted_filtered_alpha(p.sigma, p.tau_across, p.tau_along, s)},
              {"filter_sigma_m", s}});
    });
  });

  auto* c = gen->add_subcommand("cylinders", "Parallel cylinders (or grooves) along --angle");
  add_common(c, *a, "1024");
  c->add_option("--radius", a->radius, "Cylinder radius")->capture_default_str()->check(distance());
  c->add_option("--pitch", a->pitch, "Axis spacing")->capture_default_str()->check(distance());
  c->add_option("--angle", a->angle, "Axis direction from the x axis")
      ->capture_default_str()
      ->check(direction());
  c->add_option("--jitter", a->jitter, "Random axis shift, fraction of the pitch (0..0.5)")
      ->capture_default_str()
      ->check(number_in(0, 0.5));
  c->add_flag("--grooves", a->grooves, "Cut grooves into a plane instead of raising cylinders");
  c->callback([a] {
    run_guarded("generate", [&] {
      CylindersParams p;
      set_grid(p, *a);
      p.radius = parse_length(a->radius);
      p.pitch = parse_length(a->pitch);
      p.angle = parse_angle(a->angle);
      p.jitter = a->jitter;
      p.grooves = a->grooves;
      p.seed = a->seed;
      finish("cylinders", *a, generate_cylinders(p),
             {{"radius_m", p.radius},
              {"pitch_m", p.pitch},
              {"angle_rad", p.angle},
              {"jitter", p.jitter},
              {"grooves", p.grooves}});
    });
  });

  auto* gr = gen->add_subcommand("grating", "Sinusoidal grating z = A sin(2 pi u / P)");
  add_common(gr, *a, "1024");
  gr->add_option("--amplitude", a->amplitude, "Amplitude A")
      ->capture_default_str()
      ->check(height());
  gr->add_option("--period", a->period, "Period P")->capture_default_str()->check(distance());
  gr->add_option("--angle", a->angle, "Direction of u from the x axis")
      ->capture_default_str()
      ->check(direction());
  gr->callback([a] {
    run_guarded("generate", [&] {
      GratingParams p;
      set_grid(p, *a);
      p.amplitude = parse_length(a->amplitude);
      p.period = parse_length(a->period);
      p.angle = parse_angle(a->angle);
      finish("grating", *a, generate_grating(p),
             {{"amplitude_m", p.amplitude}, {"period_m", p.period}, {"angle_rad", p.angle}});
    });
  });
}

}  // namespace microbrdf::cli

// `microbrdf tabulate`: an analytic NDF (Beckmann, GGX, ellipsoid) on the 1025 x 1025 disk table.
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/units.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {
namespace {

struct TabulateArgs {
  SpecFlags model;
  std::size_t resolution = 1025;
  std::vector<double> window;  // CX, CY, HALF (disk coordinates)
  std::string output;
  bool json = false;
};

void run(const TabulateArgs& a) {
  const NdfSpec s = ndf_spec(a.model);
  if (a.resolution < 3 || a.resolution > 8193) throw InputError("--resolution must lie in 3..8193");
  NdfWindow w;
  if (!a.window.empty()) {
    if (a.window.size() != 3)
      throw InputError("--window takes three numbers: CX,CY,HALF (disk coordinates)");
    const double cx = a.window[0], cy = a.window[1], half = a.window[2];
    if (!(half > 0 && half <= 1) || !(std::abs(cx) + half <= 1) || !(std::abs(cy) + half <= 1))
      throw InputError(
          "--window CX,CY,HALF must lie inside [-1, 1]^2 (0 < HALF <= 1, |CX| + HALF <= 1, "
          "|CY| + HALF <= 1)");
    w = zoom_window(cx, cy, half);
  }
  auto d = make_distribution(s);
  auto t = tabulate(*d, s.model, a.resolution, w);
  write_ndf(t, a.output);
  const Eigen::Vector3d peak = t.peak();
  if (a.json) {
    print_json({{"output", a.output},
                {"model", s.model},
                {"description", d->describe()},
                {"alpha_x", s.alpha_x},
                {"alpha_y", s.alpha_y},
                {"phi_rad", s.phi},
                {"theta_rad", {s.theta_x, s.theta_y, s.theta_z}},
                {"resolution", a.resolution},
                {"window", {{"x", {w.x0(), w.x1()}}, {"y", {w.y0(), w.y1()}}}},
                {"sampling", t.meta.sampling},
                {"notes", t.meta.notes},
                {"peak", {peak.x(), peak.y(), peak.z()}}});
  } else {
    std::printf("%s\n  %zu x %zu table written to %s (%s)\n", d->describe().c_str(), a.resolution,
                a.resolution, a.output.c_str(), t.meta.notes.c_str());
  }
}

}  // namespace

void register_tabulate(CLI::App& app) {
  auto a = std::make_shared<TabulateArgs>();
  auto* c = app.add_subcommand(
      "tabulate", "Tabulate an analytic NDF (beckmann, ggx, ellipsoid) on the disk grid");
  c->footer(
      "The table holds D(m) (1/sr) at the nodes of the orthographic unit disk (node-centred, N x "
      "N),\n"
      "normalised so that sum D Delta^2 = 1; lobes narrower than ~6/(N-1) are under-resolved (the\n"
      "node sum before normalising is recorded in the metadata); --window CX,CY,HALF tabulates "
      "only\n"
      "that square of the disk (a zoomed table resolving a narrow lobe; its extent is in the "
      "metadata).\n"
      "The table records \"sampling\": \"point\" (D at the nodes), which `fit` follows.\n"
      "Ellipsoid (Dong 2015 eqs. 10-12): A = S R, R = Rx(theta_x) Ry(theta_y) Rz(theta_z); the "
      "peak\n"
      "is at R^T z: theta_x > 0 tilts it towards +y, theta_y > 0 towards -x.\n"
      "Angles take units (5deg, 0.05rad; a bare number is degrees); --json reports radians\n"
      "(phi_rad, theta_rad), as `fit --json` does.\n\n"
      "Examples:\n"
      "  microbrdf tabulate --model ggx --alpha 0.1 -o ggx.npy\n"
      "  microbrdf tabulate --model beckmann --alpha-x 0.05 --alpha-y 0.2 --phi 30deg -o b.npy\n"
      "  microbrdf tabulate --model ellipsoid --alpha-x 0.1 --alpha-y 0.3 --theta-x 5deg --theta-z "
      "20deg \\\n"
      "      --resolution 513 -o ell.npy --json\n"
      "  microbrdf tabulate --model beckmann --alpha 0.002 --window 0,0,0.02 --resolution 257 "
      "-o zoom.npy");
  add_model_flags(c, a->model);
  c->add_option("--resolution", a->resolution, "Nodes per side")
      ->capture_default_str()
      ->check(count_in(3, 8193));
  c->add_option("--window", a->window,
                "Zoomed table: CX,CY,HALF, the square [CX-HALF, CX+HALF] x [CY-HALF, CY+HALF] "
                "of the disk plane (D = 0 outside it; recorded in the metadata)")
      ->delimiter(',')
      ->expected(3);
  c->add_option("-o,--output", a->output, "Output table (.npy with a JSON sidecar, or .exr)")
      ->required();
  c->add_flag("--json", a->json, "Print a JSON summary on stdout");
  c->callback([a] { run_guarded("tabulate", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

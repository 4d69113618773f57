// `microbrdf export bsdf|mitsuba|pbrt`: renderer-ready materials (RGL .bsdf files, Mitsuba 3 and
// pbrt-v4 scenes; docs/measured.md).
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/export.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/measured_ndf.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/scene_export.hpp"

namespace microbrdf::cli {
namespace {

namespace fs = std::filesystem;

struct BsdfArgs {
  std::string input, output;
  bool anisotropic = false, json = false;
  std::size_t theta_i = 24, phi_i = 17, ndf_grid = 64, samples = 32, wavelengths = 25;
};

std::unique_ptr<Brdf> load_measured(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  for (auto& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (e == ".binary") return std::make_unique<MerlBrdf>(read_merl(path), path);
  if (e == ".bsdf") return std::make_unique<RglBrdf>(RglBrdf::load(path));
  if (e == ".csv")
    throw InputError(path + ": a goniometer point set is not a full BRDF; use `measured ndf`");
  throw InputError(path + ": unknown measured-BRDF type (use .binary MERL or .bsdf RGL)");
}

void run_bsdf(const BsdfArgs& a) {
  for (auto [v, name] : {std::pair{a.theta_i, "--theta-i"},
                         {a.ndf_grid, "--ndf-grid"},
                         {a.samples, "--samples"},
                         {a.wavelengths, "--wavelengths"}})
    if (v < 2 || v > 512) throw InputError(std::string(name) + " must lie in 2..512");
  if (a.anisotropic && (a.phi_i < 3 || a.phi_i > 512))
    throw InputError("--phi-i must lie in 3..512");
  const auto brdf = load_measured(a.input);
  RglExportOptions o;
  o.isotropic = !a.anisotropic;
  o.theta_i = a.theta_i;
  o.phi_i = a.phi_i;
  o.ndf_theta = o.ndf_phi = a.ndf_grid;
  o.samples = a.samples;
  o.wavelengths_nm.resize(a.wavelengths);
  for (std::size_t i = 0; i < a.wavelengths; ++i)
    o.wavelengths_nm[i] = 360.0 + 470.0 * double(i) / double(a.wavelengths - 1);
  o.description = "microbrdf export of " + fs::path(a.input).filename().string();
  // The grids follow the BRDF's own lobe (eq. 9 shape at theta_d = 14.14 deg).
  const auto lobe = lobe_distribution(*brdf, 257);
  {
    // One output file, renamed into place at once: it may commit now, so its size can be read.
    OutputGroup::Bypass direct;
    write_rgl_bsdf(*brdf, *lobe, o, a.output);
  }
  const auto bytes = fs::file_size(a.output);
  if (a.json)
    print_json({{"input", a.input},
                {"output", a.output},
                {"isotropic", o.isotropic},
                {"theta_i", o.theta_i},
                {"phi_i", o.isotropic ? 1 : o.phi_i},
                {"ndf_grid", a.ndf_grid},
                {"samples", o.samples},
                {"wavelengths", a.wavelengths},
                {"bytes", bytes}});
  else
    std::printf("%s -> %s (%s, %zu theta_i, %zu x %zu samples, %zu wavelengths, %.1f MB)\n",
                a.input.c_str(), a.output.c_str(), o.isotropic ? "isotropic" : "anisotropic",
                o.theta_i, o.samples, o.samples, a.wavelengths, double(bytes) / 1e6);
}

struct SceneArgs {
  std::string bsdf, output, envmap;
  bool json = false;
};

void run_scene(const SceneArgs& a, bool mitsuba) {
  (void)RglBrdf::load(a.bsdf);  // refuse a broken file before writing anything
  SceneExportOptions o;
  o.envmap = a.envmap;
  const std::string name = fs::path(a.bsdf).filename().string();
  auto files = mitsuba ? export_mitsuba_measured(name, a.output, o)
                       : export_pbrt_measured(name, a.output, o);
  if (fs::absolute(a.bsdf) != fs::absolute(fs::path(a.output) / name)) {
    write_file_atomic((fs::path(a.output) / name).string(),
                      read_file_bytes(a.bsdf, std::uint64_t{1} << 32));
    files.push_back(name);
  }
  if (a.json) {
    print_json({{"output", a.output}, {"files", files}});
  } else {
    for (const auto& f : files) std::printf("%s\n", (fs::path(a.output) / f).string().c_str());
  }
}

}  // namespace

void register_export(CLI::App& app) {
  auto* e = app.add_subcommand("export", "Renderer-ready materials: .bsdf, Mitsuba 3, pbrt-v4");
  e->require_subcommand(1);
  auto a = std::make_shared<BsdfArgs>();
  auto* b = e->add_subcommand("bsdf", "Write a measured BRDF as an RGL .bsdf tensor file");
  b->footer(
      "The RGL format of Mitsuba 3's `measured` plugin and pbrt-v4's MeasuredBxDF (Dupuy & Jakob "
      "2018).\n"
      "The grids follow the BRDF's own lobe; the file returns the BRDF exactly at its sample "
      "nodes.\n"
      "Defaults (isotropic): 24 theta_i, 64 x 64 ndf grid, 32 x 32 samples, 25 wavelengths "
      "360-830 nm:\n"
      "about 2.9 MB; median error of f cos(theta_o) on the lobe 0.07-0.25 % for GGX lobes "
      "(docs/measured.md).\n\n"
      "Examples:\n"
      "  microbrdf export bsdf alum.binary -o alum.bsdf\n"
      "  microbrdf export bsdf alum.binary --theta-i 32 --samples 48 -o alum_fine.bsdf");
  b->add_option("file", a->input, "Measured BRDF: .binary (MERL) or .bsdf (RGL)")->required();
  b->add_option("-o,--output", a->output, "Output .bsdf file")->required();
  b->add_flag("--anisotropic", a->anisotropic, "Store incident azimuths (phi_i over 2 pi)");
  b->add_option("--theta-i", a->theta_i, "Incident elevations over [0, 89] deg")
      ->capture_default_str();
  b->add_option("--phi-i", a->phi_i, "Incident azimuths (--anisotropic)")->capture_default_str();
  b->add_option("--ndf-grid", a->ndf_grid, "ndf/sigma/vndf nodes per axis")->capture_default_str();
  b->add_option("--samples", a->samples, "luminance/spectra nodes per axis")->capture_default_str();
  b->add_option("--wavelengths", a->wavelengths, "Wavelengths over 360-830 nm")
      ->capture_default_str();
  b->add_flag("--json", a->json, "Print a JSON summary on stdout");
  b->callback([a] { run_guarded("export bsdf", [&] { run_bsdf(*a); }); });

  for (bool mitsuba : {true, false}) {
    auto s = std::make_shared<SceneArgs>();
    auto* c = e->add_subcommand(mitsuba ? "mitsuba" : "pbrt",
                                mitsuba ? "Mitsuba 3 material + sphere scene for a .bsdf file"
                                        : "pbrt-v4 material + sphere scene for a .bsdf file");
    c->footer(std::string("Writes material.") + (mitsuba ? "xml" : "pbrt") + " and scene." +
              (mitsuba ? "xml" : "pbrt") +
              " into DIR with a `measured` material referencing the .bsdf (copied into DIR).\n" +
              (mitsuba ? "--envmap FILE lights the sphere with that map (copied); default: a "
                         "constant emitter.\n"
                       : "pbrt-v4 wants equal-area environment maps: the scene uses a uniform "
                         "infinite light.\n") +
              "\nExample:\n  microbrdf export " + (mitsuba ? "mitsuba" : "pbrt") +
              " --bsdf alum.bsdf -o scene/");
    c->add_option("--bsdf", s->bsdf, "The .bsdf file (from `export bsdf`)")->required();
    c->add_option("-o,--output", s->output, "Output directory")->required();
    if (mitsuba) c->add_option("--envmap", s->envmap, "Environment map (EXR/HDR lat-long)");
    c->add_flag("--json", s->json, "Print a JSON summary on stdout");
    c->callback([s, mitsuba] {
      run_guarded(mitsuba ? "export mitsuba" : "export pbrt", [&] { run_scene(*s, mitsuba); });
    });
  }
}

}  // namespace microbrdf::cli

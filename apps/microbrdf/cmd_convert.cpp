// `microbrdf convert IN OUT`: between every readable and every writable format.
#include <cstdio>
#include <memory>

#include "cli_checks.hpp"
#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/height_preview.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct ConvertArgs {
  std::string in, out, preview;
  ReadFlags read;
  bool json = false;
};

void run(const ConvertArgs& a) {
  // The outputs before the input is read (a large scan takes seconds).
  Preflight pre;
  pre.height_map_output("output", a.out);
  if (!a.preview.empty()) pre.output("--preview", a.preview, {".png"});
  pre.done();
  std::string lev;
  Surface s = load_surface(a.in, a.read, &lev);
  write_surface(s, a.out);
  if (!a.preview.empty()) write_png(a.preview, render_height_preview(s));
  if (a.json) {
    print_json({{"input", a.in},
                {"output", a.out},
                {"format", format_name(format_from_extension(a.out))},
                {"nx", s.nx},
                {"ny", s.ny},
                {"dx_m", s.dx},
                {"dy_m", s.dy},
                {"valid_count", s.valid_count()},
                {"leveling", s.meta.leveling},
                {"leveling_report", lev}});
  } else {
    std::fprintf(
        stderr,
        "microbrdf convert: %s -> %s (%zu x %zu, spacing %s x %s, %zu invalid, levelling %s)\n",
        a.in.c_str(), a.out.c_str(), s.nx, s.ny, format_length(s.dx).c_str(),
        format_length(s.dy).c_str(), s.size() - s.valid_count(), lev.c_str());
  }
}

}  // namespace

void register_convert(CLI::App& app) {
  auto args = std::make_shared<ConvertArgs>();
  auto* cmd = app.add_subcommand("convert", "Convert a height map between formats");
  cmd->footer(
      "Reads:  .x3p .dat (Zygo MetroPro) .datx (Zygo HDF5) .sur (Digital Surf) .plu (Sensofar)\n"
      "        .gwy .xyz .txt/.asc/.csv .npy .exr .tif\n"
      "Writes: .x3p .gwy .xyz .txt .npy (+ .json sidecar with the spacing)\n"
      "Heights are written in metres; invalid samples stay invalid (NaN / mask / valid.bin).\n"
      "The output appears only when complete (written to a temporary name, then renamed).\n\n"
      "Examples:\n"
      "  microbrdf convert metropro-1.dat scan.x3p\n"
      "  microbrdf convert scan.x3p scan.npy --level plane");
  cmd->add_option("input", args->in, "Height map to read")->required();
  cmd->add_option("output", args->out, "File to write; the format comes from the extension")
      ->required();
  add_read_flags(cmd, args->read, "none");
  cmd->add_option("--preview", args->preview, "Also write a false-colour height-map PNG");
  cmd->add_flag("--json", args->json, "Print a JSON summary on stdout");
  cmd->callback([args] { run_guarded("convert", [&] { run(*args); }); });
}

}  // namespace microbrdf::cli

// `microbrdf texture`: per-texel ellipsoid fits of scan sets and separable Fourier synthesis of
// large parameter textures (Dong 2015 section 9). See docs/texture.md.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli_common.hpp"
#include "commands.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/scanset.hpp"
#include "microbrdf/texture.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf::cli {
namespace {

struct TextureArgs {
  std::vector<std::string> inputs, along, across;
  std::string texel = "53um";
  std::string filter_sigma = "1um";
  std::size_t resolution = 129;
  std::size_t size = 0;
  std::string pitch;
  std::uint64_t seed = 1;
  std::string output, texels_out, preview;
  bool no_preview = false;
  std::size_t preview_size = 512;
  bool tent = false;
  bool lognormal = false;
  bool no_histogram = false;
  bool json = false;
  ReadFlags read;
};

// An exemplar: a parameter-texture EXR as is, or the texels fitted from scans.
ParamTexture exemplar(const std::vector<std::string>& inputs, const TextureArgs& a, bool stack_y,
                      const char* role, nlohmann::json& mpi) {
  if (inputs.size() == 1 && is_param_texture_file(inputs[0])) {
    std::fprintf(stderr, "microbrdf texture: %s exemplar: parameter texture %s\n", role,
                 inputs[0].c_str());
    return read_param_texture(inputs[0]);
  }
  for (const auto& p : inputs)
    if (is_param_texture_file(p))
      throw InputError("give a parameter texture (" + p +
                       ") alone, not mixed with other inputs, as an exemplar");
  const auto paths = scan_inputs(inputs);
  TexelFitOptions o;
  o.texel_m = parse_length(a.texel);
  o.filter_sigma_m = parse_length(a.filter_sigma);
  o.ndf_resolution = a.resolution;
  o.leveling = LevelingSpec::parse(a.read.level);
  o.stack_along_y = stack_y;
  o.sampling = a.tent ? FitSampling::Tent : FitSampling::Node;
  std::size_t done = 0;
  o.progress = [&](double f) {
    const auto k = static_cast<std::size_t>(std::llround(f * static_cast<double>(paths.size())));
    if (k > done && paths.size() > 1)
      std::fprintf(stderr, "microbrdf texture: %s: [%zu/%zu] scans fitted\n", role, k,
                   paths.size());
    done = k;
  };
  std::fprintf(stderr, "microbrdf texture: %s: fitting %s texels of %zu scan(s)\n", role,
               format_length(o.texel_m).c_str(), paths.size());
  const auto t0 = std::chrono::steady_clock::now();
  WorkStats stats;
  ParamTexture t = fit_texels(paths, read_options(a.read), o, &stats);
  // One scan set: "mpi" as for ndf; two strips: one record each under "along" and "across".
  (stack_y || std::string(role) == "along" ? mpi[role] : mpi) = stats.to_json("scans_per_rank");
  std::fprintf(stderr, "microbrdf texture: %s: %zu x %zu texels, %zu failed, %.3g s\n", role, t.nx,
               t.ny, t.size() - t.valid_count(),
               std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  return t;
}

nlohmann::json summary(const ParamTexture& t) {
  nlohmann::json ch = nlohmann::json::object();
  for (int c = 0; c < 5; ++c) {
    const ChannelStats s = channel_stats(t, c);
    ch[ParamTexture::channel_names[c]] = {
        {"mean", s.mean}, {"std", std::sqrt(s.variance)}, {"min", s.min}, {"max", s.max}};
  }
  nlohmann::json j = {{"nx", t.nx},
                      {"ny", t.ny},
                      {"texel_m", t.texel_m},
                      {"valid", t.valid_count()},
                      {"failed", t.size() - t.valid_count()},
                      {"channels", ch}};
  // Fitted texels: how many had a width below a table node (refitted on a zoomed table) and how
  // many were still lifted to alpha_min.
  for (const char* k : {"alpha_zoomed", "alpha_lifted_to_min"})
    if (t.meta.contains(k)) j[k] = t.meta.at(k);
  return j;
}

std::string preview_path(const TextureArgs& a) {
  if (a.no_preview) return {};
  if (!a.preview.empty()) return a.preview;
  return std::filesystem::path(a.output).replace_extension(".png").string();
}

void run(const TextureArgs& a) {
  const auto t0 = std::chrono::steady_clock::now();
  if (a.output.empty()) throw InputError("-o OUT.exr is required");
  const bool strips = !a.along.empty() || !a.across.empty();
  if (strips && (a.along.empty() || a.across.empty()))
    throw InputError("--along and --across go together (one exemplar strip each)");
  if (strips && !a.inputs.empty())
    throw InputError("give either scans (a 2-D exemplar) or --along/--across strips, not both");
  if (!strips && a.inputs.empty()) throw InputError("no scans or parameter texture given");
  if (strips && a.size == 0) throw InputError("--along/--across synthesise: give --size");
  if (a.resolution < 17 || a.resolution > 1025)
    throw InputError("--resolution must lie in 17..1025");
  parse_length(a.texel);  // validate early

  nlohmann::json j;
  ParamTexture out;
  if (a.size == 0) {  // fit only: the texel parameter image of the scans
    out = exemplar(a.inputs, a, false, "texels", j["mpi"]);
    if (!mpi_is_root()) return;  // rank 0 writes the outputs
    j["mode"] = "fit";
  } else {
    SynthesisOptions so;
    so.size = a.size;
    so.seed = a.seed;
    so.lognormal_alpha = a.lognormal;
    so.match_histogram = !a.no_histogram;
    so.texel_m = a.pitch.empty() ? 0.0 : parse_length(a.pitch);
    if (strips) {
      const ParamTexture along = exemplar(a.along, a, false, "along", j["mpi"]);
      const ParamTexture across = exemplar(a.across, a, true, "across", j["mpi"]);
      if (!mpi_is_root()) return;
      if (!a.texels_out.empty()) {
        const auto stem = std::filesystem::path(a.texels_out);
        write_param_texture(along, stem.string() + ".along.exr");
        write_param_texture(across, stem.string() + ".across.exr");
      }
      out = synthesize_texture(along, across, so);
      j["exemplars"] = {{"along", summary(along)}, {"across", summary(across)}};
    } else {
      const ParamTexture ex = exemplar(a.inputs, a, false, "exemplar", j["mpi"]);
      if (!mpi_is_root()) return;
      if (!a.texels_out.empty()) write_param_texture(ex, a.texels_out);
      out = synthesize_texture(ex, so);
      j["exemplars"] = {{"exemplar", summary(ex)}};
    }
    j["mode"] = "synthesis";
    j["seed"] = a.seed;
    std::fprintf(stderr, "microbrdf texture: synthesised %zu x %zu texels of %s (seed %llu)\n",
                 out.nx, out.ny, format_length(out.texel_m).c_str(),
                 static_cast<unsigned long long>(a.seed));
  }
  write_param_texture(out, a.output);
  const std::string pv = preview_path(a);
  if (!pv.empty()) write_param_preview(out, pv, a.preview_size);
  j["output"] = a.output;
  j["preview"] = pv;
  j.update(summary(out));
  j["meta"] = out.meta;
  j["seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (a.json) {
    print_json(j);
    return;
  }
  std::printf("%s: %zu x %zu texels of %s, %zu valid\n", a.output.c_str(), out.nx, out.ny,
              format_length(out.texel_m).c_str(), out.valid_count());
  for (int c = 0; c < 5; ++c) {
    const ChannelStats s = channel_stats(out, c);
    std::printf("  %-8s mean %-10.4g std %-10.4g range [%.4g, %.4g]%s\n",
                ParamTexture::channel_names[c], s.mean, std::sqrt(s.variance), s.min, s.max,
                c >= 2 ? " rad" : "");
  }
  if (!pv.empty()) std::printf("  preview %s\n", pv.c_str());
}

}  // namespace

void register_texture(CLI::App& app) {
  auto a = std::make_shared<TextureArgs>();
  auto* c = app.add_subcommand(
      "texture", "Per-texel ellipsoid fits of scans and synthesised parameter textures");
  c->footer(
      "Spatially varying ellipsoid NDFs (Dong 2015 section 9). Channels: alpha_x, alpha_y "
      "(dimensionless),\n"
      "theta_x, theta_y, theta_z (rad), plus 'valid' (0 where a fit failed; why is in the "
      "metadata).\n\n"
      "Fit mode (no --size): every scan is levelled, cut into square texels of --texel "
      "(partial texels\n"
      "at the borders are dropped), each texel's filtered NDF (Gaussian plane fit of "
      "--filter-sigma,\n"
      "--resolution^2 table) is fitted with the ellipsoid NDF; the texels of successive "
      "scans are laid\n"
      "side by side along x. Output: the texel parameter image.\n"
      "Synthesis mode (--size N): from a 2-D exemplar (the scans' texels, or a parameter "
      "texture .exr),\n"
      "or from two strips: --along (scans along the brushing, texels laid along x, e.g. "
      "Dong's 100 x 1)\n"
      "and --across (texels laid along y, Dong's 1 x 100). Per parameter: 1-D power spectra "
      "along x\n"
      "and y, their outer product as the 2-D spectrum, resampled to N x N texels of --pitch "
      "(default the\n"
      "exemplar's; band power kept, nothing beyond the exemplar's extent or Nyquist "
      "frequency), random\n"
      "phases from --seed, inverse FFT, then each channel matched to the exemplars' "
      "histogram\n"
      "(its values are the exemplars' quantiles, so within their range; rounds of the "
      "iterative\n"
      "amplitude-adjusted Fourier transform keep the spectrum within 1%). The texture's x axis "
      "is the\n"
      "brushing direction.\n"
      "Output: OUT.exr (5 float channels + valid, metadata in the header) and OUT.png "
      "(one panel per\n"
      "channel, numbered 1-5, range under it; 6th panel: valid/total, failed texels red).\n\n"
      "Examples:\n"
      "  microbrdf texture 'scans/*.x3p' --texel 53um -o texels.exr\n"
      "  microbrdf texture 'scans/*.x3p' --texel 53um --size 2048 --seed 7 -o tex.exr --json\n"
      "  microbrdf texture --along 'along/*.dat' --across 'across/*.dat' --texel 53um --size "
      "2048 -o tex.exr\n"
      "  microbrdf texture texels.exr --size 4096 --pitch 25um -o fine.exr");
  c->add_option("scans", a->inputs,
                "Scans (files, directories, globs, @manifest) or one parameter texture .exr");
  c->add_option("--along", a->along, "Exemplar strip along the brushing (scans or a .exr)");
  c->add_option("--across", a->across, "Exemplar strip across the brushing (scans or a .exr)");
  c->add_option("--texel", a->texel, "Texel size (square), e.g. 53um")
      ->capture_default_str()
      ->check(distance());
  c->add_option("--filter-sigma", a->filter_sigma, "Filtered-NDF Gaussian (Dong sec. 5.1)")
      ->capture_default_str()
      ->check(distance());
  c->add_option("--resolution", a->resolution, "Texel NDF table size N")
      ->capture_default_str()
      ->check(count_in(17, 1025));
  c->add_flag("--tent", a->tent,
              "Fit with the exact histogram (tent) operator: ~100x slower (docs/texture.md)");
  c->add_option("--size", a->size, "Synthesise an N x N texture (omit: fit only)")
      ->check(count_in(2, 32768));
  c->add_option("--pitch", a->pitch, "Output texel pitch (default: the exemplar's)")
      ->check(distance());
  c->add_option("--seed", a->seed, "Random phases' seed")->capture_default_str();
  c->add_flag("--lognormal-alpha", a->lognormal,
              "Also try log-normal alpha fields; keep whichever matches the spectra better");
  c->add_flag("--no-histogram-match", a->no_histogram,
              "Match only the exemplars' mean and variance and clamp to the valid range, instead "
              "of their histogram (values then leave the exemplars' range)");
  c->add_option("-o,--output", a->output, "Output parameter texture (.exr)")->required();
  c->add_option("--texels-out", a->texels_out,
                "Synthesis: also write the fitted exemplar texels (strips: FILE.along.exr, "
                "FILE.across.exr)");
  c->add_option("--preview", a->preview, "Preview PNG (default: OUT with .png)");
  c->add_flag("--no-preview", a->no_preview, "Write no preview");
  c->add_option("--preview-size", a->preview_size, "Longest side of each preview panel, pixels")
      ->capture_default_str()
      ->check(count_in(16, 16384));
  c->add_flag("--json", a->json, "Print a JSON summary on stdout");
  add_read_flags(c, a->read, "plane");
  c->callback([a] { run_guarded("texture", [&] { run(*a); }); });
}

}  // namespace microbrdf::cli

#pragma once
// The Sun 2002 flags of `microbrdf render` (Sun's Figs. 8 and 11): --sun-form, --sun-ftp,
// --s-texture, --s-range, --color-texture (docs/render.md, "Sun 2002 Figs. 8-11").
#include <CLI/CLI.hpp>
#include <memory>
#include <vector>

#include "microbrdf/sun_svbrdf.hpp"
#include "spec_flags.hpp"

namespace microbrdf::cli {

/// The --help footer lines about the Sun options.
extern const char* const kRenderSunHelp;

/// Adds the five flags to `cmd`, writing into `o`.
void add_render_sun_flags(CLI::App* cmd, sun2002::SunRenderOptions& o);

/// The BRDF of the flags, where --s-texture stands for --sun; InputError for the combinations
/// that do not go together (--s-texture with --sun, Sun options without Sun's BRDF,
/// --color-texture with a material flag) and bad Sun option values. Reads no file.
BrdfSpec render_brdf_spec(const SpecFlags& spec, const sun2002::SunRenderOptions& sun);

/// The scene's one material: make_sun_svbrdf when Sun options are given, else make_svbrdf.
std::vector<std::shared_ptr<const Svbrdf>> render_materials(const SpecFlags& spec,
                                                            const sun2002::SunRenderOptions& sun);

}  // namespace microbrdf::cli

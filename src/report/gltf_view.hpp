#pragma once
// The report's glTF view: each fit's exported .glb (export/gltf_<model>.glb) as three.js'
// GLTFLoader and its physically based material show it, beside the project's own WebGL view,
// under the same environment map and exposure (docs/report.md, "glTF view"). three.js is embedded
// by the build (report_js.hpp); the page fetches nothing.
#include <nlohmann/json.hpp>
#include <string>

namespace microbrdf::report {

/// The view's HTML in two parts: `beside`, the canvas and its file buttons, to sit next to the
/// project's sphere; `after`, the caption, the .glb files as base64, the three.js modules as inert
/// text and a module script that loads them from blob: URLs.
struct GltfViewHtml {
  std::string beside, after;
};

/// `dir` is the report folder (the .glb paths in the summary are relative to it). Without
/// embedded three.js, or without any .glb, `beside` is empty and `after` a sentence saying why.
GltfViewHtml gltf_view_html(const nlohmann::json& summary, const std::string& dir);

}  // namespace microbrdf::report

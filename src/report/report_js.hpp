#pragma once
// three.js and its glTF loader for the report's glTF view, as the build embedded them
// (cmake/embed_report_js.cmake, from report-js/node_modules: the npm package `three` at the
// version pinned in report-js/package-lock.json). Empty, with the reason in `missing`, when the
// package was not installed at configure time.
#include <string>
#include <vector>

namespace microbrdf::report {

struct EmbeddedModule {
  const char* name;  ///< core, three, loader, buffer_utils, skeleton_utils
  const char* path;  ///< path inside the npm package, e.g. examples/jsm/loaders/GLTFLoader.js
  const char* text;  ///< the ES module's source, unchanged
};

struct EmbeddedThree {
  std::string version;                  ///< the package's version, e.g. 0.187.0
  std::vector<EmbeddedModule> modules;  ///< empty when missing
  std::string missing;                  ///< why the modules are absent (empty when present)
};

/// The embedded modules (generated source; cheap: pointers to static text).
EmbeddedThree embedded_three();

}  // namespace microbrdf::report

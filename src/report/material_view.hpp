#pragma once
// The report's interactive material view: the fitted analytic NDFs (ellipsoid, Beckmann, GGX)
// as microfacet BRDFs with exact conductor Fresnel on a sphere under the environment map, drawn
// by WebGL 2 inside the self-contained page (docs/report.md, "Interactive view").
#include <nlohmann/json.hpp>
#include <string>

namespace microbrdf::report {

/// The data the view needs, from the summary: the fitted models (their alphas and the rotation R
/// of the ellipsoid convention, Beckmann/GGX as R = Rz(-phi)), the metal's n and k at the three
/// display wavelengths, and the environment map box-filtered to 128 x 64 (or the built-in sky and
/// two lights when the report had no map). Never throws for a missing map or metal: the view then
/// says what it used instead.
nlohmann::json material_view_data(const nlohmann::json& summary);

/// Anchors of false_colour (image.hpp): 6, piecewise linear between them.
constexpr int kRampAnchors = 6;
/// A CSS linear-gradient of the report's false-colour scale ("to right", "to top"): the exact
/// map of its images, for colour bars drawn by the page.
std::string colour_gradient(const std::string& direction);

/// The HTML of the view: a canvas, its controls, the data as JSON and the script (plain WebGL 2,
/// no library, nothing fetched). Without JavaScript or WebGL 2 the page shows a sentence instead.
/// `beside` (HTML, e.g. gltf_view_html's) goes next to the sphere's canvas, `after` after the
/// sphere view's caption, before the lobe view.
std::string material_view_html(const nlohmann::json& summary, const std::string& beside = "",
                               const std::string& after = "");

}  // namespace microbrdf::report

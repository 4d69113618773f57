// Values on hover for the NDF previews (ndf_hover.hpp).
#include "report/ndf_hover.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <vector>

#include "microbrdf/ndf_io.hpp"
#include "report/html.hpp"

namespace microbrdf::report {
namespace {
constexpr int kStep = 2;                  // one value per 2 x 2 pixels of the panel
constexpr int kGrid = kNdfPanel / kStep;  // values per side
constexpr double kDecades = 12;           // range below the maximum that is kept
constexpr std::uint16_t kZero = 0, kOutside = 65535, kUnmeasured = 65534;
}  // namespace

std::string ndf_hover_html(const std::string& npy_path, const std::string& img_id) {
  std::vector<double> v(std::size_t(kGrid) * kGrid, 0.0);
  std::vector<bool> inside(v.size(), false);
  double vmax = 0;
  try {
    const TabulatedNdf ndf = read_ndf(npy_path);
    // Pixel (x, y) of the panel shows m = (-1 + 2 (x + 0.5)/size, 1 - 2 (y + 0.5)/size); the
    // centre of block (i, j) is pixel (kStep i + kStep/2 - 0.5, ...).
    for (int j = 0; j < kGrid; ++j)
      for (int i = 0; i < kGrid; ++i) {
        const double mx = -1 + 2.0 * (kStep * i + 0.5 * kStep) / kNdfPanel;
        const double my = 1 - 2.0 * (kStep * j + 0.5 * kStep) / kNdfPanel;
        if (mx * mx + my * my > 1) continue;
        const std::size_t k = std::size_t(j) * kGrid + i;
        inside[k] = true;
        v[k] = ndf.eval_disk(mx, my);
        if (std::isfinite(v[k])) vmax = std::max(vmax, v[k]);
      }
  } catch (const std::exception&) {
    return "";
  }
  if (!(vmax > 0)) return "";
  const double top = std::log10(vmax), bottom = top - kDecades;
  std::vector<std::uint8_t> bytes(v.size() * 2);
  for (std::size_t k = 0; k < v.size(); ++k) {
    std::uint16_t q;
    if (!inside[k])
      q = kOutside;
    else if (std::isnan(v[k]))
      q = kUnmeasured;
    else if (!(v[k] > 0))
      q = kZero;
    else
      q = std::uint16_t(std::clamp<double>(
          std::lround((std::log10(v[k]) - bottom) / kDecades * 65532.0) + 1, 1, 65533));
    bytes[2 * k] = std::uint8_t(q & 0xff);  // little-endian
    bytes[2 * k + 1] = std::uint8_t(q >> 8);
  }
  const nlohmann::json data = {{"img", img_id},       {"panel", kNdfPanel}, {"margin", 10},
                               {"step", kStep},       {"grid", kGrid},      {"top", top},
                               {"decades", kDecades}, {"q", base64(bytes)}};
  return "<div class=\"cap\" id=\"" + escape(img_id) +
         "-val\">Point at the full disk (left panel) to read D(m).</div>\n<script "
         "type=\"application/json\" class=\"ndf-hover\">" +
         data.dump() + "</script>\n";
}

std::string ndf_hover_script() {
  return R"JS(<script>
(function () {
  "use strict";
  document.querySelectorAll("script.ndf-hover").forEach(function (el) {
    var d = JSON.parse(el.textContent), img = document.getElementById(d.img);
    var out = document.getElementById(d.img + "-val");
    if (!img || !out) return;
    var bin = atob(d.q), q = new Uint16Array(bin.length / 2);
    for (var i = 0; i < q.length; ++i) q[i] = bin.charCodeAt(2 * i) | (bin.charCodeAt(2 * i + 1) << 8);
    img.addEventListener("mousemove", function (e) {
      var b = img.getBoundingClientRect();
      var x = (e.clientX - b.left) * img.naturalWidth / b.width - d.margin;
      var y = (e.clientY - b.top) * img.naturalHeight / b.height - d.margin;
      if (x < 0 || y < 0 || x >= d.panel || y >= d.panel) return;
      var gi = Math.floor(x / d.step), gj = Math.floor(y / d.step), v = q[gj * d.grid + gi];
      var mx = -1 + 2 * (d.step * gi + 0.5 * d.step) / d.panel;
      var my = 1 - 2 * (d.step * gj + 0.5 * d.step) / d.panel;
      if (v === 65535) return;
      var where = " at m_x " + mx.toFixed(3) + ", m_y " + my.toFixed(3) + " (" +
          (Math.asin(Math.min(1, Math.hypot(mx, my))) * 180 / Math.PI).toFixed(1) +
          " deg from the normal)";
      out.textContent = v === 65534 ? "not measured" + where
          : v === 0 ? "D = 0 1/sr" + where
          : "D = " + Math.pow(10, d.top - d.decades + (v - 1) / 65532 * d.decades).toPrecision(4) +
            " 1/sr" + where;
    });
  });
})();
</script>
)JS";
}

}  // namespace microbrdf::report

// The exposure that scales an image to its brightest pixels (include/microbrdf/render.hpp).
#include <algorithm>
#include <cmath>
#include <vector>

#include "microbrdf/render.hpp"

namespace microbrdf {

double normalizing_exposure(const RenderImage& img, double percentile) {
  std::vector<float> m(img.rgb.size() / 3);
  for (std::size_t i = 0; i < m.size(); ++i)
    m[i] = std::max({img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]});
  if (m.empty()) return 0;
  const double q = std::clamp(percentile, 0.0, 1.0) * double(m.size());
  const std::size_t k = std::min(m.size() - 1, static_cast<std::size_t>(q));
  std::nth_element(m.begin(), m.begin() + static_cast<std::ptrdiff_t>(k), m.end());
  const double top = m[k];
  return top > 0 && std::isfinite(top) ? -std::log2(top) : 0.0;
}

}  // namespace microbrdf

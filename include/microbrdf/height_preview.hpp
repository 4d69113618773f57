#pragma once
// The height-map preview: what a scan looks like, in false colour with a scale bar.

#include <cstddef>

#include "microbrdf/image.hpp"
#include "microbrdf/surface.hpp"

namespace microbrdf {

/// Heights between the 0.5th and 99.5th percentile mapped to false colour with light
/// hill-shading, invalid samples grey; at most `max_size` pixels on the long side (box-filtered),
/// row 0 at the top, and a colour bar with the height range on the right.
RgbImage render_height_preview(const Surface& s, std::size_t max_size = 1024);

}  // namespace microbrdf

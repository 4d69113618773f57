#pragma once
// Log-scale false-colour pictures of a tabulated NDF on the disk.

#include <cstddef>
#include <string>

#include "microbrdf/image.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

struct NdfPreviewOptions {
  std::size_t size = 512;      ///< output image width/height of the disk view, pixels
  double decades = 4;          ///< log scale spans this many decades below the maximum
  bool zoom = false;           ///< add a second panel zoomed on the peak
  double zoom_half_width = 0;  ///< disk units; 0 = automatic (4 x the rms slope, >= 8 nodes)
  std::string title;           ///< drawn above the image when not empty
};
/// Log-scale false-colour preview of the disk (m_x to the right, m_y up), unit circle drawn,
/// with a colour bar (labels in decades of 1/sr) and optionally a zoom panel around the peak.
/// Unmeasured (NaN) regions are drawn flat grey (96, 96, 104), distinct from zero.
/// Written atomically as PNG. Throws FileError.
void write_ndf_preview(const TabulatedNdf& ndf, const std::string& png_path,
                       const NdfPreviewOptions& opt = {});
/// The image write_ndf_preview writes: disk panel(s) `size` pixels square (full view at the
/// left, zoom panel right of it), colour bar and labels at the right, dark background; pixel
/// (10 + x, 10 + y) (no title; a title moves everything down by 20) of the full view shows
/// m_x = -1 + 2 (x + 0.5)/size, m_y = 1 - 2 (y + 0.5)/size.
RgbImage render_ndf_preview(const TabulatedNdf& ndf, const NdfPreviewOptions& opt = {});

}  // namespace microbrdf

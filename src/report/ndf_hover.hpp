#pragma once
// Values on hover for the report's NDF previews: D(m) of the table under the pointer.
#include <string>

namespace microbrdf::report {

/// Pixel geometry of the full-view panel of write_ndf_preview (ndf_preview.hpp) as predict
/// writes it: panel `kNdfPanel` pixels square at (10, 10), no title.
constexpr int kNdfPanel = 300;

/// The HTML that makes the preview image with id `img_id` show D(m) under the pointer: a line
/// for the value and the data as JSON (the table interpolated, as the preview samples it, at
/// the centre of every 2 x 2 block of the full view, log-quantised to 16 bits: 1.8e-4 decade
/// steps over the 12 decades below the maximum). Reads the table `npy_path`; returns an empty
/// string when it cannot (the image then simply has no hover).
std::string ndf_hover_html(const std::string& npy_path, const std::string& img_id);

/// The script shared by every hover block (once per page, after them).
std::string ndf_hover_script();

}  // namespace microbrdf::report

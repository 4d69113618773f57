#pragma once
// Error numbers between two renders of the same scene: SSIM (Wang et al. 2004) on luminance and
// the RMS relative error. Images are grey (one value per pixel), row-major from the top.
#include <cstddef>
#include <vector>

namespace microbrdf::detail {

/// Relative luminance Y (Rec. 709 / sRGB primaries) of linear sRGB pixels, 3 floats each.
std::vector<double> luminance(const std::vector<float>& rgb);

/// Mean structural similarity of a and b (width x height, same size; values in [0, L] with L =
/// `dynamic_range`), after Z. Wang, A. C. Bovik, H. R. Sheikh, E. P. Simoncelli, "Image quality
/// assessment: from error visibility to structural similarity", IEEE Trans. Image Processing
/// 13(4):600-612, 2004: local means, variances and covariance under an 11 x 11 Gaussian window
/// (standard deviation 1.5 pixels, weights summing to 1), C1 = (0.01 L)^2, C2 = (0.03 L)^2,
/// SSIM = (2 mu_a mu_b + C1)(2 s_ab + C2) / ((mu_a^2 + mu_b^2 + C1)(s_a^2 + s_b^2 + C2)),
/// averaged over every window lying wholly inside the image. Images smaller than the window
/// give one SSIM over the whole image with uniform weights. 1 for identical images, in [-1, 1].
/// Throws std::invalid_argument on a size mismatch or an empty image.
double ssim(const std::vector<double>& a, const std::vector<double>& b, std::size_t width,
            std::size_t height, double dynamic_range = 1.0);

/// sqrt(sum (a - b)^2 / sum b^2): the RMS error of a against the reference b, relative to the
/// reference's RMS value (0 = identical; NaN-free: 0 when both are 0, +inf never returned for a
/// zero reference, which gives the RMS of a instead).
double rms_relative(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace microbrdf::detail

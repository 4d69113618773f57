#pragma once
// Reading and writing tabulated NDFs, previews, importance sampling and instrument convolution.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "microbrdf/preview.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Writes the table: ".npy" (float64 N x N, row iy, numpy-readable as is) plus a JSON sidecar
/// with the same stem holding NdfMetadata and the conventions; ".exr" (single float channel
/// "D", metadata as string/float attributes). Atomic. Values are non-negative or NaN (NaN =
/// unmeasured, as in effective NDFs from measured BRDFs); infinities are refused. Throws FileError.
void write_ndf(const TabulatedNdf& ndf, const std::string& path);
/// Reads what write_ndf wrote (npy + optional sidecar, or exr). Throws FileError.
TabulatedNdf read_ndf(const std::string& path);

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

/// Importance sampling of m with density D(m)(m.n) (solid angle), i.e. density D on the disk,
/// consistent with TabulatedNdf::eval (piecewise bilinear on the cells, restricted to the
/// disk): pdf(m) = eval(m) * (m.n) / Z with Z the exact integral of the interpolant over the
/// disk (= 1 up to rim effects).
/// The table is referenced, not copied: it must outlive the sampler and stay unchanged.
/// Throws std::invalid_argument if the table has no mass inside the disk.
class NdfSampler {
 public:
  explicit NdfSampler(const TabulatedNdf& ndf);
  /// Z: the integral of the bilinear interpolant over the unit disk (cells the circle crosses
  /// integrated numerically, relative error ~1e-6 of their mass).
  double normalisation() const { return z_; }
  /// u1, u2 uniform in [0,1). Returns a unit m with m_z > 0.
  Eigen::Vector3d sample(double u1, double u2) const;
  /// Density of sample() per steradian of m.
  double pdf(const Eigen::Vector3d& m) const;

 private:
  const TabulatedNdf* ndf_;
  std::vector<double> row_cdf_;   ///< over cell rows
  std::vector<double> cell_cdf_;  ///< per row, over cells
  double z_ = 1;
  std::size_t cells_ = 0;  ///< cells per side, N - 1
};

/// Convolves with an instrument signature: an angular Gaussian of full width at half maximum
/// `fwhm_rad` on the sphere (e.g. 1.5 deg, Dong section 7). Conserves integral D(m)(m.n) dw.
/// Each node's mass D_j Delta^2 is spread over the nodes within 4 sigma (angle) with weights
/// exp(-angle^2 / (2 sigma^2)) * (solid angle Delta^2 / m_z of the receiving node), normalised
/// per source node. Nodes on or outside the unit circle carry no mass. fwhm_rad <= 0 returns
/// the input unchanged. Cost ~ (pi/4) N^2 * pi (4 sigma / Delta)^2 kernel evaluations, twice.
TabulatedNdf convolve_angular_gaussian(const TabulatedNdf& ndf, double fwhm_rad);

}  // namespace microbrdf

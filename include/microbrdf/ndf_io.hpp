#pragma once
// Reading and writing tabulated NDFs, previews, importance sampling and instrument convolution.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Writes the table: ".npy" (float64 N x N, row iy, numpy-readable as is) plus a JSON sidecar
/// with the same stem holding NdfMetadata and the conventions; ".exr" (single float channel
/// "D", metadata as string/float attributes). Atomic. Throws FileError.
void write_ndf(const TabulatedNdf& ndf, const std::string& path);
/// Reads what write_ndf wrote (npy + optional sidecar, or exr). Throws FileError.
TabulatedNdf read_ndf(const std::string& path);

struct NdfPreviewOptions {
  std::size_t size = 512;        ///< output image width/height of the disk view, pixels
  double decades = 4;            ///< log scale spans this many decades below the maximum
  bool zoom = false;             ///< add a second panel zoomed on the peak
  double zoom_half_width = 0;    ///< disk units; 0 = automatic (4 x the rms slope, >= 8 nodes)
  std::string title;             ///< drawn above the image when not empty
};
/// Log-scale false-colour preview of the disk (m_x to the right, m_y up), unit circle drawn,
/// with a colour bar (labels in decades of 1/sr) and optionally a zoom panel around the peak.
/// Written atomically as PNG. Throws FileError.
void write_ndf_preview(const TabulatedNdf& ndf, const std::string& png_path, const NdfPreviewOptions& opt = {});

/// Importance sampling of m with density D(m)(m.n) (solid angle), i.e. density D on the disk,
/// consistent with TabulatedNdf::eval (piecewise bilinear on the cells, restricted to the
/// disk): pdf(m) = eval(m) * (m.n) / Z with Z the exact integral of the interpolant over the
/// disk (= 1 up to rim effects).
class NdfSampler {
 public:
  explicit NdfSampler(const TabulatedNdf& ndf);
  /// u1, u2 uniform in [0,1). Returns a unit m with m_z > 0.
  Eigen::Vector3d sample(double u1, double u2) const;
  /// Density of sample() per steradian of m.
  double pdf(const Eigen::Vector3d& m) const;

 private:
  const TabulatedNdf* ndf_;
  std::vector<double> row_cdf_;     ///< over cell rows
  std::vector<double> cell_cdf_;    ///< per row, over cells
  double z_ = 1;
};

/// Convolves with an instrument signature: an angular Gaussian of full width at half maximum
/// `fwhm_rad` on the sphere (e.g. 1.5 deg, Dong section 7). Conserves integral D(m)(m.n) dw.
TabulatedNdf convolve_angular_gaussian(const TabulatedNdf& ndf, double fwhm_rad);

}  // namespace microbrdf

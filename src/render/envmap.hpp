#pragma once
// Equirectangular environment maps: reading (OpenEXR, Radiance RGBE), lookup and importance
// sampling.
//
// Direction convention (world frame, y up): row 0 of the image is the zenith (+y), the last row
// the nadir; theta = acos(d.y) in [0, pi] maps to v = theta / pi; the azimuth
// phi = atan2(d.x, -d.z) in (-pi, pi] maps to u = 1/2 + phi / (2 pi) (+ rotation / (2 pi)), so the
// middle column lies straight ahead of a camera looking along -z and u grows to its right (the
// map is seen as from inside, not mirrored). Radiance is piecewise constant per pixel (nearest
// pixel), the same function the sampler draws from, so light-sampling and BRDF-sampling
// estimates agree exactly.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "render/distribution2d.hpp"

namespace microbrdf::pt {

/// A linear RGB float image, row-major from the top, 3 floats per pixel.
struct RgbFloatImage {
  int width = 0, height = 0;
  std::vector<float> rgb;
};

/// Radiance .hdr (RGBE, "#?RADIANCE" or "#?RGBE", FORMAT=32-bit_rle_rgbe, orientation
/// "-Y H +X W"), flat or new-style run-length encoded scanlines. Every read is bounds-checked;
/// at most 2^15 pixels a side and no more pixels than the file can encode. Throws FileError.
RgbFloatImage read_radiance_hdr(const std::string& path);
RgbFloatImage read_radiance_hdr_bytes(const std::vector<std::uint8_t>& data,
                                      const std::string& name);
/// Writes flat (uncompressed) RGBE, "-Y H +X W"; atomic. For fixtures and tests.
void write_radiance_hdr(const RgbFloatImage& img, const std::string& path);
/// OpenEXR with R, G, B channels (HALF or FLOAT; Y alone is taken as grey). Throws FileError.
RgbFloatImage read_exr_rgb(const std::string& path);
/// By the file's magic number: EXR or Radiance HDR.
RgbFloatImage read_envmap_image(const std::string& path);

class EnvironmentMap {
 public:
  /// From an image; negative pixels (lossy compression) are clamped to 0. `scale` multiplies the
  /// radiance, `rotation_rad` turns the map about +y (positive = the map moves to the left).
  EnvironmentMap(RgbFloatImage img, double scale = 1, double rotation_rad = 0);
  /// Radiance rgb everywhere (uniform sampling over the sphere).
  static EnvironmentMap uniform(const Eigen::Vector3d& rgb);

  /// Linear sRGB radiance in direction d (unit, world frame).
  Eigen::Vector3d rgb(const Eigen::Vector3d& d) const;
  /// Draws a direction with density pdf(d) per steradian (proportional to the pixel's largest
  /// channel times its solid angle) from a 2D point (u1 -> azimuth, u2 -> polar angle, each
  /// monotone); returns the pdf through `pdf`. `rgb`, when given, receives the radiance in that
  /// direction (saves a lookup).
  Eigen::Vector3d sample(double u1, double u2, double& pdf, Eigen::Vector3d* rgb = nullptr) const;
  double pdf(const Eigen::Vector3d& d) const;
  /// Memory prefetches (no effect on results): of what rgb_and_pdf(d) reads, and of what
  /// sample(u1, u2, ...) reads first.
  /// Returns the pixel (col, row) of d for rgb_and_pdf_at (-1, -1 for a uniform map).
  std::pair<int, int> prefetch_lookup(const Eigen::Vector3d& d) const {
    if (uniform_) return {-1, -1};
    int c, r;
    pixel_of(d, c, r);
    dist_.prefetch_cell(std::size_t(c), std::size_t(r));
    return {c, r};
  }
  void prefetch_sample(double u1, double u2, bool cells = false) const {
    if (!uniform_) dist_.prefetch_sample(u1, u2, cells);
  }
  /// rgb(d) and pdf(d) with one pixel look-up.
  Eigen::Vector3d rgb_and_pdf(const Eigen::Vector3d& d, double& pdf) const;
  /// The same with the pixel of d given (from prefetch_lookup(d)).
  Eigen::Vector3d rgb_and_pdf_at(const Eigen::Vector3d& d, std::pair<int, int> pixel,
                                 double& pdf) const;

  int width() const { return img_.width; }
  int height() const { return img_.height; }
  bool is_uniform() const { return uniform_; }
  /// Pixel (column, row) that direction d falls into: the row from a table over y where its
  /// cell holds no row edge, else from a polynomial guess of theta; the column from a
  /// polynomial guess of the azimuth; a guess decides alone when it lies further from a pixel
  /// edge than its error bound, else exact tests against the pixel boundaries (tables of the
  /// boundaries' cosines and azimuth vectors) decide, falling back to pixel_of_exact() where
  /// the tests are undecided (the poles).
  void pixel_of(const Eigen::Vector3d& d, int& col, int& row) const;
  /// The same from acos and atan2 (the definition; the tests compare the two).
  void pixel_of_exact(const Eigen::Vector3d& d, int& col, int& row) const;
  /// Unit direction through the centre of (u, v) in [0,1]^2 of the map.
  Eigen::Vector3d direction(double u, double v) const;
  /// Direction at (col + fu, row + fv) pixels with fu, fv in [0, 1): from the tables of the
  /// pixels' edge angles and short series for the small angles inside a pixel (no sin/cos
  /// calls); also returns sin(theta). Equal to direction() to ~1e-15.
  Eigen::Vector3d direction_in_pixel(std::size_t col, double fu, std::size_t row, double fv,
                                     double& sin_theta) const;

 private:
  EnvironmentMap() = default;
  RgbFloatImage img_;
  bool uniform_ = false;
  Eigen::Vector3d uniform_rgb_ = Eigen::Vector3d::Zero();
  double rotation_u_ = 0;  // rotation / (2 pi)
  PiecewiseConstant2D dist_;
  bool tables_ = false;  // the edge tables below are in use (maps of >= 64 x 32 pixels)
  // pixel_of: rows per radian; the guesses' error bounds (with margin) in rows and columns
  double row_scale_ = 0, row_margin_ = 0, col_margin_ = 0;
  std::vector<std::int16_t>
      row_by_y_;  // pixel_of: the row of a cell of y, or -1 (see the constructor)
  double y_scale_ = 0;
  double row_step_ = 0, col_step_ = 0;     // direction_in_pixel: radians per row, per column
  std::vector<double> row_cos_, row_sin_;  // cos, sin of theta at the top edge of row r (h + 1)
  std::vector<double> col_sin_, col_cos_;  // sin, cos of phi at the left edge of column c (w + 1)
};

}  // namespace microbrdf::pt

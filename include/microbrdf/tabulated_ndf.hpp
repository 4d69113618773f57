#pragma once
// TabulatedNdf: a normal distribution function tabulated on the projected unit disk
// (Dong 2015 section 5.1; docs/theory.md §2; docs/architecture.md).
//
//  - N x N nodes (default 1025), node-centred: m_x = -1 + 2 ix/(N-1), m_y = -1 + 2 iy/(N-1),
//    row iy; value D(m) per steradian; 0 outside the unit disk.
//  - Orthographic map m = (m_x, m_y, sqrt(1 - m_x^2 - m_y^2)); dw = dm_x dm_y / m_z, so
//    D(m)(m.n) dw = D dm_x dm_y: the table IS the density of (m_x, m_y) of the projected-area
//    weighted normal, and the normalisation  integral D(m)(m.n) dw = 1  reads
//    sum_ij D_ij Delta^2 = 1 with Delta = 2/(N-1) (node-centred, bilinear "tent" cells).
//  - Evaluation: bilinear interpolation of the nodes, 0 outside the disk.
//  - Zoomed tables: a table may cover only a square window of the disk plane (centre (c_x, c_y),
//    half-width h <= 1), m_x = c_x - h + 2h ix/(N-1), and likewise m_y; Delta = 2h/(N-1). Such a
//    table resolves a narrow lobe with N nodes across the window; D is 0 outside the window
//    (the mass there, if any, is recorded in meta.window_mass) and the normalisation is over the
//    window. The default window is the whole square [-1, 1]^2.
//  - Sampling (meta.sampling): "point" tables hold D at the nodes (analytic models, Kirchhoff,
//    effective NDFs from measured BRDFs); "cell" tables hold the average of D over each node's
//    bilinear (tent) cell (histograms of normals). Fits compare a model with a table the same way.

#include <Eigen/Core>
#include <cstddef>
#include <string>
#include <vector>

namespace microbrdf {

/// The square of the disk plane a table covers: centre (cx, cy), half-width `half`; nodes from
/// cx - half to cx + half. The default is the whole square [-1, 1]^2.
struct NdfWindow {
  double cx = 0, cy = 0, half = 1;
  bool full() const { return cx == 0 && cy == 0 && half == 1; }
  double x0() const { return cx - half; }
  double x1() const { return cx + half; }
  double y0() const { return cy - half; }
  double y1() const { return cy + half; }
  bool operator==(const NdfWindow&) const = default;
};

/// A window of half-width `half` (clamped to (0, 1]) centred as near (cx, cy) as it can be while
/// staying inside [-1, 1]^2.
NdfWindow zoom_window(double cx, double cy, double half);

/// Where an NDF came from; travels into .npy sidecars / EXR attributes / JSON.
struct NdfMetadata {
  std::string method;                ///< "naive", "filtered", "kirchhoff", "beckmann", ...
  double filter_sigma_m = 0;         ///< Gaussian filter std (filtered method), m
  double wavelength_m = 0;           ///< lambda_q (Kirchhoff), m
  std::vector<std::string> sources;  ///< input files
  std::size_t samples_used = 0;      ///< elements (triangles / points) accumulated
  std::size_t samples_skipped = 0;   ///< elements rejected (invalid samples, thin support)
  double projected_area_m2 = 0;      ///< total projected area accumulated, m^2
  std::string leveling;              ///< levelling applied to the inputs
  std::string parameterisation = "orthographic-disk node-centred";
  std::string notes;
  /// How the nodes were obtained: "point" (D evaluated at the nodes) or "cell" (D averaged over
  /// each node's tent cell, as histogram estimators produce). "" = not recorded (files written
  /// before the record existed): ndf_sampling() infers it from `method`.
  std::string sampling;
  /// Zoomed tables: the fraction of the estimator's mass (projected area) that fell inside the
  /// window; 1 for tables of the whole disk.
  double window_mass = 1;
};

/// "point" or "cell": meta.sampling when recorded, else inferred from meta.method as the fits
/// always did (analytic model names, "kirchhoff", "measured", "lobe": point; anything else,
/// e.g. "naive", "filtered", "*-tent": cell).
std::string ndf_sampling(const NdfMetadata& meta);
/// Whether meta.sampling was recorded (false: ndf_sampling() inferred it).
inline bool ndf_sampling_recorded(const NdfMetadata& meta) { return !meta.sampling.empty(); }

/// A 1-D cut through the table along an in-plane direction.
struct NdfSlice {
  std::vector<double>
      t;  ///< signed disk coordinate along the direction (m_x cos phi + m_y sin phi)
  std::vector<double> theta;  ///< signed polar angle of m, rad
  std::vector<double> value;  ///< D(m), 1/sr
};

class TabulatedNdf {
 public:
  /// Throws std::invalid_argument for resolution < 3 or a window outside [-1, 1]^2.
  explicit TabulatedNdf(std::size_t resolution = 1025, const NdfWindow& window = {});
  /// A table holding `values` (D per steradian at the nodes, row iy = m_y, N x N row-major),
  /// taken without a copy. Also throws std::invalid_argument when values.size() != N^2.
  TabulatedNdf(std::size_t resolution, std::vector<double>&& values, const NdfWindow& window = {});

  std::size_t resolution() const { return n_; }
  /// The part of the disk plane the nodes cover (the whole [-1, 1]^2 unless zoomed).
  const NdfWindow& window() const { return w_; }
  /// Node spacing Delta = 2 half/(N-1) in disk coordinates (2/(N-1) for the whole disk).
  double spacing() const { return 2.0 * w_.half / static_cast<double>(n_ - 1); }
  double node_x(std::size_t ix) const { return w_.x0() + spacing() * static_cast<double>(ix); }
  double node_y(std::size_t iy) const { return w_.y0() + spacing() * static_cast<double>(iy); }
  double& at(std::size_t ix, std::size_t iy) { return d_[iy * n_ + ix]; }
  double at(std::size_t ix, std::size_t iy) const { return d_[iy * n_ + ix]; }
  std::vector<double>& values() { return d_; }
  const std::vector<double>& values() const { return d_; }

  /// D(m) per steradian by bilinear interpolation; 0 for m_z <= 0, outside the disk or outside
  /// the window.
  /// `m` need not be normalised.
  double eval(const Eigen::Vector3d& m) const;
  double eval_disk(double mx, double my) const;

  /// sum D_ij Delta^2 = integral D(m)(m.n) dw (1 for a normalised table).
  double integral() const;
  /// Scales to integral 1. Throws std::domain_error if the table is empty.
  void normalise();
  /// Zeroes nodes outside the unit disk (keeps the integral by renormalising if it was 1).
  void clear_outside_disk();

  /// Mean normal: the unit vector along integral m D(m)(m.n) dw.
  Eigen::Vector3d mean_normal() const;
  /// Covariance of the slopes (-m_x/m_z, -m_y/m_z) under D(m)(m.n) dw (about their mean).
  Eigen::Matrix2d slope_covariance() const;
  /// rms slope along the in-plane direction at azimuth phi (rad), about the mean:
  /// sqrt(u^T C u). For Beckmann this is alpha / sqrt(2).
  double rms_slope(double phi) const;
  /// The node with the largest value, as a unit vector.
  Eigen::Vector3d peak() const;
  /// Values along the line through the disk centre at azimuth phi, `samples` points over
  /// [-1, 1] (bilinear); for a zoomed table over the part of the line inside the window (the
  /// whole [-1, 1] with zeros when the line misses it).
  NdfSlice slice(double phi, std::size_t samples = 1025) const;

  /// Adds `weight` at disk point (mx, my) spread bilinearly over the four surrounding nodes
  /// (weights sum to `weight`; points outside the square or window are ignored). Histogram
  /// estimators call this with the element's projected area and then finish with normalise().
  void splat(double mx, double my, double weight);
  /// this += w * other (same resolution and window; throws std::invalid_argument otherwise).
  void add(const TabulatedNdf& other, double w = 1.0);

  /// Bilinear resampling to another resolution (same window; normalised again).
  TabulatedNdf resampled(std::size_t resolution) const;
  /// Bilinear resampling onto another window (0 where this table has no nodes; normalised
  /// again when anything is left).
  TabulatedNdf resampled(std::size_t resolution, const NdfWindow& window) const;

  NdfMetadata meta;

 private:
  std::size_t n_;
  NdfWindow w_;
  std::vector<double> d_;
};

}  // namespace microbrdf

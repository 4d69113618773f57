#pragma once
// Importance sampling of the micro-normals of a tabulated NDF.

#include <Eigen/Core>
#include <cstddef>
#include <vector>

#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

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

}  // namespace microbrdf

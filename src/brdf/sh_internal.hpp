#pragma once
// Internals shared by the sh_*.cpp files: rotations of the kept basis about n and the sampling
// table of ShBrdf (a tabulated CDF over outgoing cells per incident node).
#include <mutex>
#include <vector>

#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"

namespace microbrdf {
namespace detail {
/// A <- R^T A R, where Y(Rz(alpha) w) = R Y(w) on the kept basis (blocks of (l, +-m) pairs).
void sh_rotate_z(const ShOddBasis& basis, Eigen::MatrixXd& a, double alpha);
}  // namespace detail

/// Piecewise-constant densities over outgoing cells (theta_o x phi_o, equal steps in angle), one
/// per incident node (theta_i at cell centres; phi_i too unless isotropic), mixed with a cosine
/// lobe of weight `cos_mix` so that every direction where rho > 0 can be drawn.
struct ShBrdf::SamplingTable {
  int n_ti = 0, n_pi = 1;  // incident nodes: theta_i = (k + 0.5) d_ti, phi_i = q 2 pi / n_pi
  int n_to = 0, n_po = 0;  // outgoing cells
  double d_ti = 0, d_pi = 0, d_to = 0, d_po = 0;
  bool isotropic = true;
  double cos_mix = 0.1;
  std::vector<double> z_edge;     // cos(t d_to), t = 0..n_to (decreasing)
  std::vector<double> inv_omega;  // 1 / solid angle of a cell in row t
  std::vector<float> cdf;         // per node: n_cells + 1 values from 0 to 1
  int cells() const { return n_to * n_po; }
  const float* node_cdf(int node) const {
    return cdf.data() + static_cast<std::size_t>(node) * (cells() + 1);
  }
};

struct ShBrdf::LazyTable {
  std::once_flag once;
  std::unique_ptr<SamplingTable> table;
};

}  // namespace microbrdf

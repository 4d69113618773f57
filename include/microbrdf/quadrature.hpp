#pragma once
// Quadrature rules shared by the models, the BRDFs and the tests.

#include <vector>

namespace microbrdf {

/// Gauss-Legendre nodes x and weights w of the n-point rule on [-1, 1] (exact for polynomials of
/// degree 2n - 1; nodes by Newton's method on P_n, accurate to ~1e-15).
void gauss_legendre(int n, std::vector<double>& x, std::vector<double>& w);

}  // namespace microbrdf

#pragma once
// Parametric fits of tabulated NDFs (Dong 2015 section 8, Fig. 12): any registered model
// (ndf_model.hpp: the ellipsoid NDF (alpha_x, alpha_y, theta_x, theta_y, theta_z), anisotropic
// Beckmann and GGX (alpha_x, alpha_y, phi), ..., and two-lobe mixtures "mixture:A+B"), fitted to
// any TabulatedNdf by Levenberg-Marquardt (the models' Jacobians; Ceres and Nelder-Mead as
// references). Conventions, objective and error measures are in docs/fitting.md.
//
//  - Parameters are the model's own (NdfParams, by name). Beckmann/GGX report phi in
//    [-pi/2, pi/2) and, in JSON, the ellipsoid convention's theta_z = -phi as well; the
//    ellipsoid's theta_z lies in (-pi/2, pi/2] (its symmetry (theta_x, theta_y, theta_z) ==
//    (-theta_x, -theta_y, theta_z + pi) is used to get there).
//  - Forward operator: the model is compared with the table the way the table represents a
//    function. Node: D at the nodes times a fitted amplitude (what `tabulate` writes: point
//    samples renormalised to sum D Delta^2 = 1). Tent: D averaged over each node's bilinear
//    (tent) cell, which is what the histogram estimators' bilinear splatting produce; exactly
//    normalised, no amplitude. Auto follows the table's record of how it was sampled
//    (meta.sampling, see ndf_sampling()): Node for "point", Tent for "cell"; tables that predate
//    the record get the sampling inferred from meta.method (model names, "kirchhoff",
//    "measured": point; histograms: cell) and the result says it was inferred.
//  - Zoomed tables (a window smaller than the disk): residuals on the window's nodes; the model
//    outside the window is not compared.
//  - Objective (default): least squares on sqrt(D + eps) over the disk, equal weight per node
//    (equal projected area): a Hellinger distance between the two densities; sqrt is the
//    variance-stabilising transform of histogram (Poisson) counts, so unweighted least squares is
//    close to maximum likelihood, and the tails count without a log's blow-up at D = 0.
//  - NaN nodes are unmeasured (effective NDFs inferred from measured BRDFs, measured_ndf.hpp):
//    they carry no residual and no error; such tables (or meta.method "measured") are fitted
//    in Node mode with a free amplitude and start from the moments of the measured nodes.

#include <cstddef>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>

#include "microbrdf/microfacet.hpp"
#include "microbrdf/ndf_model.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

enum class FitObjective { Sqrt, Linear, Log };
enum class FitSampling { Auto, Node, Tent };
/// LevenbergMarquardt: the library's solver (closed-form Jacobians, normal equations summed on the
/// fly); CeresAutodiff: Ceres' Levenberg-Marquardt with automatic derivatives on the same
/// objective and bounds (reference); NelderMead: derivative-free reference.
enum class FitSolver { LevenbergMarquardt, NelderMead, CeresAutodiff };

/// The canonical name of a registered model or mixture ("GGX", "gtr2" -> "ggx";
/// "mixture:ggx+beckmann"), case-insensitive. Throws InputError listing the models otherwise.
std::string parse_fit_model(const std::string& name);
/// "sqrt" | "linear" | "log".
FitObjective parse_fit_objective(const std::string& name);
std::string fit_objective_name(FitObjective o);
/// "auto" | "node" | "tent".
FitSampling parse_fit_sampling(const std::string& name);
std::string fit_sampling_name(FitSampling s);

struct FitOptions {
  std::string model = "ellipsoid";  ///< a registered model, alias or "mixture:A+B"
  FitObjective objective = FitObjective::Sqrt;
  FitSampling sampling = FitSampling::Auto;
  FitSolver solver = FitSolver::LevenbergMarquardt;
  /// Tent mode: quadrature points per node spacing and axis (midpoint rule on the tent);
  /// 0 = automatic, ceil(8 Delta / alpha_min) from the initial guess, clamped to 1..8.
  int tent_subsamples = 0;
  /// Residuals are taken on the nodes of the smallest box holding every node above this
  /// fraction of the table maximum, widened by a margin (the rest carries < ~1e-6 of the mass).
  double roi_threshold = 1e-7;
  /// Floor eps of sqrt(D + eps) / log(D + eps), relative to the table maximum; when the table
  /// knows its sample count (histogram estimators) eps is at least 3/8 of one sample's value
  /// (Anscombe).
  double floor = 1e-9;
  int max_iterations = 200;
  int threads = 0;  ///< 0 = OpenMP's default
  /// Starting point (names of the model; missing ones take their defaults); default: from
  /// slope moments (see initial_guess()).
  std::optional<NdfParams> initial;
};

struct FitResult {
  std::string model = "ellipsoid";  ///< canonical name
  /// Fitted parameters by name (the model's params(), in its units: alphas, angles in rad).
  NdfParams params;
  double phi = 0;        ///< the parameter "phi" when the model has one (azimuth, rad), else 0
  double amplitude = 1;  ///< Node sampling: fitted scale of the point samples (1/sum D Delta^2)
  NdfParams initial;     ///< where the solver started
  FitObjective objective = FitObjective::Sqrt;
  FitSampling sampling = FitSampling::Node;  ///< the one used (never Auto)
  /// How the table says it was sampled ("point" | "cell") and whether it said so (false: inferred
  /// from its method, for files written before the record existed).
  std::string table_sampling = "cell";
  bool table_sampling_recorded = true;
  NdfWindow window;  ///< the fitted table's window (fit_table uses it)
  int tent_subsamples = 1;
  double floor = 0;  ///< eps used, 1/sr
  /// Errors of the model as compared (the fit table) against the table, over all nodes inside
  /// the unit disk: rms_error = sqrt(mean (T - M)^2) in 1/sr; relative_l2_error =
  /// ||T - M||_2 / ||T||_2; hellinger = sqrt(1/2 sum (sqrt T - sqrt M)^2 Delta^2) in [0, 1].
  double rms_error = 0, relative_l2_error = 0, hellinger = 0;
  double initial_cost = 0, final_cost = 0;  ///< objective (1/2 sum r^2) at start and end
  int iterations = 0;
  /// The solver stopped on its convergence test and no parameter ended on a bound of the box
  /// (a fit held at a bound may have its optimum beyond it: not converged).
  bool converged = false;
  bool solver_converged = false;  ///< the solver's own convergence test, bounds aside
  /// Where the fit ended on a bound, e.g. "the lower alpha bound 0.000488 (alpha_x, alpha_y)";
  /// "" when inside the box. The lower alpha bound is max(1e-5, Delta / 20) (Delta the node
  /// spacing; in tent mode at least 2 Delta / subsamples), the upper 4; tilts +-1.2 rad;
  /// exponents and weights: their model's range.
  std::string at_bound;
  std::string termination;            ///< solver's message
  std::size_t residuals = 0;          ///< nodes in the region of interest
  std::size_t roi[4] = {0, 0, 0, 0};  ///< ix0, ix1, iy0, iy1 (inclusive)
  double seconds = 0;
};

/// Starting point from the table's slope moments: alpha from the eigenvalues of the slope
/// covariance (alpha = sqrt(2 lambda), the Beckmann relation), theta_z from its eigenvectors
/// (the alpha_x axis is the eigenvector nearer the +x axis), theta_x/theta_y (ellipsoid) so that
/// the peak R^T z lies along the mean normal; other parameters: the model's initial(). The solver
/// then tries a few scalings of all alphas (heavy-tailed GGX tables have inflated second moments)
/// and starts from the best.
NdfParams initial_guess(const TabulatedNdf& ndf, const std::string& model);

/// Fits `model` to the table. Throws InputError for an empty or unnormalisable table.
FitResult fit_ndf(const TabulatedNdf& ndf, const FitOptions& options);

/// The fitted distribution (normalised analytic model).
std::shared_ptr<MicrofacetDistribution> fitted_distribution(const FitResult& r);

/// The model as it is compared with the table (same resolution, window, sampling, amplitude):
/// what the fit errors are measured against.
TabulatedNdf fit_table(const FitResult& r, std::size_t resolution);

/// D averaged over every node's tent cell with `subsamples` midpoint samples per spacing and
/// axis (tent mode's forward operator, in double precision), 0 outside the disk.
TabulatedNdf tabulate_tent(const MicrofacetDistribution& d, const std::string& model,
                           std::size_t resolution, int subsamples, const NdfWindow& window = {});

/// Objective value (1/2 sum r^2) of `params` for the given options (sampling resolved as in
/// fit_ndf; amplitude as given). For references and tests.
double fit_objective(const TabulatedNdf& ndf, const FitOptions& options, const NdfParams& p,
                     double amplitude = 1);

/// Writes DIR/fit.json, DIR/compare.png (measured | fit | residual, zoomed on the region of
/// interest, log colour scale shared by the first two, residual (M - T)/max T in a diverging
/// scale), DIR/slices.png (measured and fitted cuts along the fitted axes, log scale) and
/// DIR/measured.png, DIR/fit.png (write_ndf_preview with zoom). Throws FileError.
void write_fit_report(const TabulatedNdf& ndf, const FitResult& r, const std::string& dir);

/// The fit as JSON: "model", "params" (the model's params_json: its named values; Beckmann/GGX
/// also theta_x, theta_y, theta_z in the ellipsoid convention; mixtures {weight, lobe1, lobe2}),
/// "params_deg" (the angles in degrees), "rms_error", "relative_l2_error", plus the rest of
/// FitResult.
nlohmann::json fit_result_json(const FitResult& r);

}  // namespace microbrdf

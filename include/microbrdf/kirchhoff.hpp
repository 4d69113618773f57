#pragma once
// The Kirchhoff distribution D_K (Dong 2015 eqs. 3-8 and Appendix A; docs/theory.md §4)
// computed from height maps; the Kirchhoff BRDF (Dong eq. 8) over them is kirchhoff_brdf.hpp.
// docs/kirchhoff.md has the derivations, the accuracy figures and the pictures.
//
// Definition (eq. 6, height-field form of docs/theory.md §4.1), for q = (4 pi / lambda_q) h:
//   I(q)   = integral over the patch of w (q.m) exp(-i q.s) dS
//          = integral w(x,y) (q_z - q_x h_x - q_y h_y) exp(-i (q_x x + q_y y + q_z h)) dx dy
//   D_K(q) = |I(q)|^2 / (4 pi^2 A_w),   A_w = integral w^2 dx dy
// with w the aperture: 1 on valid samples (0 at invalid ones) times an optional window.
//
// Integration over the sampled surface (KirchhoffIntegration; docs/kirchhoff.md "Integration"):
//  - Exact: the surface is the piecewise-linear one through the samples, two triangles
//    per grid cell split along the (ix,iy)-(ix+1,iy+1) diagonal (as the naive NDF). On a triangle
//    T with vertices s_0, s_1, s_2 the slope, hence (q.m), is constant and the phase linear, and
//      integral_T exp(-i q.s) dx dy = 2 A_T exp[z_0, z_1, z_2],   z_k = -i q.s_k        (K1)
//    with A_T the projected area and exp[.,.,.] the second divided difference of exp
//    (exp_divided_difference). Triangles with an invalid vertex are left out; the window is
//    constant on a triangle (the mean of its vertices' weights).
//  - Midpoint (default): each valid sample j stands for its projected cell dx dy, at s_j, with the
//  slope
//    (g_x, g_y) of central differences over its valid neighbours (one-sided beside a hole or the
//    edge of the surface, 0 along an axis with no valid neighbour):
//      I(q) = dx dy sum_j w_j (q_z - q_x g_xj - q_y g_yj) exp(-i q.s_j).
// The (q.m) factor is kept as it is (no integration by parts, so the edge-diffraction term of the
// patch outline and of holes is included). Invalid samples are excluded, never filled.
//
// Normalisation: D_K above is the physical quantity of eq. 6 (dimensionless, per steradian of h
// in the BRDF of eq. 7). By Parseval its integral over the disk, sum D_K Delta^2 on the table, is
// close to 1 (exactly 1 for a mirror at normal q); the tables returned by the estimators are
// divided by that sum so that sum D Delta^2 = 1 like every TabulatedNdf, and the sum before
// normalising is reported (KirchhoffAccumulator::raw_integral, metadata notes).

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "microbrdf/surface.hpp"
#include "microbrdf/tabulated_ndf.hpp"

namespace microbrdf {

/// Apodisation of each patch (docs/theory.md §4.5). D_K is the true D_K blurred by |FT(w)|^2 / (4
/// pi^2 A_w):
///  - None: sinc^2 blur, first zero at q = 2 pi / L, side lobes decaying as 1/q^2 (a hard
///    aperture diffracts into a cross along the patch axes);
///  - Hann: sin^2 taper over the whole patch; main lobe twice as wide, side lobes 1/q^6;
///  - Gauss: exp(-u^2 / (2 s^2)) per axis about the patch centre with s = gauss_fraction * side
///    (default 1/8: 3.4e-4 at the edges); Gaussian blur of std 1/(sqrt(2) s) in q.
enum class KirchhoffWindow { None, Hann, Gauss };
KirchhoffWindow parse_kirchhoff_window(const std::string& name);  ///< none|hann|gauss; InputError
std::string to_string(KirchhoffWindow w);

/// How the surface integral of eq. 6 is evaluated (see the top of this file): exactly over the
/// triangles of the piecewise-linear surface, or by the midpoint rule per sample (faster).
enum class KirchhoffIntegration { Exact, Midpoint };
KirchhoffIntegration parse_kirchhoff_integration(const std::string& name);  ///< exact|midpoint
std::string to_string(KirchhoffIntegration m);

/// exp[z0, z1, z2], the second divided difference of exp (docs/kirchhoff.md eq. K2):
/// sum_k exp(z_k) / prod_{j != k} (z_k - z_j), continued to coincident points (exp[z,z,z] =
/// exp(z)/2). The integral of exp over the standard triangle {a, b >= 0, a + b <= 1} of the
/// linear function taking z0, z1, z2 at its corners. Stable everywhere: a series about the mean
/// when the points are within 1 of it, otherwise differences of first divided differences.
std::complex<double> exp_divided_difference(std::complex<double> z0, std::complex<double> z1,
                                            std::complex<double> z2);

/// One patch prepared for evaluation: heights, slopes and aperture weights on its samples.
struct KirchhoffPatch {
  std::size_t nx = 0, ny = 0;
  double dx = 0, dy = 0;
  std::vector<double> h;       ///< height, m (0 where invalid)
  std::vector<double> gx, gy;  ///< slopes (central differences over valid neighbours)
  std::vector<double> w;       ///< aperture: window x validity (0 where invalid)
  double area_w2 = 0;          ///< A_w = dx dy sum w^2, m^2 (midpoint rule)
  double valid_area = 0;       ///< dx dy x valid samples, m^2
  double area_w2_tri = 0;      ///< A_w over the triangles, sum_T A_T w_T^2 (exact integration)
  double valid_area_tri = 0;   ///< projected area of the valid triangles, m^2
  std::size_t triangles = 0;   ///< valid triangles (all three vertices valid)
  std::size_t valid = 0, invalid = 0;
  std::size_t no_slope = 0;  ///< valid samples with no valid neighbour along an axis (slope 0)
};

/// Cuts the window [ix0, ix0+nx) x [iy0, iy0+ny) out of `s` (neighbours outside the window are
/// used for the slopes of its border samples). Throws InputError for an empty or out-of-range
/// window.
KirchhoffPatch make_kirchhoff_patch(const Surface& s, std::size_t ix0, std::size_t iy0,
                                    std::size_t nx, std::size_t ny,
                                    KirchhoffWindow window = KirchhoffWindow::None,
                                    double gauss_fraction = 0.125);
/// The whole surface as one patch.
KirchhoffPatch make_kirchhoff_patch(const Surface& s,
                                    KirchhoffWindow window = KirchhoffWindow::None,
                                    double gauss_fraction = 0.125);

/// A_w of the patch for the given integration (area_w2_tri or area_w2).
double kirchhoff_area_w2(const KirchhoffPatch& p, KirchhoffIntegration m);

/// I(q) by direct summation (the reference; O(samples) per q). Positions are relative to the
/// patch's first sample (a global phase, irrelevant to D_K). q in 1/m.
std::complex<double> kirchhoff_amplitude(const KirchhoffPatch& p, const Eigen::Vector3d& q,
                                         KirchhoffIntegration m = KirchhoffIntegration::Midpoint);
/// Physical D_K(q) = |I|^2 / (4 pi^2 A_w) by direct summation.
double kirchhoff_dk_direct(const KirchhoffPatch& p, const Eigen::Vector3d& q,
                           KirchhoffIntegration m = KirchhoffIntegration::Midpoint);

/// The node q of an N x N table at lambda_q: q = (4 pi / lambda_q) (m_x, m_y, m_z).
Eigen::Vector3d kirchhoff_node_q(std::size_t n, std::size_t ix, std::size_t iy, double lambda_q);

/// Physical D_K at the given table nodes (index iy * N + ix) by direct summation, in parallel
/// over nodes; nodes on or outside the unit circle give 0.
std::vector<double> kirchhoff_nodes_direct(const KirchhoffPatch& p, double lambda_q,
                                           std::size_t resolution,
                                           const std::vector<std::size_t>& nodes,
                                           KirchhoffIntegration m = KirchhoffIntegration::Midpoint);

/// What the fast method did (for reports and the accuracy knob).
struct KirchhoffFastInfo {
  std::size_t terms = 0;         ///< Chebyshev terms in q_z (each: 3 x-passes + 2 y-passes)
  double height_half_range = 0;  ///< H = (max - min)/2 of the valid heights, m
  double z_max = 0;              ///< |q| H / 2, the Bessel argument that sets the term count
  double tail_bound = 0;         ///< 2 sum_{n > terms-1} |J_n(z_max)| (plus the q_z-factor term)
  /// Exact integration: quadrature points per triangle (pu x pv, collapsed Gauss-Legendre,
  /// chosen from the largest phase span |q| x longest triangle edge); 1 for the midpoint rule.
  std::size_t points_per_triangle = 1;
  double phase_span = 0;  ///< largest phase difference along a valid triangle's edge (exact)
};

/// Physical D_K on all N x N nodes (0 on and outside the unit circle), fast:
/// q_z = q_c + (|q|/2) t with t in [-1, 1] over the disk, and exp(-i q_z h) expanded in Chebyshev
/// polynomials T_n(t) (Jacobi-Anger: coefficients 2 (-i)^n J_n(|q| (h - h_c) / 2)), truncated
/// where the tail is below `accuracy` (relative to one sample's unit phasor). Each term's three
/// sample arrays (q_z, q_x and q_y parts of q.m) are Fourier transformed separably (x, then y)
/// directly at the node frequencies -- by a type-2 NUFFT with a kernel accurate to accuracy/100
/// (default), or exactly by chirp-z transforms (`chirp_z`, about 3x slower) -- and the series is
/// summed per node (Clenshaw).
///
/// Exact integration (`m`): I(q) is a sum over triangles of K1. Each triangle's integral is
/// evaluated by a collapsed Gauss-Legendre rule of pu x pv points whose error for the triangle's
/// largest phase span is below accuracy/100; the points of one rule position form a shifted copy
/// of the cell grid, so each is one more set of sample arrays through the same transforms (the
/// shift is a phase after the transform). Cost: points_per_triangle x 2 x the midpoint rule's
/// x-passes. `band_x`, `band_y` (1/m): only nodes with |q_x| <= band_x and |q_y| <= band_y need
/// the rule's accuracy (the others are masked by the caller), which bounds the phase span.
/// `amplitude` (optional): the complex amplitude I / (2 pi sqrt(A_w)) per node, |a|^2 = D_K, in
/// the patch's own coordinates (origin at its first sample, heights as they are), so that the
/// amplitudes of equal tiles of one surface can be averaged coherently.
std::vector<double> kirchhoff_table_fast(const KirchhoffPatch& p, double lambda_q,
                                         std::size_t resolution, double accuracy = 1e-3,
                                         KirchhoffFastInfo* info = nullptr, bool chirp_z = false,
                                         KirchhoffIntegration m = KirchhoffIntegration::Midpoint,
                                         double band_x = INFINITY, double band_y = INFINITY,
                                         std::vector<std::complex<double>>* amplitude = nullptr);

/// Frees the large buffers kirchhoff_table_fast keeps between tables so that the next one
/// needs no fresh pages (about 110 MB after a 1025^2 midpoint table, 160 MB after an exact
/// one); the next table allocates them again. For long-lived processes (the Python module
/// calls it after each D_K). Safe to call at any time from any thread.
void kirchhoff_release_buffers();

/// Bessel functions J_0..J_nmax(x), x >= 0, by Miller's backward recurrence normalised with
/// J_0 + 2 sum J_2k = 1 (relative accuracy ~1e-14 where J_n is not negligible).
std::vector<double> bessel_j_all(std::size_t nmax, double x);

struct KirchhoffOptions {
  double wavelength_q = 555e-9;  ///< lambda_q, m (Dong section 7: 555 nm)
  std::size_t resolution = 1025;
  double patch_x = 70e-6, patch_y = 53e-6;  ///< patch size, m (<= 0: whole scan on that axis)
  /// Hann by default: a hard-edged tile diffracts the specular peak of a polished surface into a
  /// cross along the table axes (docs/kirchhoff.md "Windows").
  KirchhoffWindow window = KirchhoffWindow::Hann;
  double gauss_fraction = 0.125;  ///< Gauss window std as a fraction of the patch side
  double accuracy = 1e-3;         ///< fast method: Chebyshev tail bound (NUFFT: accuracy/100)
  /// The midpoint rule per sample (default: about 50x faster, about 1% relative L1 off on brushed
  /// steel, more on steep or coarse scans) or exact triangles (the accurate reference).
  KirchhoffIntegration integration = KirchhoffIntegration::Midpoint;
  /// Node values as averages over each node's cell of S x S sub-nodes (S odd; the table of
  /// resolution S (N-1) + 1 computed and averaged), instead of point samples. 0 = automatic: the
  /// smallest odd S with 2/(N-1)/S <= lambda_q / (2 L), L the longer tile side -- the spacing at
  /// which the sampled |I|^2, whose Fourier transform has support |lag| <= L, integrates exactly
  /// (docs/kirchhoff.md "Table resolution"). 1 = point samples.
  std::size_t supersample = 0;
  bool direct = false;  ///< use the direct sums on every node (slow; small patches)
  /// Zero the nodes whose |q_x| > pi/dx or |q_y| > pi/dy: beyond the scan's Nyquist band the
  /// sampled-surface sum only repeats the band (aliases, e.g. a copy of the specular peak at
  /// q_y = 2 pi/dy). Only matters when a spacing exceeds lambda_q / 4 (|q| > pi / d).
  bool nyquist_mask = true;
  /// Optional progress report: KirchhoffAccumulator::add calls it with the fraction (0..1) of
  /// the current scan's patches done, once before the first patch (0) and after each patch
  /// (the last call is 1). Called from the calling thread; empty = silent.
  std::function<void(double)> progress;
  /// Further lambda_q (m) at which the same tiles are evaluated: a stack of tables over lambda_q,
  /// so that a BRDF can evaluate D_K at each direction's own lambda_q = 2 lambda / |wi + wo|
  /// (eq. 5; KirchhoffBrdf interpolates between them). Empty = the one table at wavelength_q.
  /// kirchhoff_stack_wavelengths() gives the default stack.
  std::vector<double> stack_wavelengths_q;
  /// Separate the specular (coherent) part: the mean field over the tiles, whose intensity
  /// |<I>|^2 would otherwise be smeared over the window's diffraction pattern (2-5 deg wide on
  /// polished metal at 555 nm with 70 um tiles, far above the true diffuse lobe there), is
  /// removed and its energy put on the node of its peak; the rest is the diffuse part
  /// (P/(P-1)) (mean |I|^2 - |mean I|^2) over P tiles. Needs at least kKirchhoffMinTilesCoherent
  /// tiles, the fast method and point-sampled nodes; otherwise skipped (the notes say so).
  bool separate_specular = true;
};

/// Tiles needed before the mean field over them is taken for the specular part.
inline constexpr std::size_t kKirchhoffMinTilesCoherent = 8;

/// The lambda_q of the default stack for light of wavelengths [lo, hi] (m): geometric from lo to
/// kKirchhoffStackSpan x hi (every direction pair with |wi + wo| >= 2 / kKirchhoffStackSpan,
/// i.e. wi and wo at most 161 deg apart), ratio at most kKirchhoffStackRatio between
/// neighbours, both ends included (docs/kirchhoff.md "lambda_q per direction").
inline constexpr double kKirchhoffStackSpan = 6.0;
inline constexpr double kKirchhoffStackRatio = 1.3;
std::vector<double> kirchhoff_stack_wavelengths(double lo, double hi);
/// The lambda_q (m) of a named stack besides the table at `lambda` (m): "visible" (the default:
/// kirchhoff_stack_wavelengths over the renderer's band and lambda), "wavelength" (over lambda
/// only) or "single" (none); layers within 1 % of lambda are left out. Throws InputError.
std::vector<double> kirchhoff_stack_layers(const std::string& stack, double lambda);
/// The band the default stack covers (m): the renderer's hero wavelengths.
inline constexpr double kKirchhoffVisibleLo = 360e-9, kKirchhoffVisibleHi = 830e-9;

/// One scan's share of a KirchhoffAccumulator: the sum over its patches of A_w,p D_K,p and the
/// counters, so that scans can be computed anywhere and folded in scan order (distribute.hpp).
struct KirchhoffScanPartial {
  /// Sum over the scan's patches of A_w,p D_K,p (physical). A 3 x 3 placeholder until a share
  /// is filled (a default 1025^2 table would be 8.4 MB of zeros made for nothing).
  TabulatedNdf table{3};
  /// The same sums at KirchhoffOptions::stack_wavelengths_q (in that order) and their aliased
  /// masses.
  std::vector<TabulatedNdf> stack;
  std::vector<double> stack_aliased;
  /// Per layer (the table, then the stack): sum over the patches of sqrt(A_w,p) a_p, a_p the
  /// complex amplitude of kirchhoff_table_fast (empty where not kept: see separate_specular).
  std::vector<std::vector<std::complex<double>>> coherent;
  double area_w2 = 0, valid_area = 0, aliased = 0;
  std::size_t patches = 0, used = 0, skipped = 0;
  std::string tiles, leveling, source;
  KirchhoffFastInfo info;
  bool has_info = false;        ///< the fast method ran on at least one patch
  std::size_t supersample = 1;  ///< S of KirchhoffOptions::supersample used (largest over tiles)
};

/// Averages D_K over patches and scans (Dong App. A): each scan is cut into tiles of about
/// patch_x x patch_y (round(L / patch) equal tiles per axis, at least 1, the remainder of the
/// division left out at the far edges), D_K is computed per tile, and the intensities are
/// averaged weighted by A_w: D = sum |I_p|^2 / (4 pi^2 sum A_w,p).
class KirchhoffAccumulator {
 public:
  explicit KirchhoffAccumulator(const KirchhoffOptions& options);
  /// merge(estimate(s)).
  void add(const Surface& s);
  /// One scan's share, computed without touching the accumulator (any thread or rank); calls
  /// options().progress per patch.
  KirchhoffScanPartial estimate(const Surface& s) const;
  /// Folds one scan's share in (table sum node by node, counters, sources).
  void merge(const KirchhoffScanPartial& p);
  /// The same; the first share's tables become the sums instead of being copied (a single scan
  /// then holds one 1025^2 table less at the peak).
  void merge(KirchhoffScanPartial&& p);
  /// The averaged D_K normalised to sum D Delta^2 = 1; meta.method = "kirchhoff",
  /// meta.wavelength_m = lambda_q. Throws InputError if nothing was accumulated.
  TabulatedNdf result() const;
  /// result() followed by the tables at KirchhoffOptions::stack_wavelengths_q, each normalised
  /// and labelled with its lambda_q (meta.wavelength_m), sorted by lambda_q.
  std::vector<TabulatedNdf> stack_result() const;
  /// sum D_K Delta^2 of the physical average before normalising (~1; docs/theory.md §4.3).
  double raw_integral() const;
  std::size_t patches() const { return patches_; }
  /// Fraction of the (A_w-weighted, physical) D_K mass removed by the Nyquist mask.
  double aliased_fraction() const;
  const KirchhoffFastInfo& last_info() const { return info_; }
  /// Sub-nodes per axis averaged into each node (1 = point samples); largest over the scans.
  std::size_t supersample() const { return supersample_; }
  const KirchhoffOptions& options() const { return opt_; }

 private:
  KirchhoffOptions opt_;
  std::optional<TabulatedNdf> acc_;  // sum over patches of A_w,p D_K,p (from the first share)
  std::vector<TabulatedNdf> stack_;  // the same at opt_.stack_wavelengths_q
  std::vector<double> stack_aliased_;
  std::vector<std::vector<std::complex<double>>> coherent_;  // per layer, as in the partials
  bool coherent_missing_ = false;  // a scan came without mean fields: no separation
  double area_w2_ = 0, valid_area_ = 0, aliased_ = 0;
  std::size_t patches_ = 0, used_ = 0, skipped_ = 0;
  std::string tiles_, leveling_;
  std::vector<std::string> sources_;
  KirchhoffFastInfo info_;
  std::size_t supersample_ = 1;
  template <class Partial>
  void merge_impl(Partial&& p);
  TabulatedNdf labelled(const TabulatedNdf& sum, double lambda_q, double aliased,
                        const std::vector<std::complex<double>>& coherent) const;
  const std::vector<std::complex<double>>& coherent_of(std::size_t layer) const;
};

/// The S that KirchhoffOptions::supersample = 0 picks for a tile of extent lx x ly (m): the
/// smallest odd S with 2 / (N - 1) / S <= lambda_q / (2 max(lx, ly)), but at most the largest
/// odd S with S (N - 1) + 1 <= 1025 (so never a finer table than the default one).
std::size_t kirchhoff_auto_supersample(std::size_t resolution, double lambda_q, double lx,
                                       double ly);

/// One scan's D_K (KirchhoffAccumulator with one add).
TabulatedNdf estimate_kirchhoff(const Surface& s, const KirchhoffOptions& options);

}  // namespace microbrdf

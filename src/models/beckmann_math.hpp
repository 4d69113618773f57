#pragma once
// Special functions of the Beckmann distribution (models/microfacet.cpp), inline so that the
// sampler and Smith's Lambda inline them; exposed here for the tests and benchmarks.
//
//  - erfcx(x) = exp(x^2) erfc(x) for x >= 0: piecewise polynomials, relative error below
//    4e-16 in exact arithmetic (~1e-15 after rounding; tests/test_beckmann_math.cpp);
//  - exp_minus_sq(x) = exp(-x^2) with the rounding error of x^2 put back (Dekker's product);
//  - erfc(x) for every x from the two, with one exp: erfc(x) = exp(-x^2) erfcx(x) for x >= 0,
//    2 - exp(-x^2) erfcx(-x) below;
//  - gauss_quantile(u): the x with erfc(-x)/2 = u (x = erfinv(2u - 1)), a polynomial guess good
//    to 1e-7 relative and one Halley step, i.e. converged to the double-precision CDF;
//  - smith_lambda(a): Beckmann's Lambda = (exp(-a^2)/(a sqrt(pi)) - erfc(a))/2, a > 0;
//  - visible_slope(mu, u): the visible-slope quantile (see its comment).
// The polynomial coefficients interpolate the functions at Chebyshev nodes in 40-digit arithmetic
// (scripts/fit_beckmann_math.py prints them and their errors).

#include <algorithm>
#include <cmath>
#include <limits>

namespace microbrdf::beckmann {

inline constexpr double kSqrtPi = 1.77245385090551602730;
inline constexpr double kInvSqrtPi = 0.56418958354775628695;

// clang-format off
inline constexpr double kErfcx[32][11] = {
    {0.87322184508215084, -0.91007370582499425, 0.75946263185403651, -0.54342725120405799, 0.3457671127155682, -0.20008255372526002, 0.10691893499540547, -0.053346611331948283, 0.025062105475336258, -0.011241794727261573, 0.0047658487887604966},
    {0.68585723310129287, -0.61398624226954912, 0.45561239225021655, -0.29542106344256319, 0.17241474672521298, -0.092306216205819192, 0.045933306621224385, -0.021451363747273959, 0.0094720686785975308, -0.0040042055920252164, 0.0016059298876242056},
    {0.55681388087336248, -0.43236181600381152, 0.28658774587098235, -0.16882964988695542, 0.090534607344039231, -0.04489820907817136, 0.020824409427611986, -0.0091092748261095736, 0.0037827068272243487, -0.0015078921876836157, 0.00057234033744595362},
    {0.46431158320266902, -0.31583389649084259, 0.18795692377318265, -0.1009143921252508, 0.049828415331057072, -0.022925811826342957, 0.0099227768753096836, -0.00406948767777393, 0.0015904660842271697, -0.00059827712106897161, 0.00021502790820934295},
    {0.39569807955299591, -0.23805848810127209, 0.12788228043906522, -0.062793948404524638, 0.028619544241672224, -0.012238784581326163, 0.0049503039515217647, -0.0019056077009121191, 0.0007016125657343616, -0.00024926641973208914, 8.4890489417434607e-05},
    {0.34329588986212539, -0.18431546997466788, 0.089862118646957215, -0.040503371223260497, 0.017084991607347656, -0.0068046031556782665, 0.002576220794496157, -0.00093207821354162517, 0.0003236485398748151, -0.00010870798967450373, 3.5108049339457118e-05},
    {0.30226120936348594, -0.14603023666418338, 0.064962074784188001, -0.026977910093194141, 0.010561485441310105, -0.0039261985211393674, 0.0013938042986928185, -0.00047464455124503267, 0.00015562461872444875, -4.9472750827735275e-05, 1.5165382393619986e-05},
    {0.26942998516467043, -0.1180167227279984, 0.048148630049673492, -0.018492027589882314, 0.0067380391592920521, -0.0023432816753552904, 0.0007814620139901888, -0.00025086738756981413, 7.7770449438826835e-05, -2.3427026333027326e-05, 6.8230055217634627e-06},
    {0.24267036461265454, -0.097030117491730766, 0.036481364942726704, -0.013004811325613323, 0.0044230704378845865, -0.0014423146619940196, 0.00045271726422007263, -0.00013722527218092565, 4.027793111112062e-05, -1.1511363559153676e-05, 3.1887110439165964e-06},
    {0.22050569220490668, -0.080977129122205921, 0.028185010539667613, -0.0093584860603251364, 0.002979303073190383, -0.00091305650642387374, 0.00027026462538100581, -7.7479167664401807e-05, 2.1562674955207998e-05, -5.8543779743398382e-06, 1.5441153853125706e-06},
    {0.20188755454601701, -0.068469505728923269, 0.022155102007593415, -0.0068749086393246062, 0.0020542334146793841, -0.00059301837118857733, 0.00016585339774243289, -4.5043644448627433e-05, 1.19033433797722e-05, -3.0742476823398073e-06, 7.7293814331816106e-07},
    {0.1860549346844711, -0.058563292659803728, 0.017685468287535391, -0.0051450475554251215, 0.00144672828284208, -0.00039428149733201825, 0.00010438965984892021, -2.6903144258658387e-05, 6.7607202928067843e-06, -1.6631571129360924e-06, 3.990726573289239e-07},
    {0.1724443521021736, -0.050601966456927522, 0.014313206924275092, -0.0039154632123779625, 0.0010386921927958918, -0.00026782004417515658, 6.725151852568319e-05, -1.6473981923059301e-05, 3.9425491880985989e-06, -9.2505254261710093e-07, 2.1208418353528852e-07},
    {0.1606310681265444, -0.044119457241337846, 0.011727899937029176, -0.0030251966359092653, 0.00075893064541709639, -0.00018552228316506925, 4.4264313397927362e-05, -1.0322904813854125e-05, 2.3561097484927855e-06, -5.2796810412584515e-07, 1.1579323359221605e-07},
    {0.15028972247426936, -0.038778679157059709, 0.009717010529927907, -0.002369677324047195, 0.00056346511512806667, -0.00013084651274462462, 2.9715502229641297e-05, -6.6079387718384263e-06, 1.4404210760272527e-06, -3.0866694550747915e-07, 6.4834481682094081e-08},
    {0.1411674197630518, -0.034331663931861184, 0.0081322220270897, -0.0018795357179256396, 0.0004245105600637216, -9.3822919105298038e-05, 2.0315582893825808e-05, -4.314290879935021e-06, 8.9942067775181359e-07, -1.8454674174570341e-07, 3.7167462066379583e-08},
    {0.13306497124120825, -0.030593154355544459, 0.0068682095245873546, -0.0015078600444143624, 0.00032414342068893566, -6.8307373648040739e-05, 1.412516816000467e-05, -2.8688700683492296e-06, 5.7276638744403054e-07, -1.1266909717499688e-07, 2.1781766781174449e-08},
    {0.12582358819498807, -0.027422770389366968, 0.005848967741507582, -0.0012223576801808343, 0.00025057644535814361, -5.0434292706538971e-05, 9.9754716069676303e-06, -1.9404568045789063e-06, 3.7149122931746092e-07, -7.0143181719279616e-08, 1.3031241273570106e-08},
    {0.11931528862713332, -0.02471274729452929, 0.0050188323899353557, -0.0010004316607188282, 0.00019591797955534324, -3.7724402116580912e-05, 7.1475399330913437e-06, -1.333436180385549e-06, 2.4509814756628101e-07, -4.4472969362499347e-08, 7.9483405242419527e-09},
    {0.11343587721474049, -0.022379364251792787, 0.0043364764872506484, -0.00082602758429724114, 0.00015479600690077098, -2.8558820266244942e-05, 5.1905860411811426e-06, -9.299175266356738e-07, 1.6430874341286992e-07, -2.8683265865992461e-08, 4.9367783232865449e-09},
    {0.10809973724654746, -0.020356860318401043, 0.0037708281147421233, -0.00068757748689843399, 0.00012349674719380665, -2.1862663014417645e-05, 3.8168664193628682e-06, -6.5749183232241522e-07, 1.1180469902235207e-07, -1.8798147674794205e-08, 3.1189288512792594e-09},
    {0.10323591747815693, -0.018593054205325601, 0.0032982511245318153, -0.00057663627397805883, 9.9415575949863061e-05, -1.6911021300473254e-05, 2.8396121561082092e-06, -4.7088720464474933e-07, 7.7148038394754771e-08, -1.2506180856832052e-08, 2.0022430484332211e-09},
    {0.098785157173407537, -0.017046148894677749, 0.0029005696408452076, -0.00048696310994896739, 8.0701073691125534e-05, -1.3207828175471131e-05, 2.1356800698908328e-06, -3.4132208943171067e-07, 5.3935620351060659e-08, -8.4384099083225313e-09, 1.3048665415304251e-09},
    {0.09469759959536303, -0.015682371849997035, 0.0025636649766304447, -0.00041389340819544633, 6.6020601741093743e-05, -1.040894918719431e-05, 1.6226750900093093e-06, -2.5020935237264277e-07, 3.8173647719670769e-08, -5.7697478509735647e-09, 8.6252721365740834e-10},
    {0.090931016718836855, -0.014474212289761141, 0.0022764664440498702, -0.0003539035466371228, 5.4403610448743062e-05, -8.2725730558087297e-06, 1.2447001614681646e-06, -1.853669634848682e-07, 2.7331784496897138e-08, -3.9946218149829265e-09, 5.7780961961703136e-10},
    {0.087449417784622493, -0.013399090341575739, 0.0020302168570771567, -0.0003043052518059107, 4.5135438407235578e-05, -6.6267327841633951e-06, 9.6333896996326171e-07, -1.3869906363492489e-07, 1.9783046544837053e-08, -2.798370790310264e-09, 3.9199079831172794e-10},
    {0.084221949049140182, -0.012438342194405214, 0.001817932011205636, -0.00026302841344524966, 3.7684386065426976e-05, -5.3477423048847062e-06, 7.5186443224475736e-07, -1.0475438745763194e-07, 1.4466610288997652e-08, -1.9822448890218209e-09, 2.6911871347641527e-10},
    {0.081222016591888005, -0.011576438957052513, 0.0016339987621519715, -0.00022846497817180636, 3.1651018610400228e-05, -4.3456900902339929e-06, 5.9146641361850515e-07, -7.9816696922231912e-08, 1.0681625269297319e-08, -1.4189432777565429e-09, 1.8685663253600374e-10},
    {0.078426581542616017, -0.010800380113234368, 0.0014738732358211464, -0.00019935553867246576, 2.6732511389913229e-05, -3.5545580078099668e-06, 4.6876186161339632e-07, -6.1322772774646219e-08, 7.959255092172096e-09, -1.0258439860688765e-09, 1.3113223925322307e-10},
    {0.07581558972469768, -0.010099218656221841, 0.0013338521350615962, -0.00017470610676171311, 2.2697298846980443e-05, -2.925411106145548e-06, 3.7413064652144994e-07, -4.7485017460437614e-08, 5.9821455556512097e-09, -7.4864681388681691e-10, 9.2961886118289423e-11},
    {0.073371506929172992, -0.0094636864256243489, 0.0012108979337873366, -0.00015372645366393853, 1.9366862299902188e-05, -2.42165145091036e-06, 3.0058999566766155e-07, -3.7043632912843985e-08, 4.5330628277235713e-09, -5.5123815333028238e-10, 6.6538023755139824e-11},
    {0.071078937825894375, -0.0088858963376761066, 0.0011025041666950371, -0.00013578401663512604, 1.6602517846709481e-05, -2.0156754369412932e-06, 2.4302459366947472e-07, -2.9101928176054496e-08, 3.4617194721480047e-09, -4.0932704640870651e-10, 4.8061233917069827e-11},
};
inline constexpr double kErfcxTail[1][9] = {
    {1, -0.49999999999983968, 0.74999999972518139, -1.8749998179102214, 6.5624392457413823, -29.519774033107606, 161.13156959527583, -968.96196585311759, 4565.5548889797928},
};
inline constexpr double kErfinvW[1][11] = {
    {1.6536545626831027, 0.24015818130870092, -0.006033683153015207, -0.00074069870851445568, 0.00018675940221723361, -1.3887019697590711e-05, -1.37997428444425e-06, 4.2566279061253253e-07, -2.5652876737032751e-08, -4.6076465066097856e-09, 6.9836807302724098e-10},
};
inline constexpr double kErfinvS1[1][8] = {
    {3.0838856307387981, 1.0052589060074881, 0.0053697962862446595, -0.0037477055004574334, 0.0024997690055618988, -0.0017191089428599863, 0.0009413204033573106, -0.00026965833091659131},
};
inline constexpr double kErfinvS2[1][9] = {
    {5.6074830714321475, 1.0098320781429804, -0.00043165798360279931, -6.841902665500837e-05, 2.9478353214823297e-05, -7.108470289695574e-06, 1.4989306901779226e-06, -3.8715775907481636e-07, 7.3379778461131144e-08},
};
// clang-format on

/// c[0] + c[1] t + ... + c[10] t^10 by Estrin's scheme (shorter dependency chains than Horner).
inline double poly10(const double* c, double t) {
  const double t2 = t * t, t4 = t2 * t2, t8 = t4 * t4;
  const double a = (c[0] + c[1] * t) + t2 * (c[2] + c[3] * t);
  const double b = (c[4] + c[5] * t) + t2 * (c[6] + c[7] * t);
  const double d = (c[8] + c[9] * t) + t2 * c[10];
  return (a + t4 * b) + t8 * d;
}
/// c[0] + ... + c[n-1] t^(n-1) by Horner's rule.
template <int N>
inline double horner(const double (&c)[N], double t) {
  double r = c[N - 1];
  for (int i = N - 2; i >= 0; --i) r = r * t + c[i];
  return r;
}

/// exp(x^2) erfc(x) for x >= 0 (also for x = +inf: 0); NaN for NaN.
inline double erfcx(double x) {
  if (x < 8) return poly10(kErfcx[int(x * 4)], x - (int(x * 4) + 0.5) * 0.25);
  const double y = 1 / (x * x);
  return horner(kErfcxTail[0], y) * kInvSqrtPi / x;
}

/// exp(-x^2): exp of the rounded -x^2, times 1 - (its rounding error) from Dekker's exact
/// product (no FMA needed); relative error a few ulp where std::exp(-x*x) loses x^2 ulp.
inline double exp_minus_sq(double x) {
  const double s = x * x;
  if (s > 746) return 0;                  // exp underflows (and the split below would overflow)
  constexpr double kSplit = 134217729.0;  // 2^27 + 1
  const double c = kSplit * x, hi = c - (c - x), lo = x - hi;
  const double err = ((hi * hi - s) + 2 * hi * lo) + lo * lo;  // x^2 - s exactly
  return std::exp(-s) * (1 - err);
}

/// erfc(x) for every x with one exp.
inline double erfc(double x) {
  const double e = exp_minus_sq(x);
  return x >= 0 ? e * erfcx(x) : 2 - e * erfcx(-x);
}

/// erfinv(2u - 1) from u in (0, 1) (the polynomial guess of gauss_quantile, relative error
/// < 1e-7 for 1e-24 < u < 1 - 1e-16), or NaN outside that range.
inline double erfinv_guess_u(double u) {
  const double w = -std::log(4 * u * (1 - u));  // -ln(1 - t^2), t = 2u - 1, without cancellation
  const double t = 2 * u - 1;
  if (w < 6.25) return t * horner(kErfinvW[0], w - 3.125);
  const double s = std::sqrt(w);
  if (w < 16) return t * horner(kErfinvS1[0], s - 3.25);
  if (w < 56) return t * horner(kErfinvS2[0], s - 5.75);
  return std::numeric_limits<double>::quiet_NaN();
}

/// The x <= 0 with erfc(-x)/2 = q, 0 <= q <= 1/2 (q = 0 is taken as 1e-300: x ~ -26.2).
inline double lower_gauss_quantile(double q) {
  double x = erfinv_guess_u(q);
  if (x == x) {
    // Halley on f = erfc(-x)/2 - q, f' = exp(-x^2)/sqrt(pi), f''/f' = -2x: cubic convergence
    // from the 1e-7 guess, so the first step already leaves ~1e-20.
    for (int it = 0; it < 8; ++it) {
      const double e = exp_minus_sq(x);
      const double r = (0.5 * e * erfcx(-x) - q) * kSqrtPi / e;  // f / f'
      const double dx = r / (1 + x * r);
      x -= dx;
      if (!(std::abs(dx) > 1e-6 * (1 + std::abs(x)))) break;
    }
    return std::min(x, 0.0);
  }
  // Far tail (q < 1e-24): Newton on ln(erfc(-x)/2) = -x^2 + ln(erfcx(-x)/2), nearly linear.
  const double lq = std::log(std::max(q, 1e-300));
  x = -std::sqrt(-lq);
  for (int it = 0; it < 50; ++it) {
    const double ex = erfcx(-x);
    const double g = -x * x + std::log(0.5 * ex) - lq;
    const double dg = 2 * kInvSqrtPi / ex;
    const double dx = g / dg;
    x -= dx;
    if (!(std::abs(dx) > 1e-12 * (1 + std::abs(x)))) break;
  }
  return x;
}

/// x with erfc(-x)/2 = u, u in [0, 1) (antisymmetric: q = min(u, 1 - u), both exact).
inline double gauss_quantile(double u) {
  return u <= 0.5 ? lower_gauss_quantile(u) : -lower_gauss_quantile(1 - u);
}

/// Smith's Lambda of the Beckmann distribution, a = 1/(alpha tan theta) > 0:
/// (exp(-a^2)/(a sqrt(pi)) - erfc(a))/2 = exp(-a^2) (1/(a sqrt(pi)) - erfcx(a))/2.
inline double smith_lambda(double a) { return 0.5 * exp_minus_sq(a) * (kInvSqrtPi / a - erfcx(a)); }

/// Draws x with density proportional to <mu - x>+ exp(-x^2) (mu = cot theta of the stretched
/// view, >= 0; mu >= 1e8 means exp(-x^2)) by inverting the CDF
///   C(x) = mu sqrt(pi)/2 erfc(-x) + exp(-x^2)/2  (x <= mu),  u C(mu) = C(x).
/// C(x)/(mu sqrt(pi)) = Phi(x) + phi(x)/(2 mu) exactly (Phi the CDF of exp(-x^2)/sqrt(pi), phi
/// its density), whose root for large mu is x0 - 1/(2 mu) - x0/(4 mu^2) + (1 - 2 x0^2)/(12 mu^3)
/// + O(mu^-4), x0 the Gaussian quantile of u C(mu)/(mu sqrt(pi)); that is the start for mu > 1, mu
/// - sqrt(-ln u) (exact for mu = 0) below, raised for u > 1/2 and mu < 5 to mu - z0 (the mass above
/// x is >= exp(-mu^2) (mu - x)^2 / 2 for x >= -mu, so the root lies at or above mu - z0, z0 =
/// sqrt(2 (1-u) C(mu) exp(mu^2)); also the asymptotic root for u -> 1). Below the median Halley's
/// method runs on ln C (nearly quadratic in the lower tail; written as -x^2 + ln(...) for x <= 0,
/// so nothing underflows), above it on the ln of the mass above x (C(mu) - C(x) ~ (mu - x)^2 near
/// the end); both are monotone with a bracket [lo, mu], and a step leaving the bracket is replaced
/// by bisection. A Halley step below 1e-4 (1 + |x|) (above the median: 1e-4 min(1 + |x|, mu - x),
/// the scale of ln(mu - x)) ends the iteration (cubic convergence: ~1e-12 left;
/// tests/test_beckmann_math.cpp asserts 1e-10 (1 + |x|) against a long-double bisection), as does a
/// Newton step (taken where Halley's correction is large) below 1e-8 (1 + |x|).
inline double visible_slope(double mu, double u) {
  if (!(mu < 1e8)) return gauss_quantile(u);
  const double e_mu = exp_minus_sq(mu);
  const double half_mu_sqrt_pi = 0.5 * mu * kSqrtPi;
  // C(mu) with erfc(-mu) = 2 - erfc(mu)
  const double erfc_mu = e_mu * erfcx(mu);
  const double c_mu = half_mu_sqrt_pi * (2 - erfc_mu) + 0.5 * e_mu;
  const bool upper = u > 0.5;
  const double tail = (1 - u) * c_mu;  // mass above the root
  double x = std::numeric_limits<double>::quiet_NaN();
  if (mu > 1) {
    const double eps = 1 / mu;
    const double x0 = erfinv_guess_u(u * (c_mu / (mu * kSqrtPi)));
    x = x0 - eps * (0.5 + eps * (0.25 * x0 - eps * (1 - 2 * x0 * x0) / 12));
  }
  if (!(x == x)) x = mu - std::sqrt(-std::log(std::max(u, 1e-300)));
  if (upper && mu < 5) {
    const double z0 = std::sqrt(2 * tail / e_mu);
    if (!(x < mu) || x < mu - z0) x = mu - z0;
  }
  double lo = -30, hi = mu;
  if (!(x > lo && x < hi)) x = 0.5 * (std::max(lo, -6.0) + hi);
  const double target = std::log(upper ? tail : u * c_mu);
  for (int it = 0; it < 200; ++it) {
    // g = ln C - target (below the median) or ln(C(mu) - C) - target, with g' and g''.
    double g, g1, g2;
    const double d = mu - x;
    if (!upper && x <= 0) {
      // C = exp(-x^2) A, A = mu sqrt(pi)/2 erfcx(-x) + 1/2; C' = d exp(-x^2),
      // C'' = -(1 + 2 x d) exp(-x^2)
      const double a = half_mu_sqrt_pi * erfcx(-x) + 0.5;
      g = std::log(a) - x * x - target;
      g1 = d / a;
      g2 = -(1 + 2 * x * d) / a - g1 * g1;
    } else {
      const double e = exp_minus_sq(x);
      const double erfc_x = x >= 0 ? e * erfcx(x) : 2 - e * erfcx(-x);
      const double p = d * e, c2 = -(1 + 2 * x * d) * e;
      if (!upper) {
        const double c = half_mu_sqrt_pi * (2 - erfc_x) + 0.5 * e;
        g = std::log(c) - target;
        g1 = p / c;
        g2 = c2 / c - g1 * g1;
      } else {
        // C(mu) - C(x) from the differences of erfc and exp (no cancellation against
        // mu sqrt(pi), which C(mu) - C(x) computed directly would suffer for large mu)
        const double s = half_mu_sqrt_pi * (erfc_x - erfc_mu) - 0.5 * (e - e_mu);
        if (s > 0) {
          g = std::log(s) - target;
          g1 = -p / s;
          g2 = -c2 / s - g1 * g1;
        } else {
          g = -1e300;
          g1 = -1e300;
          g2 = 0;
        }
      }
    }
    if (upper ? g < 0 : g > 0)  // x lies right of the root
      hi = x;
    else
      lo = x;
    const double n = g / g1, h = 0.5 * n * g2 / g1;
    const bool halley = std::abs(h) < 0.5;
    const double dx = halley ? n / (1 - h) : n;
    const double xn = x - dx;
    // (near the end of the range, the upper function ~ 2 ln(mu - x): steps relative to mu - x)
    const double scale = upper ? std::min(1 + std::abs(x), d) : 1 + std::abs(x);
    if (std::abs(dx) <= (halley ? 1e-4 : 1e-8) * scale) return std::clamp(xn, lo, hi);
    if (xn > lo && xn < hi) {
      x = xn;
    } else {
      x = 0.5 * (lo + hi);
      if (hi - lo <= 1e-14 * (1 + std::abs(x))) return x;
    }
  }
  return x;
}

}  // namespace microbrdf::beckmann

// `--filter-sigma auto`: a sweep of the filter sigma against D_K by Hellinger distance
// (filter_sigma_auto.hpp; docs/guide.md §7, docs/validation.md §6).
#include "microbrdf/filter_sigma_auto.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/ndf_estimate.hpp"
#include "microbrdf/units.hpp"

namespace microbrdf {

double hellinger_distance(const TabulatedNdf& a, const TabulatedNdf& b) {
  if (a.resolution() != b.resolution())
    throw std::invalid_argument("hellinger_distance: tables of different resolutions");
  const auto& p = a.values();
  const auto& q = b.values();
  double sp = 0, sq = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    sp += std::max(p[i], 0.0);
    sq += std::max(q[i], 0.0);
  }
  if (!(sp > 0) || !(sq > 0)) throw InputError("Hellinger distance of an empty NDF table");
  double bc = 0;  // Bhattacharyya coefficient sum sqrt(p q)
  for (std::size_t i = 0; i < p.size(); ++i)
    bc += std::sqrt(std::max(p[i], 0.0) * std::max(q[i], 0.0));
  bc /= std::sqrt(sp * sq);  // Delta^2 cancels in the normalisation
  return std::sqrt(std::max(0.0, 1.0 - bc));
}

namespace {

std::vector<double> log_spaced(double lo, double hi, std::size_t n) {
  std::vector<double> v;
  if (n == 1) return {lo};
  for (std::size_t i = 0; i < n; ++i)
    v.push_back(lo * std::pow(hi / lo, static_cast<double>(i) / static_cast<double>(n - 1)));
  return v;
}

void say(const FilterSigmaAutoOptions& o, const std::string& line) {
  if (o.log) o.log(line);
}

NdfEstimateOptions filtered_options(const FilterSigmaAutoOptions& o, double sigma) {
  NdfEstimateOptions f;
  f.method = NdfMethod::Filtered;
  f.resolution = o.resolution;
  f.filter_sigma_m = sigma;
  f.truncate_sigmas = o.truncate_sigmas;
  f.min_support = o.min_support;
  return f;
}

}  // namespace

FilterSigmaAuto choose_filter_sigma(const ScanVisitor& for_each_scan,
                                    const FilterSigmaAutoOptions& o) {
  if (o.resolution < 17 || o.resolution > 8193)
    throw InputError("filter sigma sweep: resolution must lie in 17..8193");
  if (o.coarse_points < 3) throw InputError("filter sigma sweep: need at least 3 coarse points");
  FilterSigmaAuto r;
  r.resolution = o.resolution;
  r.wavelength_q_m = o.kirchhoff.wavelength_q;
  KirchhoffOptions ko = o.kirchhoff;
  ko.resolution = o.resolution;
  ko.stack_wavelengths_q.clear();  // the sweep compares one table at lambda_q
  KirchhoffAccumulator dk(ko);
  NdfEstimateOptions no;
  no.method = NdfMethod::Naive;
  no.resolution = o.resolution;
  NdfAccumulator naive(no);
  std::vector<double> coarse;
  std::vector<std::unique_ptr<NdfAccumulator>> acc;
  std::size_t scans = 0;

  // Pass 1: D_K, the naive NDF and the coarse sweep (its range from the first scan).
  say(o, "filter sigma auto: D_K and the coarse sweep");
  for_each_scan([&](const Surface& s) {
    if (scans++ == 0) {
      const double d = std::max(s.dx, s.dy);
      r.sigma_min_m = o.sigma_min_m > 0 ? o.sigma_min_m : d;
      r.sigma_max_m =
          o.sigma_max_m > 0
              ? o.sigma_max_m
              : std::min(o.field_fraction * std::min(s.width(), s.height()), o.max_spacings * d);
      if (!(r.sigma_max_m > 1.5 * r.sigma_min_m))
        throw InputError("--filter-sigma auto: the sweep from " + format_length(r.sigma_min_m) +
                         " to " + format_length(r.sigma_max_m) + " is empty (a field of " +
                         format_length(s.width()) + " x " + format_length(s.height()) +
                         " is too small for it); give a filter sigma instead");
      coarse = log_spaced(r.sigma_min_m, r.sigma_max_m, o.coarse_points);
      for (double sg : coarse)
        acc.push_back(std::make_unique<NdfAccumulator>(filtered_options(o, sg)));
    }
    dk.add(s);
    naive.add(s);
    for (auto& a : acc) a->add(s);
  });
  if (scans == 0) throw InputError("--filter-sigma auto: no scan");
  r.kirchhoff = dk.result();
  r.kirchhoff_raw_integral = dk.raw_integral();
  r.kirchhoff_aliased_fraction = dk.aliased_fraction();
  r.naive = naive.result();
  // A sigma whose filter skips every sample (a field narrower than the kernel) gives no table:
  // it is left off the curve.
  std::vector<std::pair<double, TabulatedNdf>> tables;
  auto evaluate = [&](double sigma, const NdfAccumulator& a) {
    try {
      TabulatedNdf t = a.result();
      r.curve.push_back({sigma, hellinger_distance(t, r.kirchhoff)});
      tables.emplace_back(sigma, std::move(t));
    } catch (const InputError&) {
    } catch (const FileError&) {
    }
  };
  for (std::size_t i = 0; i < coarse.size(); ++i) evaluate(coarse[i], *acc[i]);
  acc.clear();
  if (r.curve.empty())
    throw InputError("--filter-sigma auto: no sigma of the sweep left a filtered sample");

  // Pass 2: refine between the coarse neighbours of the coarse minimum.
  auto argmin = [&] {
    std::size_t k = 0;
    for (std::size_t i = 1; i < r.curve.size(); ++i)
      if (r.curve[i].hellinger < r.curve[k].hellinger) k = i;
    return k;
  };
  const std::size_t k = argmin();
  const double lo = r.curve[k > 0 ? k - 1 : 0].sigma_m;
  const double hi = r.curve[std::min(k + 1, r.curve.size() - 1)].sigma_m;
  std::vector<double> fine;
  if (o.refine_points > 0 && hi > lo) {
    auto inner = log_spaced(lo, hi, o.refine_points + 2);
    for (std::size_t i = 1; i + 1 < inner.size(); ++i) {
      bool known = false;
      for (const auto& p : r.curve) known |= std::abs(p.sigma_m / inner[i] - 1) < 1e-9;
      if (!known) fine.push_back(inner[i]);
    }
  }
  if (!fine.empty()) {
    say(o,
        "filter sigma auto: refining between " + format_length(lo) + " and " + format_length(hi));
    for (double sg : fine) acc.push_back(std::make_unique<NdfAccumulator>(filtered_options(o, sg)));
    for_each_scan([&](const Surface& s) {
      for (auto& a : acc) a->add(s);
    });
    for (std::size_t i = 0; i < fine.size(); ++i) evaluate(fine[i], *acc[i]);
  }
  // Ascending sigma; the chosen one is the smallest distance (the first of equals).
  std::vector<std::size_t> order(r.curve.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](std::size_t a, std::size_t b) { return r.curve[a].sigma_m < r.curve[b].sigma_m; });
  std::vector<FilterSigmaPoint> sorted;
  std::vector<std::pair<double, TabulatedNdf>> sorted_tables;
  for (std::size_t i : order) {
    sorted.push_back(r.curve[i]);
    sorted_tables.push_back(std::move(tables[i]));
  }
  r.curve = std::move(sorted);
  const std::size_t best = argmin();
  r.sigma_m = r.curve[best].sigma_m;
  r.hellinger = r.curve[best].hellinger;
  r.at_lower_end = best == 0;
  r.at_upper_end = best + 1 == r.curve.size();
  r.filtered = std::move(sorted_tables[best].second);
  r.hellinger_filtered_kirchhoff = r.hellinger;
  r.hellinger_naive_kirchhoff = hellinger_distance(r.naive, r.kirchhoff);
  r.hellinger_naive_filtered = hellinger_distance(r.naive, r.filtered);
  return r;
}

FilterSigmaAuto choose_filter_sigma(const std::vector<Surface>& surfaces,
                                    const FilterSigmaAutoOptions& options) {
  return choose_filter_sigma(
      [&](const std::function<void(const Surface&)>& f) {
        for (const auto& s : surfaces) f(s);
      },
      options);
}

FilterSigmaAuto choose_filter_sigma(const std::vector<std::string>& paths, const ReadOptions& read,
                                    const LevelingSpec& leveling,
                                    const FilterSigmaAutoOptions& options) {
  return choose_filter_sigma(
      [&](const std::function<void(const Surface&)>& f) {
        for (const auto& path : paths) {
          Surface s = read_surface(path, read);
          about_file(path, [&] {
            level_surface(s, leveling);
            f(s);
          });
        }
      },
      options);
}

nlohmann::json FilterSigmaAuto::to_json() const {
  nlohmann::json c = nlohmann::json::array();
  for (const auto& p : curve) c.push_back({{"sigma_m", p.sigma_m}, {"hellinger", p.hellinger}});
  return {{"sigma_m", sigma_m},
          {"hellinger", hellinger},
          {"curve", c},
          {"sweep",
           {{"sigma_min_m", sigma_min_m},
            {"sigma_max_m", sigma_max_m},
            {"points", curve.size()},
            {"resolution", resolution},
            {"wavelength_q_m", wavelength_q_m},
            {"kirchhoff_raw_integral", kirchhoff_raw_integral},
            {"kirchhoff_aliased_fraction", kirchhoff_aliased_fraction},
            {"at_lower_end", at_lower_end},
            {"at_upper_end", at_upper_end}}},
          {"distances",
           {{"naive_kirchhoff", hellinger_naive_kirchhoff},
            {"naive_filtered", hellinger_naive_filtered},
            {"filtered_kirchhoff", hellinger_filtered_kirchhoff},
            {"resolution", resolution}}}};
}

void write_filter_sigma_curve_csv(const FilterSigmaAuto& r, const std::string& path) {
  std::string text = "sigma_m,hellinger\n";
  char line[96];
  for (const auto& p : r.curve) {
    std::snprintf(line, sizeof line, "%.9g,%.9g\n", p.sigma_m, p.hellinger);
    text += line;
  }
  write_file_atomic(path, text);
}

}  // namespace microbrdf

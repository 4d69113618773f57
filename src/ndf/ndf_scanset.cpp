// Scan sets over ranks for the geometric and Kirchhoff NDFs: per-scan shares packed for the trip
// to rank 0 and folded there in scan order (docs/scale.md, "Determinism").
#include "microbrdf/ndf_scanset.hpp"

#include <memory>
#include <type_traits>
#include <utility>

#include "microbrdf/error.hpp"
#include "microbrdf/kirchhoff.hpp"
#include "microbrdf/scanset.hpp"

namespace microbrdf {
namespace {

nlohmann::json scan_info(const Surface& s) {
  return {{"nx", s.nx},
          {"ny", s.ny},
          {"dx_m", s.dx},
          {"dy_m", s.dy},
          {"valid", s.valid_count()},
          {"leveling", s.meta.leveling}};
}

// Table rows [first, last] holding a non-zero value, appended after `head` numbers; the empty
// table sends no row.
void pack_rows(const TabulatedNdf& t, std::vector<double>& out) {
  const std::size_t n = t.resolution();
  const auto& v = t.values();
  std::size_t first = n, last = 0;
  for (std::size_t iy = 0; iy < n; ++iy)
    for (std::size_t ix = 0; ix < n; ++ix)
      if (v[iy * n + ix] != 0) {
        first = std::min(first, iy);
        last = iy;
        break;
      }
  if (first == n) {
    out.push_back(0);
    out.push_back(0);
    return;
  }
  out.push_back(static_cast<double>(first));
  out.push_back(static_cast<double>(last + 1));
  out.insert(out.end(), v.begin() + static_cast<std::ptrdiff_t>(first * n),
             v.begin() + static_cast<std::ptrdiff_t>((last + 1) * n));
}

// The table packed at `at` (advanced past it).
TabulatedNdf unpack_rows_at(const std::vector<double>& in, std::size_t& at, std::size_t n) {
  TabulatedNdf t(n);
  if (in.size() < at + 2) throw std::runtime_error("NDF share: short message");
  const auto first = static_cast<std::size_t>(in[at]), end = static_cast<std::size_t>(in[at + 1]);
  if (end < first || end > n || in.size() < at + 2 + (end - first) * n)
    throw std::runtime_error("NDF share: table rows do not match the resolution");
  const auto from = in.begin() + static_cast<std::ptrdiff_t>(at + 2);
  std::copy(from, from + static_cast<std::ptrdiff_t>((end - first) * n),
            t.values().begin() + static_cast<std::ptrdiff_t>(first * n));
  at += 2 + (end - first) * n;
  return t;
}

// The one table that ends the message.
TabulatedNdf unpack_rows(const std::vector<double>& in, std::size_t at, std::size_t n) {
  TabulatedNdf t = unpack_rows_at(in, at, n);
  if (at != in.size())
    throw std::runtime_error("NDF share: table rows do not match the resolution");
  return t;
}

void report(const ScanSetOptions& set, std::size_t i, const std::vector<std::string>& paths,
            const WorkResult& r) {
  if (set.on_scan) set.on_scan(i, paths[i], nlohmann::json::parse(r.text).at("scan"));
}

// A share computed on rank 0 stays there: the object itself, with only the scan's record as
// text; on other ranks it is packed for the trip.
template <class Partial>
WorkResult pack_or_keep(Partial&& p, const nlohmann::json& info) {
  if (!mpi_is_root()) return pack_partial(p, info);
  WorkResult r;
  r.text = nlohmann::json{{"scan", info}}.dump();
  r.local = std::make_shared<std::decay_t<Partial>>(std::move(p));
  return r;
}

}  // namespace

WorkResult pack_partial(const NdfScanPartial& p, const nlohmann::json& info) {
  WorkResult r;
  r.values.push_back(p.meta.projected_area_m2);
  pack_rows(p.table, r.values);
  r.text = nlohmann::json{
      {"used", p.meta.samples_used},
      {"skipped", p.meta.samples_skipped},
      {"sources", p.meta.sources},
      {"leveling", p.meta.leveling},
      {"scan",
       info}}.dump();
  return r;
}

NdfScanPartial unpack_ndf_partial(const WorkResult& r, std::size_t resolution) {
  const auto j = nlohmann::json::parse(r.text);
  if (r.values.empty()) throw std::runtime_error("NDF share: short message");
  NdfScanPartial p{unpack_rows(r.values, 1, resolution), {}};
  p.meta.projected_area_m2 = r.values[0];
  p.meta.samples_used = j.at("used");
  p.meta.samples_skipped = j.at("skipped");
  p.meta.sources = j.at("sources").get<std::vector<std::string>>();
  p.meta.leveling = j.at("leveling");
  return p;
}

WorkResult pack_partial(const KirchhoffScanPartial& p, const nlohmann::json& info) {
  WorkResult r;
  r.values = {p.area_w2,    p.valid_area,     p.aliased, p.info.height_half_range,
              p.info.z_max, p.info.tail_bound};
  for (double a : p.stack_aliased) r.values.push_back(a);
  pack_rows(p.table, r.values);
  for (const auto& t : p.stack) pack_rows(t, r.values);
  for (const auto& m : p.coherent) {  // the mean-field sums: length, then re, im per node
    r.values.push_back(static_cast<double>(m.size()));
    for (const auto& c : m) {
      r.values.push_back(c.real());
      r.values.push_back(c.imag());
    }
  }
  r.text = nlohmann::json{
      {"patches", p.patches},
      {"used", p.used},
      {"skipped", p.skipped},
      {"tiles", p.tiles},
      {"leveling", p.leveling},
      {"source", p.source},
      {"terms", p.info.terms},
      {"stack", p.stack.size()},
      {"has_info", p.has_info},
      {"supersample", p.supersample},
      {"points", p.info.points_per_triangle},
      {"phase_span", p.info.phase_span},
      {"scan",
       info}}.dump();
  return r;
}

KirchhoffScanPartial unpack_kirchhoff_partial(const WorkResult& r, std::size_t resolution) {
  const auto j = nlohmann::json::parse(r.text);
  if (r.values.size() < 6) throw std::runtime_error("Kirchhoff share: short message");
  KirchhoffScanPartial p;
  const std::size_t layers = j.value("stack", std::size_t{0});
  if (r.values.size() < 6 + layers) throw std::runtime_error("Kirchhoff share: short message");
  p.stack_aliased.assign(r.values.begin() + 6,
                         r.values.begin() + 6 + static_cast<std::ptrdiff_t>(layers));
  std::size_t at = 6 + layers;
  p.table = unpack_rows_at(r.values, at, resolution);
  for (std::size_t l = 0; l < layers; ++l)
    p.stack.push_back(unpack_rows_at(r.values, at, resolution));
  p.coherent.resize(layers + 1);
  for (auto& m : p.coherent) {
    if (at >= r.values.size()) throw std::runtime_error("Kirchhoff share: short message");
    const auto n = static_cast<std::size_t>(r.values[at++]);
    if (n != 0 && n < resolution * resolution)
      throw std::runtime_error("Kirchhoff share: bad mean field");
    if (r.values.size() < at + 2 * n) throw std::runtime_error("Kirchhoff share: short message");
    m.resize(n);
    for (std::size_t i = 0; i < n; ++i, at += 2) m[i] = {r.values[at], r.values[at + 1]};
  }
  if (at != r.values.size())
    throw std::runtime_error("Kirchhoff share: tables do not match the resolution");
  p.area_w2 = r.values[0];
  p.valid_area = r.values[1];
  p.aliased = r.values[2];
  p.info.height_half_range = r.values[3];
  p.info.z_max = r.values[4];
  p.info.tail_bound = r.values[5];
  p.patches = j.at("patches");
  p.used = j.at("used");
  p.skipped = j.at("skipped");
  p.tiles = j.at("tiles");
  p.leveling = j.at("leveling");
  p.source = j.at("source");
  p.info.terms = j.at("terms");
  p.has_info = j.at("has_info");
  p.supersample = j.value("supersample", std::size_t{1});
  p.info.points_per_triangle = j.value("points", std::size_t{1});
  p.info.phase_span = j.value("phase_span", 0.0);
  return p;
}

std::optional<NdfAccumulator> accumulate_ndf_scans(const std::vector<std::string>& paths,
                                                   const NdfEstimateOptions& options,
                                                   const ScanSetOptions& set, WorkStats* stats) {
  NdfAccumulator acc(options);
  WorkStats st = distribute_scans(
      paths, set.read,
      [&](std::size_t, const std::string& path, Surface& s) {
        // Errors about the data (too few valid samples, no normal) name the scan.
        return about_file(path, [&] {
          level_surface(s, set.leveling);
          return pack_or_keep(acc.estimate(s), scan_info(s));
        });
      },
      [&](std::size_t i, WorkResult&& r) {
        report(set, i, paths, r);
        if (r.local)
          acc.merge(std::move(*std::static_pointer_cast<NdfScanPartial>(r.local)));
        else
          acc.merge(unpack_ndf_partial(r, options.resolution));
      },
      set.distribute);
  if (!mpi_is_root()) return std::nullopt;
  if (stats) *stats = st;
  return acc;
}

std::optional<KirchhoffAccumulator> accumulate_kirchhoff_scans(
    const std::vector<std::string>& paths, const KirchhoffOptions& options,
    const ScanSetOptions& set, WorkStats* stats) {
  // Per-patch progress only makes sense when one rank does every scan in order.
  const bool local = mpi_size() == 1;
  KirchhoffAccumulator acc(options);
  WorkStats st = distribute_scans(
      paths, set.read,
      [&](std::size_t i, const std::string& path, Surface& s) {
        about_file(path, [&] { level_surface(s, set.leveling); });
        KirchhoffOptions o = options;
        o.progress = nullptr;
        if (local && options.progress)
          o.progress = [&, i](double f) {
            options.progress((static_cast<double>(i) + f) / static_cast<double>(paths.size()));
          };
        // Errors about the data (a height range the series cannot hold) name the scan.
        return about_file(
            path, [&] { return pack_or_keep(KirchhoffAccumulator(o).estimate(s), scan_info(s)); });
      },
      [&](std::size_t i, WorkResult&& r) {
        report(set, i, paths, r);
        if (r.local)
          acc.merge(std::move(*std::static_pointer_cast<KirchhoffScanPartial>(r.local)));
        else
          acc.merge(unpack_kirchhoff_partial(r, options.resolution));
        r.local.reset();  // the share's tables go before the next scan's
      },
      set.distribute);
  kirchhoff_release_buffers();  // the transforms' large buffers, kept between tables and scans
  if (!mpi_is_root()) return std::nullopt;
  if (stats) *stats = st;
  return acc;
}

}  // namespace microbrdf

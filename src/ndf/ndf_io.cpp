// Tabulated NDF files: .npy (float64, numpy-readable) + JSON sidecar, or single-channel .exr
// with metadata attributes. See include/microbrdf/ndf_io.hpp.
//
// Layout in both: array row iy = m_y = -1 + 2 iy/(N-1), column ix = m_x = -1 + 2 ix/(N-1)
// (the first row written / the first EXR scanline is iy = 0, i.e. m_y = -1); a zoomed table
// records its window [x0, x1] x [y0, y1] and has m_x = x0 + (x1 - x0) ix/(N-1), likewise m_y.
// "sampling" ("point" | "cell") says how the nodes were obtained; files without it get the value
// ndf_sampling() infers from the method.
#include "microbrdf/ndf_io.hpp"

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfDoubleAttribute.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfIntAttribute.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>
#include <OpenEXR/ImfStringVectorAttribute.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/npy.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"

namespace microbrdf {
namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxResolution = 16385;  // 2 GiB of float64; far above any real table
constexpr std::uint64_t kMaxNpyBytes = std::uint64_t{4} << 30;

constexpr const char* kConvMx = "m_x = -1 + 2 ix/(N-1)";
constexpr const char* kConvMy = "m_y = -1 + 2 iy/(N-1), row iy";
constexpr const char* kConvValue = "D per steradian";
constexpr const char* kConvNorm = "integral of D(m)(m.n) = 1";
constexpr const char* kConvDisk = "0 outside the unit disk; dw = dm_x dm_y / m_z";

enum class Kind { Npy, Exr };

Kind kind_of(const std::string& path) {
  std::string e = fs::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  if (e == ".npy") return Kind::Npy;
  if (e == ".exr") return Kind::Exr;
  throw FileError(path, "unsupported NDF file extension '" + e + "' (use .npy or .exr)");
}

std::string sidecar_path(const std::string& path) {
  return fs::path(path).replace_extension(".json").string();
}

// Validates a table read from `path`: square N x N, N >= 3, non-negative values; NaN is allowed
// and means "unmeasured" (effective NDFs inferred from measured BRDFs), infinities are not.
void validate(const std::string& path, std::size_t rows, std::size_t cols,
              const std::vector<double>& v, const NdfWindow& w) {
  if (rows != cols)
    throw FileError(path, "NDF table must be square, got " + std::to_string(rows) + " x " +
                              std::to_string(cols));
  if (rows < 3) throw FileError(path, "NDF table resolution " + std::to_string(rows) + " < 3");
  if (rows > kMaxResolution)
    throw FileError(path, "NDF table resolution " + std::to_string(rows) + " is absurdly large");
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isinf(v[i]) || v[i] < 0)
      throw FileError(path, "NDF value at row " + std::to_string(i / cols) + ", column " +
                                std::to_string(i % cols) + " is " +
                                (std::isfinite(v[i]) ? "negative" : "infinite"));
  }
  // Finite values whose sum overflows (1e308 everywhere) cannot be normalised, nor can a
  // table with nothing inside the unit disk (the only part that counts).
  double sum = 0, inside = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (std::isnan(v[i])) continue;  // an unmeasured node (NaN) adds nothing
    sum += v[i];
    const double mx = w.x0() + 2 * w.half * double(i % cols) / double(cols - 1);
    const double my = w.y0() + 2 * w.half * double(i / cols) / double(rows - 1);
    if (mx * mx + my * my < 1) inside += v[i];
  }
  if (!std::isfinite(sum))
    throw FileError(path,
                    "NDF values are so large that their integral overflows (not a "
                    "normalisable table)");
  if (!(inside > 0))
    throw FileError(path, "the NDF table holds no positive value inside the unit disk");
}

// The window of a table from its extent [x0, x1] x [y0, y1] (a square inside [-1, 1]^2).
NdfWindow window_from_extent(const std::string& path, double x0, double x1, double y0, double y1) {
  constexpr double kTol = 1e-9;
  if (!(std::isfinite(x0) && std::isfinite(x1) && std::isfinite(y0) && std::isfinite(y1)) ||
      !(x1 > x0) || !(y1 > y0) || std::abs((x1 - x0) - (y1 - y0)) > kTol * (x1 - x0) + 1e-15 ||
      x0 < -1 - kTol || y0 < -1 - kTol || x1 > 1 + kTol || y1 > 1 + kTol)
    throw FileError(path,
                    "the table's window must be a square inside [-1, 1]^2 (x0 < x1, y0 < y1, "
                    "equal sides)");
  NdfWindow w;
  w.half = std::min(1.0, 0.5 * (x1 - x0));
  w.cx = 0.5 * (x0 + x1);
  w.cy = 0.5 * (y0 + y1);
  if (std::abs(w.cx) < 1e-15 && std::abs(w.cy) < 1e-15 && std::abs(w.half - 1) < 1e-12) return {};
  w.cx = std::clamp(w.cx, -(1 - w.half), 1 - w.half);
  w.cy = std::clamp(w.cy, -(1 - w.half), 1 - w.half);
  return w;
}

std::string num_text(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}
std::string conv_mx(const NdfWindow& w) {
  return w.full() ? kConvMx
                  : "m_x = " + num_text(w.x0()) + " + " + num_text(2 * w.half) + " ix/(N-1)";
}
std::string conv_my(const NdfWindow& w) {
  return w.full()
             ? kConvMy
             : "m_y = " + num_text(w.y0()) + " + " + num_text(2 * w.half) + " iy/(N-1), row iy";
}

void check_writable(const TabulatedNdf& ndf, const std::string& path, bool as_float) {
  for (double v : ndf.values()) {
    if (std::isinf(v) || v < 0)  // NaN = unmeasured is kept
      throw FileError(path, "cannot write an NDF with negative or infinite values");
    if (as_float && v > std::numeric_limits<float>::max())
      throw FileError(path, "NDF value exceeds the float range of EXR");
  }
}

nlohmann::json metadata_json(const TabulatedNdf& ndf) {
  const NdfMetadata& m = ndf.meta;
  return {{"format", "microbrdf-ndf"},
          {"version", 1},
          {"resolution", ndf.resolution()},
          {"conventions",
           {{"m_x", conv_mx(ndf.window())},
            {"m_y", conv_my(ndf.window())},
            {"value", kConvValue},
            {"normalisation", kConvNorm},
            {"disk", kConvDisk}}},
          {"method", m.method},
          {"sampling", ndf_sampling(m)},
          {"window",
           {{"x", {ndf.window().x0(), ndf.window().x1()}},
            {"y", {ndf.window().y0(), ndf.window().y1()}}}},
          {"window_mass", m.window_mass},
          {"filter_sigma_m", m.filter_sigma_m},
          {"wavelength_m", m.wavelength_m},
          {"sources", m.sources},
          {"samples_used", m.samples_used},
          {"samples_skipped", m.samples_skipped},
          {"projected_area_m2", m.projected_area_m2},
          {"leveling", m.leveling},
          {"parameterisation", m.parameterisation},
          {"notes", m.notes}};
}

void read_sidecar(const std::string& side, std::size_t resolution, NdfMetadata& m,
                  NdfWindow& window) {
  const nlohmann::json j = read_json_file(side);
  if (!j.is_object()) throw FileError(side, "JSON sidecar is not an object");
  auto bad = [&](const char* key, const char* what) {
    throw FileError(side, std::string("'") + key + "' must be " + what);
  };
  auto str = [&](const char* key, std::string& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_string()) bad(key, "a string");
    out = j[key].get<std::string>();
  };
  auto num = [&](const char* key, double& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_number() || !std::isfinite(j[key].get<double>())) bad(key, "a finite number");
    out = j[key].get<double>();
  };
  auto count = [&](const char* key, std::size_t& out) {
    if (!j.contains(key)) return;
    if (!j[key].is_number_unsigned()) bad(key, "a non-negative integer");
    out = j[key].get<std::size_t>();
  };
  if (j.contains("resolution")) {
    if (!j["resolution"].is_number_unsigned()) bad("resolution", "a positive integer");
    if (j["resolution"].get<std::size_t>() != resolution)
      throw FileError(side, "sidecar says resolution " +
                                std::to_string(j["resolution"].get<std::size_t>()) +
                                " but the table is " + std::to_string(resolution));
  }
  str("method", m.method);
  str("sampling", m.sampling);
  if (!m.sampling.empty() && m.sampling != "point" && m.sampling != "cell")
    bad("sampling", "\"point\" or \"cell\"");
  if (j.contains("window")) {
    const auto& w = j["window"];
    auto pair = [&](const char* axis, double& lo, double& hi) {
      if (!w.is_object() || !w.contains(axis) || !w[axis].is_array() || w[axis].size() != 2 ||
          !w[axis][0].is_number() || !w[axis][1].is_number())
        bad("window", "{\"x\": [x0, x1], \"y\": [y0, y1]}");
      lo = w[axis][0].get<double>();
      hi = w[axis][1].get<double>();
    };
    double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
    pair("x", x0, x1);
    pair("y", y0, y1);
    window = window_from_extent(side, x0, x1, y0, y1);
  }
  num("window_mass", m.window_mass);
  if (!(m.window_mass >= 0 && m.window_mass <= 1)) bad("window_mass", "a fraction in [0, 1]");
  num("filter_sigma_m", m.filter_sigma_m);
  num("wavelength_m", m.wavelength_m);
  if (j.contains("sources")) {
    if (!j["sources"].is_array()) bad("sources", "an array of strings");
    m.sources.clear();
    for (const auto& s : j["sources"]) {
      if (!s.is_string()) bad("sources", "an array of strings");
      m.sources.push_back(s.get<std::string>());
    }
  }
  count("samples_used", m.samples_used);
  count("samples_skipped", m.samples_skipped);
  num("projected_area_m2", m.projected_area_m2);
  str("leveling", m.leveling);
  str("parameterisation", m.parameterisation);
  str("notes", m.notes);
}

// One table (2-D array) or a stack of tables over lambda_q (3-D array, `primary` first in the
// sidecar's metadata); the sidecar lists the layers' lambda_q and notes.
void write_npy_ndf(const std::vector<TabulatedNdf>& layers, std::size_t primary,
                   const std::string& path) {
  const TabulatedNdf& ndf = layers.at(primary);
  const std::size_t n = ndf.resolution();
  std::vector<double> all;
  for (const auto& t : layers) {
    if (t.resolution() != n) throw FileError(path, "the tables of a stack differ in resolution");
    check_writable(t, path, false);
  }
  std::vector<std::uint8_t> bytes;
  try {
    if (layers.size() == 1) {
      bytes = detail::encode_npy_f64(ndf.values(), n, n);
    } else {
      all.reserve(layers.size() * n * n);
      for (const auto& t : layers) all.insert(all.end(), t.values().begin(), t.values().end());
      bytes = detail::encode_npy_f64(all, n, n, layers.size());
    }
  } catch (const std::exception& e) {
    throw FileError(path, e.what());
  }
  const std::string side = sidecar_path(path);
  nlohmann::json meta = metadata_json(ndf);
  if (layers.size() > 1) {
    nlohmann::json lq = nlohmann::json::array(), notes = nlohmann::json::array();
    for (const auto& t : layers) {
      lq.push_back(t.meta.wavelength_m);
      notes.push_back(t.meta.notes);
    }
    meta["stack"] = {{"axis", "the first axis of the array: one table per lambda_q"},
                     {"wavelengths_q_m", lq},
                     {"primary", primary},
                     {"notes", notes}};
  }
  const std::string json = meta.dump(2) + "\n";
  // Both temporaries first, then both renames: a failure leaves no new half pair behind.
  AtomicFile out(path), out_side(side);
  auto put = [](const std::string& target, const std::string& tmp, const char* data,
                std::size_t size) {
    std::ofstream f(tmp, std::ios::binary | std::ios::trunc);
    if (!f) throw FileError(target, "cannot create file");
    f.write(data, static_cast<std::streamsize>(size));
    f.flush();
    if (!f) throw FileError(target, write_failure_problem(errno));
  };
  put(path, out.temp_path(), reinterpret_cast<const char*>(bytes.data()), bytes.size());
  put(side, out_side.temp_path(), json.data(), json.size());
  out.commit();
  out_side.commit();
}

// The sidecar's stack: the layers' lambda_q (m), their notes, and which layer is the primary.
struct StackInfo {
  std::vector<double> wavelengths_q;
  std::vector<std::string> notes;
  std::size_t primary = 0;
};

StackInfo read_stack_info(const std::string& side, std::size_t layers) {
  StackInfo st;
  std::error_code ec;
  if (!fs::exists(side, ec))
    throw FileError(side, "a stack of " + std::to_string(layers) +
                              " tables needs its sidecar (the lambda_q of each layer)");
  const nlohmann::json j = read_json_file(side);
  if (!j.contains("stack") || !j["stack"].is_object())
    throw FileError(side, "the table is a stack of " + std::to_string(layers) +
                              " layers but the sidecar has no \"stack\" object");
  const auto& k = j["stack"];
  if (!k.contains("wavelengths_q_m") || !k["wavelengths_q_m"].is_array() ||
      k["wavelengths_q_m"].size() != layers)
    throw FileError(side, "\"stack\".\"wavelengths_q_m\" must list " + std::to_string(layers) +
                              " wavelengths (one per layer)");
  for (const auto& v : k["wavelengths_q_m"]) {
    if (!v.is_number() || !(v.get<double>() > 0) || !(v.get<double>() < 1))
      throw FileError(side, "\"stack\".\"wavelengths_q_m\" must hold wavelengths in m (0..1)");
    st.wavelengths_q.push_back(v.get<double>());
  }
  for (std::size_t i = 1; i < layers; ++i)
    if (!(st.wavelengths_q[i] > st.wavelengths_q[i - 1]))
      throw FileError(side, "\"stack\".\"wavelengths_q_m\" must increase");
  if (k.contains("notes") && k["notes"].is_array() && k["notes"].size() == layers)
    for (const auto& v : k["notes"]) st.notes.push_back(v.is_string() ? v.get<std::string>() : "");
  if (k.contains("primary")) {
    if (!k["primary"].is_number_unsigned() || k["primary"].get<std::size_t>() >= layers)
      throw FileError(
          side, "\"stack\".\"primary\" must be a layer index below " + std::to_string(layers));
    st.primary = k["primary"].get<std::size_t>();
  }
  return st;
}

std::vector<TabulatedNdf> read_npy_stack(const std::string& path, std::size_t* primary) {
  auto data = read_file_bytes(path, kMaxNpyBytes);
  detail::NpyArray a = detail::parse_npy(data, path);
  // The sidecar first: it holds the window the values are validated against.
  NdfMetadata meta;
  NdfWindow window;
  const std::string side = sidecar_path(path);
  std::error_code ec;
  if (fs::exists(side, ec)) read_sidecar(side, a.rows, meta, window);
  StackInfo st;
  if (a.layers > 1) st = read_stack_info(side, a.layers);
  std::vector<TabulatedNdf> out;
  const std::size_t per = a.rows * a.cols;
  for (std::size_t l = 0; l < a.layers; ++l) {
    std::vector<double> v(a.values.begin() + static_cast<std::ptrdiff_t>(l * per),
                          a.values.begin() + static_cast<std::ptrdiff_t>((l + 1) * per));
    validate(path, a.rows, a.cols, v, window);
    TabulatedNdf ndf(a.rows, window);
    ndf.values() = std::move(v);
    ndf.meta = meta;
    if (a.layers > 1) {
      ndf.meta.wavelength_m = st.wavelengths_q[l];
      if (l < st.notes.size()) ndf.meta.notes = st.notes[l];
    }
    out.push_back(std::move(ndf));
  }
  if (primary) *primary = st.primary;
  return out;
}

TabulatedNdf read_npy_ndf(const std::string& path) {
  std::size_t primary = 0;
  auto layers = read_npy_stack(path, &primary);
  return std::move(layers[primary]);
}

void write_exr_ndf(const TabulatedNdf& ndf, const std::string& path) {
  check_writable(ndf, path, true);
  const int n = static_cast<int>(ndf.resolution());
  std::vector<float> buf(ndf.values().size());
  std::transform(ndf.values().begin(), ndf.values().end(), buf.begin(),
                 [](double v) { return static_cast<float>(v); });
  const NdfMetadata& m = ndf.meta;
  AtomicFile out(path);
  try {
    Imf::Header h(n, n);
    h.compression() = Imf::ZIP_COMPRESSION;
    h.channels().insert("D", Imf::Channel(Imf::FLOAT));
    h.insert("microbrdf_format", Imf::StringAttribute("ndf"));
    const NdfWindow& win = ndf.window();
    h.insert("convention_m_x", Imf::StringAttribute(conv_mx(win)));
    h.insert("convention_m_y",
             Imf::StringAttribute(conv_my(win) + " (first scanline = iy 0 = m_y " +
                                  num_text(win.y0()) + ")"));
    h.insert("window_x0", Imf::DoubleAttribute(win.x0()));
    h.insert("window_x1", Imf::DoubleAttribute(win.x1()));
    h.insert("window_y0", Imf::DoubleAttribute(win.y0()));
    h.insert("window_y1", Imf::DoubleAttribute(win.y1()));
    h.insert("window_mass", Imf::DoubleAttribute(m.window_mass));
    h.insert("sampling", Imf::StringAttribute(ndf_sampling(m)));
    h.insert("convention_value", Imf::StringAttribute(kConvValue));
    h.insert("convention_normalisation", Imf::StringAttribute(kConvNorm));
    h.insert("convention_disk", Imf::StringAttribute(kConvDisk));
    h.insert("resolution", Imf::IntAttribute(n));
    h.insert("method", Imf::StringAttribute(m.method));
    h.insert("filter_sigma_m", Imf::DoubleAttribute(m.filter_sigma_m));
    h.insert("wavelength_m", Imf::DoubleAttribute(m.wavelength_m));
    h.insert("sources", Imf::StringVectorAttribute(m.sources));
    // Counts: int when they fit, else double (exact up to 2^53).
    auto put_count = [&](const char* name, std::size_t v) {
      if (v <= static_cast<std::size_t>(std::numeric_limits<int>::max()))
        h.insert(name, Imf::IntAttribute(static_cast<int>(v)));
      else
        h.insert(name, Imf::DoubleAttribute(static_cast<double>(v)));
    };
    put_count("samples_used", m.samples_used);
    put_count("samples_skipped", m.samples_skipped);
    h.insert("projected_area_m2", Imf::DoubleAttribute(m.projected_area_m2));
    h.insert("leveling", Imf::StringAttribute(m.leveling));
    h.insert("parameterisation", Imf::StringAttribute(m.parameterisation));
    h.insert("notes", Imf::StringAttribute(m.notes));
    Imf::OutputFile file(out.temp_path().c_str(), h, 0);
    Imf::FrameBuffer fb;
    fb.insert("D", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(buf.data()), sizeof(float),
                              sizeof(float) * static_cast<std::size_t>(n)));
    file.setFrameBuffer(fb);
    file.writePixels(n);
  } catch (const FileError&) {
    throw;
  } catch (const std::exception& e) {
    throw FileError(path, std::string("EXR write failed: ") + e.what());
  }
  out.commit();
}

TabulatedNdf read_exr_ndf(const std::string& path) {
  require_regular_file(path);
  try {
    Imf::InputFile file(path.c_str(), 0);
    const Imf::Header& h = file.header();
    const auto dw = h.dataWindow();
    const std::int64_t w = std::int64_t{dw.max.x} - dw.min.x + 1;
    const std::int64_t ht = std::int64_t{dw.max.y} - dw.min.y + 1;
    if (w <= 0 || ht <= 0 || w > static_cast<std::int64_t>(kMaxResolution) ||
        ht > static_cast<std::int64_t>(kMaxResolution))
      throw FileError(path, "EXR data window " + std::to_string(w) + " x " + std::to_string(ht) +
                                " is not a valid NDF table size");
    const Imf::Channel* ch = h.channels().findChannel("D");
    if (!ch) throw FileError(path, "EXR has no channel 'D'");
    if (ch->xSampling != 1 || ch->ySampling != 1)
      throw FileError(path, "channel 'D' is subsampled");
    const auto nx = static_cast<std::size_t>(w), ny = static_cast<std::size_t>(ht);
    std::vector<float> buf(nx * ny);
    Imf::FrameBuffer fb;
    char* base = reinterpret_cast<char*>(buf.data()) -
                 (static_cast<std::ptrdiff_t>(dw.min.x) +
                  static_cast<std::ptrdiff_t>(dw.min.y) * static_cast<std::ptrdiff_t>(nx)) *
                     static_cast<std::ptrdiff_t>(sizeof(float));
    fb.insert("D", Imf::Slice(Imf::FLOAT, base, sizeof(float), sizeof(float) * nx));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    std::vector<double> v(buf.begin(), buf.end());
    NdfWindow window;
    {
      const auto* a0 = h.findTypedAttribute<Imf::DoubleAttribute>("window_x0");
      const auto* a1 = h.findTypedAttribute<Imf::DoubleAttribute>("window_x1");
      const auto* b0 = h.findTypedAttribute<Imf::DoubleAttribute>("window_y0");
      const auto* b1 = h.findTypedAttribute<Imf::DoubleAttribute>("window_y1");
      if (a0 || a1 || b0 || b1) {
        if (!(a0 && a1 && b0 && b1))
          throw FileError(path,
                          "the window needs all of window_x0, window_x1, window_y0, window_y1");
        window = window_from_extent(path, a0->value(), a1->value(), b0->value(), b1->value());
      }
    }
    validate(path, ny, nx, v, window);
    TabulatedNdf ndf(nx, window);
    ndf.values() = std::move(v);
    NdfMetadata& m = ndf.meta;
    auto str = [&](const char* name, std::string& out) {
      if (auto* a = h.findTypedAttribute<Imf::StringAttribute>(name)) out = a->value();
    };
    auto dbl = [&](const char* name, double& out) {
      if (auto* a = h.findTypedAttribute<Imf::DoubleAttribute>(name))
        out = a->value();
      else if (auto* f = h.findTypedAttribute<Imf::FloatAttribute>(name))
        out = f->value();
    };
    auto count = [&](const char* name, std::size_t& out) {
      if (auto* a = h.findTypedAttribute<Imf::IntAttribute>(name)) {
        if (a->value() < 0) throw FileError(path, std::string("attribute '") + name + "' < 0");
        out = static_cast<std::size_t>(a->value());
      } else if (auto* d = h.findTypedAttribute<Imf::DoubleAttribute>(name)) {
        if (!(d->value() >= 0 && d->value() < 1.8e19))
          throw FileError(path, std::string("attribute '") + name + "' out of range");
        out = static_cast<std::size_t>(d->value());
      }
    };
    str("method", m.method);
    str("sampling", m.sampling);
    if (!m.sampling.empty() && m.sampling != "point" && m.sampling != "cell")
      throw FileError(path, "attribute 'sampling' must be \"point\" or \"cell\"");
    dbl("window_mass", m.window_mass);
    if (!(m.window_mass >= 0 && m.window_mass <= 1))
      throw FileError(path, "attribute 'window_mass' must be a fraction in [0, 1]");
    dbl("filter_sigma_m", m.filter_sigma_m);
    dbl("wavelength_m", m.wavelength_m);
    if (auto* a = h.findTypedAttribute<Imf::StringVectorAttribute>("sources"))
      m.sources = a->value();
    count("samples_used", m.samples_used);
    count("samples_skipped", m.samples_skipped);
    dbl("projected_area_m2", m.projected_area_m2);
    str("leveling", m.leveling);
    str("parameterisation", m.parameterisation);
    str("notes", m.notes);
    return ndf;
  } catch (const FileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw FileError(path, "corrupt EXR (implausible sizes)");
  } catch (const std::exception& e) {
    throw FileError(path, std::string("cannot read EXR: ") + e.what());
  }
}

}  // namespace

void write_ndf(const TabulatedNdf& ndf, const std::string& path) {
  if (kind_of(path) == Kind::Npy)
    write_npy_ndf({ndf}, 0, path);
  else
    write_exr_ndf(ndf, path);
}

bool write_ndf_stack(const std::vector<TabulatedNdf>& layers, std::size_t primary,
                     const std::string& path) {
  if (layers.empty() || primary >= layers.size())
    throw FileError(path, "no table to write (empty stack or bad primary layer)");
  for (std::size_t i = 1; i < layers.size(); ++i)
    if (!(layers[i].meta.wavelength_m > layers[i - 1].meta.wavelength_m))
      throw FileError(path, "a stack's tables must be sorted by increasing lambda_q");
  if (kind_of(path) == Kind::Npy) {
    write_npy_ndf(layers, primary, path);
    return true;
  }
  write_exr_ndf(layers[primary], path);
  return layers.size() == 1;
}

TabulatedNdf read_ndf(const std::string& path) {
  return kind_of(path) == Kind::Npy ? read_npy_ndf(path) : read_exr_ndf(path);
}

std::size_t ndf_file_layers(const std::string& path) {
  if (kind_of(path) != Kind::Npy) return 1;
  const std::string side = sidecar_path(path);
  std::error_code ec;
  if (!fs::exists(side, ec)) return 1;
  const nlohmann::json j = read_json_file(side);
  if (!j.is_object() || !j.contains("stack") || !j["stack"].is_object()) return 1;
  const auto& lq = j["stack"].value("wavelengths_q_m", nlohmann::json());
  return lq.is_array() && !lq.empty() ? lq.size() : 1;
}

std::vector<TabulatedNdf> read_ndf_stack(const std::string& path) {
  if (kind_of(path) == Kind::Npy) return read_npy_stack(path, nullptr);
  return {read_exr_ndf(path)};
}

}  // namespace microbrdf

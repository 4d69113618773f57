// Parameter textures as OpenEXR files (5 float channels + "valid", JSON metadata in the header
// attribute "microbrdf_param_texture") and their PNG previews.
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "core/bitmap_font.hpp"
#include "core/exr_guard.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf {
namespace {

constexpr const char* kAttr = "microbrdf_param_texture";
constexpr std::size_t kMaxSide = 1 << 15;
constexpr std::uint64_t kMaxFileBytes = std::uint64_t{1} << 32;

}  // namespace

void write_param_texture(const ParamTexture& t, const std::string& path) {
  if (t.nx == 0 || t.ny == 0) throw FileError(path, "cannot write an empty parameter texture");
  for (const auto& c : t.channel)
    if (c.size() != t.size()) throw FileError(path, "parameter texture channels have wrong sizes");
  if (t.valid.size() != t.size()) throw FileError(path, "validity channel has the wrong size");
  // Metadata: everything the struct holds besides the pixels, reasons as a compact list.
  nlohmann::json j;
  j["format"] = "microbrdf parameter texture 1";
  j["texel_m"] = t.texel_m;
  j["channels"] = {"alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z", "valid"};
  j["units"] = "alphas dimensionless, thetas rad, texel_m m";
  j["meta"] = t.meta;
  nlohmann::json why = nlohmann::json::array();
  for (std::size_t i = 0; i < t.why_invalid.size(); ++i)
    if (!t.valid[i] && !t.why_invalid[i].empty()) why.push_back({i, t.why_invalid[i]});
  j["why_invalid"] = why;

  std::vector<float> valid(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) valid[i] = t.valid[i] ? 1.0f : 0.0f;
  AtomicFile out(path);
  try {
    Imf::Header h(static_cast<int>(t.nx), static_cast<int>(t.ny));
    h.compression() = Imf::ZIP_COMPRESSION;
    h.insert(kAttr, Imf::StringAttribute(j.dump()));
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float), ys = sizeof(float) * t.nx;
    for (int c = 0; c < 5; ++c) {
      h.channels().insert(ParamTexture::channel_names[c], Imf::Channel(Imf::FLOAT));
      fb.insert(ParamTexture::channel_names[c],
                Imf::Slice(Imf::FLOAT,
                           reinterpret_cast<char*>(
                               const_cast<float*>(t.channel[static_cast<std::size_t>(c)].data())),
                           xs, ys));
    }
    h.channels().insert("valid", Imf::Channel(Imf::FLOAT));
    fb.insert("valid", Imf::Slice(Imf::FLOAT, reinterpret_cast<char*>(valid.data()), xs, ys));
    Imf::OutputFile file(out.temp_path().c_str(), h, 0);
    file.setFrameBuffer(fb);
    file.writePixels(static_cast<int>(t.ny));
  } catch (const std::exception& e) {
    throw FileError(path, std::string("EXR write failed: ") + e.what());
  }
  out.commit();
}

bool is_param_texture_file(const std::string& path) {
  try {
    // Only the header matters: read at most the first 16 MB (header and line-offset table come
    // first) and check it before OpenEXR parses it, as read_param_texture does.
    std::ifstream f(path, std::ios::binary);
    std::vector<std::uint8_t> head(static_cast<std::size_t>(
        std::min<std::uintmax_t>(std::filesystem::file_size(path), std::uintmax_t{1} << 24)));
    f.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
    head.resize(static_cast<std::size_t>(f.gcount()));
    if (head.size() < 4 || head[0] != 0x76 || head[1] != 0x2f || head[2] != 0x31 || head[3] != 0x01)
      return false;
    detail::init_openexr_limits();
    detail::check_exr_header_bytes(head, path);
    detail::ExrMemIStream stream(head, path);
    Imf::InputFile file(stream, 0);
    return file.header().channels().findChannel("alpha_x") != nullptr;
  } catch (...) {
    return false;
  }
}

ParamTexture read_param_texture(const std::string& path) {
  if (!std::filesystem::exists(path)) throw FileError::missing(path);
  ParamTexture t;
  // The file is read into memory and its header checked as the height-map EXR reader does
  // (src/surface/exr_guard.hpp) before OpenEXR parses it: OpenEXR allocates whatever an
  // attribute claims (fuzz_paramtex: a 778-byte file asked for 2 GB) and trusts the data window.
  const std::vector<std::uint8_t> bytes = read_file_bytes(path, kMaxFileBytes);
  detail::init_openexr_limits();
  detail::check_exr_header_bytes(bytes, path);
  try {
    detail::ExrMemIStream stream(bytes, path);
    Imf::InputFile file(stream, 0);
    const Imf::Header& h = file.header();
    const Imath::Box2i dw = h.dataWindow();
    detail::check_exr_data_window(dw, bytes.size(), path);
    const long w = static_cast<long>(dw.max.x) - dw.min.x + 1,
               ht = static_cast<long>(dw.max.y) - dw.min.y + 1;
    if (w <= 0 || ht <= 0 || static_cast<std::size_t>(w) > kMaxSide ||
        static_cast<std::size_t>(ht) > kMaxSide)
      throw FileError(path, "data window " + std::to_string(w) + " x " + std::to_string(ht) +
                                " is empty or larger than 32768 texels a side");
    for (int c = 0; c < 5; ++c)
      if (!h.channels().findChannel(ParamTexture::channel_names[c]))
        throw FileError(path, std::string("not a parameter texture: no channel '") +
                                  ParamTexture::channel_names[c] + "'");
    // Five channels and the valid mask (float each), the flags and an empty reason per texel.
    check_expansion(
        path, bytes.size(),
        mul_sat(static_cast<std::uint64_t>(w) * static_cast<std::uint64_t>(ht),
                6 * sizeof(float) + 1 + sizeof(std::string)),
        "a parameter texture of " + std::to_string(w) + " x " + std::to_string(ht) + " texels");
    t.nx = static_cast<std::size_t>(w);
    t.ny = static_cast<std::size_t>(ht);
    for (auto& c : t.channel) c.assign(t.size(), 0.0f);
    std::vector<float> valid(t.size(), 1.0f);
    Imf::FrameBuffer fb;
    const std::size_t xs = sizeof(float), ys = sizeof(float) * t.nx;
    // Slices are addressed in data-window coordinates.
    const std::ptrdiff_t origin =
        -static_cast<std::ptrdiff_t>(dw.min.x) - static_cast<std::ptrdiff_t>(dw.min.y) * w;
    auto base = [&](float* p) { return reinterpret_cast<char*>(p + origin); };
    for (int c = 0; c < 5; ++c)
      fb.insert(
          ParamTexture::channel_names[c],
          Imf::Slice(Imf::FLOAT, base(t.channel[static_cast<std::size_t>(c)].data()), xs, ys));
    fb.insert("valid", Imf::Slice(Imf::FLOAT, base(valid.data()), xs, ys, 1, 1, 1.0));
    file.setFrameBuffer(fb);
    file.readPixels(dw.min.y, dw.max.y);
    t.valid.resize(t.size());
    t.why_invalid.assign(t.size(), "");
    for (std::size_t i = 0; i < t.size(); ++i) {
      bool ok = valid[i] > 0.5f;
      for (const auto& c : t.channel) ok = ok && std::isfinite(c[i]);
      t.valid[i] = ok ? 1 : 0;
      if (!ok) t.why_invalid[i] = valid[i] > 0.5f ? "non-finite parameter in file" : "invalid";
    }
    if (const auto* a = h.findTypedAttribute<Imf::StringAttribute>(kAttr)) {
      const auto j = parse_json_text(a->value(), path + " (" + kAttr + " attribute)");
      t.texel_m = j.value("texel_m", 0.0);
      t.meta = j.value("meta", nlohmann::json::object());
      if (j.contains("why_invalid"))
        for (const auto& e : j.at("why_invalid")) {
          const auto i = e.at(0).get<std::size_t>();
          if (i < t.size() && !t.valid[i]) t.why_invalid[i] = e.at(1).get<std::string>();
        }
    } else {
      t.meta = nlohmann::json::object();
    }
  } catch (const FileError&) {
    throw;
  } catch (const std::bad_alloc&) {
    throw FileError(path, "out of memory reading the parameter texture (--max-memory)");
  } catch (const std::exception& e) {
    throw FileError(path, std::string("cannot read parameter texture: ") + e.what());
  }
  if (!(t.texel_m > 0))
    throw FileError(
        path, "parameter texture has no texel size (header attribute " + std::string(kAttr) + ")");
  return t;
}

void write_param_preview(const ParamTexture& t, const std::string& path, std::size_t max_panel) {
  if (t.size() == 0) throw FileError(path, "cannot preview an empty parameter texture");
  // Panel size: nearest-texel resampling so that the long side is max_panel pixels (small
  // exemplars are enlarged, large textures reduced).
  const double longest = static_cast<double>(std::max(t.nx, t.ny));
  const double scale = static_cast<double>(std::max<std::size_t>(max_panel, 16)) / longest;
  const auto pw = std::max<std::size_t>(1, static_cast<std::size_t>(t.nx * scale));
  const auto ph = std::max<std::size_t>(1, static_cast<std::size_t>(t.ny * scale));
  const int ts = 2;
  const std::size_t gap = 8, label = detail::text_height(ts) * 2 + 12;
  const std::size_t panel_w = std::max<std::size_t>(pw, 40 * ts);
  RgbImage img(6 * panel_w + 7 * gap, ph + label + 2 * gap);
  std::fill(img.pixels.begin(), img.pixels.end(), 255);
  for (int c = 0; c < 6; ++c) {
    double lo = 0, hi = 1;
    if (c < 5) {
      std::vector<float> v;
      for (std::size_t i = 0; i < t.size(); ++i)
        if (t.valid[i]) v.push_back(t.channel[static_cast<std::size_t>(c)][i]);
      if (!v.empty()) {
        std::sort(v.begin(), v.end());
        lo = v[static_cast<std::size_t>(0.01 * static_cast<double>(v.size() - 1))];
        hi = v[static_cast<std::size_t>(0.99 * static_cast<double>(v.size() - 1))];
        if (!(hi > lo)) hi = lo + 1e-12;
      }
    }
    const std::size_t x0 = gap + static_cast<std::size_t>(c) * (panel_w + gap), y0 = gap;
    for (std::size_t py = 0; py < ph; ++py)
      for (std::size_t px = 0; px < pw; ++px) {
        const std::size_t ix = std::min(t.nx - 1, static_cast<std::size_t>(px / scale));
        const std::size_t iy = std::min(t.ny - 1, static_cast<std::size_t>(py / scale));
        const std::size_t i = ix + t.nx * iy;
        std::uint8_t rgb[3] = {128, 128, 128};
        if (c == 5) {
          if (t.valid[i])
            rgb[0] = rgb[1] = rgb[2] = 235;
          else
            rgb[0] = 220, rgb[1] = 40, rgb[2] = 40;
        } else if (t.valid[i]) {
          false_colour(
              std::clamp((t.channel[static_cast<std::size_t>(c)][i] - lo) / (hi - lo), 0.0, 1.0),
              rgb);
        }
        img.set(x0 + px, y0 + py, rgb[0], rgb[1], rgb[2]);
      }
    // Labels: the channel number (the font has digits only) and the range.
    char line[64];
    if (c < 5)
      std::snprintf(line, sizeof line, "%d %.3g/%.3g", c + 1, lo, hi);
    else
      std::snprintf(line, sizeof line, "%zu/%zu", t.valid_count(), t.size());
    detail::draw_text(img, x0, y0 + ph + 6, line, ts);
  }
  write_png(path, img);
}

}  // namespace microbrdf

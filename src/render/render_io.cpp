// Scene names and render outputs (EXR, tone-mapped PNG).
#include <Imath/half.h>
#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFloatAttribute.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfOutputFile.h>
#include <OpenEXR/ImfStringAttribute.h>

#include <cmath>

#include "core/npy.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/image.hpp"
#include "microbrdf/render.hpp"
#include "microbrdf/spectrum.hpp"

namespace microbrdf {
namespace {

struct SceneName {
  PreviewScene s;
  const char* name;
};
constexpr SceneName kScenes[] = {{PreviewScene::Cylinders, "cylinders"},
                                 {PreviewScene::Plate, "plate"},
                                 {PreviewScene::Sphere, "sphere"},
                                 {PreviewScene::Vase, "vase"},
                                 {PreviewScene::Obj, "obj"},
                                 {PreviewScene::FurnaceSphere, "furnace_sphere"}};

}  // namespace

PreviewScene parse_preview_scene(const std::string& name) {
  std::string all;
  for (const auto& s : kScenes) {
    if (name == s.name) return s.s;
    all += std::string(all.empty() ? "" : ", ") + s.name;
  }
  throw InputError("unknown scene '" + name + "' (known: " + all + ")");
}

std::string preview_scene_name(PreviewScene s) {
  for (const auto& k : kScenes)
    if (k.s == s) return k.name;
  return "unknown";
}

void write_render_exr(const RenderImage& img, const std::string& path) {
  if (img.width <= 0 || img.height <= 0 ||
      img.rgb.size() != std::size_t(img.width) * img.height * 3)
    throw FileError(path, "cannot write an empty or inconsistent image");
  const std::size_t npx = std::size_t(img.width) * img.height;
  std::vector<Imath::half> buf(npx * 3);
  for (std::size_t i = 0; i < npx * 3; ++i) {
    const float v = img.rgb[i];
    buf[i] = Imath::half(std::isfinite(v) ? std::clamp(v, -65000.0f, 65000.0f) : 0.0f);
  }
  AtomicFile out(path);
  try {
    Imf::Header h(img.width, img.height);
    h.channels().insert("R", Imf::Channel(Imf::HALF));
    h.channels().insert("G", Imf::Channel(Imf::HALF));
    h.channels().insert("B", Imf::Channel(Imf::HALF));
    h.insert("comments",
             Imf::StringAttribute("microbrdf render: linear sRGB (D65), " + img.settings));
    h.insert("microbrdf_seconds", Imf::FloatAttribute(float(img.seconds)));
    Imf::OutputFile f(out.temp_path().c_str(), h);
    Imf::FrameBuffer fb;
    const char* names[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; ++c)
      fb.insert(names[c], Imf::Slice(Imf::HALF, reinterpret_cast<char*>(buf.data() + c),
                                     3 * sizeof(Imath::half),
                                     std::size_t(img.width) * 3 * sizeof(Imath::half)));
    f.setFrameBuffer(fb);
    f.writePixels(img.height);
  } catch (const std::exception& e) {
    throw FileError(path, std::string("exr write failed: ") + e.what());
  }
  out.commit();
}

void write_render_npy(const RenderImage& img, const std::string& path) {
  if (img.width <= 0 || img.height <= 0 ||
      img.rgb.size() != std::size_t(img.width) * img.height * 3)
    throw FileError(path, "cannot write an empty or inconsistent image");
  const std::vector<double> values(img.rgb.begin(), img.rgb.end());
  std::vector<std::uint8_t> bytes;
  try {
    // (layers, rows, cols) = (height, width, channel): the layout of img.rgb.
    // (always 3-D: an image one pixel high is (1, width, 3), as documented)
    bytes =
        detail::encode_npy_f64(values, std::size_t(img.width), 3, std::size_t(img.height), true);
  } catch (const std::exception& e) {
    throw FileError(path, e.what());
  }
  write_file_atomic(path, bytes);
}

void write_render_png(const RenderImage& img, const std::string& path, double exposure_stops) {
  if (img.width <= 0 || img.height <= 0 ||
      img.rgb.size() != std::size_t(img.width) * img.height * 3)
    throw FileError(path, "cannot write an empty or inconsistent image");
  RgbImage out(img.width, img.height);
  const double scale = std::exp2(exposure_stops);
  for (std::size_t i = 0; i < std::size_t(img.width) * img.height; ++i) {
    const Eigen::Vector3d c(img.rgb[3 * i], img.rgb[3 * i + 1], img.rgb[3 * i + 2]);
    const auto p =
        linear_srgb_to_srgb8(c.allFinite() ? Eigen::Vector3d(c * scale) : Eigen::Vector3d::Zero());
    out.pixels[3 * i] = p[0];
    out.pixels[3 * i + 1] = p[1];
    out.pixels[3 * i + 2] = p[2];
  }
  write_png(path, out);
}

}  // namespace microbrdf

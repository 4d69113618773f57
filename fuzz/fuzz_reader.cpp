// libFuzzer target for one binary reader; the format is chosen at compile time
// (-DFUZZ_FORMAT=X3p, ...), so every reader shares this one harness.
// A reader may reject input only with FileError or InputError; anything else (a crash, an
// ASan/UBSan report, a leak, a hang, another exception) is a bug.
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <span>
#include <string>
#include <vector>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/memory_budget.hpp"
#include "microbrdf/microscene.hpp"
#include "microbrdf/ndf_io.hpp"
#include "microbrdf/sh_brdf.hpp"
#include "microbrdf/texture.hpp"
#include "render/envmap.hpp"

#ifdef FUZZ_PARAMTEX
namespace {
/// read_param_texture takes a path (OpenEXR opens the file itself): each input is written to one
/// scratch file per process, in /dev/shm when it exists.
const std::string& scratch_path() {
  // Leaked on purpose: the atexit handler runs after function-local statics are destroyed.
  static const std::string& path = *new std::string([] {
    std::string tmpl =
        (access("/dev/shm", W_OK) == 0 ? std::string("/dev/shm") : std::string(P_tmpdir)) +
        "/microbrdf-fuzz-paramtex-XXXXXX";
    const int fd = mkstemp(tmpl.data());
    if (fd < 0) std::abort();
    close(fd);
    std::atexit([] { std::remove(scratch_path().c_str()); });
    return tmpl;
  }());
  return path;
}
}  // namespace
#endif

#ifdef FUZZ_SIDECAR
namespace {
/// A scratch folder (in /dev/shm when it exists) holding a valid height map h.npy and NDF
/// table n.npy; each input becomes both of their JSON sidecars.
const std::string& scratch_dir() {
  // Leaked on purpose: the atexit handler below runs after function-local statics are
  // destroyed, so the path must outlive them.
  static const std::string& dir = *new std::string([] {
    std::string tmpl =
        (access("/dev/shm", W_OK) == 0 ? std::string("/dev/shm") : std::string(P_tmpdir)) +
        "/microbrdf-fuzz-sidecar-XXXXXX";
    if (!mkdtemp(tmpl.data())) std::abort();
    microbrdf::Surface s(8, 8, 1e-6, 1e-6);
    for (std::size_t i = 0; i < s.z.size(); ++i) s.z[i] = 1e-8 * double(i % 5);
    s.sync_mask();
    microbrdf::write_surface(s, tmpl + "/h.npy");
    microbrdf::TabulatedNdf ndf(9);
    for (double& v : ndf.values()) v = 1;
    ndf.clear_outside_disk();
    ndf.normalise();
    microbrdf::write_ndf(ndf, tmpl + "/n.npy");
    std::atexit([] {
      for (const char* f : {"/h.npy", "/h.json", "/n.npy", "/n.json", ""})
        std::remove((scratch_dir() + f).c_str());
    });
    return tmpl;
  }());
  return dir;
}
void write_scratch(const std::string& path, const std::uint8_t* data, std::size_t size) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) std::abort();
}
}  // namespace
#endif

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  // What a reader may allocate, as in a run with --max-memory 512M: a fuzzer input that asks
  // for more must be refused with a message, not grow to the fuzzer's RSS limit.
  microbrdf::set_memory_budget(std::uint64_t{512} << 20);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#if defined(FUZZ_SCENE)
  // A micro-scene JSON: parsed with the depth limit, interpreted (objects built, no tracing).
  try {
    const auto j = microbrdf::parse_json_text(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-scene.json", true);
    const auto d = microbrdf::parse_micro_scene(j, "/nonexistent-fuzz-dir", "fuzz-scene.json");
    if (!(d.width > 0) || !(d.height > 0)) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#elif defined(FUZZ_SIDECAR)
  // JSON sidecars: the spacing sidecar of a .npy height map and the metadata of an NDF table.
  const std::string& dir = scratch_dir();
  write_scratch(dir + "/h.json", data, size);
  write_scratch(dir + "/n.json", data, size);
  try {
    const auto s = microbrdf::read_surface(dir + "/h.npy");
    s.check();
    if (!(s.dx > 0) || !(s.dy > 0)) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  try {
    const auto ndf = microbrdf::read_ndf(dir + "/n.npy");
    if (ndf.resolution() != 9) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#elif defined(FUZZ_HDR)
  // The Radiance .hdr environment-map reader: what it accepts must be a consistent image.
  try {
    const std::vector<std::uint8_t> bytes(data, data + size);
    const auto img = microbrdf::pt::read_radiance_hdr_bytes(bytes, "fuzz-input");
    if (img.width <= 0 || img.height <= 0 ||
        img.rgb.size() != std::size_t(img.width) * std::size_t(img.height) * 3)
      __builtin_trap();
    for (float v : img.rgb)
      if (!(v >= 0) || !std::isfinite(v)) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#elif defined(FUZZ_PARAMTEX)
  // The ellipsoid parameter-texture EXR reader: what it accepts must be a consistent texture.
  {
    std::FILE* f = std::fopen(scratch_path().c_str(), "wb");
    if (!f || std::fwrite(data, 1, size, f) != size || std::fclose(f) != 0) std::abort();
  }
  (void)microbrdf::is_param_texture_file(scratch_path());  // never throws
  try {
    const auto t = microbrdf::read_param_texture(scratch_path());
    if (t.nx == 0 || t.ny == 0 || !(t.texel_m > 0) || t.valid.size() != t.size() ||
        t.why_invalid.size() != t.size())
      __builtin_trap();
    for (const auto& c : t.channel)
      if (c.size() != t.size()) __builtin_trap();
    for (std::size_t i = 0; i < t.size(); ++i)
      if (t.valid[i])
        for (const auto& c : t.channel)
          if (!std::isfinite(c[i])) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#elif defined(FUZZ_SHBRDF)
  // The .shbrdf reader (-DFUZZ_SHBRDF): whatever it accepts must evaluate to finite numbers.
  try {
    auto b = microbrdf::ShBrdf::load_bytes(std::span<const std::uint8_t>(data, size), "fuzz-input");
    const microbrdf::Vec3 wi(0.3, 0.1, 0.9), wo(-0.2, 0.4, 0.8);
    if (!std::isfinite(b.eval(wi, wo, 5e-7)) || !std::isfinite(b.albedo(wi))) __builtin_trap();
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#else
  microbrdf::ReadOptions opt;
  opt.dx = 1e-6;  // formats that store no spacing need one
  opt.dy = 1e-6;
  try {
    auto s =
        microbrdf::read_surface_bytes(std::span<const std::uint8_t>(data, size),
                                      microbrdf::SurfaceFormat::FUZZ_FORMAT, "fuzz-input", opt);
    s.check();  // whatever is accepted must be a consistent Surface
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
#endif
}

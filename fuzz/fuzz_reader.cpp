// libFuzzer target for one binary reader; the format is chosen at compile time
// (-DFUZZ_FORMAT=X3p, ...), so every reader shares this one harness.
// A reader may reject input only with FileError or InputError; anything else (a crash, an
// ASan/UBSan report, a leak, a hang, another exception) is a bug.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"
#include "microbrdf/sh_brdf.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
#ifdef FUZZ_SHBRDF
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

// libFuzzer target for one binary reader; the format is chosen at compile time
// (-DFUZZ_FORMAT=X3p, ...), so every reader shares this one harness.
// A reader may reject input only with FileError or InputError; anything else (a crash, an
// ASan/UBSan report, a leak, a hang, another exception) is a bug.
#include <cstddef>
#include <cstdint>
#include <span>

#include "microbrdf/error.hpp"
#include "microbrdf/io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
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
}

// libFuzzer targets for the measured-BRDF readers, chosen at compile time:
// -DFUZZ_MEASURED_BSDF (RGL tensor file + RglBrdf), -DFUZZ_MEASURED_MERL (MERL .binary),
// -DFUZZ_MEASURED_GONIO (goniometer CSV). A reader may reject input only with FileError or
// InputError; whatever it accepts must evaluate to finite, non-negative numbers.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "microbrdf/error.hpp"
#include "microbrdf/measured.hpp"
#include "microbrdf/rgl_bsdf.hpp"
#include "microbrdf/tensor_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  try {
#if defined(FUZZ_MEASURED_BSDF)
    const auto file = microbrdf::parse_tensor_file(bytes, "fuzz-input");
    for (const auto& f : file.fields)
      if (f.data.size() != f.count() * microbrdf::tensor_dtype_size(f.dtype)) __builtin_trap();
    const microbrdf::RglBrdf b(file, "fuzz-input");
    const microbrdf::Vec3 wi(0.3, 0.1, 0.948683), wo(-0.2, 0.4, 0.894427);
    const double v = b.eval(wi, wo, 550e-9), p = b.pdf(wi, wo);
    if (std::isnan(v) || std::isnan(p)) __builtin_trap();
    if (auto s = b.sample(wi, 0.37, 0.61, 550e-9))
      if (!(s->wo.z() > 0) || std::isnan(s->weight)) __builtin_trap();
#elif defined(FUZZ_MEASURED_MERL)
    const auto t = microbrdf::parse_merl(bytes, "fuzz-input");
    if (t.rgb.size() != 3 * microbrdf::MerlTable::kBins) __builtin_trap();
#elif defined(FUZZ_MEASURED_GONIO)
    const auto d = microbrdf::parse_gonio_csv(
        std::string_view(reinterpret_cast<const char*>(data), size), "fuzz-input");
    if (d.points.empty()) __builtin_trap();
    for (const auto& p : d.points)
      if (!std::isfinite(p.brdf) || !(p.wavelength_m > 0) || p.theta_i < 0 || p.theta_o < 0 ||
          p.theta_i > 1.5708 || p.theta_o > 1.5708)
        __builtin_trap();
#endif
  } catch (const microbrdf::FileError&) {
  } catch (const microbrdf::InputError&) {
  }
  return 0;
}

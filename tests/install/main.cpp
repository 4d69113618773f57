// Uses an installed microbrdf through its documented API: reads a height map, levels it with a
// plane and estimates its NDF (include/microbrdf/io.hpp, level.hpp, ndf_estimate.hpp), then
// prints what consumer.sh checks, one `key value` per line:
//   version        microbrdf::version() (the library actually loaded)
//   nx, ny         the scan's grid
//   integral       sum of D * Delta^2 over the table, Delta = 2 / (N - 1), computed here from the
//                  definition of a normalised table (docs/architecture.md), not by the library
//   slope_rms_x/y  rms slopes of the NDF (as `microbrdf ndf --json` reports them)
//   samples_used
#include <cstddef>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <microbrdf/io.hpp>
#include <microbrdf/level.hpp>
#include <microbrdf/ndf_estimate.hpp>
#include <microbrdf/version.hpp>
#include <numbers>

int main(int argc, char** argv) {
  const long resolution = argc == 3 ? std::atol(argv[2]) : 0;
  if (resolution < 3) {
    std::fprintf(stderr, "usage: consumer SCAN RESOLUTION (table nodes per side, >= 3)\n");
    return 2;
  }
  try {
    microbrdf::Surface s = microbrdf::read_surface(argv[1]);
    microbrdf::level_surface(s, microbrdf::LevelingSpec{});  // plane, as the CLI does by default
    microbrdf::NdfEstimateOptions options;
    options.method = microbrdf::NdfMethod::Naive;
    options.resolution = static_cast<std::size_t>(resolution);
    const microbrdf::TabulatedNdf ndf = microbrdf::estimate_ndf(s, options);

    const std::size_t n = options.resolution;
    const double delta = 2.0 / static_cast<double>(n - 1);
    double sum = 0;
    for (std::size_t iy = 0; iy < n; ++iy)
      for (std::size_t ix = 0; ix < n; ++ix) sum += ndf.at(ix, iy) * delta * delta;

    std::printf("version %s\n", microbrdf::version());
    std::printf("nx %zu\nny %zu\n", s.nx, s.ny);
    std::printf("integral %.9f\n", sum);
    std::printf("slope_rms_x %.9g\nslope_rms_y %.9g\n", ndf.rms_slope(0),
                ndf.rms_slope(std::numbers::pi / 2));
    std::printf("samples_used %zu\n", ndf.meta.samples_used);
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: error: %s\n", e.what());
    return 1;
  }
}

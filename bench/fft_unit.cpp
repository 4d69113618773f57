// `microbrdf_fft_unit NX NY [--threads T] [--r2c] [--phasor [--data DXxDY]] [--runs R]`: the honest
// FFT unit of docs/benchmarks.md ("Yardsticks", "Whole runs") as a process of its own, so that
// bench/whole_process.py can express whole command runs in it, measured in the same session.
//
// One 2-D FFT of NX x NY (NX along rows, contiguous) by FFTW itself: an FFTW_MEASURE plan made
// once (FFTW's threads = T, default 2), then R timed calls (default 30), each including the fill
// of the input, as bench/bench_kirchhoff.cpp's honest unit does:
//  - complex-to-complex (default): the copy of NX x NY precomputed complex samples into FFTW's
//    buffer (the cheapest fill there is: the unit of a whole `ndf` run on an NX x NY scan);
//  - complex-to-complex with --phasor: w exp(-i phi) on the first DX x DY samples (one sincos per
//    sample from precomputed phases and weights) and zeros on the rest, as the D_K unit of
//    bench_kirchhoff.cpp (a 640 x 480 tile: NX x NY = 1280 x 960, --data 640x480; default: all
//    samples);
//  - real-to-complex (--r2c): the copy of NX x NY heights into FFTW's buffer (the areal PSD's
//    unit).
// Prints one JSON object on stdout: best and median wall time in ms, the setup, the load
// average (/proc/loadavg) before and after. Usage errors exit 2.
#include <fftw3.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "bench_load.hpp"

namespace {

[[noreturn]] void usage(const std::string& problem) {
  std::fprintf(stderr,
               "microbrdf_fft_unit: error: %s\n"
               "usage: microbrdf_fft_unit NX NY [--threads T] [--r2c] [--phasor [--data DXxDY]] "
               "[--runs R]\n",
               problem.c_str());
  std::exit(2);
}

std::size_t count(const std::string& text, const std::string& what, std::size_t hi) {
  char* end = nullptr;
  const unsigned long long v = std::strtoull(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || text[0] == '-' || v < 1 || v > hi)
    usage(what + ": '" + text + "' is not a count in 1.." + std::to_string(hi));
  return static_cast<std::size_t>(v);
}

struct Args {
  std::size_t nx = 0, ny = 0, dx = 0, dy = 0, threads = 2, runs = 30;
  bool r2c = false, phasor = false;
};

Args parse(int argc, char** argv) {
  Args a;
  std::vector<std::string> pos;
  for (int i = 1; i < argc; ++i) {
    const std::string s = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) usage(s + " needs a value");
      return argv[++i];
    };
    if (s == "--threads")
      a.threads = count(value(), "--threads", 256);
    else if (s == "--runs")
      a.runs = count(value(), "--runs", 100000);
    else if (s == "--r2c")
      a.r2c = true;
    else if (s == "--phasor")
      a.phasor = true;
    else if (s == "--data") {
      const std::string v = value();
      const auto x = v.find('x');
      if (x == std::string::npos) usage("--data: '" + v + "' is not DXxDY");
      a.dx = count(v.substr(0, x), "--data", 1 << 20);
      a.dy = count(v.substr(x + 1), "--data", 1 << 20);
    } else if (!s.empty() && s[0] == '-')
      usage("unknown flag " + s);
    else
      pos.push_back(s);
  }
  if (pos.size() != 2) usage("expected NX NY");
  a.nx = count(pos[0], "NX", 1 << 16);
  a.ny = count(pos[1], "NY", 1 << 16);
  if (a.r2c && a.phasor) usage("--phasor applies to the c2c transform");
  if (a.dx != 0 && !a.phasor) usage("--data needs --phasor");
  if (a.dx == 0) a.dx = a.nx, a.dy = a.ny;
  if (a.dx > a.nx || a.dy > a.ny) usage("--data must fit inside NX x NY");
  return a;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int main(int argc, char** argv) {
  const Args a = parse(argc, argv);
  const double load0 = microbrdf::bench::load_average();
  fftw_init_threads();
  fftw_plan_with_nthreads(static_cast<int>(a.threads));
  const std::size_t n = a.nx * a.ny, nd = a.dx * a.dy;
  // The samples the fill reads: random phases (a rough surface's q_z h spans many radians) and
  // window weights, or heights for the r2c transform.
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  std::vector<double> phase(a.r2c ? n : nd), weight(a.phasor ? nd : 0);
  for (double& p : phase) p = u(rng);
  for (double& w : weight) w = 0.5 + u(rng) / 80;
  std::vector<double> samples(a.r2c || a.phasor ? 0 : 2 * n);  // re, im interleaved
  for (std::size_t i = 0; i < samples.size() / 2; ++i) {
    samples[2 * i] = std::cos(phase[i]);
    samples[2 * i + 1] = std::sin(phase[i]);
  }
  std::vector<double> times;
  const auto t_plan = std::chrono::steady_clock::now();
  double plan_ms = 0;
  if (a.r2c) {
    double* in = fftw_alloc_real(n);
    fftw_complex* out = fftw_alloc_complex(a.ny * (a.nx / 2 + 1));
    fftw_plan p =
        fftw_plan_dft_r2c_2d(static_cast<int>(a.ny), static_cast<int>(a.nx), in, out, FFTW_MEASURE);
    plan_ms = ms_since(t_plan);
    for (std::size_t r = 0; r < a.runs; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      std::copy(phase.begin(), phase.end(), in);
      fftw_execute(p);
      times.push_back(ms_since(t0));
    }
    fftw_destroy_plan(p);
    fftw_free(in);
    fftw_free(out);
  } else {
    fftw_complex* d = fftw_alloc_complex(n);
    fftw_plan p = fftw_plan_dft_2d(static_cast<int>(a.ny), static_cast<int>(a.nx), d, d,
                                   FFTW_FORWARD, FFTW_MEASURE);
    plan_ms = ms_since(t_plan);
    for (std::size_t r = 0; r < a.runs; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      if (!a.phasor) {
        std::memcpy(d, samples.data(), samples.size() * sizeof(double));
        fftw_execute(p);
        times.push_back(ms_since(t0));
        continue;
      }
      for (std::size_t y = 0; y < a.ny; ++y) {
        fftw_complex* row = d + y * a.nx;
        std::size_t x = 0;
        if (y < a.dy)
          for (; x < a.dx; ++x) {
            const double ph = phase[y * a.dx + x], w = weight[y * a.dx + x];
            row[x][0] = w * std::cos(ph);
            row[x][1] = -w * std::sin(ph);
          }
        for (; x < a.nx; ++x) row[x][0] = row[x][1] = 0.0;  // the zero padding
      }
      fftw_execute(p);
      times.push_back(ms_since(t0));
    }
    fftw_destroy_plan(p);
    fftw_free(d);
  }
  std::vector<double> sorted = times;
  std::sort(sorted.begin(), sorted.end());
  const std::size_t m = sorted.size();
  const double median = m % 2 ? sorted[m / 2] : 0.5 * (sorted[m / 2 - 1] + sorted[m / 2]);
  std::printf(
      "{\"transform\": \"%s\", \"fill\": \"%s\", \"nx\": %zu, \"ny\": %zu, \"data_nx\": %zu, "
      "\"data_ny\": %zu, "
      "\"threads\": %zu, \"runs\": %zu, \"plan\": \"FFTW_MEASURE\", \"plan_ms\": %.3f, "
      "\"best_ms\": %.4f, \"median_ms\": %.4f, \"fill_included\": true, \"load_before\": %.2f, "
      "\"load_after\": %.2f}\n",
      a.r2c ? "r2c" : "c2c",
      a.r2c      ? "copy of reals"
      : a.phasor ? "phasors, zero padding"
                 : "copy",
      a.nx, a.ny, a.dx, a.dy, a.threads, a.runs, plan_ms, sorted.front(), median, load0,
      microbrdf::bench::load_average());
  fftw_cleanup_threads();
  return 0;
}

// SSIM and RMS relative error of images (core/image_metrics.hpp).
#include "core/image_metrics.hpp"

#include <array>
#include <cmath>
#include <stdexcept>

namespace microbrdf::detail {

std::vector<double> luminance(const std::vector<float>& rgb) {
  std::vector<double> y(rgb.size() / 3);
  for (std::size_t i = 0; i < y.size(); ++i)
    y[i] = 0.2126 * rgb[3 * i] + 0.7152 * rgb[3 * i + 1] + 0.0722 * rgb[3 * i + 2];
  return y;
}

namespace {

// SSIM of one window from its weighted moments (Wang et al. 2004, eq. 13).
double ssim_of(double ma, double mb, double saa, double sbb, double sab, double c1, double c2) {
  return ((2 * ma * mb + c1) * (2 * sab + c2)) / ((ma * ma + mb * mb + c1) * (saa + sbb + c2));
}

}  // namespace

double ssim(const std::vector<double>& a, const std::vector<double>& b, std::size_t w,
            std::size_t h, double range) {
  if (w == 0 || h == 0 || a.size() != w * h || b.size() != w * h)
    throw std::invalid_argument("ssim: images of different or zero size");
  const double c1 = (0.01 * range) * (0.01 * range), c2 = (0.03 * range) * (0.03 * range);
  constexpr int kR = 5;  // 11 x 11 window
  if (w < 2 * kR + 1 || h < 2 * kR + 1) {
    double ma = 0, mb = 0;
    for (std::size_t i = 0; i < a.size(); ++i) ma += a[i], mb += b[i];
    ma /= a.size(), mb /= b.size();
    double saa = 0, sbb = 0, sab = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      saa += (a[i] - ma) * (a[i] - ma);
      sbb += (b[i] - mb) * (b[i] - mb);
      sab += (a[i] - ma) * (b[i] - mb);
    }
    const double n = static_cast<double>(a.size());
    return ssim_of(ma, mb, saa / n, sbb / n, sab / n, c1, c2);
  }
  // Separable Gaussian weights, sigma 1.5 px, normalised (the window of Wang et al.).
  std::array<double, 2 * kR + 1> g{};
  double sum = 0;
  for (int i = -kR; i <= kR; ++i) sum += g[i + kR] = std::exp(-0.5 * i * i / (1.5 * 1.5));
  for (double& x : g) x /= sum;
  double total = 0;
  std::size_t count = 0;
  for (std::size_t y = kR; y + kR < h; ++y)
    for (std::size_t x = kR; x + kR < w; ++x) {
      double ma = 0, mb = 0, saa = 0, sbb = 0, sab = 0;
      for (int dy = -kR; dy <= kR; ++dy)
        for (int dx = -kR; dx <= kR; ++dx) {
          const double wt = g[dy + kR] * g[dx + kR];
          const std::size_t i = (y + dy) * w + (x + dx);
          ma += wt * a[i];
          mb += wt * b[i];
          saa += wt * a[i] * a[i];
          sbb += wt * b[i] * b[i];
          sab += wt * a[i] * b[i];
        }
      total += ssim_of(ma, mb, saa - ma * ma, sbb - mb * mb, sab - ma * mb, c1, c2);
      ++count;
    }
  return total / static_cast<double>(count);
}

double rms_relative(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("rms_relative: images of different size");
  double num = 0, den = 0, aa = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    num += (a[i] - b[i]) * (a[i] - b[i]);
    den += b[i] * b[i];
    aa += a[i] * a[i];
  }
  if (den > 0) return std::sqrt(num / den);
  return a.empty() ? 0.0 : std::sqrt(aa / static_cast<double>(a.size()));
}

}  // namespace microbrdf::detail

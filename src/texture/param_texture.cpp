// ParamTexture basics: per-texel access, statistics, 1-D line spectra (texture.hpp).
#include <cmath>
#include <complex>
#include <limits>

#include "core/fft.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/texture.hpp"

namespace microbrdf {

EllipsoidParams ParamTexture::at(std::size_t ix, std::size_t iy) const {
  const std::size_t i = ix + nx * iy;
  return {channel[0][i], channel[1][i], channel[2][i], channel[3][i], channel[4][i]};
}

std::size_t ParamTexture::valid_count() const {
  std::size_t n = 0;
  for (auto v : valid) n += v != 0;
  return n;
}

EllipsoidParams ParamTexture::mean_valid() const {
  if (valid_count() == 0) return {};
  double m[5];
  for (int c = 0; c < 5; ++c) m[c] = channel_stats(*this, c).mean;
  return {m[0], m[1], m[2], m[3], m[4]};
}

ParamTexture ParamTexture::empty(std::size_t nx, std::size_t ny, double texel_m,
                                 const std::string& why) {
  ParamTexture t;
  t.nx = nx;
  t.ny = ny;
  t.texel_m = texel_m;
  for (auto& c : t.channel) c.assign(nx * ny, std::numeric_limits<float>::quiet_NaN());
  t.valid.assign(nx * ny, 0);
  t.why_invalid.assign(nx * ny, why);
  t.meta = nlohmann::json::object();
  return t;
}

ChannelStats channel_stats(const ParamTexture& t, int channel) {
  if (channel < 0 || channel > 4) throw InputError("channel index must be 0..4");
  ChannelStats s;
  s.min = std::numeric_limits<double>::infinity();
  s.max = -s.min;
  const auto& c = t.channel[static_cast<std::size_t>(channel)];
  // Two passes (mean, then centred squares): no cancellation for narrow, offset channels.
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t.valid[i]) {
      s.mean += c[i];
      ++s.count;
      s.min = std::min(s.min, static_cast<double>(c[i]));
      s.max = std::max(s.max, static_cast<double>(c[i]));
    }
  if (s.count == 0) return ChannelStats{};
  s.mean /= static_cast<double>(s.count);
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t.valid[i]) s.variance += (c[i] - s.mean) * (c[i] - s.mean);
  s.variance /= static_cast<double>(s.count);
  return s;
}

std::vector<double> line_power_spectrum(const ParamTexture& t, int channel, int axis) {
  if (axis != 0 && axis != 1) throw InputError("axis must be 0 (x) or 1 (y)");
  if (t.size() == 0) throw InputError("empty parameter texture");
  const ChannelStats st = channel_stats(t, channel);
  const auto& c = t.channel[static_cast<std::size_t>(channel)];
  // Lines along the chosen axis become rows of `a` (n long, lines of them).
  const std::size_t n = axis == 0 ? t.nx : t.ny, lines = axis == 0 ? t.ny : t.nx;
  std::vector<double> a(n * lines);
  for (std::size_t iy = 0; iy < t.ny; ++iy)
    for (std::size_t ix = 0; ix < t.nx; ++ix) {
      const std::size_t i = ix + t.nx * iy;
      const double v = t.valid[i] ? c[i] - st.mean : 0.0;
      if (axis == 0)
        a[ix + n * iy] = v;
      else
        a[iy + n * ix] = v;
    }
  // One 2-D transform: sum over the line-frequency of |X(k, l)|^2 = lines * sum over lines of
  // |X_line(k)|^2 (Parseval along the other axis).
  const auto spec = detail::fft2_r2c(n, lines, a);
  const std::size_t h = n / 2 + 1;
  std::vector<double> p(h, 0.0);
  for (std::size_t l = 0; l < lines; ++l)
    for (std::size_t k = 0; k < h; ++k) p[k] += std::norm(spec[l * h + k]);
  const double nn = static_cast<double>(n), ln = static_cast<double>(lines);
  for (std::size_t k = 0; k < h; ++k) {
    const bool twice = k > 0 && 2 * k != n;
    p[k] *= (twice ? 2.0 : 1.0) / (nn * nn * ln * ln);
  }
  return p;
}

}  // namespace microbrdf

#include "microbrdf/surface.hpp"

#include <stdexcept>
#include <string>

namespace microbrdf {

void SurfaceMetadata::set(const std::string& key, const std::string& value) {
  for (auto& kv : extra) {
    if (kv.first == key) {
      kv.second = value;
      return;
    }
  }
  extra.emplace_back(key, value);
}

std::string SurfaceMetadata::get(const std::string& key) const {
  for (const auto& kv : extra)
    if (kv.first == key) return kv.second;
  return {};
}

Surface::Surface(std::size_t nx_, std::size_t ny_, double dx_, double dy_)
    : nx(nx_), ny(ny_), dx(dx_), dy(dy_), z(nx_ * ny_, 0.0), valid(nx_ * ny_, 1) {}

void Surface::sync_mask() {
  if (valid.size() != z.size()) valid.assign(z.size(), 1);
  for (std::size_t i = 0; i < z.size(); ++i) {
    if (!std::isfinite(z[i]) || valid[i] == 0) invalidate(i);
  }
}

std::size_t Surface::valid_count() const {
  std::size_t n = 0;
  for (auto v : valid) n += v != 0;
  return n;
}

double Surface::valid_mean() const {
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < z.size(); ++i)
    if (valid[i]) {
      sum += z[i];
      ++n;
    }
  return n ? sum / static_cast<double>(n) : std::numeric_limits<double>::quiet_NaN();
}

double Surface::valid_fraction() const {
  return size() == 0 ? 0.0 : static_cast<double>(valid_count()) / static_cast<double>(size());
}

void Surface::check() const {
  if (z.size() != nx * ny || valid.size() != nx * ny)
    throw std::logic_error("Surface: data size does not match nx*ny");
  if (!(dx > 0) || !(dy > 0) || !std::isfinite(dx) || !std::isfinite(dy))
    throw std::logic_error("Surface: spacing must be positive and finite");
  for (std::size_t i = 0; i < z.size(); ++i) {
    if ((valid[i] != 0) != std::isfinite(z[i]))
      throw std::logic_error("Surface: mask and NaN disagree at sample " + std::to_string(i));
  }
}

}  // namespace microbrdf

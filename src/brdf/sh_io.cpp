// The .shbrdf file: magic "MBSHBRDF", uint32 LE header length, JSON header, then the symmetric
// coefficient matrix as size x size little-endian float64, row-major (see sh_brdf.hpp and
// docs/westin.md). The reader trusts nothing: every length is checked against the bytes present.
#include <bit>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>

#include "core/byte_reader.hpp"
#include "microbrdf/atomic_file.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_read.hpp"
#include "microbrdf/json_read.hpp"
#include "microbrdf/sh_basis.hpp"
#include "microbrdf/sh_brdf.hpp"

namespace microbrdf {
namespace {

constexpr char kMagic[8] = {'M', 'B', 'S', 'H', 'B', 'R', 'D', 'F'};
constexpr std::uint32_t kMaxHeader = 16u << 20;  // 16 MiB of JSON is more than any real header
constexpr double kMaxCoefficient = 1e30;
constexpr const char* kBasis =
    "real SH, Y_l0 = K P_l, Y_lm = sqrt2 K P_l^|m| cos(m phi) (m>0) / sin(|m| phi) (m<0), no "
    "Condon-Shortley phase, theta from n = +z, phi from +x; kept l + m odd, ordered by l^2+l+m";
constexpr const char* kQuantity = "rho cos(theta_i) cos(theta_o), odd completion in z";

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}

}  // namespace

std::vector<std::uint8_t> ShBrdf::to_bytes() const {
  nlohmann::json h = {{"format", "microbrdf-shbrdf"},
                      {"version", 1},
                      {"lmax", lmax()},
                      {"size", basis_.size()},
                      {"basis", kBasis},
                      {"quantity", kQuantity},
                      {"dtype", "<f8"},
                      {"order", "row-major"},
                      {"meta", meta_}};
  const std::string hs = h.dump();
  std::vector<std::uint8_t> out(kMagic, kMagic + 8);
  put_u32(out, static_cast<std::uint32_t>(hs.size()));
  out.insert(out.end(), hs.begin(), hs.end());
  const int n = basis_.size();
  out.reserve(out.size() + static_cast<std::size_t>(n) * n * 8);
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      std::uint64_t bits = std::bit_cast<std::uint64_t>(m_(r, c));
      for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(bits >> (8 * i)));
    }
  return out;
}

void ShBrdf::save(const std::string& path) const { write_file_atomic(path, to_bytes()); }

ShBrdf ShBrdf::load_bytes(std::span<const std::uint8_t> bytes, const std::string& name) {
  detail::ByteReader r(bytes, name);
  r.require(0, 12, "magic and header length");
  if (std::memcmp(bytes.data(), kMagic, 8) != 0)
    r.fail("not a .shbrdf file (magic 'MBSHBRDF' missing)");
  const auto hlen = r.le<std::uint32_t>(8, "header length");
  if (hlen > kMaxHeader) r.fail("corrupt: JSON header length " + std::to_string(hlen));
  auto hb = r.bytes(12, hlen, "JSON header");
  // Depth-limited: the header's "meta" is copied into the BRDF.
  nlohmann::json h =
      parse_json_text(std::string_view(reinterpret_cast<const char*>(hb.data()), hb.size()), name);
  if (!h.is_object()) r.fail("corrupt: the JSON header is not an object");
  auto get_int = [&](const char* key) -> long long {
    auto it = h.find(key);
    if (it == h.end() || !it->is_number_integer())
      r.fail(std::string("header lacks the integer '") + key + "'");
    return it->get<long long>();
  };
  auto fmt = h.find("format");
  if (fmt == h.end() || !fmt->is_string() || fmt->get<std::string>() != "microbrdf-shbrdf")
    r.fail("header 'format' is not microbrdf-shbrdf");
  if (get_int("version") != 1)
    r.fail("unsupported version " + std::to_string(get_int("version")) + " (this reader: 1)");
  const long long lmax = get_int("lmax"), size = get_int("size");
  if (lmax < 1 || lmax > kShMaxL) r.fail("lmax " + std::to_string(lmax) + " out of range");
  if (size != lmax * (lmax + 1) / 2)
    r.fail("size " + std::to_string(size) + " does not match lmax " + std::to_string(lmax));
  if (auto dt = h.find("dtype");
      dt != h.end() && (!dt->is_string() || dt->get<std::string>() != "<f8"))
    r.fail("dtype must be <f8");
  const std::size_t n = static_cast<std::size_t>(size), off = 12 + std::size_t{hlen};
  const std::size_t need = n * n * 8;
  if (bytes.size() - off != need)
    r.fail("truncated or corrupt: " + std::to_string(n) + " x " + std::to_string(n) +
           " coefficients need " + std::to_string(need) + " bytes after the header, found " +
           std::to_string(bytes.size() - off));
  Eigen::MatrixXd m(n, n);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j) {
      const double v = r.le<double>(off + 8 * (i * n + j), "coefficient");
      if (!std::isfinite(v))
        r.fail("non-finite coefficient at (" + std::to_string(i) + ", " + std::to_string(j) + ")");
      // No BRDF has coefficients near 1e100 (a delta-like lobe of solid angle 1e-12 sr is
      // ~1e12); bounding them keeps every sum the evaluation makes finite.
      if (std::abs(v) > 1e100) {
        char num[32];
        std::snprintf(num, sizeof num, "%.3g", v);
        r.fail("coefficient at (" + std::to_string(i) + ", " + std::to_string(j) + ") is " + num +
               ", beyond any BRDF (|c| <= 1e100)");
      }
      m(i, j) = v;
    }
  auto mt = h.find("meta");
  nlohmann::json meta = mt != h.end() ? *mt : nlohmann::json::object();
  if (!meta.is_object()) meta = nlohmann::json::object({{"value", meta}});
  return ShBrdf(static_cast<int>(lmax), m, std::move(meta));
}

ShBrdf ShBrdf::load(const std::string& path) {
  // A regular file (a FIFO would block), checked against the memory budget.
  return load_bytes(read_file_bytes(path, std::uint64_t{1} << 34), path);
}

}  // namespace microbrdf

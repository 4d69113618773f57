// OpenGPS / ISO 5436-2 / ISO 25178-72 `.x3p` reader and writer.
//
// An x3p file is a ZIP archive holding main.xml (the description), md5checksum.hex (MD5 of
// main.xml), the binary heights (conventionally bindata/data.bin) and optionally a validity bit
// array (bindata/valid.bin). See docs/formats.md §1 for the layout and the real-world
// deviations handled here (main.xml in a subfolder, ISO5436 root without namespace, +Inf for
// invalid points, upper-case MD5, empty <Offset/>).
//
// Hostile input: every size in main.xml is checked against the archive's member sizes before
// anything is allocated, members with an implausible compression ratio (zip bombs) are refused,
// and exactly the bytes the grid needs are read. All libzip / pugixml / OpenSSL resources are
// owned by RAII wrappers.
#include <openssl/evp.h>
#include <zip.h>

#include <algorithm>
#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <limits>
#include <memory>
#include <optional>
#include <pugixml.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/memory_budget.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr const char* kNamespace = "http://www.opengps.eu/2008/ISO5436_2";
/// main.xml larger than this is refused (inline DataLists of a few million points fit).
constexpr std::uint64_t kMaxXmlBytes = std::uint64_t{256} << 20;
/// Deflate cannot expand more than ~1032:1; anything claiming more is corrupt or a zip bomb.
constexpr std::uint64_t kMaxRatio = 1100;
constexpr std::uint64_t kRatioSlack = 64 * 1024;

// ---------------------------------------------------------------- small helpers

std::string_view trim(std::string_view s) {
  const char* ws = " \t\r\n\v\f";
  auto b = s.find_first_not_of(ws);
  if (b == std::string_view::npos) return {};
  auto e = s.find_last_not_of(ws);
  return s.substr(b, e - b + 1);
}

std::string lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

/// Quotes a value from the file for an error message, shortened and without control characters.
std::string quote(std::string_view s) {
  std::string out = "'";
  for (std::size_t i = 0; i < s.size() && i < 60; ++i) {
    unsigned char c = static_cast<unsigned char>(s[i]);
    out += (c < 32 || c == 127) ? '?' : static_cast<char>(c);
  }
  if (s.size() > 60) out += "...";
  return out + "'";
}

std::optional<double> parse_double(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  double v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

std::optional<std::uint64_t> parse_uint(std::string_view s) {
  s = trim(s);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  if (s.empty()) return std::nullopt;
  std::uint64_t v = 0;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || p != s.data() + s.size()) return std::nullopt;
  return v;
}

std::string md5_hex(const std::uint8_t* data, std::size_t n) {
  unsigned char md[EVP_MAX_MD_SIZE];
  unsigned int len = 0;
  if (EVP_Digest(data, n, md, &len, EVP_md5(), nullptr) != 1) return {};
  static const char* hex = "0123456789abcdef";
  std::string out;
  for (unsigned int i = 0; i < len; ++i) {
    out += hex[md[i] >> 4];
    out += hex[md[i] & 15];
  }
  return out;
}

template <class T>
T load_le(const std::uint8_t* p) {
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
  T v;
  std::memcpy(&v, b, sizeof(T));
  return v;
}

template <class T>
void store_le(std::uint8_t* p, T v) {
  std::uint8_t b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));
  if constexpr (std::endian::native == std::endian::big) std::reverse(b, b + sizeof(T));
  std::memcpy(p, b, sizeof(T));
}

/// Shortest text that reads back as exactly the same double.
std::string format_double(double v) {
  char buf[64];
  auto [p, ec] = std::to_chars(buf, buf + sizeof(buf), v);
  return ec == std::errc() ? std::string(buf, p) : std::string("0");
}

// ---------------------------------------------------------------- XML helpers

std::string_view local_name(const char* n) {
  std::string_view s(n);
  auto p = s.rfind(':');
  return p == std::string_view::npos ? s : s.substr(p + 1);
}

/// First element child whose local name (namespace prefix ignored) is `name`.
pugi::xml_node child(pugi::xml_node n, std::string_view name) {
  if (!n) return {};
  for (auto c : n.children())
    if (c.type() == pugi::node_element && local_name(c.name()) == name) return c;
  return {};
}

std::string text(pugi::xml_node n) { return std::string(trim(n.text().get())); }

// ---------------------------------------------------------------- libzip RAII

struct ZipError {
  zip_error_t e;
  ZipError() { zip_error_init(&e); }
  ~ZipError() { zip_error_fini(&e); }
  ZipError(const ZipError&) = delete;
  ZipError& operator=(const ZipError&) = delete;
};
struct ArchiveDiscard {
  void operator()(zip_t* z) const { zip_discard(z); }
};
using ArchivePtr = std::unique_ptr<zip_t, ArchiveDiscard>;
struct FileClose {
  void operator()(zip_file_t* f) const { zip_fclose(f); }
};
using ZipFilePtr = std::unique_ptr<zip_file_t, FileClose>;
struct SourceFree {
  void operator()(zip_source_t* s) const { zip_source_free(s); }
};
using SourcePtr = std::unique_ptr<zip_source_t, SourceFree>;

/// A read-only archive opened from memory, with its member names.
class Archive {
 public:
  Archive(Bytes data, const ByteReader& r) : r_(r), archive_bytes_(data.size()) {
    ZipError err;
    SourcePtr src(
        zip_source_buffer_create(data.empty() ? nullptr : data.data(), data.size(), 0, &err.e));
    if (!src) r.fail(std::string("x3p: cannot read the archive: ") + zip_error_strerror(&err.e));
    zip_t* z = zip_open_from_source(src.get(), ZIP_RDONLY, &err.e);
    if (!z) {
      r.fail(std::string("not a valid x3p file (the ZIP container cannot be opened: ") +
             zip_error_strerror(&err.e) + ")");
    }
    src.release();  // the archive owns the source now
    za_.reset(z);
    zip_int64_t n = zip_get_num_entries(z, 0);
    if (n < 0) r.fail("x3p: cannot list the archive");
    names_.reserve(static_cast<std::size_t>(n));
    for (zip_int64_t i = 0; i < n; ++i) {
      const char* nm = zip_get_name(z, static_cast<zip_uint64_t>(i), 0);
      names_.emplace_back(nm ? nm : "");
    }
  }

  const std::vector<std::string>& names() const { return names_; }

  /// Index of the member at `path` (exact, then case-insensitive), or -1.
  std::int64_t find(const std::string& path) const {
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (names_[i] == path) return static_cast<std::int64_t>(i);
    std::string lp = lower(path);
    for (std::size_t i = 0; i < names_.size(); ++i)
      if (lower(names_[i]) == lp) return static_cast<std::int64_t>(i);
    return -1;
  }

  /// Uncompressed size of member `idx`, after checking it is plausible for this archive.
  std::uint64_t size(std::size_t idx) const {
    zip_stat_t st;
    zip_stat_init(&st);
    if (zip_stat_index(za_.get(), idx, 0, &st) != 0 || !(st.valid & ZIP_STAT_SIZE))
      r_.fail("x3p: cannot read the ZIP entry of '" + names_[idx] + "'");
    std::uint64_t comp = archive_bytes_;
    if (st.valid & ZIP_STAT_COMP_SIZE) {
      if (st.comp_size > archive_bytes_)
        r_.fail("corrupt ZIP entry: '" + names_[idx] + "' claims " + std::to_string(st.comp_size) +
                " compressed bytes but the archive has only " + std::to_string(archive_bytes_));
      comp = st.comp_size;
    }
    if (st.size > comp * kMaxRatio + kRatioSlack)
      r_.fail("refusing ZIP entry '" + names_[idx] + "': it claims " + std::to_string(st.size) +
              " bytes from " + std::to_string(comp) +
              " compressed bytes, an implausible ratio (corrupt file or zip bomb)");
    return st.size;
  }

  /// Reads exactly `n` bytes of member `idx` (whose size the caller has checked) and verifies
  /// that the member ends there (which also makes libzip check its CRC).
  std::vector<std::uint8_t> read(std::size_t idx, std::uint64_t n) const {
    ZipFilePtr f(zip_fopen_index(za_.get(), idx, 0));
    if (!f)
      r_.fail("x3p: cannot open '" + names_[idx] + "' in the archive: " + zip_strerror(za_.get()));
    std::vector<std::uint8_t> buf(static_cast<std::size_t>(n));
    std::uint64_t got = 0;
    while (got < n) {
      std::uint64_t want = std::min<std::uint64_t>(n - got, std::uint64_t{1} << 30);
      zip_int64_t k = zip_fread(f.get(), buf.data() + got, want);
      if (k < 0) r_.fail("x3p: cannot read '" + names_[idx] + "': " + zip_file_strerror(f.get()));
      if (k == 0)
        r_.fail("truncated x3p: '" + names_[idx] + "' ends after " + std::to_string(got) + " of " +
                std::to_string(n) + " bytes");
      got += static_cast<std::uint64_t>(k);
    }
    std::uint8_t extra = 0;
    zip_int64_t k = zip_fread(f.get(), &extra, 1);
    if (k < 0) r_.fail("corrupt x3p: '" + names_[idx] + "': " + zip_file_strerror(f.get()));
    if (k > 0) r_.fail("corrupt x3p: '" + names_[idx] + "' is longer than its ZIP entry says");
    return buf;
  }

 private:
  const ByteReader& r_;
  std::uint64_t archive_bytes_;
  ArchivePtr za_;
  std::vector<std::string> names_;
};

// ---------------------------------------------------------------- reader pieces

enum class ZType { I16, I32, F32, F64 };

std::size_t type_size(ZType t) {
  switch (t) {
    case ZType::I16:
      return 2;
    case ZType::I32:
    case ZType::F32:
      return 4;
    case ZType::F64:
      return 8;
  }
  return 8;
}

const char* type_letter(ZType t) {
  switch (t) {
    case ZType::I16:
      return "I (int16)";
    case ZType::I32:
      return "L (int32)";
    case ZType::F32:
      return "F (float32)";
    case ZType::F64:
      return "D (float64)";
  }
  return "?";
}

struct Axis {
  double increment = 1;
  double offset = 0;
  bool has_increment = false;
};

/// Increment and Offset of one axis; empty elements take the defaults (1 and 0).
Axis read_axis(const ByteReader& r, pugi::xml_node axis, const char* name) {
  Axis a;
  if (auto inc = child(axis, "Increment")) {
    std::string t = text(inc);
    if (!t.empty()) {
      auto v = parse_double(t);
      if (!v || !std::isfinite(*v))
        r.fail(std::string("x3p main.xml: ") + name + "/Increment " + quote(t) +
               " is not a finite number");
      a.increment = *v;
      a.has_increment = true;
    }
  }
  if (auto off = child(axis, "Offset")) {
    std::string t = text(off);
    if (!t.empty()) {
      auto v = parse_double(t);
      if (!v || !std::isfinite(*v))
        r.fail(std::string("x3p main.xml: ") + name + "/Offset " + quote(t) +
               " is not a finite number");
      a.offset = *v;
    }
  }
  return a;
}

std::uint64_t read_size(const ByteReader& r, pugi::xml_node dim, const char* name, bool required) {
  auto n = child(dim, name);
  if (!n) {
    if (required) r.fail(std::string("x3p main.xml: MatrixDimension has no ") + name);
    return 1;
  }
  std::string t = text(n);
  auto v = parse_uint(t);
  if (!v)
    r.fail(std::string("x3p main.xml: MatrixDimension/") + name + " " + quote(t) +
           " is not a non-negative integer");
  return *v;
}

void add_md5_warning(Surface& s, const std::string& w) {
  std::string prev = s.meta.get("md5_warning");
  s.meta.set("md5_warning", prev.empty() ? w : prev + "; " + w);
}

/// Compares a stored MD5 (any case, surrounding blanks) with the digest of `bytes`.
void check_md5(Surface& s, const std::string& stored, const std::vector<std::uint8_t>& bytes,
               const std::string& member) {
  if (stored.empty()) return;
  std::string actual = md5_hex(bytes.data(), bytes.size());
  if (actual.empty()) return;  // MD5 unavailable (e.g. FIPS mode): nothing to compare
  if (lower(stored) != actual)
    add_md5_warning(s, "MD5 of " + member + " is " + actual + ", main.xml says " + stored);
}

}  // namespace

// ================================================================= reader

Surface read_x3p(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  Archive zip(data, r);

  // main.xml: at the root, else in a subfolder (not macOS resource-fork junk); shallowest wins.
  std::int64_t main_idx = -1;
  std::size_t main_depth = 0;
  for (std::size_t i = 0; i < zip.names().size(); ++i) {
    const std::string& n = zip.names()[i];
    bool is_main = n == "main.xml" || (n.size() > 9 && n.ends_with("/main.xml"));
    if (!is_main || n.starts_with("__MACOSX/") || n.find("/__MACOSX/") != std::string::npos)
      continue;
    std::size_t depth = static_cast<std::size_t>(std::count(n.begin(), n.end(), '/'));
    if (main_idx < 0 || depth < main_depth) {
      main_idx = static_cast<std::int64_t>(i);
      main_depth = depth;
    }
  }
  if (main_idx < 0) r.fail("not an x3p file: the archive has no main.xml");
  const std::string main_path = zip.names()[static_cast<std::size_t>(main_idx)];
  const std::string base = main_path.substr(0, main_path.size() - 8);  // folder, with '/'

  std::uint64_t xml_size = zip.size(static_cast<std::size_t>(main_idx));
  if (xml_size > kMaxXmlBytes)
    r.fail("x3p: main.xml is " + std::to_string(xml_size) + " bytes, over the limit of " +
           std::to_string(kMaxXmlBytes));
  // pugixml's tree takes about eight times the text (a node per empty <Datum/>).
  check_expansion(name, data.size(), mul_sat(xml_size, 10), "main.xml and its document tree");
  std::vector<std::uint8_t> xml = zip.read(static_cast<std::size_t>(main_idx), xml_size);

  pugi::xml_document doc;
  pugi::xml_parse_result pr = doc.load_buffer(xml.data(), xml.size());
  if (!pr)
    r.fail(std::string("x3p: main.xml is not well-formed XML (") + pr.description() + " at byte " +
           std::to_string(pr.offset) + ")");
  pugi::xml_node root = doc.document_element();
  std::string_view root_name = local_name(root.name());
  if (root_name != "ISO5436_2" && root_name != "ISO5436")
    r.fail("x3p main.xml: root element is " + quote(root.name()) + ", expected ISO5436_2");

  // ---- Record1: feature type and axes
  pugi::xml_node rec1 = child(root, "Record1");
  if (!rec1) r.fail("x3p main.xml: Record1 is missing");
  std::string feature = text(child(rec1, "FeatureType"));
  if (feature == "PCL")
    r.fail(
        "x3p: FeatureType PCL (point cloud) is not supported; only SUR (areal) and PRF "
        "(profile) files can be read");
  if (feature != "SUR" && feature != "PRF")
    r.fail("x3p main.xml: FeatureType " + quote(feature) + " is not SUR, PRF or PCL");
  pugi::xml_node axes = child(rec1, "Axes");
  pugi::xml_node cx = child(axes, "CX"), cy = child(axes, "CY"), cz = child(axes, "CZ");
  if (!cx || !cz || (!cy && feature == "SUR"))
    r.fail("x3p main.xml: Record1/Axes must contain CX, CY and CZ");
  for (auto [node, nm] : {std::pair{cx, "CX"}, std::pair{cy, "CY"}}) {
    if (!node) continue;
    std::string t = text(child(node, "AxisType"));
    if (!t.empty() && t != "I")
      r.fail(std::string("x3p: ") + nm + " AxisType " + quote(t) +
             " is not supported (only incremental x/y grids can be read)");
  }
  Axis ax = read_axis(r, cx, "CX");
  Axis ay = cy ? read_axis(r, cy, "CY") : Axis{};
  Axis az = read_axis(r, cz, "CZ");
  if (!ax.has_increment || !(ax.increment > 0))
    r.fail("x3p main.xml: CX/Increment (the x spacing) is missing or not positive");
  if (feature == "PRF" && !(ay.has_increment && ay.increment > 0)) {
    ay.increment = ax.increment;
    ay.has_increment = true;
  }
  if (!ay.has_increment || !(ay.increment > 0))
    r.fail("x3p main.xml: CY/Increment (the y spacing) is missing or not positive");

  std::string zt = text(child(cz, "DataType"));
  ZType ztype;
  if (zt == "I")
    ztype = ZType::I16;
  else if (zt == "L")
    ztype = ZType::I32;
  else if (zt == "F")
    ztype = ZType::F32;
  else if (zt == "D")
    ztype = ZType::F64;
  else
    r.fail("x3p main.xml: CZ/DataType " + quote(zt) + " is not one of I, L, F, D");

  // ---- Record3: grid and data
  pugi::xml_node rec3 = child(root, "Record3");
  if (!rec3) r.fail("x3p main.xml: Record3 is missing");
  pugi::xml_node dim = child(rec3, "MatrixDimension");
  if (!dim) {
    if (child(rec3, "ListDimension"))
      r.fail("x3p: ListDimension (unordered point lists) is not supported; only matrix data");
    r.fail("x3p main.xml: Record3 has no MatrixDimension");
  }
  std::uint64_t nx = read_size(r, dim, "SizeX", true);
  std::uint64_t ny = read_size(r, dim, "SizeY", true);
  std::uint64_t nz = read_size(r, dim, "SizeZ", false);
  if (nz != 1)
    r.fail("x3p main.xml: SizeZ is " + std::to_string(nz) +
           "; only single-layer data (1) is "
           "supported");
  if (feature == "PRF" && ny != 1)
    r.fail("x3p main.xml: a PRF (profile) file must have SizeY 1, not " + std::to_string(ny));
  check_grid(r, nx, ny, 0, 0);  // zero or absurd sizes
  const std::uint64_t n = nx * ny;
  const std::size_t tsize = type_size(ztype);
  const std::string grid_text = std::to_string(nx) + " x " + std::to_string(ny);

  Surface s;
  s.nx = static_cast<std::size_t>(nx);
  s.ny = static_cast<std::size_t>(ny);
  s.dx = ax.increment;
  s.dy = ay.increment;
  s.x0 = ax.offset;
  s.y0 = ay.offset;
  const bool scale = az.increment != 1.0 || az.offset != 0.0;
  auto to_z = [&](double raw) { return scale ? raw * az.increment + az.offset : raw; };

  pugi::xml_node link = child(rec3, "DataLink");
  pugi::xml_node list = child(rec3, "DataList");
  if (link) {
    std::string point_link = text(child(link, "PointDataLink"));
    if (point_link.empty()) r.fail("x3p main.xml: DataLink has no PointDataLink");
    auto member_path = [&](std::string p) {
      std::replace(p.begin(), p.end(), '\\', '/');
      while (p.starts_with("./")) p.erase(0, 2);
      while (p.starts_with("/")) p.erase(0, 1);
      return base + p;
    };
    std::string data_path = member_path(point_link);
    std::int64_t di = zip.find(data_path);
    if (di < 0)
      r.fail("x3p: the data file " + quote(data_path) + " named by main.xml is not in the archive");
    std::uint64_t need = n * tsize;
    std::uint64_t have = zip.size(static_cast<std::size_t>(di));
    if (have != need)
      r.fail("x3p: " + quote(data_path) + " holds " + std::to_string(have) +
             " bytes, but main.xml declares " + grid_text + " points of type " +
             type_letter(ztype) + " = " + std::to_string(need) + " bytes");
    check_surface_memory(name, data.size(), n, need);
    std::vector<std::uint8_t> raw = zip.read(static_cast<std::size_t>(di), need);
    check_md5(s, text(child(link, "MD5ChecksumPointData")), raw, data_path);

    std::vector<std::uint8_t> bits;
    std::string valid_link = text(child(link, "ValidPointsLink"));
    std::string valid_path;
    if (!valid_link.empty()) {
      valid_path = member_path(valid_link);
      std::int64_t vi = zip.find(valid_path);
      if (vi < 0)
        r.fail("x3p: the validity file " + quote(valid_path) +
               " named by main.xml is not in the archive");
      std::uint64_t vneed = (n + 7) / 8;
      std::uint64_t vhave = zip.size(static_cast<std::size_t>(vi));
      if (vhave != vneed)
        r.fail("x3p: " + quote(valid_path) + " holds " + std::to_string(vhave) +
               " bytes, but a bit array for " + grid_text + " points needs " +
               std::to_string(vneed) + " bytes");
      bits = zip.read(static_cast<std::size_t>(vi), vneed);
      check_md5(s, text(child(link, "MD5ChecksumValidPoints")), bits, valid_path);
    }

    s.z.resize(static_cast<std::size_t>(n));
    s.valid.assign(static_cast<std::size_t>(n), 1);
    const std::uint8_t* p = raw.data();
    for (std::size_t i = 0; i < s.z.size(); ++i, p += tsize) {
      switch (ztype) {
        case ZType::I16:
          s.z[i] = to_z(load_le<std::int16_t>(p));
          break;
        case ZType::I32:
          s.z[i] = to_z(load_le<std::int32_t>(p));
          break;
        case ZType::F32:
          s.z[i] = to_z(load_le<float>(p));
          break;
        case ZType::F64:
          s.z[i] = to_z(load_le<double>(p));
          break;
      }
    }
    if (!bits.empty()) {
      for (std::size_t i = 0; i < s.z.size(); ++i)
        if (((bits[i >> 3] >> (i & 7)) & 1) == 0) s.valid[i] = 0;
    }
  } else if (list) {
    std::uint64_t count = 0;
    for (auto c : list.children())
      if (c.type() == pugi::node_element && local_name(c.name()) == "Datum") ++count;
    if (count != n)
      r.fail("x3p: DataList holds " + std::to_string(count) +
             " Datum values, but main.xml "
             "declares " +
             grid_text + " = " + std::to_string(n) + " points");
    check_surface_memory(name, data.size(), n);
    s.z.resize(static_cast<std::size_t>(n));
    s.valid.assign(static_cast<std::size_t>(n), 1);
    std::size_t i = 0;
    for (auto c : list.children()) {
      if (c.type() != pugi::node_element || local_name(c.name()) != "Datum") continue;
      std::string t = text(c);
      if (t.empty()) {
        s.z[i] = std::numeric_limits<double>::quiet_NaN();
        s.valid[i] = 0;
      } else {
        auto v = parse_double(t);
        if (!v)
          r.fail("x3p: DataList Datum " + std::to_string(i) + " " + quote(t) + " is not a number");
        s.z[i] = to_z(*v);
      }
      ++i;
    }
  } else {
    r.fail("x3p main.xml: Record3 has neither DataLink nor DataList");
  }

  // ---- Record2: metadata (all optional)
  s.meta.format = "x3p";
  s.meta.z_unit_in_file = "m";
  if (pugi::xml_node rec2 = child(root, "Record2")) {
    s.meta.date = text(child(rec2, "Date"));
    s.meta.comment = text(child(rec2, "Comment"));
    auto keep = [&](const char* key, const std::string& v) {
      if (!v.empty()) s.meta.set(key, v);
    };
    keep("creator", text(child(rec2, "Creator")));
    keep("calibration_date", text(child(rec2, "CalibrationDate")));
    pugi::xml_node inst = child(rec2, "Instrument");
    std::string joined;
    for (auto [el, key] :
         {std::pair{"Manufacturer", "instrument_manufacturer"},
          std::pair{"Model", "instrument_model"}, std::pair{"Serial", "instrument_serial"},
          std::pair{"Version", "instrument_version"}}) {
      std::string v = text(child(inst, el));
      if (v == "not available") v.clear();  // the placeholder our writer (and others) use
      keep(key, v);
      if (!v.empty()) joined += (joined.empty() ? "" : " ") + v;
    }
    s.meta.instrument = joined;
    pugi::xml_node probe = child(rec2, "ProbingSystem");
    keep("probing_type", text(child(probe, "Type")));
    keep("probing_identification", text(child(probe, "Identification")));
  }
  s.meta.set("x3p_feature_type", feature);
  s.meta.set("x3p_z_data_type", zt);
  if (!base.empty()) s.meta.set("x3p_main_xml", main_path);

  // ---- Record4 / md5checksum.hex: checksum of main.xml itself
  std::string sum_name = text(child(child(root, "Record4"), "ChecksumFile"));
  if (sum_name.empty()) sum_name = "md5checksum.hex";
  std::int64_t si = zip.find(base + sum_name);
  if (si >= 0) {
    std::uint64_t sz = zip.size(static_cast<std::size_t>(si));
    if (sz <= 4096) {
      auto sum = zip.read(static_cast<std::size_t>(si), sz);
      std::string_view sv(reinterpret_cast<const char*>(sum.data()), sum.size());
      sv = trim(sv);
      std::string stored(sv.substr(0, std::min<std::size_t>(sv.find_first_of(" \t*"), sv.size())));
      check_md5(s, stored, xml, "main.xml");
    }
  }

  s.sync_mask();
  return s;
}

// ================================================================= writer

namespace {

std::string clean_text(const std::string& v) {
  std::string out = v;
  for (auto& c : out) {
    unsigned char u = static_cast<unsigned char>(c);
    if ((u < 32 && c != '\t' && c != '\n' && c != '\r') || u == 127) c = ' ';
  }
  return out;
}

std::string now_iso8601() {
  std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  char buf[32];
  std::strftime(buf, sizeof(buf), "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

void add_text(pugi::xml_node parent, const char* name, const std::string& value) {
  parent.append_child(name).text().set(clean_text(value).c_str());
}

std::string or_na(const std::string& v) { return v.empty() ? "not available" : v; }

}  // namespace

void write_x3p(const Surface& s, const std::string& path) {
  const std::size_t n = s.nx * s.ny;
  if (n == 0 || s.z.size() != n || s.valid.size() != n)
    throw FileError(path, "x3p: cannot write an empty or inconsistent surface");
  for (double v : {s.dx, s.dy, s.x0, s.y0})
    if (!std::isfinite(v)) throw FileError(path, "x3p: spacing and offsets must be finite");

  // Heights: float64 little-endian, NaN where invalid; validity bits (LSB first, 1 = valid).
  std::vector<std::uint8_t> data(n * 8);
  std::vector<std::uint8_t> bits((n + 7) / 8, 0);
  bool any_invalid = false;
  for (std::size_t i = 0; i < n; ++i) {
    bool ok = s.valid[i] != 0 && std::isfinite(s.z[i]);
    store_le<double>(data.data() + 8 * i, ok ? s.z[i] : std::numeric_limits<double>::quiet_NaN());
    if (ok)
      bits[i >> 3] = static_cast<std::uint8_t>(bits[i >> 3] | (1u << (i & 7)));
    else
      any_invalid = true;
  }

  pugi::xml_document doc;
  auto decl = doc.append_child(pugi::node_declaration);
  decl.append_attribute("version") = "1.0";
  decl.append_attribute("encoding") = "UTF-8";
  auto root = doc.append_child("p:ISO5436_2");
  root.append_attribute("xmlns:p") = kNamespace;
  root.append_attribute("xmlns:xsi") = "http://www.w3.org/2001/XMLSchema-instance";
  root.append_attribute("xsi:schemaLocation") =
      "http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2.xsd";

  auto rec1 = root.append_child("Record1");
  add_text(rec1, "Revision", "ISO5436 - 2000");
  add_text(rec1, "FeatureType", "SUR");
  auto axes = rec1.append_child("Axes");
  auto add_axis = [&](const char* nm, double inc, double off) {
    auto a = axes.append_child(nm);
    add_text(a, "AxisType", "I");
    add_text(a, "DataType", "D");
    add_text(a, "Increment", format_double(inc));
    add_text(a, "Offset", format_double(off));
  };
  add_axis("CX", s.dx, s.x0);
  add_axis("CY", s.dy, s.y0);
  auto cz = axes.append_child("CZ");
  add_text(cz, "AxisType", "A");
  add_text(cz, "DataType", "D");
  // The heights are written as they are in the Surface: a levelled surface stays levelled
  // (the removed offset z0 is not folded back in), so what `info` showed is what the file holds.

  const SurfaceMetadata& m = s.meta;
  auto rec2 = root.append_child("Record2");
  std::string date = m.date.empty() ? now_iso8601() : m.date;
  add_text(rec2, "Date", date);
  add_text(rec2, "Creator", "microbrdf");
  auto inst = rec2.append_child("Instrument");
  std::string manufacturer = m.get("instrument_manufacturer");
  if (manufacturer.empty() && m.get("instrument_model").empty()) manufacturer = m.instrument;
  add_text(inst, "Manufacturer", or_na(manufacturer));
  add_text(inst, "Model", or_na(m.get("instrument_model")));
  add_text(inst, "Serial", or_na(m.get("instrument_serial")));
  add_text(inst, "Version", or_na(m.get("instrument_version")));
  std::string cal = m.get("calibration_date");
  add_text(rec2, "CalibrationDate", cal.empty() ? date : cal);
  auto probe = rec2.append_child("ProbingSystem");
  std::string ptype = m.get("probing_type");
  if (ptype != "Contacting" && ptype != "NonContacting" && ptype != "Software") ptype = "Software";
  add_text(probe, "Type", ptype);
  add_text(probe, "Identification", or_na(m.get("probing_identification")));
  if (!m.comment.empty()) add_text(rec2, "Comment", m.comment);

  auto rec3 = root.append_child("Record3");
  auto dim = rec3.append_child("MatrixDimension");
  add_text(dim, "SizeX", std::to_string(s.nx));
  add_text(dim, "SizeY", std::to_string(s.ny));
  add_text(dim, "SizeZ", "1");
  auto link = rec3.append_child("DataLink");
  add_text(link, "PointDataLink", "bindata/data.bin");
  add_text(link, "MD5ChecksumPointData", md5_hex(data.data(), data.size()));
  if (any_invalid) {
    add_text(link, "ValidPointsLink", "bindata/valid.bin");
    add_text(link, "MD5ChecksumValidPoints", md5_hex(bits.data(), bits.size()));
  }
  auto rec4 = root.append_child("Record4");
  add_text(rec4, "ChecksumFile", "md5checksum.hex");

  std::ostringstream os;
  doc.save(os, "  ", pugi::format_default, pugi::encoding_utf8);
  const std::string xml = os.str();
  const std::string sum =
      md5_hex(reinterpret_cast<const std::uint8_t*>(xml.data()), xml.size()) + " *main.xml\n";

  // The buffers above outlive the archive: libzip reads them in zip_close.
  int zerr = 0;
  ArchivePtr za(zip_open(path.c_str(), ZIP_CREATE | ZIP_TRUNCATE, &zerr));
  if (!za) {
    ZipError e;
    zip_error_init_with_code(&e.e, zerr);
    throw FileError(path,
                    std::string("x3p: cannot create the archive: ") + zip_error_strerror(&e.e));
  }
  auto add = [&](const char* member, const void* bytes, std::size_t len) {
    SourcePtr src(zip_source_buffer(za.get(), bytes, len, 0));
    if (!src) throw FileError(path, std::string("x3p: ") + zip_strerror(za.get()));
    zip_int64_t idx = zip_file_add(za.get(), member, src.get(), ZIP_FL_ENC_UTF_8);
    if (idx < 0)
      throw FileError(path,
                      std::string("x3p: cannot add ") + member + ": " + zip_strerror(za.get()));
    src.release();
    zip_set_file_compression(za.get(), static_cast<zip_uint64_t>(idx), ZIP_CM_DEFLATE, 0);
  };
  add("main.xml", xml.data(), xml.size());
  add("md5checksum.hex", sum.data(), sum.size());
  if (zip_dir_add(za.get(), "bindata", ZIP_FL_ENC_UTF_8) < 0)
    throw FileError(path, std::string("x3p: ") + zip_strerror(za.get()));
  add("bindata/data.bin", data.data(), data.size());
  if (any_invalid) add("bindata/valid.bin", bits.data(), bits.size());
  if (zip_close(za.get()) != 0)
    throw FileError(path, std::string("x3p: cannot write the archive: ") + zip_strerror(za.get()));
  za.release();  // closed successfully (zip_close freed it)
}

}  // namespace microbrdf::detail

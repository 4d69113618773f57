// Gwyddion native .gwy (GWYP), read + write. Layout: docs/formats.md §4.
//
// Reader: a recursive parser for the serialized object tree (depth-limited, every size checked
// against the bytes that remain before anything is allocated). From the top GwyContainer it
// takes the lowest-numbered channel "/N/data" whose z unit is a length (or empty), its mask
// "/N/mask" (> 0.5 = invalid) and title "/N/data/title". Everything else is validated and
// skipped.
//
// Writer: GWYP + GwyContainer with "/0/data" (GwyDataField, units "m", invalid points filled
// with the mean of the valid ones because Gwyddion fields hold no NaN), "/0/mask" when any point
// is invalid (1.0 = invalid), "/0/data/title", and two extra doubles "/0/microbrdf/dx" and
// "/0/microbrdf/dy" holding the exact spacing in metres: xreal/xres does not always reproduce dx
// bit for bit. The reader prefers them when they agree with xreal/xres to 1e-12 (relative), so
// a file resampled in Gwyddion (which keeps unknown items) falls back to xreal/xres.
#include <algorithm>
#include <bit>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <variant>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "microbrdf/file_size_limit.hpp"
#include "microbrdf/units.hpp"
#include "surface/formats.hpp"

namespace microbrdf::detail {
namespace {

constexpr int kMaxDepth = 32;

struct GwyObject;

/// A float64 array as it sits in the file (little-endian), not copied.
struct DoubleArray {
  std::span<const std::uint8_t> bytes;
  std::size_t count = 0;
  double at(std::size_t i) const {
    std::uint64_t u = 0;
    for (int b = 7; b >= 0; --b) u = (u << 8) | bytes[i * 8 + static_cast<std::size_t>(b)];
    return std::bit_cast<double>(u);
  }
};

struct Skipped {};  // a component we validated but do not keep

using Value = std::variant<Skipped, bool, std::int64_t, double, std::string, DoubleArray,
                           std::shared_ptr<GwyObject>>;

struct GwyObject {
  std::string type;
  std::vector<std::pair<std::string, Value>> items;

  const Value* find(const std::string& key) const {
    for (const auto& kv : items)
      if (kv.first == key) return &kv.second;
    return nullptr;
  }
  template <class T>
  const T* get(const std::string& key) const {
    const Value* v = find(key);
    return v ? std::get_if<T>(v) : nullptr;
  }
  const GwyObject* object(const std::string& key) const {
    auto p = get<std::shared_ptr<GwyObject>>(key);
    return p ? p->get() : nullptr;
  }
};

// Objects whose components we keep; the components of any other object type are parsed (so
// corrupt files are caught) but dropped, which bounds memory by what we need.
bool keep_components(const std::string& type) {
  return type == "GwyContainer" || type == "GwyDataField" || type == "GwySIUnit";
}

class Parser {
 public:
  explicit Parser(const ByteReader& r) : r_(r) {}

  std::shared_ptr<GwyObject> object(ByteCursor& c, int depth) {
    if (depth > kMaxDepth)
      r_.fail("corrupt: objects nested deeper than " + std::to_string(kMaxDepth) + " levels");
    auto obj = std::make_shared<GwyObject>();
    obj->type = c.cstring(256, "object type name");
    if (obj->type.empty()) r_.fail("corrupt: empty object type name at offset " + at(c));
    const std::uint32_t size = c.le<std::uint32_t>("object size");
    if (size > c.remaining())
      r_.fail("truncated or corrupt: object " + obj->type + " claims " + std::to_string(size) +
              " bytes, only " + std::to_string(c.remaining()) + " remain");
    ByteCursor body(r_, c.pos(), c.pos() + size);
    c.skip(size, "object body");
    const bool keep = keep_components(obj->type);
    while (body.remaining() > 0) {
      std::string name = body.cstring(4096, "component name");
      Value v = component(body, depth);
      if (keep) obj->items.emplace_back(std::move(name), std::move(v));
    }
    return obj;
  }

 private:
  std::string at(const ByteCursor& c) const { return std::to_string(c.pos()); }

  // Element count of an array, checked against the bytes that remain (elements of at least
  // `min_elem` bytes each) before anything is read or allocated.
  std::uint32_t count(ByteCursor& c, std::size_t min_elem, const char* what) {
    const std::uint32_t n = c.le<std::uint32_t>(what);
    if (static_cast<std::uint64_t>(n) * min_elem > c.remaining())
      r_.fail(std::string("truncated or corrupt: ") + what + " of " + std::to_string(n) +
              " elements needs at least " +
              std::to_string(static_cast<std::uint64_t>(n) * min_elem) + " bytes, only " +
              std::to_string(c.remaining()) + " remain");
    return n;
  }

  Value component(ByteCursor& c, int depth) {
    const char type = static_cast<char>(c.le<std::uint8_t>("component type"));
    switch (type) {
      case 'b':
        return c.le<std::uint8_t>("boolean") != 0;
      case 'c':
        c.skip(1, "char");
        return Skipped{};
      case 'i':
        return static_cast<std::int64_t>(c.le<std::int32_t>("int32"));
      case 'q':
        return c.le<std::int64_t>("int64");
      case 'd':
        return c.le<double>("double");
      case 's':
        return c.cstring(1 << 20, "string value");
      case 'o':
        return object(c, depth + 1);
      case 'C':
        c.skip(count(c, 1, "char array"), "char array");
        return Skipped{};
      case 'I':
        c.skip(std::size_t{4} * count(c, 4, "int32 array"), "int32 array");
        return Skipped{};
      case 'Q':
        c.skip(std::size_t{8} * count(c, 8, "int64 array"), "int64 array");
        return Skipped{};
      case 'D': {
        DoubleArray a;
        a.count = count(c, 8, "double array");
        a.bytes = c.bytes(a.count * 8, "double array");
        return a;
      }
      case 'S': {
        const std::uint32_t n = count(c, 1, "string array");
        for (std::uint32_t i = 0; i < n; ++i) (void)c.cstring(1 << 20, "string array element");
        return Skipped{};
      }
      case 'O': {
        const std::uint32_t n = count(c, 6, "object array");  // name, NUL, size: >= 6 bytes
        for (std::uint32_t i = 0; i < n; ++i) (void)object(c, depth + 1);
        return Skipped{};
      }
      default: {
        char buf[64];
        std::snprintf(buf, sizeof buf, "corrupt: unknown component type 0x%02x before offset %zu",
                      static_cast<unsigned>(static_cast<unsigned char>(type)), c.pos());
        r_.fail(buf);
      }
    }
  }

  const ByteReader& r_;
};

// "/123/data" -> 123 (with `suffix` = "/data"); nullopt for anything else.
std::optional<std::uint64_t> channel_number(const std::string& key, const std::string& suffix) {
  if (key.size() < 2 + suffix.size() || key[0] != '/') return std::nullopt;
  if (key.compare(key.size() - suffix.size(), suffix.size(), suffix) != 0) return std::nullopt;
  std::string digits = key.substr(1, key.size() - 1 - suffix.size());
  // Canonical decimal only ("/01/data" is not a channel), so "/" + to_string(n) rebuilds the key.
  if (digits.empty() || digits.size() > 18 || (digits.size() > 1 && digits[0] == '0'))
    return std::nullopt;
  for (char ch : digits)
    if (ch < '0' || ch > '9') return std::nullopt;
  std::uint64_t n = 0;
  std::from_chars(digits.data(), digits.data() + digits.size(), n);
  return n;
}

std::optional<std::string> unit_string(const GwyObject& field, const char* key) {
  const GwyObject* u = field.object(key);
  if (!u) return std::nullopt;
  if (u->type != "GwySIUnit") return std::nullopt;
  const std::string* s = u->get<std::string>("unitstr");
  return s ? *s : std::string();
}

// Metres per unit for a length unit; 0 when not a length. Empty = no unit (assumed metres).
// "A" is ampere in Gwyddion, not angstrom, so it is not a length here.
double gwy_length_scale(const std::string& unit) {
  if (unit.empty()) return 1.0;
  if (unit == "A") return 0.0;
  return length_unit_to_metres(unit);
}

struct Field {
  std::size_t xres = 0, yres = 0;
  double xreal = 0, yreal = 0, xoff = 0, yoff = 0;
  std::string xy_unit, z_unit;
  bool has_xy_unit = false, has_z_unit = false;
  DoubleArray data;
};

Field parse_field(const ByteReader& r, const GwyObject& obj, const std::string& key) {
  if (obj.type != "GwyDataField")
    r.fail("'" + key + "' is a " + obj.type + ", expected a GwyDataField");
  Field f;
  const auto* xres = obj.get<std::int64_t>("xres");
  const auto* yres = obj.get<std::int64_t>("yres");
  if (!xres || !yres) r.fail("'" + key + "' has no xres/yres");
  if (*xres <= 0 || *yres <= 0)
    r.fail("'" + key + "' has invalid size " + std::to_string(*xres) + " x " +
           std::to_string(*yres));
  check_grid(r, static_cast<std::uint64_t>(*xres), static_cast<std::uint64_t>(*yres), 0, 0);
  f.xres = static_cast<std::size_t>(*xres);
  f.yres = static_cast<std::size_t>(*yres);
  const auto* xreal = obj.get<double>("xreal");
  const auto* yreal = obj.get<double>("yreal");
  if (!xreal || !yreal) r.fail("'" + key + "' has no xreal/yreal (physical size)");
  f.xreal = *xreal;
  f.yreal = *yreal;
  if (!(f.xreal > 0) || !(f.yreal > 0) || !std::isfinite(f.xreal) || !std::isfinite(f.yreal))
    r.fail("'" + key + "' has a non-positive or non-finite physical size");
  if (const auto* v = obj.get<double>("xoff")) f.xoff = *v;
  if (const auto* v = obj.get<double>("yoff")) f.yoff = *v;
  if (!std::isfinite(f.xoff) || !std::isfinite(f.yoff))
    r.fail("'" + key + "' has a non-finite offset");
  if (auto u = unit_string(obj, "si_unit_xy")) f.xy_unit = *u, f.has_xy_unit = true;
  if (auto u = unit_string(obj, "si_unit_z")) f.z_unit = *u, f.has_z_unit = true;
  const auto* data = obj.get<DoubleArray>("data");
  if (!data) r.fail("'" + key + "' has no data array");
  if (data->count != f.xres * f.yres)
    r.fail("'" + key + "' data has " + std::to_string(data->count) + " values, expected " +
           std::to_string(f.xres) + " x " + std::to_string(f.yres));
  f.data = *data;
  return f;
}

}  // namespace

Surface read_gwy(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  if (data.size() >= 4 && std::memcmp(data.data(), "GWYO", 4) == 0)
    r.fail("Gwyddion 1.x file (GWYO) not supported; re-save it with Gwyddion 2");
  if (data.size() < 4 || std::memcmp(data.data(), "GWYP", 4) != 0)
    r.fail("not a Gwyddion file (no GWYP magic)");
  ByteCursor c(r, 4);
  Parser parser(r);
  auto top = parser.object(c, 0);
  if (top->type != "GwyContainer")
    r.fail("top-level object is a " + top->type + ", expected a GwyContainer");

  // Channels in number order; take the first whose z unit is a length (or empty).
  std::map<std::uint64_t, const GwyObject*> channels;
  for (const auto& [key, value] : top->items) {
    auto n = channel_number(key, "/data");
    if (!n) continue;
    const auto* p = std::get_if<std::shared_ptr<GwyObject>>(&value);
    if (!p) r.fail("'" + key + "' is not an object");
    channels.emplace(*n, p->get());
  }
  if (channels.empty()) r.fail("no image channel (/N/data) in the Gwyddion container");
  std::optional<std::uint64_t> chosen;
  std::string skipped_units;
  for (const auto& [n, obj] : channels) {
    if (obj->type != "GwyDataField") continue;
    auto zu = unit_string(*obj, "si_unit_z");
    if (gwy_length_scale(zu.value_or("")) > 0) {
      chosen = n;
      break;
    }
    skipped_units += (skipped_units.empty() ? "" : ", ") + std::string("/") + std::to_string(n) +
                     " ('" + zu.value_or("") + "')";
  }
  if (!chosen) {
    if (skipped_units.empty()) r.fail("no GwyDataField channel in the Gwyddion container");
    r.fail("no height channel: every channel has a non-length z unit: " + skipped_units);
  }
  const std::string prefix = "/" + std::to_string(*chosen);
  Field f = parse_field(r, *channels[*chosen], prefix + "/data");

  const double sxy = gwy_length_scale(f.xy_unit);
  if (sxy == 0) r.fail("lateral unit '" + f.xy_unit + "' of " + prefix + "/data is not a length");
  const double sz = gwy_length_scale(f.z_unit);

  Surface s;
  s.nx = f.xres;
  s.ny = f.yres;
  s.dx = f.xreal * sxy / static_cast<double>(f.xres);
  s.dy = f.yreal * sxy / static_cast<double>(f.yres);
  s.x0 = f.xoff * sxy;
  s.y0 = f.yoff * sxy;
  // Exact spacing written by microbrdf, used when it agrees with xreal/xres.
  auto exact = [&](const char* k, double derived) {
    const auto* v = top->get<double>(prefix + k);
    if (v && *v > 0 && std::isfinite(*v) && std::fabs(*v - derived) <= 1e-12 * derived) return *v;
    return derived;
  };
  s.dx = exact("/microbrdf/dx", s.dx);
  s.dy = exact("/microbrdf/dy", s.dy);

  s.z.resize(s.nx * s.ny);
  s.valid.assign(s.nx * s.ny, 1);
  for (std::size_t i = 0; i < s.z.size(); ++i) s.z[i] = f.data.at(i) * sz;

  if (auto mv = top->find(prefix + "/mask")) {
    const auto* p = std::get_if<std::shared_ptr<GwyObject>>(mv);
    if (!p) r.fail("'" + prefix + "/mask' is not an object");
    Field m = parse_field(r, **p, prefix + "/mask");
    if (m.xres != f.xres || m.yres != f.yres)
      r.fail("mask " + std::to_string(m.xres) + " x " + std::to_string(m.yres) +
             " does not match the data " + std::to_string(f.xres) + " x " + std::to_string(f.yres));
    for (std::size_t i = 0; i < s.z.size(); ++i)
      if (m.data.at(i) > 0.5) s.invalidate(i);
  }

  s.meta.format = "gwy";
  s.meta.z_unit_in_file = f.z_unit;
  if (const auto* t = top->get<std::string>(prefix + "/data/title")) s.meta.comment = *t;
  s.meta.set("gwy_channel", std::to_string(*chosen));
  std::string warn;
  if (f.xy_unit.empty()) warn += "no lateral unit in the file (assumed metres)";
  if (f.z_unit.empty())
    warn += std::string(warn.empty() ? "" : "; ") + "no z unit (assumed metres)";
  if (!warn.empty()) s.meta.set("unit_warning", warn);
  return s;
}

// ---------------------------------------------------------------------------------------------
// Writer

namespace {

class Writer {
 public:
  std::vector<std::uint8_t> out;

  void raw(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::uint8_t*>(p);
    out.insert(out.end(), b, b + n);
  }
  void cstr(const std::string& s) {
    raw(s.data(), s.size());
    out.push_back(0);
  }
  void u32(std::uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  }
  void f64(double d) {
    const auto u = std::bit_cast<std::uint64_t>(d);
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<std::uint8_t>(u >> (8 * i)));
  }
  void comp_int(const std::string& name, std::int32_t v) {
    cstr(name);
    out.push_back('i');
    u32(static_cast<std::uint32_t>(v));
  }
  void comp_double(const std::string& name, double v) {
    cstr(name);
    out.push_back('d');
    f64(v);
  }
  void comp_string(const std::string& name, const std::string& v) {
    cstr(name);
    out.push_back('s');
    cstr(v);
  }
  void comp_doubles(const std::string& name, const std::vector<double>& v) {
    cstr(name);
    out.push_back('D');
    u32(static_cast<std::uint32_t>(v.size()));
    for (double d : v) f64(d);
  }
  /// Starts "name" 'o' object of `type`; returns the position of its size field.
  std::size_t begin_object(const std::string& name, const std::string& type) {
    cstr(name);
    out.push_back('o');
    return begin_bare(type);
  }
  std::size_t begin_bare(const std::string& type) {
    cstr(type);
    std::size_t at = out.size();
    u32(0);
    return at;
  }
  void end_object(std::size_t size_at) {
    const std::uint64_t size = out.size() - size_at - 4;
    if (size > 0xFFFFFFFFu) throw std::length_error("gwy object over 4 GiB");
    for (int i = 0; i < 4; ++i)
      out[size_at + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(size >> (8 * i));
  }
  void unit(const std::string& name, const std::string& u) {
    auto at = begin_object(name, "GwySIUnit");
    comp_string("unitstr", u);
    end_object(at);
  }
  void field(const std::string& key, const Surface& s, const std::vector<double>& values,
             const std::string& z_unit) {
    auto at = begin_object(key, "GwyDataField");
    comp_int("xres", static_cast<std::int32_t>(s.nx));
    comp_int("yres", static_cast<std::int32_t>(s.ny));
    comp_double("xreal", static_cast<double>(s.nx) * s.dx);
    comp_double("yreal", static_cast<double>(s.ny) * s.dy);
    comp_double("xoff", s.x0);
    comp_double("yoff", s.y0);
    unit("si_unit_xy", "m");
    unit("si_unit_z", z_unit);
    comp_doubles("data", values);
    end_object(at);
  }
};

}  // namespace

void write_gwy(const Surface& s, const std::string& path) {
  // data + mask (8 bytes each) must fit in the container's 32-bit size field.
  if (s.nx > 0x7FFFFFFF || s.ny > 0x7FFFFFFF || s.size() > (0xFFFFFFFFu - 65536) / 16)
    throw FileError(path, "surface too large for a Gwyddion file (4 GiB object limit)");
  double sum = 0;
  std::size_t n = 0;
  for (std::size_t i = 0; i < s.size(); ++i)
    if (s.is_valid(i)) sum += s.z[i], ++n;
  const double fill = n ? sum / static_cast<double>(n) : 0.0;
  std::vector<double> data(s.size());
  std::vector<double> mask;
  for (std::size_t i = 0; i < s.size(); ++i) data[i] = s.is_valid(i) ? s.z[i] : fill;
  if (n != s.size()) {
    mask.resize(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) mask[i] = s.is_valid(i) ? 0.0 : 1.0;
  }

  Writer w;
  w.raw("GWYP", 4);
  auto top = w.begin_bare("GwyContainer");
  w.field("/0/data", s, data, "m");
  w.comp_string("/0/data/title", s.meta.comment.empty() ? "Height" : s.meta.comment);
  if (!mask.empty()) w.field("/0/mask", s, mask, "");
  w.comp_double("/0/microbrdf/dx", s.dx);
  w.comp_double("/0/microbrdf/dy", s.dy);
  w.end_object(top);

  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw FileError(path, std::string("cannot create: ") + std::strerror(errno));
  const bool ok = std::fwrite(w.out.data(), 1, w.out.size(), f) == w.out.size();
  int err = ok ? 0 : errno;
  const bool closed = std::fclose(f) == 0;
  if (!closed && ok) err = errno;
  if (!ok || !closed) throw FileError(path, write_failure_problem(err));
}

}  // namespace microbrdf::detail

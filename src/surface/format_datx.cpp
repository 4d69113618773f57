// Zygo .datx reader (HDF5 container written by MetroPro >= 8 / Mx).
//
// Layout (docs/formats.md §3): the height map is the first dataset under
// /Data/Surface, a 2-D float64 (or float32) array (rows, columns), row-major, x fastest. Its
// attributes give Unit ("Fringes" -> x Wavelength x Interferometric Scale Factor x Obliquity
// Factor; or a length unit), "No Data" (values >= it are invalid) and the X/Y Converter
// compounds whose Parameters[1] is the lateral resolution in metres per pixel. Metadata comes
// from the attributes of the /Attributes/{GUID} group. Rows are kept in file order.
//
// The file is opened from memory (core driver + file image). Every dimension is checked
// against the file size before anything is read, only the Surface dataset is touched (other
// datasets may use Zygo's proprietary filter 44440), and every HDF5 handle is closed on every
// path. libhdf5 (serial) is not thread-safe, so reads are serialised by a mutex. libhdf5 is
// loaded at the first read (surface/hdf5_runtime.hpp), not at process start.
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <ctime>
#include <limits>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "core/byte_reader.hpp"
#include "microbrdf/error.hpp"
#include "surface/formats.hpp"
#include "surface/hdf5_runtime.hpp"
#include "surface/isolated_reader.hpp"

namespace microbrdf::detail {
namespace {

/// Owns one HDF5 identifier and closes it with the matching H5?close.
class H5Id {
 public:
  using Closer = herr_t (*)(hid_t);
  H5Id() = default;
  H5Id(hid_t id, Closer close) : id_(id), close_(close) {}
  H5Id(const H5Id&) = delete;
  H5Id& operator=(const H5Id&) = delete;
  H5Id(H5Id&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  H5Id& operator=(H5Id&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      close_ = o.close_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  ~H5Id() { reset(); }
  void reset() {
    if (id_ >= 0 && close_ != nullptr) close_(id_);
    id_ = H5I_INVALID_HID;
  }
  hid_t get() const { return id_; }
  bool ok() const { return id_ >= 0; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer close_ = nullptr;
};

std::string num(double v) {
  std::ostringstream o;
  o.precision(9);
  o << v;
  return o.str();
}

std::string clean_text(const std::string& s) {
  std::string out;
  for (unsigned char c : s) out += (c >= 0x20 && c < 0x7F) ? static_cast<char>(c) : ' ';
  std::size_t a = out.find_first_not_of(' ');
  if (a == std::string::npos) return "";
  return out.substr(a, out.find_last_not_of(' ') - a + 1);
}

bool attr_exists(hid_t obj, const char* name) { return H5Aexists(obj, name) > 0; }

/// Type (H5I_GROUP, H5I_DATASET, ...) of the object a hard link `name` under `loc` names;
/// H5I_BADID when there is none. Soft and external links are not followed.
H5I_type_t hard_link_type(hid_t loc, const char* name) {
  if (H5Lexists(loc, name, H5P_DEFAULT) <= 0) return H5I_BADID;
  H5L_info_t linfo;
  if (H5Lget_info(loc, name, &linfo, H5P_DEFAULT) < 0 || linfo.type != H5L_TYPE_HARD)
    return H5I_BADID;
  H5Id obj(H5Oopen(loc, name, H5P_DEFAULT), H5Oclose);
  if (!obj.ok()) return H5I_BADID;
  return H5Iget_type(obj.get());
}

/// Opens attribute `name` of `obj` if it exists and holds exactly one element.
H5Id open_scalar_attr(hid_t obj, const char* name) {
  if (!attr_exists(obj, name)) return {};
  H5Id a(H5Aopen(obj, name, H5P_DEFAULT), H5Aclose);
  if (!a.ok()) return {};
  H5Id space(H5Aget_space(a.get()), H5Sclose);
  if (!space.ok() || H5Sget_simple_extent_npoints(space.get()) != 1) return {};
  return a;
}

std::optional<double> attr_double(hid_t obj, const char* name) {
  H5Id a = open_scalar_attr(obj, name);
  if (!a.ok()) return std::nullopt;
  H5Id type(H5Aget_type(a.get()), H5Tclose);
  if (!type.ok()) return std::nullopt;
  H5T_class_t c = H5Tget_class(type.get());
  if (c != H5T_FLOAT && c != H5T_INTEGER) return std::nullopt;
  double v = 0;
  if (H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v) < 0) return std::nullopt;
  return v;
}

std::optional<std::string> attr_string(hid_t obj, const char* name) {
  H5Id a = open_scalar_attr(obj, name);
  if (!a.ok()) return std::nullopt;
  H5Id type(H5Aget_type(a.get()), H5Tclose);
  if (!type.ok() || H5Tget_class(type.get()) != H5T_STRING) return std::nullopt;
  const htri_t is_var = H5Tis_variable_str(type.get());
  if (is_var < 0) return std::nullopt;
  if (is_var > 0) {
    H5Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
    if (!mem.ok() || H5Tset_size(mem.get(), H5T_VARIABLE) < 0) return std::nullopt;
    char* p = nullptr;
    if (H5Aread(a.get(), mem.get(), &p) < 0) return std::nullopt;
    std::string s = p != nullptr ? std::string(p, strnlen(p, 1 << 16)) : std::string();
    if (p != nullptr) H5free_memory(p);
    return s;
  }
  const std::size_t size = H5Tget_size(type.get());
  if (size == 0 || size > (1 << 16)) return std::nullopt;
  H5Id mem(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!mem.ok() || H5Tset_size(mem.get(), size + 1) < 0) return std::nullopt;
  std::vector<char> buf(size + 1, 0);
  if (H5Aread(a.get(), mem.get(), buf.data()) < 0) return std::nullopt;
  return std::string(buf.data(), strnlen(buf.data(), size));
}

/// The "time" member (Unix seconds) of a Zygo time-stamp compound attribute.
std::optional<long long> attr_timestamp(hid_t obj, const char* name) {
  H5Id a = open_scalar_attr(obj, name);
  if (!a.ok()) return std::nullopt;
  H5Id type(H5Aget_type(a.get()), H5Tclose);
  if (!type.ok() || H5Tget_class(type.get()) != H5T_COMPOUND) return std::nullopt;
  int idx = H5Tget_member_index(type.get(), "time");
  if (idx < 0) return std::nullopt;
  H5Id mtype(H5Tget_member_type(type.get(), static_cast<unsigned>(idx)), H5Tclose);
  if (!mtype.ok() || H5Tget_class(mtype.get()) != H5T_INTEGER) return std::nullopt;
  H5Id mem(H5Tcreate(H5T_COMPOUND, sizeof(long long)), H5Tclose);
  if (!mem.ok() || H5Tinsert(mem.get(), "time", 0, H5T_NATIVE_LLONG) < 0) return std::nullopt;
  long long t = 0;
  if (H5Aread(a.get(), mem.get(), &t) < 0) return std::nullopt;
  return t;
}

struct Converter {
  std::string category, base_unit;
  std::vector<double> parameters;
};

/// Reads an X/Y/Z Converter compound {Category: vlen str, BaseUnit: vlen str,
/// Parameters: vlen<float64>}. nullopt when absent or of another shape.
std::optional<Converter> attr_converter(hid_t obj, const char* name) {
  H5Id a = open_scalar_attr(obj, name);
  if (!a.ok()) return std::nullopt;
  H5Id ftype(H5Aget_type(a.get()), H5Tclose);
  if (!ftype.ok() || H5Tget_class(ftype.get()) != H5T_COMPOUND) return std::nullopt;
  // Check the file type's members before asking HDF5 to convert.
  auto member_class = [&](const char* m) -> H5T_class_t {
    int i = H5Tget_member_index(ftype.get(), m);
    if (i < 0) return H5T_NO_CLASS;
    return H5Tget_member_class(ftype.get(), static_cast<unsigned>(i));
  };
  if (member_class("Category") != H5T_STRING || member_class("BaseUnit") != H5T_STRING ||
      member_class("Parameters") != H5T_VLEN)
    return std::nullopt;
  // Member layout must be sane (offset + size inside the compound): libhdf5 1.10 converts
  // whatever the header claims and can crash on a corrupt layout.
  {
    const std::size_t total = H5Tget_size(ftype.get());
    const int nm = H5Tget_nmembers(ftype.get());
    if (total == 0 || total > 4096 || nm <= 0 || nm > 16) return std::nullopt;
    for (int i = 0; i < nm; ++i) {
      H5Id mt(H5Tget_member_type(ftype.get(), static_cast<unsigned>(i)), H5Tclose);
      if (!mt.ok()) return std::nullopt;
      const std::size_t off = H5Tget_member_offset(ftype.get(), static_cast<unsigned>(i));
      const std::size_t sz = H5Tget_size(mt.get());
      if (sz == 0 || off > total || sz > total - off) return std::nullopt;
      const H5T_class_t mc = H5Tget_class(mt.get());
      // The type as opened describes the in-memory layout of vlen members.
      if (mc == H5T_VLEN && sz != sizeof(hvl_t)) return std::nullopt;
      if (mc == H5T_STRING && H5Tis_variable_str(mt.get()) > 0 && sz != sizeof(char*))
        return std::nullopt;
    }
  }
  {
    int i = H5Tget_member_index(ftype.get(), "Parameters");
    H5Id vt(H5Tget_member_type(ftype.get(), static_cast<unsigned>(i)), H5Tclose);
    if (!vt.ok()) return std::nullopt;
    H5Id base(H5Tget_super(vt.get()), H5Tclose);
    if (!base.ok() || H5Tget_class(base.get()) != H5T_FLOAT) return std::nullopt;
    for (const char* m : {"Category", "BaseUnit"}) {
      int k = H5Tget_member_index(ftype.get(), m);
      H5Id st(H5Tget_member_type(ftype.get(), static_cast<unsigned>(k)), H5Tclose);
      if (!st.ok() || H5Tis_variable_str(st.get()) <= 0) return std::nullopt;
    }
  }
  // Each member is read on its own (a one-member compound memory type): when HDF5 fails half
  // way through a multi-member vlen conversion it leaks what it had already converted.
  H5Id space(H5Aget_space(a.get()), H5Sclose);
  if (!space.ok()) return std::nullopt;
  auto read_member = [&](const char* member, hid_t member_type, void* out) {
    H5Id mem(H5Tcreate(H5T_COMPOUND, H5Tget_size(member_type)), H5Tclose);
    if (!mem.ok() || H5Tinsert(mem.get(), member, 0, member_type) < 0) return false;
    if (H5Aread(a.get(), mem.get(), out) < 0) return false;
    return true;
  };
  auto reclaim = [&](hid_t member_type, void* buf) {
#if H5_VERSION_GE(1, 12, 0)
    H5Treclaim(member_type, space.get(), H5P_DEFAULT, buf);
#else
    H5Dvlen_reclaim(member_type, space.get(), H5P_DEFAULT, buf);
#endif
  };
  H5Id str(H5Tcopy(H5T_C_S1), H5Tclose);
  if (!str.ok() || H5Tset_size(str.get(), H5T_VARIABLE) < 0) return std::nullopt;
  Converter c;
  for (auto [member, out] :
       {std::pair{"Category", &c.category}, std::pair{"BaseUnit", &c.base_unit}}) {
    char* p = nullptr;
    if (!read_member(member, str.get(), &p)) return std::nullopt;
    if (p != nullptr) *out = std::string(p, strnlen(p, 256));
    reclaim(str.get(), &p);
  }
  H5Id vlen(H5Tvlen_create(H5T_NATIVE_DOUBLE), H5Tclose);
  if (!vlen.ok()) return std::nullopt;
  hvl_t params{};
  if (!read_member("Parameters", vlen.get(), &params)) return std::nullopt;
  if (params.p != nullptr && params.len <= 64) {
    const double* p = static_cast<const double*>(params.p);
    c.parameters.assign(p, p + params.len);
  }
  reclaim(vlen.get(), &params);
  return c;
}

/// Name of the first link under `group` that is a dataset (by creation order of names).
std::optional<std::string> first_dataset(hid_t file, const char* group) {
  if (H5Lexists(file, "/Data", H5P_DEFAULT) <= 0 || hard_link_type(file, group) != H5I_GROUP)
    return std::nullopt;
  H5Id g(H5Gopen2(file, group, H5P_DEFAULT), H5Gclose);
  if (!g.ok()) return std::nullopt;
  H5G_info_t ginfo;
  if (H5Gget_info(g.get(), &ginfo) < 0) return std::nullopt;
  const hsize_t n = ginfo.nlinks < 1024 ? ginfo.nlinks : 1024;
  for (hsize_t i = 0; i < n; ++i) {
    char buf[512];
    ssize_t len = H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, buf, sizeof buf,
                                     H5P_DEFAULT);
    if (len <= 0 || static_cast<std::size_t>(len) >= sizeof buf) continue;
    if (hard_link_type(g.get(), buf) == H5I_DATASET) return std::string(group) + "/" + buf;
  }
  return std::nullopt;
}

/// The /Attributes/{GUID} group holding "Data Context.Data Attributes.*" metadata.
H5Id metadata_group(hid_t file) {
  if (hard_link_type(file, "/Attributes") != H5I_GROUP) return {};
  H5Id g(H5Gopen2(file, "/Attributes", H5P_DEFAULT), H5Gclose);
  if (!g.ok()) return {};
  H5G_info_t ginfo;
  if (H5Gget_info(g.get(), &ginfo) < 0) return {};
  const hsize_t n = ginfo.nlinks < 64 ? ginfo.nlinks : 64;
  for (hsize_t i = 0; i < n; ++i) {
    char buf[512];
    ssize_t len = H5Lget_name_by_idx(g.get(), ".", H5_INDEX_NAME, H5_ITER_INC, i, buf, sizeof buf,
                                     H5P_DEFAULT);
    if (len <= 0 || static_cast<std::size_t>(len) >= sizeof buf) continue;
    if (hard_link_type(g.get(), buf) != H5I_GROUP) continue;
    H5Id sub(H5Gopen2(g.get(), buf, H5P_DEFAULT), H5Gclose);
    if (sub.ok() && attr_exists(sub.get(), "Data Context.Data Attributes.System Type")) return sub;
  }
  return {};
}

/// Metres per unit for a Zygo unit name; 0 for unknown, -1 for "Fringes", -2 for "Waves".
double zygo_unit(const std::string& u) {
  if (u == "Meters") return 1;
  if (u == "MilliMeters" || u == "MiliMeters" || u == "Millimeters") return 1e-3;
  if (u == "MicroMeters" || u == "Micrometers") return 1e-6;
  if (u == "NanoMeters" || u == "Nanometers") return 1e-9;
  if (u == "Angstroms") return 1e-10;
  if (u == "Fringes") return -1;
  if (u == "Waves") return -2;
  return 0;
}

std::string iso_utc(long long t) {
  std::time_t tt = static_cast<std::time_t>(t);
  std::tm tm{};
  if (gmtime_r(&tt, &tm) == nullptr) return "";
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::mutex g_hdf5_mutex;

/// Checks every HDF5 global heap collection ("GCOL") in the image before libhdf5 sees it.
/// Variable-length strings and sequences live in these heaps, and libhdf5 1.10 trusts the
/// object sizes stored there: an object running past its collection makes H5HG_read copy
/// beyond the heap buffer, and a zero-sized free-space object makes the collection loader
/// loop forever. Any collection that is inconsistent makes the file corrupt. (The signature is
/// looked for at every offset, since the heap addresses are only known to libhdf5.)
void check_global_heaps(const ByteReader& r) {
  const auto d = r.data();
  const std::size_t n = d.size();
  // Size of "lengths" from the superblock (byte 14 for versions 0/1, byte 10 for 2/3).
  const unsigned L = d[8] <= 1 ? d[14] : d[10];
  if (L != 2 && L != 4 && L != 8)
    r.fail("corrupt HDF5 superblock (size of lengths " + std::to_string(L) + ")");
  auto len_at = [&](std::size_t off) {
    std::uint64_t v = 0;
    for (unsigned i = 0; i < L; ++i) v |= std::uint64_t{d[off + i]} << (8 * i);
    return v;
  };
  auto align8 = [](std::uint64_t v) { return (v + 7) & ~std::uint64_t{7}; };
  const std::uint64_t hdr = align8(8 + L), objhdr = align8(8 + L);
  for (std::size_t p = 0; p + 4 <= n; ++p) {
    if (d[p] != 'G' || d[p + 1] != 'C' || d[p + 2] != 'O' || d[p + 3] != 'L') continue;
    if (hdr > n - p)
      r.fail("corrupt HDF5 global heap at offset " + std::to_string(p) + ": truncated");
    const std::uint64_t size = len_at(p + 8);
    if (size < hdr || size > n - p)
      r.fail("corrupt HDF5 global heap at offset " + std::to_string(p) + ": collection size " +
             std::to_string(size) + " does not fit the file");
    const std::uint64_t end = p + size;
    std::uint64_t q = p + hdr;
    while (q < end && objhdr <= end - q) {
      const unsigned idx = d[q] | (d[q + 1] << 8);
      const std::uint64_t osize = len_at(q + 8);
      const std::uint64_t room = end - q;
      if (osize > room)
        r.fail("corrupt HDF5 global heap at offset " + std::to_string(p) + ": object " +
               std::to_string(idx) + " of " + std::to_string(osize) +
               " bytes runs past its collection");
      const std::uint64_t need = idx > 0 ? objhdr + align8(osize) : osize;
      if (need > room || need < objhdr)
        r.fail("corrupt HDF5 global heap at offset " + std::to_string(p) + ": bad object " +
               std::to_string(idx) + " size " + std::to_string(osize));
      q += need;
    }
  }
}

Surface read_datx_locked(const ByteReader& r) {
  const auto data = r.data();
  static const std::uint8_t kMagic[8] = {0x89, 'H', 'D', 'F', 0x0D, 0x0A, 0x1A, 0x0A};
  if (r.size() < 8 || std::memcmp(data.data(), kMagic, 8) != 0)
    r.fail("not a Zygo .datx file (HDF5 signature missing at offset 0)");
  // Superblock version (byte 8): 0..3 are defined; anything else is corrupt.
  if (r.size() < 48)
    r.fail("truncated: " + std::to_string(r.size()) + " bytes, no HDF5 superblock");
  if (data[8] > 3) r.fail("corrupt HDF5 superblock (version " + std::to_string(data[8]) + ")");
  check_global_heaps(r);

  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  H5Id fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  if (!fapl.ok() || H5Pset_fapl_core(fapl.get(), 1 << 20, 0) < 0 ||
      H5Pset_file_image(fapl.get(), const_cast<std::uint8_t*>(data.data()), data.size()) < 0)
    r.fail("cannot set up HDF5 in-memory access");
  // The core driver refuses a name that exists on disk, so the image gets a name of its own
  // (in a directory that does not exist), unique per open.
  static unsigned long counter = 0;
  const std::string image_name =
      "/nonexistent-microbrdf-datx-image/" + std::to_string(++counter) + ".h5";
  H5Id file(H5Fopen(image_name.c_str(), H5F_ACC_RDONLY, fapl.get()), H5Fclose);
  if (!file.ok()) r.fail("corrupt or truncated HDF5 container (libhdf5 cannot open it)");

  auto path = first_dataset(file.get(), "/Data/Surface");
  if (!path) r.fail("no surface: /Data/Surface holds no dataset");
  H5Id ds(H5Dopen2(file.get(), path->c_str(), H5P_DEFAULT), H5Dclose);
  if (!ds.ok()) r.fail("cannot open the surface dataset " + *path);

  H5Id space(H5Dget_space(ds.get()), H5Sclose);
  if (!space.ok() || H5Sget_simple_extent_type(space.get()) != H5S_SIMPLE ||
      H5Sget_simple_extent_ndims(space.get()) != 2)
    r.fail("surface dataset " + *path + " is not a 2-D array");
  hsize_t dims[2] = {0, 0};
  if (H5Sget_simple_extent_dims(space.get(), dims, nullptr) != 2)
    r.fail("cannot read the dimensions of " + *path);
  const std::uint64_t ny = dims[0], nx = dims[1];

  H5Id type(H5Dget_type(ds.get()), H5Tclose);
  if (!type.ok() || H5Tget_class(type.get()) != H5T_FLOAT)
    r.fail("surface dataset " + *path + " is not floating point");
  const std::size_t elem = H5Tget_size(type.get());
  if (elem != 4 && elem != 8)
    r.fail("surface dataset has " + std::to_string(elem) + "-byte floats (expected 4 or 8)");

  H5Id dcpl(H5Dget_create_plist(ds.get()), H5Pclose);
  if (!dcpl.ok()) r.fail("cannot read the storage properties of " + *path);
  const int nfilters = H5Pget_nfilters(dcpl.get());
  if (nfilters < 0) r.fail("cannot read the filters of " + *path);
  for (int i = 0; i < nfilters; ++i) {
    unsigned flags = 0;
    std::size_t nelmts = 0;
    unsigned cd[1];
    char fname[64] = {0};
    unsigned fconfig = 0;
    H5Z_filter_t f = H5Pget_filter2(dcpl.get(), static_cast<unsigned>(i), &flags, &nelmts, cd,
                                    sizeof fname, fname, &fconfig);
    if (f < 0 || H5Zfilter_avail(f) <= 0)
      r.fail("surface dataset uses HDF5 filter " + std::to_string(f) +
             " which this build of libhdf5 does not provide");
  }
  if (nfilters == 0) {
    // Unfiltered: every stored sample must be in the file.
    check_grid(r, nx, ny, elem, r.size());
  } else {
    // Compressed: bound by a generous decompression ratio.
    check_grid(r, nx, ny, 0, 0);
    if (nx * ny * elem > std::uint64_t{1024} * r.size())
      r.fail("corrupt: compressed surface of " + std::to_string(nx) + " x " + std::to_string(ny) +
             " samples cannot come from a " + std::to_string(r.size()) + "-byte file");
  }
  if (H5Pget_layout(dcpl.get()) == H5D_CONTIGUOUS) {
    const haddr_t off = H5Dget_offset(ds.get());
    if (off != HADDR_UNDEF && (off > r.size() || nx * ny * elem > r.size() - off))
      r.fail("truncated: surface data (" + std::to_string(nx * ny * elem) + " bytes at offset " +
             std::to_string(off) + ") run past the end of the " + std::to_string(r.size()) +
             "-byte file");
  }

  Surface s;
  s.nx = nx;
  s.ny = ny;
  const std::size_t n = nx * ny;
  s.z.assign(n, 0.0);
  s.valid.assign(n, 1);
  if (H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.z.data()) < 0)
    r.fail("cannot read the surface data of " + *path + " (corrupt or truncated)");

  // Heights.
  const hid_t d = ds.get();
  const std::string unit = attr_string(d, "Unit").value_or("");
  double k = zygo_unit(unit);
  if (k == 0)
    r.fail("surface unit '" + clean_text(unit) + "' is not supported (expected Fringes, Waves, " +
           "Meters, MilliMeters, MicroMeters, NanoMeters or Angstroms)");
  const auto wavelength = attr_double(d, "Wavelength");
  const auto scale = attr_double(d, "Interferometric Scale Factor");
  const auto obliquity = attr_double(d, "Obliquity Factor");
  if (k < 0) {
    if (!wavelength || !std::isfinite(*wavelength) || !(*wavelength > 0))
      r.fail("surface is in " + unit + " but the Wavelength attribute is missing or invalid");
    if (k == -1) {
      const double sf = scale.value_or(std::numeric_limits<double>::quiet_NaN());
      const double ob = obliquity.value_or(1.0);
      if (!std::isfinite(sf) || sf == 0 || !std::isfinite(ob) || ob == 0)
        r.fail(
            "surface is in Fringes but the Interferometric Scale Factor / Obliquity Factor "
            "attributes are missing or invalid");
      k = *wavelength * sf * ob;
    } else {
      k = *wavelength;
    }
  }
  const double no_data =
      attr_double(d, "No Data").value_or(std::numeric_limits<double>::infinity());
  std::size_t n_nodata = 0;
  for (double& v : s.z) {
    if (!std::isfinite(v) || (!std::isnan(no_data) && v >= no_data)) {
      v = std::numeric_limits<double>::quiet_NaN();
      ++n_nodata;
    } else {
      v *= k;
    }
  }

  // Lateral resolution: X/Y Converter Parameters[1] (metres per pixel).
  auto& m = s.meta;
  auto lateral = [&](const char* conv_name) -> double {
    auto c = attr_converter(d, conv_name);
    if (c && c->category == "LateralCat" && c->base_unit == "Pixels" && c->parameters.size() >= 2)
      return c->parameters[1];
    return std::numeric_limits<double>::quiet_NaN();
  };
  double dx = lateral("X Converter"), dy = lateral("Y Converter");
  std::string spacing_source = "X/Y Converter";
  H5Id meta_group = metadata_group(file.get());
  if (!std::isfinite(dx) || !std::isfinite(dy)) {
    spacing_source = "Lateral Resolution attribute";
    dx = dy = std::numeric_limits<double>::quiet_NaN();
    if (meta_group.ok()) {
      for (const char* key : {"Surface Data Context.Lateral Resolution:Value",
                              "Data Context.Lateral Resolution:Value"}) {
        if (auto v = attr_double(meta_group.get(), key)) {
          dx = dy = *v;
          break;
        }
      }
    }
  }
  if (!std::isfinite(dx) || !std::isfinite(dy) || dx < 0 || dy < 0) {
    dx = dy = 0;
    spacing_source = "none";
  }
  s.dx = dx;
  s.dy = dy;
  if (dx == 0 || dy == 0) m.set("uncalibrated_lateral", "true");
  if (std::fabs(dx - 1e-3) < 1e-9 && std::fabs(dy - 1e-3) < 1e-9)  // 1 mm (stored as float32)
    m.set("lateral_resolution_note",
          "stored spacing is exactly 1 mm per pixel, which looks like an uncalibrated default; "
          "pass --spacing if the true pixel size is known");
  m.set("lateral_resolution_source", spacing_source);

  m.format = "datx";
  m.z_unit_in_file = unit;
  m.set("surface_dataset", *path);
  if (wavelength) m.set("wavelength_m", num(*wavelength));
  if (scale) m.set("interferometric_scale_factor", num(*scale));
  if (obliquity) m.set("obliquity_factor", num(*obliquity));
  if (std::isfinite(no_data)) m.set("no_data_value", num(no_data));
  m.set("no_data_points", std::to_string(n_nodata));

  if (meta_group.ok()) {
    const hid_t g = meta_group.get();
    auto get = [&](const char* key) {
      return clean_text(attr_string(g, (std::string("Data Context.Data Attributes.") + key).c_str())
                            .value_or(""));
    };
    const std::string sys = get("System Type"), serial = get("System Serial Number");
    m.instrument = "Zygo";
    if (!sys.empty()) m.instrument += " " + sys;
    if (!serial.empty()) m.instrument += " (serial " + serial + ")";
    const std::string sw = get("Software Info Name"), ver = get("Software Info Version");
    if (!sw.empty()) m.set("software", sw + (ver.empty() ? "" : " " + ver));
    m.comment = get("Comment");
    for (auto [key, label] :
         {std::pair{"Acquisition Mode", "acquisition_mode"}, std::pair{"Objective", "objective"},
          std::pair{"Part Number", "part_name"}, std::pair{"Part Serial Number", "part_serial"}}) {
      std::string v = get(key);
      if (!v.empty()) m.set(label, v);
    }
    // Unix seconds; values before 1980 are unset placeholders (zygo_test.datx has 719529,
    // which is MATLAB's day number of 1970-01-01), so they are kept only as raw metadata.
    if (auto t = attr_timestamp(g, "Data Context.Data Attributes.Time Stamp")) {
      if (*t >= 315532800 && *t < 32503680000LL)
        m.date = iso_utc(*t);
      else
        m.set("time_stamp_raw", std::to_string(*t));
    }
  } else {
    m.instrument = "Zygo";
  }
  return s;
}

}  // namespace

Surface read_datx(Bytes data, const std::string& name) {
  ByteReader r(data, name);
  // libhdf5 1.10 can leak, crash or ask for absurd allocations on corrupt files even after the
  // checks above (fuzz/repro/), so it decodes in a child process (surface/isolated_reader.hpp).
  // libhdf5 is loaded here, before the fork, not in the child: dlopen in a child forked from a
  // process whose other threads may hold the dynamic loader's lock could wait forever.
  load_hdf5(name);
  return read_isolated(name, "libhdf5", [&] {
    std::lock_guard<std::mutex> lock(g_hdf5_mutex);
    return read_datx_locked(r);
  });
}

}  // namespace microbrdf::detail

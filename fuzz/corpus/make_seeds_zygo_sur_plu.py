#!/usr/bin/env python3
"""Writes small (< 16 KB) valid seed files for the fuzz_dat, fuzz_datx, fuzz_sur and fuzz_plu
targets into fuzz/corpus/{dat,datx,sur,plu}/.

The real fixtures are large, so each seed keeps a real file's header and shrinks the grid to
8 x 6 with matching data (a few invalid points included). The header fixtures are read from
tests/data/ (metropro-1.dat, sur-2.sur, plu-1-heights.plu).

The .datx seed is a small HDF5 file with the structure of zygo_test.datx (a /Data/Surface
dataset with Unit, No Data, Wavelength, scale factors and X/Y Converter attributes, plus an
/Attributes/{GUID} metadata group). Python has no HDF5 module here, so the script compiles and
runs a tiny C program against libhdf5 (needs cc and libhdf5-dev; skipped otherwise).

Usage: python3 fuzz/corpus/make_seeds_zygo_sur_plu.py   (from the repository root or anywhere)
"""
import os
import shutil
import struct
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", ".."))
TEST_DATA = os.path.join(ROOT, "tests", "data")

NX, NY = 8, 6


def write(sub, name, data):
    d = os.path.join(HERE, sub)
    os.makedirs(d, exist_ok=True)
    assert len(data) < 16 * 1024, (name, len(data))
    with open(os.path.join(d, name), "wb") as f:
        f.write(data)
    print(f"{sub}/{name}: {len(data)} bytes")


def read(path):
    with open(path, "rb") as f:
        return f.read()


# ---- MetroPro .dat -----------------------------------------------------------------------
def dat_seeds():
    src = read(os.path.join(TEST_DATA, "metropro-1.dat"))
    hsize = struct.unpack_from(">I", src, 6)[0]
    h = bytearray(src[:hsize])

    def build(h, buckets, phase_res=1, sign=0, lateral=None, invalid=(5, 17)):
        h = bytearray(h)
        struct.pack_into(">HHH", h, 52, NX, NY, buckets)
        struct.pack_into(">I", h, 60, 2 * NX * NY * buckets)
        struct.pack_into(">HH", h, 68, NX, NY)
        struct.pack_into(">I", h, 72, 4 * NX * NY)
        struct.pack_into(">h", h, 218, phase_res)
        struct.pack_into(">h", h, 232, sign)
        if lateral is not None:
            struct.pack_into(">f", h, 184, lateral)
        out = bytes(h)
        for _ in range(buckets):
            out += b"".join(struct.pack(">H", 35 + (i % 100)) for i in range(NX * NY))
        phase = []
        for i in range(NX * NY):
            v = 2147483647 if i in invalid else 5800000 + 1000 * (i % NX) - 700 * (i // NX)
            phase.append(struct.pack(">i", v))
        return out + b"".join(phase)

    write("dat", "metropro_8x6.dat", build(h, 1))
    write("dat", "metropro_8x6_nointensity_res2_sign.dat", build(h, 0, phase_res=2, sign=1))
    write("dat", "metropro_8x6_uncalibrated.dat", build(h, 2, phase_res=0, lateral=0.0))


# ---- Digital Surf .sur -------------------------------------------------------------------
def sur_seeds():
    src = read(os.path.join(TEST_DATA, "sur-2.sur"))
    h = bytearray(src[:512])
    zmin = 89120

    def build(bits, comment=b"", special=1):
        hh = bytearray(h)
        struct.pack_into("<H", hh, 86, special)
        struct.pack_into("<H", hh, 98, bits)
        lo = zmin if bits == 32 else -1000
        struct.pack_into("<iiiiI", hh, 100, lo, lo + 5000, NX, NY, NX * NY)
        struct.pack_into("<HH", hh, 334, len(comment), 0)
        fmt = "<i" if bits == 32 else "<h"
        pts = []
        for i in range(NX * NY):
            v = lo - 2 if i in (3, 30) else lo + 50 * (i % NX) + 37 * (i // NX)
            pts.append(struct.pack(fmt, v))
        return bytes(hh) + comment + b"".join(pts)

    write("sur", "sur_8x6_int32.sur", build(32))
    write("sur", "sur_8x6_int16_comment.sur", build(16, comment=b"seed comment \xb5m"))
    write("sur", "sur_8x6_nospecial.sur", build(32, special=0))


# ---- Sensofar .plu -----------------------------------------------------------------------
def plu_seeds():
    path = os.path.join(TEST_DATA, "plu-1-heights.plu")
    if not os.path.exists(path):
        print("plu: skipped (" + path + " not found)")
        return
    h = bytearray(read(path)[:500])
    struct.pack_into("<II", h, 388, NY, NX)  # calibration grid
    out = bytes(h) + struct.pack("<II", NY, NX)
    vals = []
    for i in range(NX * NY):
        vals.append(1000001.0 if i == 9 else -111.0 + 0.01 * (i % NX) + 0.02 * (i // NX))
    out += b"".join(struct.pack("<f", v) for v in vals)
    good = [v for v in vals if v != 1000001.0]
    out += struct.pack("<ff", min(good), max(good))
    write("plu", "plu_8x6.plu", out)


# ---- Zygo .datx (HDF5) -------------------------------------------------------------------
DATX_C = r"""
#include <hdf5.h>
#include <stdlib.h>
#include <string.h>
static void str_attr(hid_t loc, const char* name, const char* value) {
  hid_t t = H5Tcopy(H5T_C_S1); H5Tset_size(t, H5T_VARIABLE);
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, t, &value); H5Aclose(a); H5Sclose(sp); H5Tclose(t);
}
static void dbl_attr(hid_t loc, const char* name, double v) {
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, H5T_IEEE_F64LE, sp, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, H5T_NATIVE_DOUBLE, &v); H5Aclose(a); H5Sclose(sp);
}
typedef struct { char* cat; char* base; hvl_t params; } Conv;
static void conv_attr(hid_t loc, const char* name, const char* cat, const char* base,
                      double* p, size_t n) {
  hid_t s = H5Tcopy(H5T_C_S1); H5Tset_size(s, H5T_VARIABLE);
  hid_t v = H5Tvlen_create(H5T_NATIVE_DOUBLE);
  hid_t t = H5Tcreate(H5T_COMPOUND, sizeof(Conv));
  H5Tinsert(t, "Category", HOFFSET(Conv, cat), s);
  H5Tinsert(t, "BaseUnit", HOFFSET(Conv, base), s);
  H5Tinsert(t, "Parameters", HOFFSET(Conv, params), v);
  Conv c = {(char*)cat, (char*)base, {n, p}};
  hid_t sp = H5Screate(H5S_SCALAR);
  hid_t a = H5Acreate2(loc, name, t, sp, H5P_DEFAULT, H5P_DEFAULT);
  H5Awrite(a, t, &c); H5Aclose(a); H5Sclose(sp); H5Tclose(t); H5Tclose(v); H5Tclose(s);
}
int main(int argc, char** argv) {
  const int nx = 8, ny = 6;
  const char* unit = argc > 2 ? argv[2] : "Fringes";
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
  H5Pset_libver_bounds(fapl, H5F_LIBVER_EARLIEST, H5F_LIBVER_LATEST);
  hid_t f = H5Fcreate(argv[1], H5F_ACC_TRUNC, H5P_DEFAULT, fapl);
  hid_t ga = H5Gcreate2(f, "/Attributes", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hid_t gg = H5Gcreate2(ga, "{846C2331-6472-411F-9024-179B928C018D}", H5P_DEFAULT, H5P_DEFAULT,
                        H5P_DEFAULT);
  str_attr(gg, "Data Context.Data Attributes.System Type", "GPI");
  str_attr(gg, "Data Context.Data Attributes.System Serial Number", "12345");
  str_attr(gg, "Data Context.Data Attributes.Software Info Name", "MetroPro");
  str_attr(gg, "Data Context.Data Attributes.Software Info Version", "8.3.3");
  str_attr(gg, "Data Context.Data Attributes.Acquisition Mode", "PSI");
  str_attr(gg, "Data Context.Data Attributes.Comment", "seed");
  dbl_attr(gg, "Data Context.Lateral Resolution:Value", 2e-6);
  H5Gclose(gg); H5Gclose(ga);
  hid_t gd = H5Gcreate2(f, "/Data", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hid_t gs = H5Gcreate2(gd, "Surface", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  hsize_t dims[2] = {ny, nx};
  hid_t sp = H5Screate_simple(2, dims, NULL);
  hid_t ds = H5Dcreate2(gs, "{1CE20D93-8A91-4847-9CEF-B83B2F42271E}", H5T_IEEE_F64LE, sp,
                        H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  double z[6 * 8];
  for (int i = 0; i < nx * ny; ++i) z[i] = 0.01 * (i % nx) - 0.02 * (i / nx);
  z[4] = 1.7976931348623157e308; z[20] = 1.7976931348623157e308;
  H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, z);
  str_attr(ds, "Unit", unit);
  dbl_attr(ds, "No Data", 1.7976931348623157e308);
  dbl_attr(ds, "Wavelength", 632.8e-9);
  dbl_attr(ds, "Interferometric Scale Factor", 0.5);
  dbl_attr(ds, "Obliquity Factor", 1.0);
  double px[4] = {1, 2e-6, 0, 0}, pz[4] = {0, 632.8e-9, 0.5, 1};
  conv_attr(ds, "X Converter", "LateralCat", "Pixels", px, 4);
  conv_attr(ds, "Y Converter", "LateralCat", "Pixels", px, 4);
  conv_attr(ds, "Z Converter", "HeightCat", "Fringes", pz, 4);
  H5Dclose(ds); H5Sclose(sp); H5Gclose(gs); H5Gclose(gd); H5Fclose(f); H5Pclose(fapl);
  return 0;
}
"""


def datx_seeds():
    cc = shutil.which("cc") or shutil.which("gcc")
    inc = "/usr/include/hdf5/serial"
    lib = "/usr/lib/x86_64-linux-gnu/hdf5/serial"
    if cc is None or not os.path.exists(os.path.join(inc, "hdf5.h")):
        print("datx: skipped (needs cc and libhdf5-dev)")
        return
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, "mk.c")
        exe = os.path.join(tmp, "mk")
        with open(src, "w") as f:
            f.write(DATX_C)
        subprocess.run([cc, src, "-o", exe, "-I" + inc, "-L" + lib, "-lhdf5"], check=True)
        for unit, name in (("Fringes", "datx_8x6_fringes.datx"),
                           ("NanoMeters", "datx_8x6_nm.datx")):
            out = os.path.join(tmp, name)
            subprocess.run([exe, out, unit], check=True,
                           env=dict(os.environ, LD_LIBRARY_PATH=lib))
            write("datx", name, read(out))


if __name__ == "__main__":
    dat_seeds()
    sur_seeds()
    plu_seeds()
    datx_seeds()
    sys.exit(0)

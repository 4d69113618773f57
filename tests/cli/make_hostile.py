#!/usr/bin/env python3
"""Writes small hostile input files for the CLI tests (nothing big is committed).

usage: make_hostile.py KIND OUT [N]
  x3p-zeros      x3p whose bindata/data.bin is N x N float32 zeros (deflated: ~1 MB for 16384)
  x3p-datalist   x3p whose main.xml holds a DataList of N empty <Datum/> (SizeX N, SizeY 1)
  tiff-deflate   float TIFF N x N, deflate, one strip of 1 MB of junk
  exr-junk       float EXR N x N (ZIP), chunks of junk (~1 MB)
  paramtex-junk  a parameter-texture EXR (alpha_x ... theta_z, valid) N x N of junk (~1 MB)
  deep-json      N levels of nested objects: {"a":{"a": ... }}  (text only, appended by the test)
"""
import io
import os
import struct
import sys
import zipfile
import zlib

kind, out = sys.argv[1], sys.argv[2]
n = int(sys.argv[3]) if len(sys.argv) > 3 else 0

MAIN_XML = """<?xml version="1.0" encoding="UTF-8"?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2">
<Record1><Revision>ISO5436 - 2000</Revision><FeatureType>{feature}</FeatureType><Axes>
<CX><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-07</Increment><Offset>0</Offset></CX>
<CY><AxisType>I</AxisType><DataType>D</DataType><Increment>1e-07</Increment><Offset>0</Offset></CY>
<CZ><AxisType>A</AxisType><DataType>F</DataType></CZ></Axes></Record1>
<Record3><MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
{data}</Record3></p:ISO5436_2>
"""


def x3p_zeros(path, n):
    xml = MAIN_XML.format(feature="SUR", nx=n, ny=n,
                          data="<DataLink><PointDataLink>bindata/data.bin</PointDataLink></DataLink>")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("main.xml", xml)
        with z.open("bindata/data.bin", "w", force_zip64=True) as f:
            row = bytes(4 * n)
            for _ in range(n):
                f.write(row)


def x3p_datalist(path, n):
    head, tail = MAIN_XML.format(feature="PRF", nx=n, ny=1, data="<DataList>@</DataList>").split("@")
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        with z.open("main.xml", "w", force_zip64=True) as f:
            f.write(head.encode())
            block = b"<Datum/>" * 65536
            left = n
            while left > 0:
                k = min(left, 65536)
                f.write(block if k == 65536 else b"<Datum/>" * k)
                left -= k
            f.write(tail.encode())


def tiff_deflate(path, n):
    junk = os.urandom(1 << 20)
    entries = [  # tag, type (3 SHORT, 4 LONG), value
        (256, 4, n), (257, 4, n), (258, 3, 32), (259, 3, 8), (262, 3, 1), (273, 4, 0),
        (277, 3, 1), (278, 4, n), (279, 4, len(junk)), (339, 3, 3)]
    ifd_off = 8
    data_off = ifd_off + 2 + 12 * len(entries) + 4
    b = io.BytesIO()
    b.write(b"II*\0" + struct.pack("<I", ifd_off))
    b.write(struct.pack("<H", len(entries)))
    for tag, typ, val in entries:
        if tag == 273:
            val = data_off
        b.write(struct.pack("<HHI", tag, typ, 1))
        b.write(struct.pack("<HH", val, 0) if typ == 3 else struct.pack("<I", val))
    b.write(struct.pack("<I", 0))
    b.write(junk)
    open(path, "wb").write(b.getvalue())


def exr_attr(name, typ, value):
    return name.encode() + b"\0" + typ.encode() + b"\0" + struct.pack("<i", len(value)) + value


def exr_junk(path, n, channels):
    chlist = b"".join(c.encode() + b"\0" + struct.pack("<iBBBBii", 2, 0, 0, 0, 0, 1, 1)
                      for c in sorted(channels)) + b"\0"
    box = struct.pack("<iiii", 0, 0, n - 1, n - 1)
    hdr = b"\x76\x2f\x31\x01" + struct.pack("<I", 2)
    hdr += exr_attr("channels", "chlist", chlist)
    hdr += exr_attr("compression", "compression", b"\x03")  # ZIP, 16 lines per chunk
    hdr += exr_attr("dataWindow", "box2i", box)
    hdr += exr_attr("displayWindow", "box2i", box)
    hdr += exr_attr("lineOrder", "lineOrder", b"\0")
    hdr += exr_attr("pixelAspectRatio", "float", struct.pack("<f", 1))
    hdr += exr_attr("screenWindowCenter", "v2f", struct.pack("<ff", 0, 0))
    hdr += exr_attr("screenWindowWidth", "float", struct.pack("<f", 1))
    hdr += b"\0"
    chunks = (n + 15) // 16
    per = max(16, (1 << 20) // chunks)
    start = len(hdr) + 8 * chunks
    table = b"".join(struct.pack("<Q", start + i * (8 + per)) for i in range(chunks))
    body = b"".join(struct.pack("<ii", 16 * i, per) + os.urandom(per) for i in range(chunks))
    open(path, "wb").write(hdr + table + body)


if kind == "x3p-zeros":
    x3p_zeros(out, n or 16384)
elif kind == "x3p-datalist":
    x3p_datalist(out, n or 33_000_000)
elif kind == "tiff-deflate":
    tiff_deflate(out, n or 16000)
elif kind == "exr-junk":
    exr_junk(out, n or 16384, ["Z"])
elif kind == "paramtex-junk":
    exr_junk(out, n or 16384, ["alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z", "valid"])
elif kind == "deep-json":
    open(out, "w").write('{"a":' * n + "1" + "}" * n)
else:
    sys.exit("unknown kind " + kind)

#!/usr/bin/env python3
"""Seeds for fuzz_hdr (Radiance RGBE): small synthetic images, flat and new-style RLE.

Usage: python3 fuzz/corpus/make_seeds_hdr.py fuzz/corpus/hdr
"""
import math
import os
import sys


def rgbe(r, g, b):
    m = max(r, g, b)
    if m < 1e-32:
        return bytes([0, 0, 0, 0])
    e = math.frexp(m)[1]
    s = 256.0 / 2.0**e
    return bytes([int(r * s), int(g * s), int(b * s), e + 128])


def rle_channel(vals):
    """New-style run-length encoding of one channel of one scanline."""
    out, i, n = bytearray(), 0, len(vals)
    while i < n:
        run = 1
        while i + run < n and run < 127 and vals[i + run] == vals[i]:
            run += 1
        if run >= 3:
            out += bytes([128 + run, vals[i]])
            i += run
        else:
            j = i
            while j < n and j - i < 128 and not (j + 2 < n and vals[j] == vals[j + 1] == vals[j + 2]):
                j += 1
            out += bytes([j - i]) + bytes(vals[i:j])
            i = j
    return out


def write(path, w, h, pix, rle, magic=b"#?RADIANCE"):
    data = bytearray(magic + b"\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n")
    data += b"-Y %d +X %d\n" % (h, w)
    for y in range(h):
        row = [rgbe(*pix(x, y)) for x in range(w)]
        if rle:
            data += bytes([2, 2, w >> 8, w & 255])
            for ch in range(4):
                data += rle_channel([p[ch] for p in row])
        else:
            data += b"".join(row)
    open(path, "wb").write(data)


out = sys.argv[1]
os.makedirs(out, exist_ok=True)
write(f"{out}/flat_4x3.hdr", 4, 3, lambda x, y: (x + 0.5, y * 2.0, 0.25), False)
write(f"{out}/rle_16x4.hdr", 16, 4, lambda x, y: (1.0, 0.5 if x < 9 else 2.0, x * 0.1 * y), True)
write(f"{out}/rgbe_magic_8x2.hdr", 8, 2, lambda x, y: (1e3, 1e-3, 0.0), True, b"#?RGBE")

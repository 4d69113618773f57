#!/usr/bin/env bash
# Hostile measured-BRDF headers: tiny .bsdf and MERL files whose headers claim huge (or zero
# times huge) dimensions are refused by every command that reads them, naming the file, before
# any large allocation: peak RSS (GNU time) stays below 1 GiB and nothing is written.
set -u
BIN=$1
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*"; exit 1; }
cd "$T" || exit 1
[ -x /usr/bin/time ] || { echo "SKIP: /usr/bin/time (GNU time) not installed"; exit 0; }

/usr/bin/python3 - <<'PY' || fail "python could not write the files"
import struct
def tensor(fields):
    """An RGL tensor file v1.0: fields (name, dtype code, shape, data bytes), 8-byte aligned."""
    head = b"tensor_file\0" + bytes([1, 0]) + struct.pack("<I", len(fields))
    size = len(head) + sum(2 + len(n) + 2 + 1 + 8 + 8 * len(s) for n, _, s, _ in fields)
    off = (size + 7) // 8 * 8
    hdr, blobs = b"", b""
    for n, dt, s, d in fields:
        hdr += struct.pack("<H", len(n)) + n.encode() + struct.pack("<HBQ", len(s), dt, off + len(blobs))
        hdr += b"".join(struct.pack("<Q", x) for x in s)
        blobs += d + b"\0" * ((8 - len(d) % 8) % 8)
    out = head + hdr
    return out + b"\0" * (off - len(out)) + blobs
f32 = lambda *v: struct.pack("<%df" % len(v), *v)
H = 1 << 40
def material(nd, vn, lum, spec):
    return [("description", 1, [1], b"x"), ("jacobian", 1, [1], b"\1"),
            ("theta_i", 10, [2], f32(0, 1)), ("phi_i", 10, [1], f32(0)),
            ("ndf", 10, nd, b""), ("sigma", 10, nd, b""), ("vndf", 10, vn, b""),
            ("luminance", 10, lum, b""), ("spectra", 10, spec, b""), ("wavelengths", 10, [1], f32(550))]
files = {
    # 2^32 x 2^32 floats claimed by a 200-byte file.
    "big.bsdf": [("description", 1, [1], b"x"), ("ndf", 10, [1 << 32, 1 << 32], f32(1, 1))],
    # Zero times huge: no bytes needed, 2^40 nodes along one axis.
    "zero_huge.bsdf": material([0, H], [1, 2, 0, H], [1, 2, 0, 0], [1, 2, 1, 0, 0]),
    # Product that wraps around 2^64 to 0 elements.
    "wrap.bsdf": [("ndf", 10, [1 << 32, 1 << 32, 4], b"")],
    # A field count of 2^32 - 1.
    "count.bsdf": None,
}
for name, fields in files.items():
    data = tensor(fields) if fields is not None else b"tensor_file\0\1\0" + struct.pack("<I", 0xFFFFFFFF) + b"\0" * 64
    open(name, "wb").write(data)
open("huge.binary", "wb").write(struct.pack("<3i", 1 << 30, 1 << 30, 1 << 30) + b"\0" * 64)
open("neg.binary", "wb").write(struct.pack("<3i", -90, 90, 180) + b"\0" * 64)
open("wide.csv", "w").write(",".join(f"c{i}" for i in range(20000)) + "\n1\n")
PY

check() {  # name, command...
  local name=$1; shift
  /usr/bin/time -f "%M" -o rss "$@" >out 2>err
  local rc=$?
  [ $rc -eq 0 ] && fail "$name accepted: $*"
  [ $rc -ge 128 ] && fail "$name crashed (exit $rc): $*"
  grep -q "$name" err || fail "message does not name $name: $(cat err)"
  local kb; kb=$(tail -1 rss)
  [ "$kb" -lt 1048576 ] || fail "$name: peak RSS $kb KB"
  echo "$name: refused (exit $rc, peak RSS $kb KB): $(head -1 err | cut -c1-110)"
}
for f in big.bsdf zero_huge.bsdf wrap.bsdf count.bsdf huge.binary neg.binary; do
  check "$f" "$BIN" measured ndf "$f" -o eff.npy
  check "$f" "$BIN" export bsdf "$f" -o x.bsdf
done
"$BIN" generate gaussian --nx 64 --ny 64 -o scan.npy >/dev/null 2>&1 || fail "generate"
for f in big.bsdf zero_huge.bsdf wrap.bsdf count.bsdf huge.binary; do
  check "$f" "$BIN" export mitsuba --bsdf "$f" -o mi
  check "$f" "$BIN" predict scan.npy --no-render --measured "$f" -o rep --quiet
done
check wide.csv "$BIN" measured ndf wide.csv -o eff.npy
for f in eff.npy x.bsdf mi rep; do [ -e "$f" ] && fail "$f written despite the errors"; done
echo OK

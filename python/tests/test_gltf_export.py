"""mb.export_gltf: the .glb is read here with struct and json (no microbrdf code), and the GGX
widths and azimuth are recovered from the written roughness, anisotropyStrength and
anisotropyRotation by KHR_materials_anisotropy's definition (alpha_t = mix(r^2, 1, s^2) along the
rotated tangent, alpha_b = r^2); the base colour equals the normal-incidence colour of the CLI's
`brdf color`."""
import json
import math
import struct
import subprocess

import pytest

import microbrdf as mb


def read_glb(path):
    data = path.read_bytes()
    magic, version, length = struct.unpack_from("<4sII", data, 0)
    assert (magic, version, length) == (b"glTF", 2, len(data))
    jlen, jtype = struct.unpack_from("<I4s", data, 12)
    assert jtype == b"JSON" and jlen % 4 == 0
    doc = json.loads(data[20:20 + jlen])
    blen, btype = struct.unpack_from("<I4s", data, 20 + jlen)
    assert btype == b"BIN\0" and 28 + jlen + blen == len(data)
    return doc


@pytest.mark.parametrize("ax, ay, phi", [(0.1, 0.3, 0.5), (0.4, 0.02, -1.3), (0.2, 0.2, 0.0)])
def test_widths_recovered(tmp_path, ax, ay, phi):
    out = tmp_path / "m.glb"
    r = mb.export_gltf(out, model="ggx", alpha_x=ax, alpha_y=ay, phi=phi, metal="Cu")
    assert r["files"] == ["m.glb"] and r["output"] == str(out)
    mat = read_glb(out)["materials"][0]
    rough = mat["pbrMetallicRoughness"]["roughnessFactor"]
    ext = mat.get("extensions", {}).get("KHR_materials_anisotropy", {})
    s, rot = ext.get("anisotropyStrength", 0.0), ext.get("anisotropyRotation", 0.0)
    wide = rough**2 * (1 - s * s) + s * s
    narrow = rough**2
    want_wide, want_narrow, want_axis = (ax, ay, phi) if ax >= ay else (ay, ax, phi + math.pi / 2)
    assert abs(wide - want_wide) < 1e-6 and abs(narrow - want_narrow) < 1e-6
    if ax != ay:
        d = math.remainder(rot - want_axis, math.pi)
        assert abs(d) < 1e-6, (rot, want_axis)
    assert r["roughness"] == pytest.approx(rough, abs=0)
    assert any("Schlick" in w for w in r["warnings"])


def test_base_colour_is_brdf_color(tmp_path, cli):
    r = mb.export_gltf(tmp_path / "au.gltf", model="ggx", alpha=0.2, metal="Au")
    assert sorted(r["files"]) == ["au.bin", "au.gltf"]
    doc = json.loads((tmp_path / "au.gltf").read_text())
    base = doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"]
    colour = json.loads(subprocess.run([str(cli), "brdf", "color", "--metal", "Au", "--json"],
                                       check=True, capture_output=True, text=True).stdout)
    for got, want in zip(base[:3], colour["linear_srgb"]):
        assert got == pytest.approx(min(max(want, 0.0), 1.0), abs=1e-12)
    assert base[3] == 1.0 and doc["materials"][0]["pbrMetallicRoughness"]["metallicFactor"] == 1.0
    assert (tmp_path / "au.bin").stat().st_size == doc["buffers"][0]["byteLength"]


def test_errors(tmp_path):
    with pytest.raises(mb.InputError):
        mb.export_gltf(tmp_path / "l.glb", lambertian=0.5)
    with pytest.raises(mb.InputError):
        mb.export_gltf(tmp_path / "x.obj", model="ggx", alpha=0.2, metal="Al")
    with pytest.raises(mb.InputError):
        mb.export_gltf(tmp_path / "x.glb", model="ggx", alpha=0.2, metal="Al", bogus=1)
    assert list(tmp_path.iterdir()) == []

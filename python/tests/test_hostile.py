"""Hostile input from Python: file content that is not UTF-8, paths with a NUL or undecodable
bytes, counts that would exhaust memory. Each is an exception of the module's own classes
(FileError naming the file, InputError naming the argument), never UnicodeDecodeError, a pybind11
cast error, a silently truncated path or gigabytes allocated."""
import json
import os
import resource

import numpy as np
import pytest

import microbrdf as mb

from conftest import gaussian_surface


def max_rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


@pytest.fixture
def scan(tmp_path):
    """A small scan saved as .npy with its JSON sidecar."""
    path = tmp_path / "scan.npy"
    mb.Surface(gaussian_surface(48, 40), spacing=0.5e-6).save(path)
    return path


def scene_text(name=b"plane"):
    return (b'{"name": "' + name + b'", "tile": "100x100um", "materials": {"m": {"type": "mirror"}},'
            b' "objects": [{"type": "plane", "material": "m"}]}')


# --- file content that is not UTF-8 -------------------------------------------------------------

def check_text(value):
    """Every string the module hands back is a str that can be printed (encoded as UTF-8)."""
    if isinstance(value, dict):
        for k, v in value.items():
            check_text(k)
            check_text(v)
    elif isinstance(value, (list, tuple)):
        for v in value:
            check_text(v)
    elif isinstance(value, str):
        value.encode("utf-8", "surrogateescape")


@pytest.mark.parametrize("where", [b'"caf\xe9"', b'"\xff\xfe"', b'"ok", "note": "\x80"'])
def test_sidecar_not_utf8_is_a_file_error_naming_it(scan, where):
    side = scan.with_suffix(".json")
    text = side.read_bytes()
    side.write_bytes(text.replace(b'"source": ""', b'"source": ' + where))
    assert side.read_bytes() != text
    try:
        s = mb.read_surface(scan)
    except mb.FileError as e:  # refused: named, printable
        assert e.filename in (str(side), str(scan)), e.filename
        assert str(side.name) in str(e) or str(scan.name) in str(e)
        str(e).encode("utf-8")
    else:  # or read, with the text escaped
        check_text(s.metadata)
        check_text(repr(s))
    with pytest.raises(mb.FileError) as info:  # a byte that breaks the JSON itself
        side.write_bytes(b'{"dx_m": 1e-6, "\xff": ')
        mb.read_surface(scan)
    assert info.value.filename == str(side)
    str(info.value).encode("utf-8")


def test_scene_not_utf8_is_a_file_error_or_an_escaped_name(tmp_path):
    scene = tmp_path / "scene.json"
    scene.write_bytes(scene_text(b"caf\xe9 \xff"))
    try:
        b = mb.simulate(scene, lmax=2, rays=64, points=4, threads=1)
    except mb.FileError as e:
        assert e.filename == str(scene)
        str(e).encode("utf-8")
    else:
        check_text(b.metadata)
        check_text(b.describe())
    scene.write_bytes(b'{"tile": "100x100um", \xff}')
    with pytest.raises(mb.FileError) as info:
        mb.simulate(scene, lmax=2, rays=64, points=4, threads=1)
    assert info.value.filename == str(scene)
    str(info.value).encode("utf-8")


def test_message_quoting_bytes_of_the_file_is_escaped(tmp_path):
    # An unknown key quoted in the message: its bytes are shown as \xNN, the error keeps its class.
    bad = tmp_path / "bad.json"
    bad.write_bytes(b'{"tile": "100x100um", "materials": {"m": {"type": "mirr\xe9r"}}, '
                    b'"objects": [{"type": "plane", "material": "m"}]}')
    with pytest.raises(mb.FileError) as info:
        mb.simulate(bad, lmax=2, rays=64, points=4, threads=1)
    assert info.value.filename == str(bad)
    str(info.value).encode("utf-8")


# --- paths ----------------------------------------------------------------------------------------

def nul_calls(path, tmp_path):
    """Every function that takes a path, given `path`."""
    D = mb.tabulate(resolution=33)
    s = mb.Surface(np.zeros((8, 8)), spacing=1e-6)
    return {
        "read_surface": lambda: mb.read_surface(path),
        "statistics": lambda: mb.statistics(path),
        "ndf": lambda: mb.ndf(path, resolution=33),
        "read_ndf": lambda: mb.read_ndf(path),
        "fit": lambda: mb.fit(path),
        "Surface.save": lambda: s.save(path),
        "TabulatedNdf.save": lambda: D.save(path),
        "save_preview": lambda: D.save_preview(path),
        "ShBrdf.load": lambda: mb.ShBrdf.load(path),
        "simulate": lambda: mb.simulate(path, lmax=2, rays=64, points=4),
        "measured_ndf": lambda: mb.measured_ndf(path, resolution=33),
        "export_bsdf": lambda: mb.export_bsdf(path, model="ggx", alpha=0.3, n=1.2, k=3.5),
        "export_gltf": lambda: mb.export_gltf(path, model="ggx", alpha=0.3, metal="Al"),
        "render envmap": lambda: mb.render(mb.brdf(model="ggx", alpha=0.3, metal="Al"), envmap=path, size=4, spp=1),
        "predict": lambda: mb.predict(path, tmp_path / "out", no_render=True, resolution=65),
        "predict out_dir": lambda: mb.predict(tmp_path / "x.npy", path, no_render=True),
    }


@pytest.mark.parametrize("name", list(nul_calls("", "").keys()))
def test_nul_in_a_path_is_refused_naming_the_argument(scan, tmp_path, name):
    # 'scan.npy\0.x3p' would open scan.npy in C: refused before anything is read or written.
    path = str(scan) + "\x00.x3p"
    before = sorted(os.listdir(tmp_path))
    with pytest.raises(mb.InputError, match="NUL") as info:
        nul_calls(path, tmp_path)[name]()
    assert isinstance(info.value, ValueError)
    arg = str(info.value).split(":")[0]
    assert arg in ("path", "surface", "ndf", "scene", "output", "envmap", "inputs", "out_dir"), str(info.value)
    assert sorted(os.listdir(tmp_path)) == before


def test_undecodable_path_names_the_same_file(tmp_path):
    # A name that is not UTF-8 reaches Python with surrogate escapes (os.listdir, os.fsdecode):
    # it must open that file, and errors must give the same str back as the file name.
    raw = os.fsencode(str(tmp_path)) + b"/h\xff\xe9.npy"
    name = os.fsdecode(raw)
    z = gaussian_surface(32, 24)
    mb.Surface(z, spacing=1e-6).save(name)
    assert os.path.exists(raw) and os.path.exists(raw[:-4] + b".json")
    s = mb.read_surface(name)
    assert np.array_equal(s.heights, z) and s.path == name and s.metadata["source_path"] == name
    assert mb.read_surface(raw).path == name  # bytes paths too
    assert mb.statistics(name)["nx"] == 32
    gone = os.fsdecode(os.fsencode(str(tmp_path)) + b"/gone\xff.x3p")
    with pytest.raises(mb.FileError) as info:
        mb.read_surface(gone)
    assert info.value.filename == gone
    assert "gone\\xff.x3p" in str(info.value)  # printable: the byte shown escaped
    str(info.value).encode("utf-8")
    repr(s).encode("utf-8")


def test_unencodable_path_is_refused_naming_the_argument(tmp_path):
    # A lone surrogate that no bytes decode to: no file can have that name.
    with pytest.raises(mb.InputError, match="^path: the path cannot be encoded"):
        mb.read_surface(str(tmp_path / "a\ud800.x3p"))
    with pytest.raises(mb.InputError, match="^output: the path cannot be encoded"):
        mb.export_bsdf(str(tmp_path / "\ud800.bsdf"), model="ggx", alpha=0.3, n=1.2, k=3.5)
    with pytest.raises(TypeError, match="path: expected a path"):
        mb.read_surface(42)


# --- counts ---------------------------------------------------------------------------------------

def test_counts_beyond_the_memory_budget_are_refused_before_allocating():
    D = mb.tabulate(resolution=33)
    rss = max_rss_mib()
    with pytest.raises(mb.InputError, match=r"^samples: needs 48\.0 TiB for the slice's arrays, "
                                            r"over the memory budget of"):
        D.slice(samples=2**40)
    with pytest.raises(mb.InputError, match="^resolution: needs .* over the memory budget"):
        D.resampled(2**24)
    with pytest.raises(mb.InputError, match="resolution must be >= 3"):
        D.resampled(2)
    with pytest.raises(mb.InputError, match="albedo: n must lie in 2..4096"):
        mb.brdf(model="ggx", alpha=0.3, metal="Al").albedo([0, 0, 1.0], n=10**6)
    with pytest.raises(mb.InputError, match="^wavelengths: needs .* for the .bsdf tensors"):
        mb.export_bsdf("never.bsdf", model="ggx", alpha=0.3, n=1.2, k=3.5, isotropic=False,
                       theta_i=512, phi_i=512, samples=512, wavelengths=512)
    assert not os.path.exists("never.bsdf")
    assert max_rss_mib() - rss < 200
    # What the budget allows still works.
    assert len(D.slice(samples=100001)["value"]) == 100001
    assert D.resampled(65).resolution == 65


def test_huge_or_negative_counts_are_errors_not_crashes():
    D = mb.tabulate(resolution=33)
    for bad in (-1, 2**64):
        with pytest.raises(TypeError):  # not a count at all: pybind11 refuses the conversion
            D.slice(samples=bad)
    with pytest.raises(ValueError):
        mb.tabulate(resolution=2**40)
    with pytest.raises(ValueError):
        mb.render(mb.brdf(model="ggx", alpha=0.3, metal="Al"), size=2**20, spp=1)
    with pytest.raises(ValueError):
        mb.render(mb.brdf(model="ggx", alpha=0.3, metal="Al"), size=8, spp=0)

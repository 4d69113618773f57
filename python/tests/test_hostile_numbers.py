"""Numbers that are valid but absurd for the data they apply to raise the project's exceptions,
naming the file, instead of crashing the interpreter: a spacing far below the filter sigma (once a
segmentation fault in the filtered-normal kernel), micro-scene geometry of 1e300 m (once an
Embree assertion that aborted Python)."""
import json

import numpy as np
import pytest

import microbrdf as mb


@pytest.fixture
def scan(tmp_path):
    path = tmp_path / "scan.npy"
    np.save(path, np.random.default_rng(1).normal(0, 1e-7, (32, 32)))
    return path


def test_spacing_of_1e30_m_is_refused_naming_the_file(scan):
    with pytest.raises(mb.FileError, match=r"spacing 1e-30 m x 1e-30 m is absurd \(below 1 pm\)") as info:
        mb.ndf(scan, spacing=1e-30, resolution=65)
    assert info.value.filename == str(scan)


def test_filter_sigma_longer_than_the_scan_is_refused(scan):
    with pytest.raises(mb.FileError, match="filter sigma 1000 m is longer than the scan") as info:
        mb.ndf(scan, spacing=1e-6, filter_sigma=1000.0, resolution=65)
    assert info.value.filename == str(scan)
    # An in-memory surface has no file: the error is an InputError (a ValueError).
    z = np.random.default_rng(2).normal(0, 1e-7, (32, 32))
    with pytest.raises(mb.InputError, match="filter sigma 1 um is longer than the scan"):
        mb.ndf(mb.Surface(z, spacing=1e-30), resolution=65)
    # The scan's own length is still a valid (if extreme) filter sigma; with the default support
    # rule (half the kernel's mass on the scan) no sample qualifies, so the rule is relaxed here.
    assert mb.ndf(mb.Surface(z, spacing=1e-6), filter_sigma=32e-6, min_support=0.0,
                  resolution=65) is not None


@pytest.mark.parametrize("obj", [
    {"type": "spheres", "radius": "1e308um", "pitch": "50um", "material": "m"},
    {"type": "plane", "z": "1e300m", "material": "m"},
    {"type": "plane", "z": "1e6m", "material": "m"},
    {"type": "fibers", "count": 4, "length": "1e300m", "material": "m"},
    {"type": "cylinders", "radius": "1um", "count": 4, "z": "-1e300m", "material": "m"},
])
def test_scene_geometry_far_outside_the_tile_is_refused(tmp_path, obj):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps({"tile": "100x100um", "materials": {"m": {"type": "mirror"}},
                                "objects": [obj]}))
    with pytest.raises(mb.FileError, match=r"must lie within 10 mm \(100 x the tile's shorter side") as info:
        mb.simulate(path, rays=1000, lmax=2)
    assert info.value.filename == str(path)


def test_file_size_limit_is_reported_like_a_full_disk(tmp_path):
    # In a child interpreter under `ulimit -f 64` (64 KiB): Python ignores SIGXFSZ, so the write
    # fails with EFBIG and the error names the file and the limit; nothing is left behind.
    import subprocess
    import sys
    code = (
        "import resource, sys, microbrdf as mb\n"
        "resource.setrlimit(resource.RLIMIT_FSIZE, (65536, 65536))\n"
        "t = mb.ndf(mb.Surface(__import__('numpy').zeros((16, 16)), spacing=1e-6), resolution=257)\n"
        "try:\n"
        "    t.save(sys.argv[1])\n"
        "except mb.FileError as e:\n"
        "    print(e.filename); print(e)\n"
        "    sys.exit(0)\n"
        "sys.exit(3)\n")
    out = tmp_path / "big.npy"
    r = subprocess.run([sys.executable, "-c", code, str(out)], capture_output=True, text=True,
                       timeout=60)
    assert r.returncode == 0, r.stdout + r.stderr
    name, message = r.stdout.splitlines()[:2]
    assert name == str(out)
    assert "the file size limit (ulimit -f: 64 KiB) was reached" in message
    assert list(tmp_path.iterdir()) == []


def test_a_kirchhoff_patch_of_1e300_m_is_refused(scan):
    # The command line refuses --patch below 1 pm itself; the library's own check must hold for
    # callers that bypass it (the patch count was once 1e295 converted to 0, then divided by).
    with pytest.raises(mb.InputError, match=r"patches of 1 x 1 samples; a patch needs at least 4"):
        mb.ndf(scan, method="kirchhoff", spacing=1e-6, patch=(1e-300, 1e-300), resolution=65)


def test_an_ndf_grid_of_two_nodes_is_refused(tmp_path):
    # Two nodes in theta are the pole and the horizon: no NDF mass to sample (once an internal
    # error of the sampling table).
    with pytest.raises(mb.InputError, match="the NDF grid needs at least 3 nodes"):
        mb.export_bsdf(tmp_path / "g.bsdf", model="ggx", alpha=0.3, metal="Al", theta_i=2,
                       ndf_grid=2, samples=2, wavelengths=2)
    assert not (tmp_path / "g.bsdf").exists()

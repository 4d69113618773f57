"""mb.ndf equals the CLI bit for bit; the table's moments and slices against numpy."""
import json
import subprocess

import numpy as np
import pytest

import microbrdf as mb
from conftest import gaussian_surface


def metres(x):
    """A length flag the CLI parses to exactly the double x (\"5um\" would be 5 * 1e-6)."""
    return f"{x!r}m"


def cli_ndf(cli, tmp_path, inputs, *flags):
    out = tmp_path / "cli.npy"
    subprocess.run([cli, "ndf", *map(str, inputs), *flags, "-o", out], check=True, capture_output=True)
    return np.load(out)


@pytest.mark.parametrize("method", ["naive", "filtered"])
def test_geometric_ndf_equals_cli_bit_for_bit(cli, data, tmp_path, method):
    path = data / "sample-land.x3p"  # real scan with holes
    ref = cli_ndf(cli, tmp_path, [path], "--method", method, "--resolution", "129",
                  "--filter-sigma", metres(5e-6))
    D = mb.ndf(path, method=method, resolution=129, filter_sigma=5e-6)
    assert np.asarray(D).dtype == np.float64 and np.asarray(D).shape == (129, 129)
    assert np.array_equal(np.asarray(D), ref)
    # The same from a Surface read in Python (levelled on a copy inside ndf).
    s = mb.read_surface(path)
    assert np.array_equal(np.asarray(mb.ndf(s, method=method, resolution=129, filter_sigma=5e-6)), ref)
    assert s.metadata["leveling"] == "none"  # the caller's surface is not touched


def test_scan_set_equals_cli_bit_for_bit(cli, data, tmp_path):
    paths = [data / "metropro-1.dat", data / "sur-2.sur"]
    ref = cli_ndf(cli, tmp_path, paths, "--method", "filtered", "--resolution", "129",
                  "--level", "poly2", "--instrument-fwhm", "1deg")
    D = mb.ndf(paths, method="filtered", resolution=129, level="poly2", instrument_fwhm=np.radians(1))
    assert np.array_equal(np.asarray(D), ref)


def test_kirchhoff_equals_cli_bit_for_bit(cli, data, tmp_path):
    path = data / "metropro-1.dat"
    ref = cli_ndf(cli, tmp_path, [path], "--method", "kirchhoff", "--resolution", "129",
                  "--wavelength", metres(600e-9), "--patch", f"{100e-6!r}x{80e-6!r}m",
                  "--window", "hann")
    fractions = []
    stack = mb.ndf(path, method="kirchhoff", resolution=129, wavelength=600e-9,
                   patch=(100e-6, 80e-6), window="hann", progress=fractions.append)
    # The default is a stack over lambda_q: the CLI's 3-D .npy holds the same layers in order.
    lq = [t.metadata["wavelength_m"] for t in stack]
    assert ref.shape == (len(stack), 129, 129) and lq == sorted(lq) and 600e-9 in lq
    assert lq[0] == pytest.approx(360e-9) and lq[-1] == pytest.approx(6 * 830e-9)
    for layer, t in zip(ref, stack):
        assert np.array_equal(np.asarray(t), layer)
    assert fractions[0] == 0.0 and fractions[-1] == 1.0 and fractions == sorted(fractions)
    D = stack[lq.index(600e-9)]
    assert D.metadata["method"] == "kirchhoff" and D.metadata["wavelength_m"] == 600e-9
    side = json.load(open(tmp_path / "cli.json"))
    assert side["stack"]["wavelengths_q_m"] == lq and side["wavelength_m"] == 600e-9


def test_kirchhoff_integration_rules_equal_cli_bit_for_bit(cli, data, tmp_path):
    # The exact triangle rule and a given supersampling reach Python as in the CLI; the two rules
    # give different tables (the midpoint rule is not exact on a rough scan).
    path = data / "metropro-1.dat"
    flags = ["--method", "kirchhoff", "--resolution", "65", "--patch", f"{60e-6!r}x{50e-6!r}m",
             "--wavelength", metres(600e-9), "--dk-stack", "single"]
    ref = cli_ndf(cli, tmp_path, [path], *flags, "--dk-integration", "exact", "--dk-supersample", "3")
    D = mb.ndf(path, method="kirchhoff", resolution=65, patch=(60e-6, 50e-6), wavelength=600e-9,
               integration="exact", supersample=3, stack="single")
    assert np.array_equal(np.asarray(D), ref)
    mid = mb.ndf(path, method="kirchhoff", resolution=65, patch=(60e-6, 50e-6), wavelength=600e-9,
                 supersample=3, stack="single")
    assert not np.array_equal(np.asarray(mid), ref)
    with pytest.raises(mb.InputError, match="integration|exact"):
        mb.ndf(path, method="kirchhoff", resolution=65, integration="simpson")
    with pytest.raises(mb.InputError, match="supersample"):
        mb.ndf(path, method="kirchhoff", resolution=65, supersample=4)


def test_naive_ndf_of_a_tilted_plane_is_one_node():
    # A plane z = a x: every facet has the normal (-a, 0, 1)/sqrt(1 + a^2).
    a = 0.25
    x = np.arange(64) * 1e-6
    z = np.tile(a * x, (48, 1))
    D = mb.ndf(mb.Surface(z, spacing=1e-6), method="naive", resolution=129, level="none")
    t = np.asarray(D)
    xs = -1 + D.spacing * np.arange(D.resolution)
    mx, my = np.meshgrid(xs, xs)
    assert D.integral() == pytest.approx(1, abs=1e-12)
    # Bilinear splatting keeps the first moment: the mean (m_x, m_y) is the facet normal's.
    w = t * D.spacing**2
    assert np.sum(w * mx) == pytest.approx(-a / np.hypot(a, 1), abs=1e-12)
    assert np.sum(w * my) == pytest.approx(0, abs=1e-12)
    assert np.count_nonzero(t) <= 4


def test_moments_and_slice_against_numpy():
    z = gaussian_surface(nx=128, ny=128)
    D = mb.ndf(mb.Surface(z, spacing=0.5e-6), method="naive", resolution=129, level="none")
    t = np.asarray(D)
    n = D.resolution
    d = 2 / (n - 1)
    assert D.spacing == d
    xs = -1 + d * np.arange(n)
    mx, my = np.meshgrid(xs, xs)
    inside = mx**2 + my**2 < 1
    mz = np.sqrt(np.where(inside, 1 - mx**2 - my**2, 1))
    w = np.where(inside, t, 0) * d * d
    assert D.integral() == pytest.approx(w.sum(), rel=1e-12)
    # Slopes -m_x/m_z, -m_y/m_z under D(m)(m.n) dw = D dm_x dm_y.
    px, py = -mx / mz, -my / mz
    ex, ey = (w * px).sum() / w.sum(), (w * py).sum() / w.sum()
    cxx = (w * (px - ex) ** 2).sum() / w.sum()
    mom = D.moments()
    assert mom["slope_rms_x"] == pytest.approx(np.sqrt(cxx), rel=1e-6)
    assert mom["slope_covariance"].shape == (2, 2)
    # The slice at azimuth 0 through the centre row reads the nodes of row (n-1)/2.
    sl = D.slice(azimuth=0.0, samples=n)
    np.testing.assert_allclose(sl["value"][1:-1], t[(n - 1) // 2, 1:-1], rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(sl["theta"], np.arcsin(np.clip(sl["t"], -1, 1)), atol=1e-12)


def test_save_and_read_round_trip(tmp_path):
    D = mb.tabulate(model="beckmann", alpha_x=0.2, alpha_y=0.1, resolution=65)
    D.save(tmp_path / "d.npy")
    assert np.array_equal(np.load(tmp_path / "d.npy"), np.asarray(D))
    E = mb.read_ndf(tmp_path / "d.npy")
    assert np.array_equal(np.asarray(E), np.asarray(D)) and E.metadata["method"] == "beckmann"
    # Beckmann: rms slope along x is alpha_x / sqrt(2).
    assert D.moments()["slope_rms_x"] == pytest.approx(0.2 / np.sqrt(2), rel=2e-2)


def test_filter_sigma_auto_equals_cli_and_hellinger_against_numpy(cli, tmp_path):
    """mb.filter_sigma_auto chooses what `ndf --filter-sigma auto` chooses; the curve's minimum is
    the chosen sigma; mb.hellinger_distance is H^2 = 1 - sum sqrt(p q) over the normalised tables."""
    z = gaussian_surface(nx=96, ny=96, spacing=50e-9, sigma=0.1e-6, tau=1e-6, seed=4)
    np.save(tmp_path / "g.npy", z)
    r = mb.filter_sigma_auto(tmp_path / "g.npy", spacing=50e-9, patch=None, resolution=65, level="none")
    out = subprocess.run([cli, "ndf", tmp_path / "g.npy", "--spacing", metres(50e-9), "--level", "none",
                          "--filter-sigma", "auto", "--patch", "whole", "--sweep-resolution", "65",
                          "--wavelength", metres(555e-9),
                          "--resolution", "65", "-o", tmp_path / "cli.npy", "--json"],
                         check=True, capture_output=True, text=True)
    j = json.loads(out.stdout)
    assert r["sigma_m"] == j["filter_sigma_m"]
    assert r["curve"] == j["filter_sigma_auto"]["curve"]
    h = [p["hellinger"] for p in r["curve"]]
    assert r["hellinger"] == min(h) and r["curve"][h.index(min(h))]["sigma_m"] == r["sigma_m"]
    p = np.clip(np.asarray(r["filtered"]), 0, None)
    q = np.clip(np.asarray(r["kirchhoff"]), 0, None)
    want = np.sqrt(max(0.0, 1 - np.sqrt((p / p.sum()) * (q / q.sum())).sum()))
    assert abs(mb.hellinger_distance(r["filtered"], r["kirchhoff"]) - want) < 1e-12
    assert abs(r["hellinger"] - want) < 1e-12
    assert mb.hellinger_distance(r["naive"], r["naive"]) < 1e-7


def test_sampling_and_zoom_window(cli, tmp_path):
    """Tables say how they were sampled; a zoomed table's window reaches Python and the fit."""
    D = mb.tabulate(model="beckmann", alpha_x=0.002, alpha_y=0.003, resolution=129,
                    window=(0.01, 0.0, 0.02))
    assert D.sampling == "point" and D.metadata["sampling_recorded"]
    assert D.window == {"x": pytest.approx((-0.01, 0.03)), "y": pytest.approx((-0.02, 0.02))}
    assert D.nodes[0] == pytest.approx(-0.01) and D.nodes_y[-1] == pytest.approx(0.02)
    assert D.spacing == pytest.approx(0.04 / 128)
    assert D.integral() == pytest.approx(1.0)
    assert D.eval([0.5, 0.0, np.sqrt(0.75)]) == 0.0  # outside the window
    f = mb.fit(D, model="beckmann")
    assert f["converged"] and f["table_sampling"] == "point"
    assert f["params"]["alpha_x"] == pytest.approx(0.002, rel=5e-3)
    assert f["window"]["x"] == pytest.approx([-0.01, 0.03])
    # The CLI writes the same table; numpy, the sidecar and read_ndf agree.
    out = tmp_path / "zoom.npy"
    subprocess.run([cli, "tabulate", "--model", "beckmann", "--alpha-x", "0.002", "--alpha-y",
                    "0.003", "--resolution", "129", "--window", "0.01,0,0.02", "-o", out],
                   check=True, capture_output=True)
    E = mb.read_ndf(out)
    assert E.sampling == "point"
    for axis in ("x", "y"):  # (the extent's text round trip: equal to rounding)
        assert E.window[axis] == pytest.approx(D.window[axis], abs=1e-15)
    np.testing.assert_allclose(np.asarray(E), np.asarray(D), rtol=1e-12)
    # A histogram says "cell".
    S = mb.ndf(mb.Surface(gaussian_surface(), spacing=0.5e-6), method="naive", resolution=65)
    assert S.sampling == "cell"


def test_kirchhoff_buffers_are_released_after_the_call(data):
    # The fast D_K keeps ~100 MB of buffers between tables; a Python session keeps its process,
    # so mb.ndf frees them when it returns (kirchhoff_release_buffers).
    def resident_mb():
        with open("/proc/self/statm") as f:
            return int(f.read().split()[1]) * 4096 / 1e6

    before = resident_mb()
    D = mb.ndf(data / "sur-2.sur", method="kirchhoff", resolution=1025, patch=None, stack="single")
    assert D.integral() == pytest.approx(1, rel=1e-9)
    # The table itself is 8.4 MB; kept buffers would add more than 100 MB.
    assert resident_mb() - before < 90

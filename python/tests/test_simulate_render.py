"""simulate -> ShBrdf (a white Lambertian plane has a known SH matrix), render (white furnace),
predict (summary dict)."""
import gc
import json

import numpy as np
import pytest

import microbrdf as mb


def test_simulated_lambert_plane(data, tmp_path):
    scene = data.parent.parent / "examples" / "scenes" / "lambert_plane.json"
    b = mb.simulate(scene, lmax=3, rays=40000, points=4, seed=2, threads=2)
    assert isinstance(b, mb.ShBrdf) and isinstance(b, mb.Brdf) and b.lmax == 3
    M = b.matrix
    assert M.shape == (6, 6) and not M.flags.owndata and not M.flags.writeable
    # rho cos cos = cos theta_i cos theta_o / pi = Y_10 Y_10 (4/3): only m_(1,0),(1,0) = 4/3.
    assert M[0, 0] == pytest.approx(4 / 3, rel=2e-2)
    assert np.max(np.abs(M - np.diag([M[0, 0]] + [0] * 5))) < 0.05
    up = np.array([0.0, 0.0, 1.0])
    assert b.eval(up, up) == pytest.approx(1 / np.pi, rel=3e-2)
    assert b.albedo(up) == pytest.approx(1.0, rel=3e-2)
    # Same seed and thread count: the same matrix, bit for bit; the file round trip is exact.
    again = mb.simulate(scene, lmax=3, rays=40000, points=4, seed=2, threads=2)
    assert np.array_equal(again.matrix, M)
    b.save(tmp_path / "p.shbrdf")
    assert np.array_equal(mb.ShBrdf.load(tmp_path / "p.shbrdf").matrix, M)
    assert b.metadata["seed"] == 2
    view = b.matrix
    del b
    gc.collect()
    assert view[0, 0] == M[0, 0]


def test_white_furnace_render():
    # A convex sphere in a uniform white sky sees only the sky: one bounce off a Lambertian of
    # albedo 0.5 gives radiance 0.5 (the centre 16 x 16 pixels lie on the sphere).
    img = mb.render(mb.brdf(lambertian=0.5), scene="furnace_sphere", size=32, spp=32, white_env=True)
    assert img.shape == (32, 32, 3) and img.dtype == np.float32
    assert img[8:24, 8:24, 1].mean() == pytest.approx(0.5, abs=0.005)


def test_predict_summary(data, tmp_path):
    lines = []
    summary = mb.predict(data / "metropro-1.dat", tmp_path / "out", resolution=129, no_render=True,
                         progress=lines.append)
    assert (tmp_path / "out" / "report.html").exists()
    on_disk = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary == on_disk
    assert any("fits" in line for line in lines)


def test_predict_filter_sigma_auto_and_render_ndf(tmp_path):
    z = np.random.default_rng(2).standard_normal((64, 64)) * 20e-9
    np.save(tmp_path / "s.npy", z)
    s = mb.predict(tmp_path / "s.npy", tmp_path / "out", spacing=50e-9, level="none", resolution=65,
                   no_render=True, filter_sigma="auto", sweep_resolution=33, render_ndf="naive",
                   theory="geometric")
    c = s["ndf_comparison"]
    assert c["render_ndf"] == "naive" and s["settings"]["filter_sigma_auto"]
    # sigma 20 nm: Kirchhoff by the regime, so forcing geometric optics warns.
    assert s["regime"]["per_incidence"][0]["method"] == "kirchhoff"
    assert s["regime"]["theory"] == {"requested": "geometric", "chosen": "geometric",
                                     "why": "asked for (theory geometric)"}
    assert "method_outside_validity" in [w["code"] for w in s["warnings"]]
    assert s["settings"]["filter_sigma_m"] == c["filter_sigma_auto"]["sigma_m"]
    h = [p["hellinger"] for p in c["filter_sigma_auto"]["curve"]]
    assert c["filter_sigma_auto"]["hellinger"] == min(h)
    with pytest.raises(ValueError):
        mb.predict(tmp_path / "s.npy", tmp_path / "bad", spacing=50e-9, filter_sigma="best")


def test_predict_takes_the_dk_settings(tmp_path):
    # integration, supersample and window reach D_K as in the CLI, and the summary says so; a bad
    # supersampling factor is refused and leaves no output.
    z = np.random.default_rng(3).standard_normal((48, 48)) * 20e-9
    np.save(tmp_path / "s.npy", z)
    s = mb.predict(tmp_path / "s.npy", tmp_path / "out", spacing=50e-9, level="none", resolution=65,
                   no_render=True, kirchhoff=True, patch=None, integration="exact", supersample=3,
                   window="hann")
    st = s["settings"]
    assert st["kirchhoff_integration"] == "exact" and st["kirchhoff_supersample"] == "3"
    assert st["kirchhoff_window"] == "hann"
    with pytest.raises(mb.InputError, match="supersample"):
        mb.predict(tmp_path / "s.npy", tmp_path / "bad", spacing=50e-9, level="none", resolution=65,
                   no_render=True, kirchhoff=True, patch=None, supersample=4)
    assert not (tmp_path / "bad").exists()

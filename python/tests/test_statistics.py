"""mb.statistics against the same statistics written in numpy."""
import numpy as np
import pytest

import microbrdf as mb
from conftest import gaussian_surface


def numpy_stats(z, dx, dy):
    v = np.isfinite(z)
    h = z[v] - z[v].mean()
    sq = np.sqrt(np.mean(h**2))
    gx = (z[:, 2:] - z[:, :-2]) / (2 * dx)  # central differences, both neighbours valid
    gy = (z[2:, :] - z[:-2, :]) / (2 * dy)
    gx, gy = gx[np.isfinite(gx)], gy[np.isfinite(gy)]
    return {
        "valid_fraction": v.mean(),
        "mean_m": z[v].mean(),
        "min_m": z[v].min(),
        "max_m": z[v].max(),
        "sq_m": sq,
        "sa_m": np.mean(np.abs(h)),
        "skewness": np.mean(h**3) / sq**3,
        "kurtosis": np.mean(h**4) / sq**4,
        "slope_rms_x": np.sqrt(np.mean(gx**2)),
        "slope_rms_y": np.sqrt(np.mean(gy**2)),
    }


@pytest.mark.parametrize("holes", [False, True])
def test_statistics_match_numpy(holes):
    z = gaussian_surface(holes=holes)
    s = mb.Surface(z, spacing=(0.5e-6, 0.6e-6))
    st = mb.statistics(s, level="none")
    ref = numpy_stats(z, 0.5e-6, 0.6e-6)
    for key, value in ref.items():
        assert st[key] == pytest.approx(value, rel=1e-10, abs=1e-300), key
    assert st["nx"] == 96 and st["ny"] == 80
    assert st["dx_m"] == 0.5e-6 and st["dy_m"] == 0.6e-6
    assert st["invalid_count"] == int(np.sum(~np.isfinite(z)))


def test_plane_levelling_matches_numpy_least_squares(data):
    path = data / "metropro-1.dat"
    raw = mb.read_surface(path)
    z = raw.heights
    ny, nx = z.shape
    # Least-squares plane in the library's coordinates (u, v scaled to [-1, 1]); the residual
    # does not depend on the scaling.
    v, u = np.mgrid[0:ny, 0:nx]
    a = np.column_stack([np.ones(z.size), u.ravel(), v.ravel()])
    coef, *_ = np.linalg.lstsq(a, z.ravel(), rcond=None)
    resid = z.ravel() - a @ coef
    st = mb.statistics(path)  # level="plane", as `microbrdf info`
    assert st["leveling"] == "plane"
    assert st["sq_m"] == pytest.approx(np.sqrt(np.mean((resid - resid.mean()) ** 2)), rel=1e-9)
    # The README's independent reference for this file: Sq 1.3335e-08 m after plane removal.
    assert st["sq_m"] == pytest.approx(1.3335e-08, rel=1e-4)
    assert mb.statistics(path, level="none")["sq_m"] == pytest.approx(np.std(z), rel=1e-12)


def test_statistics_keys_match_info_json(data, cli):
    import json
    import subprocess

    path = data / "sample-land.x3p"
    out = subprocess.run([cli, "info", "--json", path], check=True, capture_output=True, text=True)
    ref = json.loads(out.stdout)["surfaces"][0]
    st = mb.statistics(path)
    assert set(ref) <= set(st)
    for key, value in ref.items():
        if isinstance(value, float):
            assert st[key] == pytest.approx(value, rel=1e-12), key
        else:
            assert st[key] == value, key


def test_scan_list_gives_one_record_per_scan(data):
    recs = mb.statistics([data / "metropro-1.dat", data / "sample-land.x3p"])
    assert [r["nx"] for r in recs] == [640, 918]

"""mb.measured_ndf and mb.export_bsdf against physics written here in numpy: a MERL file of a
known GGX conductor gives back its width through Dong eq. 9 and a fit; a .bsdf file read by the
independent reader (tests/rgl_reference_reader.py, no microbrdf code) evaluates to the BRDF that
was exported, and its own sampler gives the same albedo."""
import importlib.util
import os
import subprocess
import sys

import numpy as np
import pytest

import microbrdf as mb
from conftest import ROOT

_spec = importlib.util.spec_from_file_location("rgl_reference_reader", ROOT / "tests" / "rgl_reference_reader.py")
rgl = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(rgl)

ETA = 1.2 + 3.5j


def fresnel(c):
    """Unpolarised reflectance of a conductor of index ETA at cos(incidence) c."""
    s2 = 1 - c * c
    ct = np.sqrt(1 - s2 / ETA**2)
    rs = (c - ETA * ct) / (c + ETA * ct)
    rp = (ETA * c - ct) / (ETA * c + ct)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def write_merl_ggx(path, alpha, invalid_from=None):
    """MERL 100 table of a GGX conductor (n 1.2, k 3.5, height-correlated Smith) at the bin
    centres; bins with theta_h index >= invalid_from marked invalid (-1)."""
    i, j, k = np.meshgrid(np.arange(90), np.arange(90), np.arange(180), indexing="ij")
    th, td, pd = ((i + .5) / 90) ** 2 * np.pi / 2, (j + .5) / 90 * np.pi / 2, (k + .5) / 180 * np.pi
    d = np.stack([np.sin(td) * np.cos(pd), np.sin(td) * np.sin(pd), np.cos(td)])
    wi = np.stack([np.cos(th) * d[0] + np.sin(th) * d[2], d[1], -np.sin(th) * d[0] + np.cos(th) * d[2]])
    h = np.stack([np.sin(th), np.zeros_like(th), np.cos(th)])
    wo = 2 * np.cos(td) * h - wi
    lam = lambda z: (np.sqrt(1 + alpha**2 * (1 - z * z) / np.maximum(z * z, 1e-12)) - 1) / 2
    D = 1 / (np.pi * alpha**2 * (np.sin(th) ** 2 / alpha**2 + np.cos(th) ** 2) ** 2)
    ok = (wi[2] > 0) & (wo[2] > 0)
    G = 1 / (1 + lam(wi[2]) + lam(wo[2]))
    f = np.where(ok, fresnel(np.cos(td)) * D * G / (4 * np.maximum(wi[2], 1e-9) * np.maximum(wo[2], 1e-9)), -1.0)
    if invalid_from is not None:
        f[invalid_from:] = -1.0
    scale = np.array([1 / 1500, 1.15 / 1500, 1.66 / 1500])
    with open(path, "wb") as out:
        np.array([90, 90, 180], "<i4").tofile(out)
        for c in range(3):
            np.where(f >= 0, f / scale[c], -1.0).astype("<f8").tofile(out)


@pytest.fixture(scope="module")
def merl(tmp_path_factory):
    path = tmp_path_factory.mktemp("merl") / "ggx.binary"
    write_merl_ggx(path, 0.3)
    return path


def test_measured_ndf_of_merl_recovers_alpha(merl):
    D = mb.measured_ndf(merl, resolution=257)
    assert D.metadata["method"] == "measured" and str(merl) in D.metadata["sources"]
    a = mb.fit(D, model="ggx")["params"]
    print(f"mb.measured_ndf(MERL ggx 0.3, G = 1) -> fit alpha {a['alpha_x']:.4f} x {a['alpha_y']:.4f}")
    assert a["alpha_x"] == pytest.approx(0.3, rel=0.03) and a["alpha_y"] == pytest.approx(0.3, rel=0.03)
    # With the material's F divided out and Smith G, the table is the NDF itself: its pole value
    # is 1/(pi alpha^2) and the fit is exact to the interpolation.
    E = mb.measured_ndf(merl, resolution=257, n=1.2, k=3.5, shadowing="smith")
    e = np.asarray(E)
    c = e.shape[0] // 2
    print(f"  with n, k and smith: D(pole) {e[c, c]:.4f} vs {1 / (np.pi * 0.09):.4f}")
    assert e[c, c] == pytest.approx(1 / (np.pi * 0.09), rel=0.02)
    b = mb.fit(E, model="ggx")["params"]
    assert b["alpha_x"] == pytest.approx(0.3, rel=0.01)


def test_unmeasured_bins_are_nan_and_the_fit_ignores_them(tmp_path):
    path = tmp_path / "gaps.binary"
    write_merl_ggx(path, 0.3, invalid_from=45)  # theta_h above ~22 deg: no data
    D = np.asarray(mb.measured_ndf(path, resolution=129))
    assert np.isnan(D).sum() > 0.3 * D.size
    a = mb.fit(mb.measured_ndf(path, resolution=129), model="ggx")["params"]
    assert a["alpha_x"] == pytest.approx(0.3, rel=0.03)


def ggx_ref(wi, wo, ax, ay):
    """GGX conductor (n 1.2, k 3.5), height-correlated Smith, axes along x and y."""
    h = wi + wo
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    D = 1 / (np.pi * ax * ay * (h[:, 0] ** 2 / ax**2 + h[:, 1] ** 2 / ay**2 + h[:, 2] ** 2) ** 2)
    lam = lambda w: (np.sqrt(1 + (w[:, 0] ** 2 * ax**2 + w[:, 1] ** 2 * ay**2) / w[:, 2] ** 2) - 1) / 2
    G = 1 / (1 + lam(wi) + lam(wo))
    return fresnel(np.sum(wi * h, axis=1)) * D * G / (4 * wi[:, 2] * wo[:, 2])


def lobe_pairs(b, n=600, seed=2):
    rng = np.random.default_rng(seed)
    t, p = np.radians(rng.uniform(0, 70, n)), rng.uniform(-np.pi, np.pi, n)
    wi = np.column_stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])
    wo, _, pdf = b.sample(wi, seed=seed + 1)
    keep = (pdf > 0) & (wo[:, 2] > 0.05)
    return wi[keep], wo[keep]


@pytest.mark.parametrize("ax, ay", [(0.3, 0.3), (0.1, 0.3)])
def test_export_bsdf_read_back_by_the_independent_reader(tmp_path, ax, ay):
    path = tmp_path / "g.bsdf"
    out = mb.export_bsdf(path, model="ggx", alpha_x=ax, alpha_y=ay, n=1.2, k=3.5, theta_i=12,
                         wavelengths=[500e-9, 550e-9, 600e-9])
    assert out["isotropic"] == (ax == ay)  # tested on the BRDF
    assert out["phi_i"] == (1 if ax == ay else 17) and out["bytes"] == os.path.getsize(path)
    assert out["wavelengths"] == pytest.approx([500e-9, 550e-9, 600e-9])
    b = mb.brdf(model="ggx", alpha_x=ax, alpha_y=ay, n=1.2, k=3.5)
    wi, wo = lobe_pairs(b)
    ref = ggx_ref(wi, wo, ax, ay)
    # The microfacet BRDF of microbrdf is the formula above...
    assert b.eval(wi, wo, wavelength=550e-9) == pytest.approx(ref, rel=1e-6)
    # ... and the file, read by code that is not microbrdf's, gives it back.
    assert rgl.read_tensor_file(str(path))["phi_i"].shape == (out["phi_i"],)
    q = tmp_path / "q.txt"
    np.savetxt(q, np.column_stack([wi, wo, np.full(len(wi), 550.0)]))
    a = tmp_path / "a.txt"
    subprocess.run([sys.executable, str(ROOT / "tests" / "rgl_reference_reader.py"), str(path), "eval",
                    str(q), str(a)], check=True)
    got = np.loadtxt(a)
    med = np.median(np.abs(got / ref - 1))
    print(f"mb.export_bsdf ggx {ax} x {ay}: independent reader median relative error {100 * med:.3f}% "
          f"over {len(ref)} sampled pairs")
    assert med < 0.02
    for deg in (0, 40):
        alb = subprocess.run([sys.executable, str(ROOT / "tests" / "rgl_reference_reader.py"), str(path),
                              "albedo", str(deg), "30", "550", "96"], check=True, capture_output=True,
                             text=True).stdout
        t, p = np.radians(deg), np.radians(30)
        own = b.albedo(np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)]), wavelength=550e-9,
                       n=256)
        print(f"  albedo theta_i {deg}: reader {float(alb):.4f}, microbrdf {own:.4f}")
        assert float(alb) == pytest.approx(own, rel=0.02)


def test_export_bsdf_of_a_brdf_object_and_of_a_merl_file(tmp_path, merl):
    b = mb.brdf(model="ggx", alpha=0.2, metal="Al")
    out = mb.export_bsdf(tmp_path / "b.bsdf", brdf=b, theta_i=6, samples=16, wavelengths=2)
    assert out["isotropic"] and out["samples"] == 16
    out = mb.export_bsdf(tmp_path / "m.bsdf", merl, theta_i=6, wavelengths=2)
    assert out["isotropic"] and out["source"] == "ggx.binary"
    fields = rgl.read_tensor_file(str(tmp_path / "m.bsdf"))
    assert fields["spectra"].shape == (1, 6, 2, 32, 32)
    # The .bsdf file is itself a measured BRDF: eq. 9 on it gives the width back.
    a = mb.fit(mb.measured_ndf(tmp_path / "m.bsdf", resolution=129), model="ggx")["params"]
    assert a["alpha_x"] == pytest.approx(0.3, rel=0.05)


def test_export_bsdf_reports_progress_and_stops_when_it_raises(tmp_path):
    seen = []
    mb.export_bsdf(tmp_path / "p.bsdf", model="ggx", alpha_x=0.1, alpha_y=0.3, metal="Al", theta_i=8,
                   samples=8, wavelengths=2, progress=seen.append)
    assert len(seen) >= 2 and seen == sorted(seen) and seen[-1] == 1.0

    def stop(f):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        mb.export_bsdf(tmp_path / "q.bsdf", model="ggx", alpha_x=0.1, alpha_y=0.3, metal="Al", theta_i=8,
                       samples=8, wavelengths=2, progress=stop)
    assert not (tmp_path / "q.bsdf").exists()


def test_errors_name_the_file_or_the_keyword(tmp_path):
    with pytest.raises(mb.FileError) as e:
        mb.measured_ndf(tmp_path / "none.csv")
    assert "none.csv" in str(e.value)
    (tmp_path / "x.binary").write_bytes(b"\0" * 1000)
    with pytest.raises(OSError):
        mb.measured_ndf(tmp_path / "x.binary")
    with pytest.raises(ValueError):
        mb.measured_ndf(tmp_path / "x.txt")
    with pytest.raises(ValueError):
        mb.measured_ndf(tmp_path / "x.binary", colour="red")  # not a material keyword
    with pytest.raises(ValueError):
        mb.measured_ndf(tmp_path / "x.binary", theta_d=-0.1)
    with pytest.raises(ValueError):
        mb.measured_ndf(tmp_path / "x.binary", fresnel="schlick")  # no material to go with it
    with pytest.raises(ValueError):
        mb.export_bsdf(tmp_path / "y.bsdf")  # no BRDF
    with pytest.raises(ValueError):
        mb.export_bsdf(tmp_path / "y.bsdf", tmp_path / "x.binary", model="ggx", alpha=0.1, metal="Al")
    with pytest.raises(ValueError):
        mb.export_bsdf(tmp_path / "y.bsdf", model="ggx", alpha=0.1)  # no material
    (tmp_path / "p.csv").write_text("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n")
    with pytest.raises(ValueError):
        mb.export_bsdf(tmp_path / "y.bsdf", tmp_path / "p.csv")
    assert not (tmp_path / "y.bsdf").exists()


def test_docstrings_teach_units():
    for f in (mb.measured_ndf, mb.export_bsdf):
        doc = f.__doc__
        assert "radians" in doc or "metres" in doc, f
    assert "NaN" in mb.measured_ndf.__doc__ and "1/sr" in mb.measured_ndf.__doc__

"""The toy model (tests/toy/toy_ndf.cpp, added through the registry alone) from Python: the
module built with it registered (build/python-toy, python/CMakeLists.txt) takes model="toy" and
its parameter `roughness` in ndf_models, tabulate, fit, brdf and export_bsdf like a built-in
model. References: numpy's isotropic GGX, and the built-in GGX of the same roughness."""
import numpy as np

import microbrdf as mb


def ggx_table(a, n):
    m = -1 + 2 * np.arange(n) / (n - 1)
    x, y = np.meshgrid(m, m)
    r2 = x * x + y * y
    z2 = np.clip(1 - r2, 0, None)
    d = np.where(r2 < 1, 1 / (np.pi * a * a * (r2 / (a * a) + z2) ** 2), 0)
    return d / (d.sum() * (2 / (n - 1)) ** 2)


def test_the_toy_is_registered_with_its_parameter():
    models = {m["name"]: m for m in mb.ndf_models()}
    assert "toy" in models
    assert [p["name"] for p in models["toy"]["params"]] == ["roughness"]


def test_tabulate_and_fit():
    D = np.asarray(mb.tabulate(model="toy", roughness=0.2, resolution=129))
    ref = ggx_table(0.2, 129)
    assert np.abs(D - ref).max() < 1e-12 * ref.max()
    r = mb.fit(mb.TabulatedNdf(ref), model="toy", sampling="node")
    print("fitted roughness", r["params"]["roughness"])
    assert r["model"] == "toy"
    assert abs(r["params"]["roughness"] / 0.2 - 1) < 1e-6


def test_brdf_equals_ggx_of_the_same_roughness():
    rng = np.random.default_rng(3)

    def dirs(k):
        v = rng.normal(size=(k, 3))
        v[:, 2] = np.abs(v[:, 2]) + 0.05
        return v / np.linalg.norm(v, axis=1, keepdims=True)

    wi, wo = dirs(200), dirs(200)
    toy = np.asarray(mb.brdf(model="toy", roughness=0.2, metal="Al").eval(wi, wo, wavelength=555e-9))
    ggx = np.asarray(mb.brdf(model="ggx", alpha=0.2, metal="Al").eval(wi, wo, wavelength=555e-9))
    assert toy.max() > 0
    assert np.abs(toy - ggx).max() <= 1e-12 * ggx.max()


def test_export_bsdf(tmp_path):
    out = tmp_path / "toy.bsdf"
    mb.export_bsdf(out, model="toy", roughness=0.2, metal="Al")
    ref = tmp_path / "ggx.bsdf"
    mb.export_bsdf(ref, model="ggx", alpha=0.2, metal="Al")
    # A tabulated .bsdf of the same lobe as GGX of the same roughness: the same bytes.
    assert out.stat().st_size > 10000
    assert out.read_bytes() == ref.read_bytes()

"""The NDF model registry from Python: the models and their parameters, tabulate's keywords,
fits of any model and of two-lobe mixtures, against numpy."""
import numpy as np
import pytest

import microbrdf as mb


def test_registry_lists_the_models_and_their_parameters():
    models = {m["name"]: m for m in mb.ndf_models()}
    assert list(models)[:3] == ["ellipsoid", "beckmann", "ggx"]
    assert [p["name"] for p in models["ggx"]["params"]] == ["alpha_x", "alpha_y", "phi"]
    assert [p["unit"] for p in models["ggx"]["params"]] == ["1", "1", "rad"]
    assert "gtr2" in models["ggx"]["aliases"]
    assert [p["name"] for p in models["ellipsoid"]["params"]] == [
        "alpha_x", "alpha_y", "theta_x", "theta_y", "theta_z"]


def test_tabulate_takes_the_model_parameters_and_refuses_others():
    D = np.asarray(mb.tabulate(model="gtr2", alpha_x=0.2, resolution=65))
    n = D.shape[0]
    m = -1 + 2 * np.arange(n) / (n - 1)
    x, y = np.meshgrid(m, m)
    r2 = x * x + y * y
    ref = np.where(r2 < 1, 1 / (np.pi * 0.04 * (r2 / 0.04 + 1 - r2) ** 2), 0)
    ref /= ref.sum() * (2 / (n - 1)) ** 2
    assert np.abs(D - ref).max() < 1e-12 * ref.max()
    with pytest.raises(mb.InputError, match="does not belong to the ggx model"):
        mb.tabulate(model="ggx", alpha_x=0.2, gamma=3.0, resolution=65)
    with pytest.raises(mb.InputError, match="unknown model"):
        mb.tabulate(model="phong", alpha_x=0.2, resolution=65)


def test_fit_of_a_two_lobe_mixture():
    # 0.7 GGX(0.05) + 0.3 GGX(0.3), written by numpy, point-sampled.
    n = 257
    m = -1 + 2 * np.arange(n) / (n - 1)
    x, y = np.meshgrid(m, m)
    r2 = x * x + y * y
    z2 = np.clip(1 - r2, 0, None)

    def ggx(a):
        return 1 / (np.pi * a * a * (r2 / (a * a) + z2) ** 2)

    D = np.where(r2 < 1, 0.7 * ggx(0.05) + 0.3 * ggx(0.3), 0)
    D /= D.sum() * (2 / (n - 1)) ** 2
    r = mb.fit(mb.TabulatedNdf(D), model="mixture:ggx+ggx", sampling="node")
    p = r["params"]
    print("mixture fit", p["weight"], p["lobe1"]["params"]["alpha_x"], p["lobe2"]["params"]["alpha_x"])
    assert r["model"] == "mixture:ggx+ggx"
    assert abs(p["weight"] - 0.7) < 0.01
    assert abs(p["lobe1"]["params"]["alpha_x"] / 0.05 - 1) < 0.01
    assert abs(p["lobe2"]["params"]["alpha_x"] / 0.3 - 1) < 0.01

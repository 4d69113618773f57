"""BRDFs over numpy arrays: eval against a GGX conductor written in numpy, sampling against pdf
(chi-square), albedo, broadcasting."""
import numpy as np
import pytest

import microbrdf as mb


def random_hemisphere(rng, n):
    v = rng.standard_normal((n, 3))
    v[:, 2] = np.abs(v[:, 2]) + 1e-3
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def fresnel_conductor(cos_i, eta):
    """Unpolarised reflectance of a conductor of complex index eta (docs/theory.md, Fresnel)."""
    sin2 = 1 - cos_i**2
    cos_t = np.sqrt(1 - sin2 / eta**2 + 0j)
    rs = (cos_i - eta * cos_t) / (cos_i + eta * cos_t)
    rp = (eta * cos_i - cos_t) / (eta * cos_i + cos_t)
    return (np.abs(rs) ** 2 + np.abs(rp) ** 2) / 2


def ggx_conductor(wi, wo, ax, ay, eta):
    """Dong 2015 eq. 1 with anisotropic GGX and the height-correlated Smith G2."""
    h = wi + wo
    h /= np.linalg.norm(h, axis=1, keepdims=True)
    d = 1 / (np.pi * ax * ay * ((h[:, 0] / ax) ** 2 + (h[:, 1] / ay) ** 2 + h[:, 2] ** 2) ** 2)

    def lam(v):
        tan2 = (v[:, 0] ** 2 * ax**2 + v[:, 1] ** 2 * ay**2) / v[:, 2] ** 2
        return (np.sqrt(1 + tan2) - 1) / 2

    g2 = 1 / (1 + lam(wi) + lam(wo))
    f = fresnel_conductor(np.sum(wi * h, axis=1), eta)
    return f * d * g2 / (4 * wi[:, 2] * wo[:, 2])


def test_eval_matches_numpy_ggx_conductor():
    rng = np.random.default_rng(7)
    wi, wo = random_hemisphere(rng, 20000), random_hemisphere(rng, 20000)
    b = mb.brdf(model="ggx", alpha_x=0.1, alpha_y=0.3, n=1.2, k=3.5)
    f = b.eval(wi, wo, wavelength=555e-9)
    assert f.shape == (20000,) and f.dtype == np.float64
    ref = ggx_conductor(wi, wo, 0.1, 0.3, 1.2 + 3.5j)
    np.testing.assert_allclose(f, ref, rtol=1e-10, atol=0)
    # Below the horizon: 0. Single vectors give a float; one of them broadcasts.
    assert b.eval([0, 0, 1], [0.1, 0, -1]) == 0.0
    assert isinstance(b.eval(wi[0], wo[0]), float)
    np.testing.assert_allclose(b.eval(wi[0], wo), ggx_conductor(np.tile(wi[0], (20000, 1)), wo, 0.1, 0.3, 1.2 + 3.5j), rtol=1e-10)


def test_angles_are_radians_or_strings_with_a_unit():
    # phi turns the alpha_x axis: at 90 degrees the roughnesses swap axes.
    rng = np.random.default_rng(8)
    wi, wo = random_hemisphere(rng, 2000), random_hemisphere(rng, 2000)
    ref = ggx_conductor(wi, wo, 0.3, 0.1, 1.2 + 3.5j)
    for phi in (np.pi / 2, "90deg"):
        b = mb.brdf(model="ggx", alpha_x=0.1, alpha_y=0.3, phi=phi, n=1.2, k=3.5)
        np.testing.assert_allclose(b.eval(wi, wo), ref, rtol=1e-9)


def test_one_vocabulary_with_files_and_tables(tmp_path):
    D = mb.tabulate(model="beckmann", alpha_x=0.3, resolution=257)
    D.save(tmp_path / "d.npy")
    from_file = mb.brdf(ndf=tmp_path / "d.npy", metal="Al")
    in_memory = mb.brdf(ndf=D, metal="Al")
    rng = np.random.default_rng(4)
    wi, wo = random_hemisphere(rng, 500), random_hemisphere(rng, 500)
    np.testing.assert_array_equal(from_file.eval(wi, wo), in_memory.eval(wi, wo))
    with pytest.raises(ValueError):
        mb.brdf(ndf=D, model="ggx", alpha=0.2, metal="Al")  # two kinds at once
    with pytest.raises(ValueError):
        mb.brdf(lambertian=0.5, metal="Al")  # a Lambertian takes no material
    with pytest.raises(ValueError):
        mb.brdf(model="ggx", alpha=0.2)  # no material
    with pytest.raises(ValueError):
        mb.brdf(model="ggx", alpha=0.2, metal="Al", colour="red")  # unknown keyword


def test_metal_by_name_uses_its_optical_constants():
    # Copper reflects red better than blue at normal incidence.
    b = mb.brdf(model="ggx", alpha=0.2, metal="Cu")
    up = np.array([0.0, 0.0, 1.0])
    assert b.eval(up, up, wavelength=650e-9) > 1.3 * b.eval(up, up, wavelength=450e-9)


def cell_probabilities(b, wi, nt, nphi, sub=8):
    """Probability of each (cos theta_o, phi_o) cell under b.pdf, by the midpoint rule."""
    c = (np.arange(nt * sub) + 0.5) / (nt * sub)
    p = (np.arange(nphi * sub) + 0.5) / (nphi * sub) * 2 * np.pi
    C, P = np.meshgrid(c, p, indexing="ij")
    s = np.sqrt(1 - C**2)
    wo = np.column_stack([(s * np.cos(P)).ravel(), (s * np.sin(P)).ravel(), C.ravel()])
    dens = b.pdf(wi, wo).reshape(C.shape) * (1 / (nt * sub)) * (2 * np.pi / (nphi * sub))
    return dens.reshape(nt, sub, nphi, sub).sum(axis=(1, 3))


@pytest.mark.parametrize("spec", [dict(model="ggx", alpha_x=0.3, alpha_y=0.5, metal="Al"),
                                  dict(model="beckmann", alpha=0.4, n=1.5, k=2.0)])
def test_sampling_matches_pdf_chi_square(spec):
    b = mb.brdf(**spec)
    wi = np.array([np.sin(0.6), 0.0, np.cos(0.6)])
    n = 200000
    wo, weight, pdf = b.sample(np.tile(wi, (n, 1)), seed=11)
    ok = pdf > 0
    assert ok.mean() > 0.7  # the rest reflect below the horizon
    # The returned pdf and weight agree with pdf() and eval().
    np.testing.assert_allclose(pdf[ok][:500], b.pdf(wi, wo[ok][:500]), rtol=1e-9)
    np.testing.assert_allclose(weight[ok][:500], b.eval(wi, wo[ok][:500]) * wo[ok][:500, 2] / pdf[ok][:500], rtol=1e-9)
    nt, nphi = 16, 32
    prob = cell_probabilities(b, wi, nt, nphi)
    assert prob.sum() == pytest.approx(ok.mean(), abs=5e-3)  # the pdf integrates to P(not absorbed)
    ct = np.minimum((wo[ok, 2] * nt).astype(int), nt - 1)
    cp = np.minimum((np.mod(np.arctan2(wo[ok, 1], wo[ok, 0]), 2 * np.pi) / (2 * np.pi) * nphi).astype(int), nphi - 1)
    observed = np.bincount(ct * nphi + cp, minlength=nt * nphi).reshape(nt, nphi)
    expected = prob / prob.sum() * ok.sum()
    keep = expected > 20
    chi2 = np.sum((observed[keep] - expected[keep]) ** 2 / expected[keep])
    dof = keep.sum() - 1
    assert keep.sum() > 50
    # chi-square with dof degrees of freedom: mean dof, std sqrt(2 dof); 5 sigma.
    assert chi2 < dof + 5 * np.sqrt(2 * dof), (chi2, dof)


def test_albedo_of_lambertian_and_white_furnace():
    lam = mb.brdf(lambertian=0.7)
    wi = random_hemisphere(np.random.default_rng(1), 5)
    np.testing.assert_allclose(lam.albedo(wi), 0.7, rtol=1e-6)
    # A nearly perfect conductor (k = 1000): the single-scattering albedo of GGX at normal
    # incidence, against the midpoint rule over (cos theta_o, phi_o) of the numpy formula.
    b = mb.brdf(model="ggx", alpha=0.2, n=1.0, k=1e3)
    m = 800
    c = (np.arange(m) + 0.5) / m
    C, P = np.meshgrid(c, (np.arange(m) + 0.5) / m * 2 * np.pi)
    s = np.sqrt(1 - C**2)
    wo = np.column_stack([(s * np.cos(P)).ravel(), (s * np.sin(P)).ravel(), C.ravel()])
    up = np.tile([0.0, 0.0, 1.0], (len(wo), 1))
    ref = np.sum(ggx_conductor(up, wo, 0.2, 0.2, 1 + 1000j) * wo[:, 2]) * (1 / m) * (2 * np.pi / m)
    a = b.albedo([0, 0, 1.0])
    assert a == pytest.approx(ref, rel=1e-4) and a < 1
    assert b.albedo([0, 0, 1.0], method="sampled", n=256) == pytest.approx(a, rel=1e-3)


def test_tabulated_ndf_brdf_close_to_analytic():
    D = mb.tabulate(model="ggx", alpha_x=0.3, resolution=513)
    tab = mb.brdf(ndf=D, metal="Al")
    ana = mb.brdf(model="ggx", alpha=0.3, metal="Al")
    rng = np.random.default_rng(5)
    wi, wo = random_hemisphere(rng, 2000), random_hemisphere(rng, 2000)
    wi, wo = wi[(wi[:, 2] > 0.3) & (wo[:, 2] > 0.3)], wo[(wi[:, 2] > 0.3) & (wo[:, 2] > 0.3)]
    np.testing.assert_allclose(tab.eval(wi, wo), ana.eval(wi, wo), rtol=2e-2)


def test_bad_arguments_raise_value_error():
    b = mb.brdf(model="ggx", alpha=0.2, metal="Au")
    with pytest.raises(ValueError):
        b.eval(np.zeros((4, 2)), np.zeros((4, 3)))
    with pytest.raises(ValueError):
        b.eval(np.zeros((4, 3)), np.zeros((5, 3)))
    with pytest.raises(mb.InputError):
        mb.brdf(model="ggx", alpha=0.2, metal="Unobtainium")
    with pytest.raises(ValueError):
        mb.brdf(model="ggx", alpha=-0.2, metal="Au")


def test_kirchhoff_brdf_is_dong_eq_8_with_the_table():
    # One D_K table, no shadowing: f = D_K(h) F(wi.h) / (4 cos_i cos_o) (Dong 2015 eq. 8, G = 1),
    # with D_K(h) read from the table by D.eval and F the numpy conductor formula.
    from conftest import gaussian_surface

    s = mb.Surface(gaussian_surface(nx=64, ny=64, spacing=0.1e-6, sigma=0.05e-6, tau=0.6e-6), spacing=0.1e-6)
    DK = mb.ndf(s, method="kirchhoff", wavelength=555e-9, patch=None, resolution=129, level="none",
                stack="single")
    b = mb.brdf(kirchhoff=DK, n=1.2, k=3.5)
    rng = np.random.default_rng(2)
    wi, wo = random_hemisphere(rng, 3000), random_hemisphere(rng, 3000)
    h = (wi + wo) / np.linalg.norm(wi + wo, axis=1, keepdims=True)
    ref = DK.eval(h) * fresnel_conductor(np.sum(wi * h, axis=1), 1.2 + 3.5j) / (4 * wi[:, 2] * wo[:, 2])
    np.testing.assert_allclose(b.eval(wi, wo), ref, rtol=1e-12, atol=0)
    assert isinstance(b, mb.KirchhoffBrdf)


def test_multiple_scattering_adds_what_single_scattering_loses():
    # White surface (n = 1, k = 1e3) at alpha 0.8: eq. 1 loses energy that the random walk gives
    # back; the numpy reference is the single-scattering GGX above, so the multiple part is the
    # difference, positive and repeatable (seeded from the arguments).
    rng = np.random.default_rng(9)
    wi, wo = random_hemisphere(rng, 200), random_hemisphere(rng, 200)
    ms = mb.brdf(model="ggx", alpha=0.8, n=1, k=1e3, multiple_scattering=True, ms_walks=32)
    single = ggx_conductor(wi, wo, 0.8, 0.8, 1 + 1e3j)
    f = ms.eval(wi, wo)
    assert np.all(f >= single * (1 - 1e-9)) and np.mean(f - single) > 0.02
    np.testing.assert_array_equal(f, ms.eval(wi, wo))
    up = [0, 0, 1.0]
    assert mb.brdf(model="ggx", alpha=0.8, n=1, k=1e3).albedo(up) < 0.8
    assert ms.albedo(up, method="sampled", n=128) == pytest.approx(1.0, abs=0.02)
    with pytest.raises(ValueError, match="multiple_scattering"):
        mb.brdf(sun=3, metal="Cu", multiple_scattering=True)


def test_multiple_scattering_white_furnace_render():
    # A white (F = 1) rough sphere under a uniform white sky: with multiple scattering it
    # disappears (radiance 1 within noise); single scattering leaves it dark at alpha 1.
    def centre(**kw):
        b = mb.brdf(model="ggx", alpha=1.0, n=1, k=1e4, **kw)
        return mb.render(b, scene="furnace_sphere", size=32, spp=64, white_env=True)[8:24, 8:24, 1]

    ms = centre(multiple_scattering=True, ms_walks=4)
    assert ms.mean() == pytest.approx(1.0, abs=0.01)
    assert centre().mean() < 0.45

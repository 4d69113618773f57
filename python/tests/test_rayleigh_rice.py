"""mb.psd, mb.rayleigh_rice, mb.tis: the PSD against numpy's own periodogram, the BRDF against
the closed form written here, polarisations, Mueller matrices, TIS and bad arguments."""
import numpy as np
import pytest

import microbrdf as mb

DX = 0.25e-6
SIGMA, TAU = 5e-9, 2e-6


def exact_gaussian(n=256, seed=4):
    """A periodic surface whose periodogram is the Gaussian PSD pi tau^2 sigma^2
    exp(-pi^2 tau^2 f^2) (cycles/m): random phases, modulus sqrt(PSD)."""
    rng = np.random.default_rng(seed)
    f = np.fft.fftfreq(n, DX)
    f2 = f[None, :] ** 2 + f[:, None] ** 2
    amp = np.sqrt(np.exp(-np.pi**2 * TAU**2 * f2))
    w = np.fft.fft2(rng.standard_normal((n, n)))  # Hermitian phases: the result is real
    z = np.fft.ifft2(amp * w / np.abs(w)).real
    z -= z.mean()
    return z * (SIGMA / z.std())


def test_psd_is_numpys_periodogram_in_cycles_per_metre():
    z = exact_gaussian()
    P = mb.psd(mb.Surface(z, spacing=DX), window="none", level="none")
    n = z.shape[0]
    ref = np.fft.fftshift(np.abs(np.fft.fft2(z - z.mean())) ** 2) * DX * DX / (n * n)
    ref[n // 2, n // 2] = 0
    assert P.value.shape == (n, n)
    np.testing.assert_allclose(P.fx, np.fft.fftshift(np.fft.fftfreq(n, DX)), rtol=1e-12)
    np.testing.assert_allclose(P.value, ref, rtol=1e-9, atol=1e-12 * ref.max())
    assert P.integral() == pytest.approx(z.var(), rel=1e-12)
    j = P.to_json()
    assert j["frequency_unit"] == "cycles/m" and j["psd_unit"] == "m^4"
    f, v = P.radial()
    assert f[0] == 0 and len(f) == len(v)
    # against the analytic PSD where it is above 1e-3 of its peak: every node (the surface's
    # renormalisation to sigma moves them by the missing zero-frequency power, < 1 %), and the
    # ring means (rings 1 step wide average a steep Gaussian over +-df/2: ~3 % in its tail)
    peak = np.pi * TAU**2 * SIGMA**2
    fr = np.hypot(P.fx[None, :], P.fy[:, None])
    ana = peak * np.exp(-np.pi**2 * TAU**2 * fr**2)
    keep = (ana > 1e-3 * peak) & (fr > 0)
    np.testing.assert_allclose(P.value[keep], ana[keep], rtol=0.01)
    ana = peak * np.exp(-np.pi**2 * TAU**2 * f**2)
    keep = (ana > 1e-3 * peak) & (f > 0)
    np.testing.assert_allclose(v[keep], ana[keep], rtol=0.04)


def q_ss(ti, ts, eps):
    wi, ws = np.sqrt(eps - np.sin(ti) ** 2 + 0j), np.sqrt(eps - np.sin(ts) ** 2 + 0j)
    return abs((eps - 1) / ((np.cos(ti) + wi) * (np.cos(ts) + ws))) ** 2


def test_in_plane_s_brdf_is_the_closed_form_and_polarisations_add_up():
    s = mb.Surface(exact_gaussian(), spacing=DX)
    P = mb.psd(s, window="none", level="none")
    lam, ti = 633e-9, np.radians(30)
    eps = complex(1.2, 7.0) ** 2
    bs = mb.rayleigh_rice(P, n=1.2, k=7.0, polarisation="s")
    bp = mb.rayleigh_rice(P, n=1.2, k=7.0, polarisation="p")
    bu = mb.rayleigh_rice(P, n=1.2, k=7.0)
    wi = np.array([-np.sin(ti), 0, np.cos(ti)])
    ts = np.radians(np.linspace(25, 35, 41))
    wo = np.stack([np.sin(ts), 0 * ts, np.cos(ts)], axis=1)
    fx = (np.sin(ts) - np.sin(ti)) / lam
    want = 16 * np.pi**2 / lam**4 * np.cos(ti) * np.cos(ts) * q_ss(ti, ts, eps) * P.at(fx, 0 * fx)
    np.testing.assert_allclose(bs.eval(wi, wo, lam), want, rtol=1e-10)
    # off the plane: unpolarised = (s + p) / 2, and the Mueller matrix's first row
    rng = np.random.default_rng(1)
    phi = rng.uniform(-0.3, 0.3, 50)
    t = rng.uniform(0.45, 0.6, 50)
    wo = np.stack([np.sin(t) * np.cos(phi), np.sin(t) * np.sin(phi), np.cos(t)], axis=1)
    fu, fs, fp = bu.eval(wi, wo, lam), bs.eval(wi, wo, lam), bp.eval(wi, wo, lam)
    assert fu.max() > 0
    np.testing.assert_allclose(fu, (fs + fp) / 2, rtol=1e-12, atol=1e-15 * fu.max())
    m = bu.mueller(wi, wo, lam)
    assert m.shape == (50, 4, 4)
    np.testing.assert_allclose(m[:, 0, 0], fu, rtol=1e-12, atol=1e-15 * fu.max())
    np.testing.assert_allclose(m[:, 0, 0] + m[:, 0, 1], fs, rtol=1e-10, atol=1e-12 * fu.max())
    assert bu.polarisation == "unpolarised" and bs.psd.sq == pytest.approx(P.sq)
    assert isinstance(bu, mb.Brdf)


def test_tis_closed_form_and_integral():
    s = mb.Surface(exact_gaussian(), spacing=DX)
    rows = mb.tis(s, metal="Al", level="none", window="none")
    assert len(rows) == 16
    for r in rows:
        g = (4 * np.pi * SIGMA * np.cos(r["theta_i_rad"]) / r["wavelength_m"]) ** 2
        assert r["rayleigh_factor"] == pytest.approx(g, rel=1e-9)
        assert r["tis_closed_form"] == pytest.approx(g * r["reflectance"], rel=1e-12)
        if r["theta_i_deg"] <= 45:  # tau 2 um: the smooth-surface limit holds
            assert r["integral_over_closed_form"] == pytest.approx(1, abs=0.03), r
    one = mb.tis(s, wavelength=633e-9, theta_i=0.0, level="none")
    assert len(one) == 1 and "tis_integral" not in one[0]
    b = mb.rayleigh_rice(s, metal="Al", level="none")
    wi = np.array([0.0, 0.0, 1.0])
    r0 = mb.tis(b.psd, metal="Al", wavelength=555e-9, theta_i=0.0)[0]
    assert b.specular_reflectance(wi, 555e-9) == pytest.approx(r0["specular_reflectance"])


def test_bad_arguments_are_input_errors():
    s = mb.Surface(exact_gaussian(64), spacing=DX)
    with pytest.raises(mb.InputError, match="polarisation"):
        mb.rayleigh_rice(s, metal="Al", polarisation="circular")
    with pytest.raises(mb.InputError, match="optical constants"):
        mb.rayleigh_rice(s)
    with pytest.raises(mb.InputError, match="fresnel"):
        mb.rayleigh_rice(s, metal="Al", fresnel="schlick")
    with pytest.raises(mb.InputError, match="material keyword"):
        mb.rayleigh_rice(s, metal="Al", alpha=0.1)
    with pytest.raises(mb.InputError, match="window"):
        mb.psd(s, window="hamming")
    with pytest.raises(mb.InputError, match="tile"):
        mb.psd(s, tile=1)
    with pytest.raises(mb.InputError, match="wavelength"):
        mb.tis(s, wavelength=5.0)


def welch_psd(z, t):
    """Welch's PSD written here: Hann tiles of t samples, 50 % overlap (the last tile ends at the
    edge), each tile's window-weighted mean removed, dx dy |FFT|^2 / sum w^2, averaged."""
    n = z.shape[0]
    starts = list(range(0, n - t + 1, t // 2))
    if starts[-1] + t < n:
        starts.append(n - t)
    w1 = np.sin(np.pi * (np.arange(t) + 0.5) / t) ** 2
    w = w1[None, :] * w1[:, None]
    acc = np.zeros((t, t))
    for y0 in starts:
        for x0 in starts:
            h = z[y0:y0 + t, x0:x0 + t]
            h = (h - (w * h).sum() / w.sum()) * w
            acc += np.abs(np.fft.fft2(h)) ** 2 * DX * DX / (w * w).sum()
    acc = np.fft.fftshift(acc / len(starts) ** 2)
    acc[t // 2, t // 2] = 0
    return acc, len(starts) ** 2


def test_default_tile_is_welch_and_averages_the_speckle_out():
    z = exact_gaussian(600)
    s = mb.Surface(z, spacing=DX)
    auto = mb.psd(s, level="none")            # default tile="auto"
    whole = mb.psd(s, level="none", tile="whole")
    assert whole.tiles == 1 and "whole scan" in whole.tile_choice
    t = auto.to_json()["tile_nx"]
    # 32 correlation lengths (tau 2 um = 8 samples, as the scan's ACF reads it): about 256.
    assert 240 <= t <= 272 and "Welch" in auto.tile_choice, auto.tile_choice
    ref, tiles = welch_psd(z, t)
    assert auto.tiles == tiles
    assert np.allclose(auto.value, ref, rtol=1e-9, atol=1e-12 * ref.max())
    # Against the analytic PSD over the halo: the median of one Hann periodogram is about ln 2 of
    # it (exponential speckle), the Welch average's near 1 with a spread three times smaller.
    def ratios(p):
        fx, fy = np.meshgrid(p.fx, p.fy)
        f2 = fx**2 + fy**2
        sel = (f2 > 0) & (f2 * TAU**2 < 0.36)
        theory = np.pi * TAU**2 * SIGMA**2 * np.exp(-np.pi**2 * TAU**2 * f2[sel])
        return p.value[sel] / theory
    rw, ra = ratios(whole), ratios(auto)
    assert abs(np.median(rw) - np.log(2)) < 0.15, np.median(rw)
    assert abs(np.median(ra) - 1) < 0.15, np.median(ra)
    assert np.std(ra) / np.mean(ra) < np.std(rw) / np.mean(rw) / 2.5
    with pytest.raises(mb.InputError, match="tile"):
        mb.psd(s, tile="often")

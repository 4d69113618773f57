"""The no-copy claims: outputs are views on the library's buffers, kept alive by their owner;
float64 C-contiguous inputs are read in place, others converted once."""
import gc

import numpy as np
import pytest

import microbrdf as mb


def test_surface_views_share_the_surface_storage(data):
    s = mb.read_surface(data / "metropro-1.dat")
    h1, h2 = s.heights, s.heights
    assert np.shares_memory(h1, h2) and not h1.flags.owndata
    assert h1.shape == (480, 640) and h1.dtype == np.float64 and h1.flags.c_contiguous
    assert s.valid.dtype == bool and not s.valid.flags.owndata and not s.valid.flags.writeable
    # A write through the view is seen by the library (no hidden copy).
    before = mb.statistics(s, level="none")["max_m"]
    h1[0, 0] = before + 1e-6
    assert mb.statistics(s, level="none")["max_m"] == before + 1e-6
    # The view keeps the surface alive.
    del s
    gc.collect()
    assert h2[0, 0] == before + 1e-6


def test_surface_input_is_copied_once():
    z = np.arange(12.0).reshape(3, 4) * 1e-9
    s = mb.Surface(z, spacing=1e-6)
    assert not np.shares_memory(s.heights, z)  # the surface owns its heights
    np.testing.assert_array_equal(s.heights, z)


def test_ndf_buffer_protocol_is_a_view():
    D = mb.tabulate(model="ggx", alpha_x=0.3, resolution=65)
    a, v = np.asarray(D), D.values
    assert np.shares_memory(a, v) and not a.flags.owndata and not v.flags.owndata
    m = np.array([0.0, 0.0, 1.0])
    centre = D.eval(m)
    a *= 2  # through the buffer
    assert D.eval(m) == 2 * centre
    del D
    gc.collect()
    assert v[32, 32] == a[32, 32]  # the views keep the table alive


def test_render_image_is_a_view():
    img = mb.render(mb.brdf(lambertian=0.5), scene="sphere", size=8, spp=1)
    assert img.shape == (8, 8, 3) and img.dtype == np.float32 and not img.flags.owndata


def test_direction_inputs_read_in_place_or_converted_once():
    a = np.random.default_rng(0).random((100, 3))
    assert mb._input_address(a) == a.ctypes.data  # float64 C-contiguous: no copy
    f32 = a.astype(np.float32)
    assert mb._input_address(f32) != f32.ctypes.data  # converted
    strided = np.asfortranarray(a)
    assert mb._input_address(strided) != strided.ctypes.data
    # Converted inputs give the same answers.
    b = mb.brdf(model="ggx", alpha=0.3, metal="Al")
    wi = a / np.linalg.norm(a, axis=1, keepdims=True)
    np.testing.assert_array_equal(b.eval(wi, wi), b.eval(np.asfortranarray(wi), wi.tolist()))


def test_tabulated_ndf_from_array_and_surface_save_round_trip(tmp_path):
    values = np.random.default_rng(1).random((33, 33))
    D = mb.TabulatedNdf(values)
    assert np.array_equal(np.asarray(D), values) and not np.shares_memory(np.asarray(D), values)
    D.normalise()
    assert D.integral() == pytest.approx(1, rel=1e-12)
    z = np.random.default_rng(2).normal(size=(20, 30)) * 1e-7
    z[3, 4] = np.nan
    s = mb.Surface(z, spacing=(1e-6, 2e-6))
    s.save(tmp_path / "s.x3p")
    back = mb.read_surface(tmp_path / "s.x3p")
    assert back.spacing == pytest.approx((1e-6, 2e-6)) and not back.valid[3, 4]
    np.testing.assert_allclose(back.heights[s.valid], z[s.valid], rtol=1e-12)

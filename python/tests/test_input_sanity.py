"""A greyscale picture is not a height map: integer TIFF counts need a height unit (z_scale),
and with one they are heights (compared with numpy on the same counts)."""
import numpy as np
import pytest

import microbrdf as mb

PIL = pytest.importorskip("PIL.Image")


@pytest.fixture
def grey_tif(tmp_path):
    y, x = np.mgrid[0:24, 0:32]
    counts = (100 + 50 * np.sin(x / 4.0) * np.cos(y / 6.0)).astype(np.uint8)
    path = tmp_path / "grey.tif"
    PIL.fromarray(counts, mode="L").save(path)
    return path, counts


def test_integer_counts_without_a_unit_are_refused_naming_the_file(grey_tif):
    path, _ = grey_tif
    with pytest.raises(mb.FileError, match="8-bit integer samples and no height unit") as info:
        mb.read_surface(path, spacing=1e-6)
    assert info.value.filename == str(path)


def test_z_scale_makes_counts_heights(grey_tif):
    path, counts = grey_tif
    s = mb.read_surface(path, spacing=1e-6, z_scale=5e-9)
    assert np.allclose(np.asarray(s.heights), counts.astype(float) * 5e-9, rtol=0, atol=1e-18)


def test_a_png_is_said_to_be_a_picture(tmp_path):
    path = tmp_path / "photo.png"
    PIL.fromarray(np.zeros((8, 8), np.uint8), mode="L").save(path)
    with pytest.raises(mb.FileError, match="a PNG picture, not a height map"):
        mb.read_surface(path, spacing=1e-6)

"""Errors become Python exceptions: files -> FileError (an OSError naming the file), bad values
-> ValueError; never a crash."""
import errno

import numpy as np
import pytest

import microbrdf as mb


def test_missing_file_is_an_oserror_naming_the_file(tmp_path):
    path = tmp_path / "no-such-scan.x3p"
    with pytest.raises(OSError) as info:
        mb.read_surface(path)
    e = info.value
    assert isinstance(e, mb.FileError)
    assert e.filename == str(path) and e.errno == errno.ENOENT
    assert str(path) in str(e)
    with pytest.raises(mb.FileError):
        mb.ndf(path, resolution=65)
    with pytest.raises(mb.FileError):
        mb.read_ndf(tmp_path / "none.npy")


@pytest.mark.parametrize("name, content", [
    ("corrupt.x3p", b"PK\x03\x04 this is not a zip archive at all"),
    ("truncated.npy", b"\x93NUMPY\x01\x00\x76\x00{'descr': '<f8', 'fortran_order': False, 'shape': (100, 100), }"),
    ("garbage.dat", bytes(range(256)) * 4),
    ("empty.sur", b""),
])
def test_corrupt_file_is_a_file_error_naming_it(tmp_path, name, content):
    path = tmp_path / name
    path.write_bytes(content)
    with pytest.raises(mb.FileError) as info:
        mb.read_surface(path, spacing=1e-6)
    assert info.value.filename == str(path) and info.value.errno is None
    assert str(info.value).startswith(str(path) + ": ") and info.value.strerror


def test_corrupt_shbrdf_and_ndf_files(tmp_path):
    bad = tmp_path / "bad.shbrdf"
    bad.write_bytes(b"MBSHBRDF\xff\xff\xff\x7f{")
    with pytest.raises(mb.FileError, match="bad.shbrdf"):
        mb.ShBrdf.load(bad)
    np.save(tmp_path / "nd.npy", np.zeros((3, 4)))
    with pytest.raises((mb.FileError, ValueError)):
        mb.fit(tmp_path / "nd.npy")


def test_negative_or_bad_values_raise_value_error(data):
    s = mb.Surface(np.zeros((8, 8)), spacing=1e-6)
    with pytest.raises(ValueError, match="filter_sigma"):
        mb.ndf(s, method="filtered", filter_sigma=-1e-6, resolution=65)
    with pytest.raises(ValueError):
        mb.ndf(s, method="kirchhoff", wavelength=-5e-7, resolution=65)
    with pytest.raises(ValueError):
        mb.ndf(s, method="sideways", resolution=65)
    with pytest.raises(ValueError):
        mb.ndf(s, resolution=5)
    with pytest.raises(ValueError):
        mb.Surface(np.zeros((8, 8)), spacing=-1e-6)
    with pytest.raises(ValueError):
        mb.Surface(np.zeros(8), spacing=1e-6)
    with pytest.raises(ValueError):
        mb.statistics(s, level="poly99")
    with pytest.raises(ValueError):
        mb.fit(mb.tabulate(model="ggx", alpha_x=0.2, resolution=65), model="gaussian")
    # An InputError is a ValueError.
    assert issubclass(mb.InputError, ValueError) and issubclass(mb.FileError, OSError)

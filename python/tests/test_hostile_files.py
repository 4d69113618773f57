"""Hostile files from Python: JSON that is long rather than deep reads in linear time, and data
problems raise FileError naming the input file (never the output), or ValueError naming the
argument."""
import shutil

import numpy as np
import pytest

import microbrdf as mb

HEADER = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,wavelength_nm,brdf_per_sr\n"


def rows(wavelength=550):
    return "".join(f"{ti},0,{to},{po},{wavelength},2.5\n" for ti in (0, 10, 20, 30)
                   for to in (5, 15, 25, 35) for po in (160, 180, 200))


def test_three_megabyte_sidecar_reads(tmp_path):
    # A million empty objects (no timing assert: a reader gone quadratic would take hours here
    # and hit the suite's timeout).
    z = np.random.default_rng(1).normal(0, 1e-7, (16, 16))
    np.save(tmp_path / "h.npy", z)
    flat = "[" + ",".join(["{}"] * 1000000) + "]"
    (tmp_path / "h.json").write_text('{"dx_m": 2e-6, "dy_m": 3e-6, "junk": ' + flat + "}")
    s = mb.read_surface(tmp_path / "h.npy")
    assert s.spacing == pytest.approx((2e-6, 3e-6))
    # One level too deep inside the same megabytes is still refused, naming the sidecar.
    (tmp_path / "h.json").write_text('{"dx_m": 2e-6, "junk": [' + ",".join(["{}"] * 300000) +
                                     "," + "[" * 64 + "]" * 64 + "]}")
    with pytest.raises(mb.FileError) as info:
        mb.read_surface(tmp_path / "h.npy")
    assert "h.json" in str(info.value) and "nested deeper than 64" in str(info.value)


def test_negative_brdf_names_the_csv_and_its_line(tmp_path):
    path = tmp_path / "neg.csv"
    path.write_text(HEADER + rows() + "10,0,12,180,550,-0.25\n")
    with pytest.raises(mb.FileError) as info:
        mb.measured_ndf(path, resolution=65)
    assert info.value.filename == str(path)
    assert "line 50: brdf_per_sr is negative" in str(info.value)


@pytest.mark.parametrize("body, message", [
    ("10,0,10,180,550,1\n10,0,10,180,550,2\n", "share one half vector"),
    ("10,0,90,180,550,1\n20,0,90,180,550,2\n", "both directions above the horizon"),
])
def test_point_set_problems_name_the_csv(tmp_path, body, message):
    path = tmp_path / "points.csv"
    path.write_text(HEADER + body)
    with pytest.raises(mb.FileError) as info:
        mb.measured_ndf(path, resolution=65)
    assert info.value.filename == str(path) and message in str(info.value)


def test_byte_order_mark_and_kernel_range(tmp_path):
    path = tmp_path / "bom.csv"
    path.write_bytes(b"\xef\xbb\xbf" + (HEADER + rows()).encode())
    t = mb.measured_ndf(path, resolution=65)
    assert np.isfinite(t.values).any()
    for kernel in (1e300, -1.0, float("nan"), 0.6):
        with pytest.raises(ValueError, match="kernel width must lie in"):
            mb.measured_ndf(path, resolution=65, kernel=kernel)
    with pytest.raises(mb.FileError, match="within two kernel widths") as info:
        mb.measured_ndf(path, resolution=65, kernel=1e-12)
    assert info.value.filename == str(path)


def test_all_negative_merl_file_is_refused_naming_it(tmp_path):
    path = tmp_path / "nodata.binary"
    with open(path, "wb") as f:
        f.write(np.array([90, 90, 180], "<i4").tobytes())
        np.full(3 * 90 * 90 * 180, -1.0, "<f8").tofile(f)
    with pytest.raises(mb.FileError, match="no valid BRDF value") as info:
        mb.measured_ndf(path, resolution=65)
    assert info.value.filename == str(path)

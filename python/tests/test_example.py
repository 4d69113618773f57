"""The example script runs on a real scan and writes its figures."""
import json
import os
import subprocess
import sys

from conftest import ROOT


def test_scan_to_fits_example(tmp_path):
    script = ROOT / "examples" / "python" / "scan_to_fits.py"
    out = tmp_path / "figs"
    env = dict(os.environ, MPLBACKEND="Agg")
    run = subprocess.run([sys.executable, script, "-o", out, "--resolution", "129"], env=env,
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    for name in ("heights.png", "ndfs.png", "slices.png"):
        png = (out / name).read_bytes()
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 10000, name
    fits = json.loads((out / "fits.json").read_text())
    assert set(fits) == {"naive", "filtered", "kirchhoff"}
    for by_model in fits.values():
        for r in by_model.values():
            assert r["params"]["alpha_x"] > 0 and r["relative_l2_error"] < 1

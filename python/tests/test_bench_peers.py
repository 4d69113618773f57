"""The numpy peers in bench/peers/ (the independent reference of bench/whole_process.py) against
the command line: the harness in --quick mode on a generated scan, and each peer on a scan with
holes (invalid samples exercise the masks, one-sided slopes and skipped elements). No timing is
asserted; the outputs must agree to 1e-3 (relative L1 of the tables, relative difference of
every info statistic)."""
import json
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT, gaussian_surface

BENCH = ROOT / "bench"
sys.path.insert(0, str(BENCH))
import whole_process  # noqa: E402


def test_harness_quick_peers_agree(cli, tmp_path):
    out = tmp_path / "whole.json"
    r = subprocess.run([sys.executable, str(BENCH / "whole_process.py"), "--quick", "--bin",
                        str(cli.parent), "--python", sys.executable, "--json", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    res = json.loads(out.read_text())
    diffs = {row["command"]: row["difference"] for row in res["rows"] if "difference" in row}
    assert set(diffs) == {"info", "naive", "filtered", "kirchhoff"}
    for command, d in diffs.items():
        assert d <= 1e-3, command
    assert "| 128x96 | kirchhoff |" in r.stdout


@pytest.fixture
def holey_scan(tmp_path):
    z = gaussian_surface(nx=96, ny=80, spacing=110e-9, sigma=0.1e-6, tau=1e-6, holes=True)
    z += 2e-3 * np.arange(96)[None, :] * 110e-9  # a tilt for the levelling to remove
    path = tmp_path / "holey.npy"
    np.save(path, z)
    (tmp_path / "holey.json").write_text(json.dumps({"dx_m": 110e-9, "dy_m": 110e-9,
                                                     "z_unit": "m", "invalid": "NaN"}))
    return path


@pytest.mark.parametrize("command", ["naive", "filtered", "kirchhoff", "info"])
def test_peer_agrees_on_scan_with_holes(cli, holey_scan, tmp_path, command):
    argv, stdout, out, pargv, pout = whole_process.invocations(
        command, str(cli), sys.executable, str(holey_scan), str(tmp_path), "holey")
    whole_process.run(argv, stdout)
    whole_process.run(pargv)
    d, what = whole_process.difference(command, out, pout)
    assert d <= 1e-3, what


def test_difference_sees_a_wrong_peer(cli, holey_scan, tmp_path):
    """The check itself can fail: a table 1 % off somewhere is reported above 1e-3."""
    argv, _, out, _, _ = whole_process.invocations("naive", str(cli), sys.executable,
                                                   str(holey_scan), str(tmp_path), "holey")
    whole_process.run(argv)
    t = np.load(out)
    t[t > 0] *= 1 + 0.02 * (np.arange((t > 0).sum()) % 2)
    np.save(tmp_path / "wrong.npy", t)
    assert whole_process.difference("naive", out, str(tmp_path / "wrong.npy"))[0] > 1e-3

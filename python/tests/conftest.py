"""Shared fixtures: where the test data and the CLI are (ctest sets MICROBRDF_TEST_DATA and
MICROBRDF_CLI; run by hand, the defaults point into the source and build trees)."""
import os
import pathlib

import numpy as np
import pytest

ROOT = pathlib.Path(os.environ.get("MICROBRDF_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))
DATA = pathlib.Path(os.environ.get("MICROBRDF_TEST_DATA", ROOT / "tests" / "data"))
CLI = pathlib.Path(os.environ.get("MICROBRDF_CLI", ROOT / "build" / "bin" / "microbrdf"))


@pytest.fixture
def data():
    return DATA


@pytest.fixture
def cli():
    if not CLI.exists():
        pytest.fail(f"the CLI is not built: {CLI}")
    return CLI


def gaussian_surface(nx=96, ny=80, spacing=0.5e-6, sigma=0.2e-6, tau=2e-6, seed=3, holes=False):
    """A random Gaussian-correlated height map made with numpy (FFT filtering of white noise)."""
    rng = np.random.default_rng(seed)
    w = rng.standard_normal((ny, nx))
    kx = np.fft.fftfreq(nx, spacing) * 2 * np.pi
    ky = np.fft.fftfreq(ny, spacing) * 2 * np.pi
    k2 = kx[None, :] ** 2 + ky[:, None] ** 2
    z = np.real(np.fft.ifft2(np.fft.fft2(w) * np.exp(-k2 * tau**2 / 8)))
    z *= sigma / z.std()
    if holes:
        z[10:14, 20:30] = np.nan
        z[50, 5] = np.nan
    return z

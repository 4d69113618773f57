# Type stubs of the microbrdf module. SI units: metres, radians, 1/sr.
import os
from typing import Any, Callable, List, Optional, Sequence, Tuple, Union, overload

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]
Length2 = Union[float, Tuple[float, float]]
Directions = npt.ArrayLike  # (N, 3) or (3,)
ScanLike = Union["Surface", PathLike]
Scans = Union[ScanLike, Sequence[ScanLike]]

__version__: str  # "MAJOR.MINOR.PATCH" of the library, as `microbrdf --version` prints

class FileError(OSError):
    """A file that cannot be read or written, or is corrupt; filename names it."""
    def __init__(self, filename: str, problem: str, errno: Optional[int] = ...) -> None: ...

class InputError(ValueError):
    """A bad value that is not a file."""

class Surface:
    """A height map (metres, NaN = invalid); heights/valid are numpy views (no copy)."""
    def __init__(self, heights: npt.ArrayLike, spacing: Length2, mask: Optional[npt.ArrayLike] = ...) -> None: ...
    @property
    def heights(self) -> npt.NDArray[np.float64]: ...
    @property
    def valid(self) -> npt.NDArray[np.bool_]: ...
    @property
    def spacing(self) -> Tuple[float, float]: ...
    @property
    def shape(self) -> Tuple[int, int]: ...
    @property
    def nx(self) -> int: ...
    @property
    def ny(self) -> int: ...
    @property
    def x0(self) -> float: ...
    @property
    def y0(self) -> float: ...
    @property
    def z0(self) -> float: ...
    @property
    def metadata(self) -> dict[str, str]: ...
    @property
    def path(self) -> str: ...
    @property
    def valid_fraction(self) -> float: ...
    def sync_mask(self) -> None: ...
    def copy(self) -> Surface: ...
    def level(self, mode: str = "plane") -> Surface: ...
    def save(self, path: PathLike) -> None: ...

def read_surface(
    path: PathLike, spacing: Optional[Length2] = ..., z_scale: Optional[float] = ...
) -> Surface: ...
@overload
def statistics(surface: ScanLike, level: str = ..., spacing: Optional[Length2] = ...) -> dict[str, Any]: ...
@overload
def statistics(surface: Sequence[ScanLike], level: str = ..., spacing: Optional[Length2] = ...) -> list[dict[str, Any]]: ...

class TabulatedNdf:
    """An N x N table of D(m) (1/sr) on the projected disk; np.asarray(D) is a view."""
    def __init__(self, values: npt.ArrayLike) -> None: ...
    def __buffer__(self, flags: int) -> memoryview: ...
    @property
    def values(self) -> npt.NDArray[np.float64]: ...
    @property
    def resolution(self) -> int: ...
    @property
    def spacing(self) -> float: ...
    @property
    def window(self) -> dict[str, tuple[float, float]]: ...
    @property
    def sampling(self) -> str: ...
    @property
    def nodes(self) -> npt.NDArray[np.float64]: ...
    @property
    def nodes_y(self) -> npt.NDArray[np.float64]: ...
    @property
    def metadata(self) -> dict[str, Any]: ...
    @overload
    def eval(self, m: Sequence[float]) -> float: ...
    @overload
    def eval(self, m: npt.ArrayLike) -> npt.NDArray[np.float64]: ...
    def integral(self) -> float: ...
    def normalise(self) -> None: ...
    def moments(self) -> dict[str, Any]: ...
    def rms_slope(self, azimuth: float) -> float: ...
    def slice(self, azimuth: float = 0.0, samples: int = 1025) -> dict[str, npt.NDArray[np.float64]]: ...
    def resampled(self, resolution: int) -> TabulatedNdf: ...
    def save(self, path: PathLike) -> None: ...
    def save_preview(self, path: PathLike, zoom: bool = False) -> None: ...

def read_ndf(path: PathLike) -> TabulatedNdf: ...
def ndf(
    surface: Scans,
    method: str = "filtered",
    filter_sigma: float = 1e-6,
    resolution: int = 1025,
    level: str = "plane",
    spacing: Optional[Length2] = None,
    min_support: float = 0.5,
    instrument_fwhm: float = 0.0,
    wavelength: float = 555e-9,
    patch: Optional[Length2] = (70e-6, 53e-6),
    window: str = "hann",
    accuracy: float = 1e-3,
    direct: bool = False,
    keep_aliases: bool = False,
    progress: Optional[Callable[[float], None]] = None,
    integration: str = "midpoint",
    supersample: int = 0,
    stack: str = "visible",
) -> Union[TabulatedNdf, List[TabulatedNdf]]: ...
def hellinger_distance(a: TabulatedNdf, b: TabulatedNdf) -> float: ...
def filter_sigma_auto(
    surface: Scans,
    wavelength: float = 555e-9,
    patch: Optional[Length2] = (70e-6, 53e-6),
    window: str = "hann",
    accuracy: float = 1e-3,
    keep_aliases: bool = False,
    resolution: int = 257,
    level: str = "plane",
    spacing: Optional[Length2] = None,
    min_support: float = 0.5,
) -> dict[str, Any]: ...
def tabulate(
    model: str = "ggx",
    alpha_x: float = 0.1,
    alpha_y: float = 0.0,
    phi: float = 0.0,
    theta_x: float = 0.0,
    theta_y: float = 0.0,
    theta_z: float = 0.0,
    resolution: int = 1025,
    window: Optional[tuple[float, float, float]] = None,
    **params: float,
) -> TabulatedNdf: ...
def ndf_models() -> list[dict[str, Any]]: ...
def fit(
    ndf: Union[TabulatedNdf, PathLike],
    model: str = "ellipsoid",
    objective: str = "sqrt",
    sampling: str = "auto",
    subsamples: int = 0,
    threads: int = 0,
) -> dict[str, Any]: ...

class Brdf:
    """f(wi, wo) in 1/sr in the local frame (n = +z); directions (N, 3) float64."""
    @overload
    def eval(self, wi: Sequence[float], wo: Sequence[float], wavelength: float = 555e-9) -> float: ...
    @overload
    def eval(self, wi: Directions, wo: Directions, wavelength: float = 555e-9) -> npt.NDArray[np.float64]: ...
    @overload
    def pdf(self, wi: Sequence[float], wo: Sequence[float]) -> float: ...
    @overload
    def pdf(self, wi: Directions, wo: Directions) -> npt.NDArray[np.float64]: ...
    def sample(
        self, wi: Directions, u: Optional[npt.ArrayLike] = None, wavelength: float = 555e-9, seed: Optional[int] = None
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def albedo(
        self, wi: Directions, wavelength: float = 555e-9, method: str = "quadrature", n: int = 128
    ) -> Union[float, npt.NDArray[np.float64]]: ...
    def describe(self) -> str: ...

class MicrofacetBrdf(Brdf): ...
class KirchhoffBrdf(Brdf): ...
class LambertianBrdf(Brdf): ...

class ShBrdf(Brdf):
    """Westin 1992 SH-matrix BRDF; matrix is a read-only view."""
    @property
    def lmax(self) -> int: ...
    @property
    def matrix(self) -> npt.NDArray[np.float64]: ...
    @property
    def metadata(self) -> dict[str, Any]: ...
    def isotropic_average(self) -> ShBrdf: ...
    def damped(self, l_filter: int, width: float) -> ShBrdf: ...
    def save(self, path: PathLike) -> None: ...
    @staticmethod
    def load(path: PathLike) -> ShBrdf: ...

def brdf(**flags: Any) -> Brdf:
    """A BRDF from the keys of the CLI's BRDF and material flags (model=, alpha=, ndf=, ...,
    metal=, ...). multiple_scattering=True (model or ndf only; default False) adds the light
    that bounces between microfacets more than once (microfacet random walk, Heitz 2016):
    eval() is then a Monte Carlo estimate seeded from its arguments (repeated calls agree),
    sample() runs one walk. See docs/multiple_scattering.md."""

class Psd:
    """Areal PSD of a scan: cycles/m, m^4, two-sided; value[iy, ix] at (fx[ix], fy[iy])."""
    @property
    def value(self) -> npt.NDArray[np.float64]: ...
    @property
    def fx(self) -> npt.NDArray[np.float64]: ...
    @property
    def fy(self) -> npt.NDArray[np.float64]: ...
    @property
    def dfx(self) -> float: ...
    @property
    def dfy(self) -> float: ...
    @property
    def sq(self) -> float: ...
    @property
    def tiles(self) -> int: ...
    @property
    def tile_choice(self) -> str: ...
    @property
    def window(self) -> str: ...
    def integral(self) -> float: ...
    def rms_slope(self) -> float: ...
    def at(self, fx: npt.ArrayLike, fy: npt.ArrayLike) -> Union[float, npt.NDArray[np.float64]]: ...
    def radial(self) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]: ...
    def to_json(self) -> dict[str, Any]: ...

class RayleighRiceBrdf(Brdf):
    """First-order Rayleigh-Rice BRDF of a smooth metal (diffuse part; the delta is separate)."""
    def mueller(self, wi: Directions, wo: Directions, wavelength: float = 555e-9) -> npt.NDArray[np.float64]: ...
    def specular_reflectance(self, wi: Sequence[float], wavelength: float = 555e-9) -> float: ...
    @property
    def psd(self) -> Psd: ...
    @property
    def polarisation(self) -> str: ...

def psd(
    surface: ScanLike,
    window: str = "hann",
    tile: Union[int, str, None] = "auto",
    level: str = "plane",
    spacing: Optional[Length2] = None,
) -> Psd: ...
def rayleigh_rice(
    surface: Union[ScanLike, Psd],
    polarisation: str = "unpolarised",
    window: str = "hann",
    tile: Union[int, str, None] = "auto",
    level: str = "plane",
    spacing: Optional[Length2] = None,
    **material: Any,
) -> RayleighRiceBrdf: ...
def tis(
    surface: Union[ScanLike, Psd],
    wavelength: Union[float, Sequence[float], None] = None,
    theta_i: Union[float, Sequence[float], None] = None,
    polarisation: str = "unpolarised",
    window: str = "hann",
    tile: Union[int, str, None] = "auto",
    level: str = "plane",
    spacing: Optional[Length2] = None,
    **material: Any,
) -> list[dict[str, Any]]: ...
def measured_ndf(
    path: PathLike,
    *,
    theta_d: float = 0.24678907,
    resolution: int = 1025,
    wavelength: float = 550e-9,
    shadowing: str = "none",
    kernel: float = 0.0,
    **material: Any,
) -> TabulatedNdf:
    """Effective NDF (1/sr, NaN = unmeasured) of a goniometer .csv, MERL .binary or RGL .bsdf
    (Dong 2015 eq. 9). theta_d in radians (default 14.14 deg), wavelength in metres; material
    keywords (metal=, n=, k=, ...) give F, else F = 1 (the shape)."""
def export_bsdf(
    output: PathLike,
    measured: Optional[PathLike] = None,
    *,
    brdf: Optional[Brdf] = None,
    isotropic: Optional[bool] = None,
    theta_i: int = 24,
    phi_i: int = 17,
    ndf_grid: int = 64,
    samples: int = 32,
    wavelengths: Union[int, Sequence[float]] = 25,
    progress: Optional[Callable[[float], None]] = None,
    **flags: Any,
) -> dict[str, Any]:
    """Writes a BRDF (measured=, brdf= or the keywords of brdf()) as an RGL .bsdf file for
    Mitsuba 3 / pbrt-v4. wavelengths: a count over 360-830 nm or metres. Returns a summary
    dict (output, source, isotropic, theta_i, phi_i, ndf_grid, samples, wavelengths [m], bytes)."""
def export_gltf(output: PathLike, *, uv_scale: float = 1.0, **flags: Any) -> dict[str, Any]:
    """Writes the material of the keywords of brdf() (tables as paths) as glTF 2.0 (.glb, or
    .gltf + .bin + PNGs) with KHR_materials_anisotropy on a sphere and a plate. Returns a
    summary dict (output, files, source, ggx, base_color_linear_srgb, roughness,
    anisotropy_strength, anisotropy_rotation, warnings)."""
def simulate(
    scene: PathLike,
    lmax: int = 15,
    rays: int = 2000000,
    points: int = 16,
    branches: int = 1,
    max_depth: int = 100,
    seed: int = 1,
    threads: int = 0,
    independent: bool = False,
    time: float = 0.0,
    progress: Optional[Callable[[float], None]] = None,
) -> ShBrdf: ...
def render(
    brdf: Union[Brdf, Sequence[Brdf]],
    scene: str = "cylinders",
    size: int = 256,
    width: int = 0,
    height: int = 0,
    spp: int = 16,
    max_depth: int = 6,
    wavelengths: int = 8,
    seed: int = 1,
    threads: int = 0,
    mis: str = "mis",
    sampler: str = "sobol",
    envmap: Optional[PathLike] = None,
    env_scale: float = 1.0,
    env_rotation: float = 0.0,
    white_env: bool = False,
    point: Sequence[Any] = ...,
    sphere_light: Sequence[Any] = ...,
    disk_light: Sequence[Any] = ...,
    brushing: str = "linear",
    brush_angle: float = 0.0,
    obj: Optional[PathLike] = None,
    uv_scale: float = 1.0,
    progress: Optional[Callable[[float], None]] = None,
    direct: str = "ris",
    ris_brdf_candidates: int = 6,
    ris_light_candidates: int = 3,
    variants: Optional[Sequence[Union[Brdf, Sequence[Brdf]]]] = None,
    variant_weights: Sequence[float] = ...,
) -> Union[npt.NDArray[np.float32], List[npt.NDArray[np.float32]]]: ...
def predict(
    inputs: Union[PathLike, Sequence[PathLike]],
    out_dir: PathLike,
    metal: str = "Fe",
    filter_sigma: Union[float, str] = 1e-6,
    resolution: int = 1025,
    kirchhoff: bool = False,
    wavelength: float = 555e-9,
    patch: Optional[Length2] = (70e-6, 53e-6),
    theta_i: Sequence[float] = ...,
    envmap: Optional[PathLike] = None,
    envmap_scale: float = 1.0,
    render_width: int = 256,
    spp: int = 32,
    no_render: bool = False,
    renders: str = "all",
    strips: Optional[Tuple[Any, Any]] = None,
    texel: float = 53e-6,
    texture_size: int = 128,
    seed: int = 1,
    threads: int = 0,
    level: str = "plane",
    spacing: Optional[Length2] = None,
    render_ndf: str = "filtered",
    sweep_resolution: int = 257,
    progress: Optional[Callable[[str], None]] = None,
    integration: str = "midpoint",
    supersample: int = 0,
    window: str = "hann",
    theory: str = "auto",
    multiple_scattering: str = "auto",
) -> dict[str, Any]: ...

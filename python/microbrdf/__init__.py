"""microbrdf: how a metal surface reflects light, predicted from its measured microgeometry.

Every stage of the command-line tool as a function on numpy arrays, in SI units (metres,
radians), with the keyword names of the CLI flags (``--filter-sigma`` -> ``filter_sigma``):

    import microbrdf as mb
    s = mb.read_surface("scan.x3p")            # Surface: s.heights, s.valid (numpy views)
    mb.statistics(s)                           # dict, the keys of `microbrdf info --json`
    D = mb.ndf(s, method="filtered", filter_sigma=1e-6, resolution=1025)
    mb.fit(D, model="ellipsoid")               # dict, the keys of `microbrdf fit --json`
    b = mb.brdf(ndf=D, metal="Al")
    b.eval(wi, wo, wavelength=555e-9)          # (N, 3), (N, 3) -> (N,), 1/sr
    mb.export_bsdf("g.bsdf", model="ggx", alpha=0.3, n=1.2, k=3.5)   # RGL .bsdf for renderers
    mb.export_gltf("al.glb", model="ggx", alpha_x=0.1, alpha_y=0.3, metal="Al")  # glTF 2.0
    E = mb.measured_ndf("goni.csv", n=1.6, k=3.2)                   # Dong eq. 9, NaN = unmeasured
    P = mb.psd(s)                              # areal PSD, cycles/m, m^4 (ISO 25178)
    rr = mb.rayleigh_rice(s, metal="Al", polarisation="s")          # smooth metals, first order
    mb.tis(s, metal="Al", wavelength=633e-9, theta_i=0.0)           # total integrated scatter

Arrays returned are views on the library's own buffers (no copies); long calls release the
GIL, take an optional ``progress`` callback and stop on Ctrl-C. File problems raise FileError
(an OSError naming the file), bad values InputError (a ValueError). See docs/python.md.
"""

from ._microbrdf import (  # noqa: F401
    Brdf,
    FileError,
    InputError,
    KirchhoffBrdf,
    LambertianBrdf,
    MicrofacetBrdf,
    Psd,
    RayleighRiceBrdf,
    ShBrdf,
    Surface,
    TabulatedNdf,
    brdf,
    export_bsdf,
    export_gltf,
    filter_sigma_auto,
    fit,
    hellinger_distance,
    measured_ndf,
    ndf,
    predict,
    psd,
    rayleigh_rice,
    read_ndf,
    _input_address,
    read_surface,
    render,
    simulate,
    statistics,
    ndf_models,
    tabulate,
    tis,
)
from ._microbrdf import __version__  # noqa: F401  (the library's, as `microbrdf --version`)

__all__ = [
    "Brdf",
    "FileError",
    "InputError",
    "KirchhoffBrdf",
    "LambertianBrdf",
    "MicrofacetBrdf",
    "Psd",
    "RayleighRiceBrdf",
    "ShBrdf",
    "Surface",
    "TabulatedNdf",
    "brdf",
    "export_bsdf",
    "export_gltf",
    "filter_sigma_auto",
    "fit",
    "hellinger_distance",
    "measured_ndf",
    "ndf",
    "predict",
    "psd",
    "rayleigh_rice",
    "read_ndf",
    "read_surface",
    "render",
    "simulate",
    "statistics",
    "ndf_models",
    "tabulate",
    "tis",
]

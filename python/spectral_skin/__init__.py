"""Spectral Skin: physically based skin appearance from four biophysical numbers.

Reflectance spectra, colours, radial profiles, layer stacks, Monte Carlo and the inverse model
(Donner & Jensen 2006 and beyond), computed by the C++ library. Units: mm, 1/mm, nm. The names
are those of the `skin` command: functions after its subcommands, keywords after its flags
(underscores for dashes), results shaped like its JSON. Parameter keywords (the keys of
``parameters()``, or the paper's symbols) take numbers or arrays of numbers; arrays broadcast,
every set is computed on all cores, and ``result["axes"]`` names the axes of every array::

    import numpy as np, spectral_skin as ss
    s = ss.spectrum(melanin=np.linspace(0, 0.5, 21))
    s["R_d"].shape        # (21, 151)
    s["axes"]["R_d"]      # ('melanin', 'wavelength_nm')

The fits take many targets at once (fit_color on an array (N, 3), fit_spectrum on N spectra),
each result the single call's. ``spectral_skin.distributed`` (with Dask) maps texture fits and
parameter sweeps onto a cluster. Bad input raises ValueError with the command's one-line message.
"""
from ._core import (  # noqa: F401  (the package's interface)
    InputError,
    __version__,
    color,
    export,
    fit_color,
    fit_spectrum,
    fit_texture,
    illuminants,
    layers,
    mc,
    parameters,
    presets,
    profile,
    rgb_profile,
    solvers,
    spectrum,
)

__all__ = [
    "InputError", "__version__", "color", "export", "fit_color", "fit_spectrum", "fit_texture", "illuminants", "layers",
    "mc", "parameters", "presets", "profile", "rgb_profile", "solvers", "spectrum",
]

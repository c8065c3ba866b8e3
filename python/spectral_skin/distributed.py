"""Fits and parameter sweeps on a Dask cluster (Debian's python3-dask, python3-distributed).

A study that outgrows one machine (thousands of face textures, a dense parameter sweep) is split
into tasks that Dask's scheduler hands to its workers; each task is one call of this package's
functions, so every number is the one the same call gives on one machine (the C++ library's
results do not depend on the machine's thread count or on how the sets are split). The results
come back in the order of the inputs.

``client``: a ``dask.distributed.Client``, or the address of a running scheduler
(``"tcp://host:8786"``), for which a client is opened for the call and closed after it. Every
worker must import ``spectral_skin`` (the same version: install it into the workers' Python
environment); file names are opened by the workers, so they must see the same files (a shared
file system), or pass arrays instead. Each task's C++ work runs on all the cores of its worker's
machine: start one worker process per machine with one thread (``dask worker ADDRESS --nworkers 1
--nthreads 1``). ``skin batch --rows`` stays the command line's way to split a table of sets across
machines.

    from dask.distributed import Client
    import numpy as np
    import spectral_skin.distributed as sd
    client = Client("tcp://scheduler:8786")
    maps = sd.fit_textures(client, ["face1.png", "face2.png"], solver="multipole")
    grid = sd.sweep(client, "color", melanin=np.linspace(0, 0.5, 201)[:, None],
                    hemoglobin=np.linspace(0.001, 0.1, 100), chunk_size=500)
    # grid == spectral_skin.color(melanin=..., hemoglobin=...), every number equal
"""
import contextlib
import math

import numpy as np

import spectral_skin as _ss

__all__ = ["fit_textures", "sweep", "SWEEPS"]

# The functions a sweep runs: those whose parameter keywords take arrays of sets.
SWEEPS = ("spectrum", "color", "profile", "rgb_profile")


@contextlib.contextmanager
def _connected(client):
    """The client given, or one opened on the scheduler address given (closed afterwards)."""
    if isinstance(client, str):
        from dask.distributed import Client  # noqa: PLC0415 (dask is needed only here)
        with Client(client) as opened:
            yield opened
    elif client is None or not hasattr(client, "submit"):
        raise ValueError(f"client = {client!r} must be a dask.distributed.Client or a scheduler address "
                         "such as 'tcp://host:8786'")
    else:
        yield client


def fit_textures(client, images, preset="caucasian", **options):
    """``spectral_skin.fit_texture(image, preset, **options)`` for every image of ``images`` (file
    names, path objects or arrays (height, width, 3) of linear sRGB in 0-1), one task per image on
    the cluster. Returns the list of their results, in the order of ``images``, each equal to the
    call on one machine. Bad input raises the call's ValueError (the first image's in the list
    that fails)."""
    images = list(images)
    if not images:
        raise ValueError("images is empty: give at least one image (a file name or an array)")
    images = [str(i) if hasattr(i, "__fspath__") else i for i in images]
    with _connected(client) as c:
        futures = [c.submit(_run, "fit_texture", image, preset, pure=False, **options) for image in images]
        try:
            return c.gather(futures)
        finally:
            c.cancel(futures)


def _run(function, *args, **kwargs):
    """spectral_skin.<function>(*args, **kwargs) on a worker (tasks name the function: the compiled
    functions themselves cannot be pickled)."""
    return getattr(_ss, function)(*args, **kwargs)


def _parameter_names():
    names = set()
    for p in _ss.parameters():
        names.add(p["key"])
        if p["symbol"]:
            names.add(p["symbol"])
    return names


def _paths(d, prefix=""):
    """Every value of a nested dict, by its dotted path (as result["axes"] names them)."""
    for k, v in d.items():
        path = f"{prefix}.{k}" if prefix else k
        if isinstance(v, dict):
            yield from _paths(v, path)
        else:
            yield path, v


def _set(d, path, value):
    *parents, last = path.split(".")
    for k in parents:
        d = d[k]
    d[last] = value


def _get(d, path):
    for k in path.split("."):
        d = d[k]
    return d


def _copy(d):
    return {k: _copy(v) if isinstance(v, dict) else v for k, v in d.items()}


def sweep(client, function, preset="caucasian", *, chunk_size=1000, **keywords):
    """``spectral_skin.<function>(preset, **keywords)`` (function: one of ``SWEEPS``, by name)
    with its parameter keywords' arrays broadcast into sets (numpy's rules, as the call does),
    computed on the cluster in tasks of at most ``chunk_size`` sets (the sets in row-major order).
    Returns the dict the call returns on one machine, with the same shapes, axes and numbers.
    The other keywords (``solver``, ``r_mm``, ``lambda_step``, ``threads``, ...) go to every task
    as they are. Bad input raises the call's ValueError."""
    if function not in SWEEPS:
        raise ValueError(f"function = {function!r} is not a sweep: one of {', '.join(SWEEPS)}")
    if isinstance(chunk_size, bool) or not isinstance(chunk_size, (int, np.integer)) or chunk_size < 1:
        raise ValueError(f"chunk_size = {chunk_size!r} is out of range: must be a whole number >= 1")
    call = getattr(_ss, function)
    names = _parameter_names()
    arrays = {k: v for k, v in keywords.items() if k in names and v is not None and np.ndim(v) > 0}
    options = {k: v for k, v in keywords.items() if k not in arrays}
    with _connected(client) as c:
        if not arrays:  # one set: one task
            return c.submit(_run, function, preset, pure=False, **options).result()
        try:
            arrays = {k: np.asarray(v) for k, v in arrays.items()}
            shape = np.broadcast_shapes(*(a.shape for a in arrays.values()))
        except ValueError:
            return call(preset, **keywords)  # the call's own message (it refuses before any work)
        count = math.prod(shape)
        if count == 0:
            return call(preset, **keywords)  # (refused: an empty array)
        flat = {k: np.broadcast_to(a, shape).reshape(-1) for k, a in arrays.items()}
        # The form of the result (its axes' names, the values every set shares) from the same call
        # on the grid's corner: each array cut to at most 2 along each of its axes, so that the
        # same axes vary and the same keywords name them.
        corner = {k: a[tuple(slice(0, 2) for _ in a.shape)] for k, a in arrays.items()}
        form = c.submit(_run, function, preset, pure=False, **corner, **options)
        chunks = [c.submit(_run, function, preset, pure=False, **{k: v[first:first + chunk_size] for k, v in flat.items()},
                           **options)
                  for first in range(0, count, chunk_size)]
        try:
            form, *parts = c.gather([form, *chunks])
        finally:
            c.cancel([form, *chunks])
    # The sets' axes: those of any parameter given as an array.
    set_axes = tuple(form["axes"]["parameters." + _key(next(iter(arrays)))])
    out = _copy(form)
    for path, axes in form["axes"].items():
        if tuple(axes[:len(shape)]) != set_axes:
            continue  # shared by every set (a grid, a name, a parameter not swept)
        blocks = [np.asarray(_get(part, path)) for part in parts]
        whole = np.concatenate(blocks, axis=0)
        _set(out, path, whole.reshape(tuple(shape) + whole.shape[1:]))
    return out


def _key(name):
    """A parameter keyword's key (the paper's symbols are aliases)."""
    for p in _ss.parameters():
        if name in (p["key"], p["symbol"]):
            return p["key"]
    return name

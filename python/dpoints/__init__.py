"""Deep Points Consolidation of raw 3D scans, on numpy arrays.

A raw, noisy, incomplete scan goes in as an (N, 3) array; out come a
consolidated, completed surface with oriented normals, its meso-skeleton and
the deep points joining the two::

    import numpy as np, dpoints
    res = dpoints.consolidate(points, samples=4000, device="pthread")
    res.surface, res.normals, res.skeleton, res.length, res.eta, res.report
    res.write("out")                       # the files `dpoints consolidate` writes

Every computation runs in libdpoints (OpenCL kernels, PoCL on the CPU) with
the GIL released. Errors raise dpoints.Error carrying the library's message;
Ctrl-C stops a run between two iterations and raises KeyboardInterrupt.
"""

import inspect
import json
import os
import threading
import time

import numpy as np

from . import _dpoints

__all__ = [
    "Error", "Cancelled", "Cloud", "Result", "Samples",
    "consolidate", "wlop", "read", "devices", "default_params", "SETTLE_WAYS", "__version__",
]

__version__ = _dpoints.version()

# dp_status values (dpoints.h)
_STATUS_NAMES = ["ok", "arg", "io", "format", "empty", "nomem", "no_device", "cl", "kernel_build",
                 "internal", "cancelled"]


class Error(Exception):
    """A libdpoints error: str(e) is the library's one-line message, e.status
    its dp_status name ("arg", "io", "format", "empty", "no_device", ...)."""

    def __init__(self, message, status="internal"):
        super().__init__(message)
        self.status = status


class Cancelled(Error):
    """The progress callback returned a true value and the run stopped."""


def _make_error(message, code):
    status = _STATUS_NAMES[code] if 0 <= code < len(_STATUS_NAMES) else "internal"
    cls = Cancelled if status == "cancelled" else Error
    return cls(message, status)


_dpoints.set_error(_make_error)

_ENUMS = {
    "wlop_weight": {"l1": 0, "gaussian": 1},
    "surface_prior": {"volume": 0, "minimal": 1},
}
_FLAGS = {  # int fields that are on/off switches: shown and taken as bool
    "wlop_sqrt_density", "normals_use_viewpoint", "surface_data_along_normal", "surface_reattach",
    "surface_same_side", "surface_orient_by_dpoint", "surface_sheet_points", "surface_silhouette",
    "surface_face_scanner", "surface_use_viewpoint", "skeleton_across_only",
}


def _python_value(name, value):
    if name in _ENUMS:
        return {v: k for k, v in _ENUMS[name].items()}[value]
    if name in _FLAGS:
        return bool(value)
    return value


def default_params():
    """Every parameter of the pipeline (libdpoints' dp_params, flattened as
    STAGE_FIELD) with the library's default."""
    return {k: _python_value(k, v) for k, v in _dpoints.default_params().items()}


_DEFAULTS = default_params()


def _c_params(params, where):
    out = {}
    for name, value in params.items():
        if name not in _DEFAULTS:
            raise TypeError("%s() got an unexpected keyword argument '%s'" % (where, name))
        if name in _ENUMS:
            choices = _ENUMS[name]
            if value not in choices:
                raise ValueError("%s must be one of %s, not %r" % (name, ", ".join(sorted(choices)), value))
            value = choices[value]
        elif name in _FLAGS:
            value = int(bool(value))
        elif name == "normals_viewpoint":
            value = tuple(float(v) for v in value)
        out[name] = value
    return out


def _points_array(points, name="points"):
    """An (N, 3) array-like as the C-contiguous float32 array the library reads."""
    # Open3D's Vector3dVector and other sequences go through np.asarray
    arr = np.asarray(points)
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.floating) or np.issubdtype(arr.dtype, np.integer)):
        raise TypeError("%s must hold real numbers (float or int), not %s" % (name, arr.dtype))
    if arr.ndim != 2 or arr.shape[1] != 3:
        raise ValueError("%s must be an (N, 3) array, got shape %s" % (name, arr.shape))
    return np.ascontiguousarray(arr, dtype=np.float32)


# One context per (backend, device): creating one builds the OpenCL program
# (seconds), and a context serves one call at a time, hence the lock.
_contexts = {}
_contexts_lock = threading.Lock()


def _context(backend, device):
    if backend not in ("cl", "ref"):
        raise ValueError("backend must be 'cl' or 'ref', not %r" % (backend,))
    if device is not None and not isinstance(device, (str, int)):
        raise TypeError("device must be an index, a name substring or None")
    key = (backend, None if device is None else str(device))
    with _contexts_lock:
        if key not in _contexts:
            _contexts[key] = (_dpoints.context(1 if backend == "ref" else 0, key[1]), threading.Lock())
        return _contexts[key]


def _threads_arg(threads):
    if isinstance(threads, bool) or not isinstance(threads, int):
        raise TypeError("threads must be an int (0: the CPUs this process may use)")
    if threads < 0:
        raise ValueError("threads must be >= 0 (0: the CPUs this process may use), not %d" % threads)
    return threads


def _progress_arg(progress):
    if progress is None:
        return None
    if not callable(progress):
        raise TypeError("progress must be callable(stage, iteration, value, elapsed) or None")
    # the library counts from the context's creation; contexts are kept, so
    # count from this call instead
    start = time.perf_counter()
    return lambda stage, iteration, value, elapsed: progress(stage, iteration, value, time.perf_counter() - start)


def _array(buf, dtype, shape):
    if buf is None:
        return None
    return np.frombuffer(buf, dtype=dtype).reshape(shape)


# How an anchor stopped sinking, by Result.settled and the `settled` property of
# anchors.ply (dp_settle in dpoints.h): still moving at the cap, an opposing
# front, past the medial axis, as deep as its part is wide, slowed down with
# its neighbours, past its plate's far face or given its flat face's or its
# crease's depth.
SETTLE_WAYS = ("unsettled", "front", "medial", "width", "slow", "flat")


class Cloud:
    """Points read from a file: .points (N, 3) float32, .normals (N, 3) or
    None, .faces (F, 3) uint32 or None (meshes), .colors (N, 3) uint8 or None."""

    def __init__(self, d):
        self.points = _array(d["points"], np.float32, (-1, 3))
        self.normals = _array(d["normals"], np.float32, (-1, 3))
        self.faces = _array(d["faces"], np.uint32, (-1, 3))
        self.colors = _array(d["colors"], np.uint8, (-1, 3))

    def __len__(self):
        return len(self.points)

    def __repr__(self):
        return "<dpoints.Cloud %d points%s%s>" % (
            len(self.points), ", normals" if self.normals is not None else "",
            ", %d faces" % len(self.faces) if self.faces is not None else "")


def read(path, mesh=False):
    """Reads PLY, XYZ, PCD, OFF or OBJ (by extension) through the library.
    mesh=True also reads triangle faces. Returns a Cloud."""
    return Cloud(_dpoints.read(os.fspath(path), bool(mesh)))


class Result:
    """What consolidate() returns. Deep point i joins surface[i] and
    skeleton[i]; all arrays are float32 numpy arrays of the deep-point count n:
    surface (n, 3), normals (n, 3), skeleton (n, 3), length (n,) = |surface -
    skeleton|, eta (n,) the input support (1 where no input is near). r is the
    spacing the last surface level ran at (with fewer deep points than the
    coarse level, that of the run they were kept from); wlop and anchors are the coarse level's WLOP
    samples and sunk anchors (Clouds), and settled (len(anchors),) uint8 says
    how each anchor stopped sinking, an index into SETTLE_WAYS;
    deep_points_run is the count the stages ran at (above n when these were
    kept from a coarse level); filled_from is the coarse level's count when a
    one-sided scan's surface stage started on a subset of it (wlop and
    anchors are then that subset, or its rows among those kept;
    refine_fill_samples), else 0; report is report.json as a dict."""

    def __init__(self, capsule, points):
        self._capsule = capsule
        self._points = points
        a = _dpoints.result_arrays(capsule)
        self.surface = _array(a["surface"], np.float32, (-1, 3))
        self.normals = _array(a["normals"], np.float32, (-1, 3))
        self.skeleton = _array(a["skeleton"], np.float32, (-1, 3))
        self.length = _array(a["length"], np.float32, (-1,))
        self.eta = _array(a["eta"], np.float32, (-1,))
        # colours of the input carried to the surface; None for uncoloured input
        self.colors = _array(a["colors"], np.uint8, (-1, 3))
        self.wlop = Cloud(a["wlop"])
        self.anchors = Cloud(a["anchors"])
        self.settled = _array(a["settled"], np.uint8, (-1,))
        self.r = a["r"]
        self.report = json.loads(_dpoints.result_report(capsule, None))
        self.deep_points_run = self.report["results"]["deep_points_run"]
        self.filled_from = self.report["results"]["filled_from"]

    def __len__(self):
        return len(self.surface)

    def __repr__(self):
        return "<dpoints.Result %d deep points from %d, r = %.6g>" % (len(self), len(self._points), self.r)

    def write(self, dir, *, ascii=False, stages=False, render=False, up_axis=1, input_name=None):
        """Writes the files `dpoints consolidate` writes into the folder `dir`
        (created if missing): surface.ply, skeleton.ply, dpoints.ply and
        report.json; stages=True adds wlop.ply and anchors.ply, render=True
        the four PNG pictures. Files of those names are replaced."""
        dir = os.fspath(dir)
        os.makedirs(dir, exist_ok=True)
        flags = ((_dpoints.WRITE_ASCII if ascii else 0) | (_dpoints.WRITE_STAGES if stages else 0)
                 | (_dpoints.WRITE_RENDER if render else 0))
        _dpoints.result_write(self._capsule, dir, flags, int(up_axis), self._points if render else None,
                              input_name)


def _signature(extra):
    pk, kw = inspect.Parameter.POSITIONAL_OR_KEYWORD, inspect.Parameter.KEYWORD_ONLY
    params = [inspect.Parameter("points", pk)]
    params += [inspect.Parameter(k, pk if k == "samples" else kw, default=v) for k, v in extra]
    return params


def consolidate(points, samples=None, *, device=None, backend="cl", progress=None, threads=0, **params):
    """The whole pipeline on a raw scan: WLOP, normals, sinking,
    meso-skeleton, surface consolidation.

    points: (N, 3) array-like of floats or ints, any memory order (copied to
    float32). samples: deep points (default: the library's rule, max(10% of
    the input, 4000) at most its distinct points). device: an OpenCL device
    index or name substring (dpoints.devices()), None for $DPOINTS_DEVICE or
    the first. backend: "cl" or "ref" (the scalar reference, slow).
    progress: called as progress(stage, iteration, value, seconds) after
    every iteration of every stage (stage: "wlop", "coarser" (coarser coarse
    levels a one-sided scan tries), "sink", "skeleton", "surface" (once per
    level), "even"; value: WLOP runs' mean move in h, the others' in r,
    sinking's settled points; seconds since the call began);
    a true return value stops the run (Cancelled). threads: host threads of
    the loops that stay on the host (0: the CPUs this process may use; 1 in
    the workers of a process pool). The result does not depend on it.
    Every other keyword is a libdpoints parameter, STAGE_FIELD, with the
    library's default (dpoints.default_params() lists them).
    """
    pts = _points_array(points)
    threads = _threads_arg(threads)
    if samples is not None:
        params["wlop_samples"] = samples
    cparams = _c_params(params, "consolidate")
    ctx, lock = _context(backend, device)
    with lock:
        _dpoints.context_set_threads(ctx, threads)
        capsule = _dpoints.consolidate(ctx, pts, cparams, _progress_arg(progress))
    return Result(capsule, pts)


consolidate.__signature__ = inspect.Signature(
    _signature([("samples", None), ("device", None), ("backend", "cl"), ("progress", None), ("threads", 0)])
    + [inspect.Parameter(k, inspect.Parameter.KEYWORD_ONLY, default=v) for k, v in _DEFAULTS.items()
       if k != "wlop_samples"])


class Samples:
    """What wlop() returns: .points (m, 3) float32, .normals (m, 3) oriented
    outwards (None with normals=False), .stats (h, iterations, converged, ...)."""

    def __init__(self, d):
        self.points = _array(d["points"], np.float32, (-1, 3))
        self.normals = _array(d["normals"], np.float32, (-1, 3))
        self.stats = d["stats"]

    def __len__(self):
        return len(self.points)

    def __repr__(self):
        return "<dpoints.Samples %d points, h = %.6g>" % (len(self.points), self.stats["h"])


def wlop(points, samples=None, *, normals=True, device=None, backend="cl", progress=None, threads=0, **params):
    """Stage 1 alone: WLOP (denoised, evenly spaced samples of the input),
    then oriented PCA normals unless normals=False. Keywords as consolidate();
    only the wlop_* and normals_* parameters matter here. Below 4000 samples
    the normals may take their signs from denser WLOP samples
    (dp_orient_from_denser), whose iterations reach progress as the stage
    "denser"."""
    pts = _points_array(points)
    threads = _threads_arg(threads)
    if samples is not None:
        params["wlop_samples"] = samples
    cparams = _c_params(params, "wlop")
    ctx, lock = _context(backend, device)
    with lock:
        _dpoints.context_set_threads(ctx, threads)
        d = _dpoints.wlop(ctx, pts, cparams, _progress_arg(progress), bool(normals))
    return Samples(d)


wlop.__signature__ = inspect.Signature(
    _signature([("samples", None), ("normals", True), ("device", None), ("backend", "cl"), ("progress", None),
                ("threads", 0)])
    + [inspect.Parameter(k, inspect.Parameter.KEYWORD_ONLY, default=v) for k, v in _DEFAULTS.items()
       if k.startswith(("wlop_", "normals_")) and k != "wlop_samples"])


def devices():
    """The OpenCL devices as dicts: index, name, type ("cpu", "gpu",
    "other"), compute_units, global_mem_bytes. `device=` takes the index or
    any substring of the name."""
    return _dpoints.devices()

"""The Python module against the library and the command-line tool.

The round trip needs the `dpoints` tool of the same tree: $DPOINTS_CLI, else
build/dpoints beside this folder's parent (what .ci/run builds)."""

import json
import os
import re
import shutil
import signal
import subprocess
import threading
import time

import numpy as np
import pytest

import dpoints
from dpoints import _dpoints

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def torus(n=3000, seed=0, noise=0.01):
    """A noisy torus (R = 1, r = 0.35), seeded, float32."""
    rng = np.random.default_rng(seed)
    u, v = rng.uniform(0, 2 * np.pi, (2, n))
    x = (1 + 0.35 * np.cos(v)) * np.cos(u)
    y = (1 + 0.35 * np.cos(v)) * np.sin(u)
    z = 0.35 * np.sin(v)
    pts = np.stack([x, y, z], axis=1) + rng.normal(0, noise, (n, 3))
    return pts.astype(np.float32)


SMALL = dict(samples=600)


def test_version_is_the_projects():
    text = open(os.path.join(ROOT, "CMakeLists.txt")).read()
    want = re.search(r"project\(dpoints VERSION ([0-9.]+)", text).group(1)
    assert dpoints.__version__ == want


def test_devices_as_data():
    devs = dpoints.devices()
    assert devs, "PoCL is a dependency: at least one device"
    for i, d in enumerate(devs):
        assert d["index"] == i
        assert d["type"] in ("cpu", "gpu", "other")
        assert d["name"] and d["compute_units"] >= 1


def test_defaults_are_the_librarys():
    p = dpoints.default_params()
    assert p["sink_omega_deg"] == 45.0
    assert p["surface_prior"] == "volume" and p["wlop_weight"] == "gaussian"
    assert p["surface_same_side"] is True
    assert p["skeleton_across_only"] is True
    # every parameter is a keyword of consolidate, with that default
    import inspect
    sig = inspect.signature(dpoints.consolidate).parameters
    for k, v in p.items():
        if k != "wlop_samples":
            assert sig[k].default == v


@pytest.mark.parametrize("convert", [
    lambda a: a.astype(np.float64),                 # float64, C order
    lambda a: np.asfortranarray(a),                 # float32, Fortran order
    lambda a: np.repeat(a, 2, axis=0)[::2],         # a strided view
    lambda a: a.tolist(),                           # nested lists
    lambda a: np.round(a * 1000).astype(np.int32),  # integers (scaled)
], ids=["float64", "fortran", "strided", "list", "int32"])
def test_inputs_accepted(convert):
    pts = torus(1500)
    given = convert(pts)
    s = dpoints.wlop(given, samples=300)
    want = np.asarray(given, dtype=np.float32)
    ref = dpoints.wlop(np.ascontiguousarray(want), samples=300)
    assert s.points.shape == (300, 3) and s.points.dtype == np.float32
    assert s.normals.shape == (300, 3)
    np.testing.assert_array_equal(s.points, ref.points)


@pytest.mark.parametrize("bad,exc,text", [
    (np.zeros((10, 2)), ValueError, r"\(N, 3\)"),
    (np.zeros((10, 3, 1)), ValueError, r"\(N, 3\)"),
    (np.zeros(30), ValueError, r"\(N, 3\)"),
    (np.zeros((10, 3), dtype=complex), TypeError, "real numbers"),
    (np.array([["a", "b", "c"]]), TypeError, "real numbers"),
    (np.empty((4, 3), dtype=object), TypeError, "real numbers"),
], ids=["2cols", "3d", "flat", "complex", "str", "object"])
def test_inputs_refused(bad, exc, text):
    with pytest.raises(exc, match=text):
        dpoints.consolidate(bad)


def test_library_errors_carry_its_message(tmp_path):
    pts = torus(1000)
    pts[5, 1] = np.nan
    with pytest.raises(dpoints.Error) as e:
        dpoints.consolidate(pts, samples=100)
    assert e.value.status == "arg" and "finite" in str(e.value)
    with pytest.raises(dpoints.Error) as e:
        dpoints.wlop(torus(100), samples=500)
    assert e.value.status == "arg" and "500" in str(e.value)
    missing = tmp_path / "missing.ply"
    with pytest.raises(dpoints.Error) as e:
        dpoints.read(missing)
    assert e.value.status == "io" and str(missing) in str(e.value)
    with pytest.raises(TypeError, match="no_such"):
        dpoints.consolidate(torus(100), no_such=1)
    with pytest.raises(ValueError, match="volume, minimal|minimal, volume"):
        dpoints.consolidate(torus(100), surface_prior="flat")
    with pytest.raises(dpoints.Error) as e:
        dpoints.consolidate(torus(1000), sink_omega_deg=200, samples=100)
    assert e.value.status == "arg"
    with pytest.raises(dpoints.Error) as e:
        dpoints.consolidate(torus(100), device="no such device")
    assert e.value.status == "no_device"


def test_result_arrays_and_report():
    pts = torus()
    res = dpoints.consolidate(pts, **SMALL)
    n = len(res)
    assert n == 600
    for a, shape in [(res.surface, (n, 3)), (res.normals, (n, 3)), (res.skeleton, (n, 3)),
                     (res.length, (n,)), (res.eta, (n,))]:
        assert a.shape == shape and a.dtype == np.float32 and np.isfinite(a).all()
    np.testing.assert_allclose(res.length, np.linalg.norm(res.surface - res.skeleton, axis=1), rtol=1e-4,
                               atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(res.normals, axis=1), 1.0, atol=1e-3)
    assert res.report["results"]["deep_points"] == n
    assert res.report["parameters"]["wlop"]["samples"] == 600
    # 600 kept from a coarse level of the torus's 3000 points (below 4000, all of them)
    assert res.deep_points_run == 3000
    assert res.filled_from == 0  # scanned from every side
    # the surface lies on the torus, the skeleton near its core circle
    d = np.hypot(np.hypot(res.surface[:, 0], res.surface[:, 1]) - 1, res.surface[:, 2])
    assert abs(np.median(d) - 0.35) < 0.05
    k = np.hypot(np.hypot(res.skeleton[:, 0], res.skeleton[:, 1]) - 1, res.skeleton[:, 2])
    assert np.median(k) < 0.15


def open_box(n=3000, seed=0):
    """A 2 x 2 x 0.3 box scanned without its underside, seeded, float32: its
    anchors settle by fronts, slow-down and the flat-face rule."""
    rng = np.random.default_rng(seed)
    half = np.array([1.0, 1.0, 0.15])
    centre = np.array([0.0, 0.0, 0.15])
    # the top (+z) and the four sides, each chosen in proportion to its area
    faces = [(2, +1), (0, +1), (0, -1), (1, +1), (1, -1)]
    area = np.array([np.prod(np.delete(2 * half, axis)) for axis, _ in faces])
    pts = []
    for (axis, sign), count in zip(faces, rng.multinomial(n, area / area.sum())):
        p = rng.uniform(-half, half, (count, 3))
        p[:, axis] = sign * half[axis]
        pts.append(centre + p)
    return np.concatenate(pts).astype(np.float32)


def test_settled_ways(tmp_path):
    res = dpoints.consolidate(open_box(), **SMALL)
    assert res.settled.shape == (len(res.anchors),) and res.settled.dtype == np.uint8
    assert dpoints.SETTLE_WAYS[_dpoints.SETTLE_FRONT] == "front"
    assert dpoints.SETTLE_WAYS[_dpoints.SETTLE_FLAT] == "flat"
    assert len(dpoints.SETTLE_WAYS) == _dpoints.SETTLE_FLAT + 1
    # each anchor's way, counted as report.json counts the ways
    sink = res.report["results"]["sink"]
    counts = np.bincount(res.settled, minlength=len(dpoints.SETTLE_WAYS))
    assert len(counts) == len(dpoints.SETTLE_WAYS)
    for way, count in zip(dpoints.SETTLE_WAYS, counts):
        assert count == sink["unsettled" if way == "unsettled" else "settled_" + way], (way, counts, sink)
    assert (counts > 0).sum() >= 3, counts  # the scene tells the ways apart
    # anchors.ply carries them row by row
    res.write(tmp_path, ascii=True, stages=True)
    with open(tmp_path / "anchors.ply") as f:
        header = []
        while not header or header[-1] != "end_header":
            header.append(f.readline().strip())
        names = [h.split()[-1] for h in header if h.startswith("property")]
        rows = np.loadtxt(f, ndmin=2)
    assert names[-1] == "settled" and len(rows) == len(res.settled)
    np.testing.assert_array_equal(rows[:, names.index("settled")], res.settled)


def near_half_sphere(res=62):
    """The half of a unit sphere that a scanner looking down the z axis sees,
    one point per ray of a res x res grid (sparser where the surface turns
    away), float32."""
    g = np.linspace(-1, 1, res)
    x, y = (a.ravel() for a in np.meshgrid(g, g))
    k = x * x + y * y < 0.98
    return np.c_[x[k], y[k], np.sqrt(1 - x[k] ** 2 - y[k] ** 2)].astype(np.float32)


def test_one_sided_scan_fills_from_a_subset():
    pts = near_half_sphere()
    # the coarse level holds every point (the default count, no coarser level tried); the surface stage
    # starts on fill_samples of them, whose samples and anchors are the first rows
    res = dpoints.consolidate(pts, refine_coarse_min=0)
    fill = res.report["parameters"]["refine"]["fill_samples"]
    assert res.filled_from == len(pts) == len(res) == res.deep_points_run
    assert res.report["results"]["surface"]["levels"][0]["points"] == fill
    assert len(res.wlop) == len(res.anchors) == len(res.settled) == fill
    # those are rows of the coarse level's WLOP samples, as run without the subset
    off = dpoints.consolidate(pts, refine_coarse_min=0, refine_fill_samples=0)
    assert off.filled_from == 0 and len(off.wlop) == len(pts)
    assert set(map(tuple, res.wlop.points)) <= set(map(tuple, off.wlop.points))
    # the far half, which no ray reached, gets its share of the points (measured: 40% of them, 20% without
    # the subset, whose first level stops at its cap with the rest still on the scanned half)
    far, far_off = ((r.surface[:, 2] < 0).mean() for r in (res, off))
    assert far > 0.3 and far > 1.5 * far_off, (far, far_off)


def test_write_and_read_back(tmp_path):
    pts = torus()
    res = dpoints.consolidate(pts, **SMALL)
    out = tmp_path / "out"
    res.write(out, stages=True, input_name="torus")
    names = sorted(os.listdir(out))
    assert names == ["anchors.ply", "dpoints.ply", "report.json", "skeleton.ply", "surface.ply", "wlop.ply"]
    surface = dpoints.read(out / "surface.ply")
    np.testing.assert_array_equal(surface.points, res.surface)
    np.testing.assert_array_equal(surface.normals, res.normals)
    report = json.load(open(out / "report.json"))
    assert report["input"] == "torus" and "wlop.ply" in report["files"]
    mesh = dpoints.read(out / "dpoints.ply", mesh=True)
    assert len(mesh) == 2 * len(res)
    anchors = dpoints.read(out / "anchors.ply")
    np.testing.assert_array_equal(anchors.points, res.anchors.points)
    np.testing.assert_array_equal(anchors.normals, res.anchors.normals)
    assert res.colors is None and surface.colors is None


def test_read_colours(tmp_path):
    src = tmp_path / "c.xyz"
    src.write_text("0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n0 0 1 10 20 30\n")
    c = dpoints.read(src)
    assert c.colors.dtype == np.uint8
    np.testing.assert_array_equal(c.colors[3], [10, 20, 30])


def test_progress_and_cancel():
    pts = torus()
    seen, times = [], []
    dpoints.consolidate(pts, progress=lambda s, i, v, t: (seen.append(s), times.append(t)) and None, **SMALL)
    assert 0 <= times[0] <= times[-1] < 60
    assert [s for i, s in enumerate(seen) if i == 0 or seen[i - 1] != s][:4] == \
        ["wlop", "sink", "skeleton", "surface"]

    def stop_in_skeleton(stage, iteration, value, elapsed):
        return stage == "skeleton" and iteration == 2

    with pytest.raises(dpoints.Cancelled, match="skeleton.*cancelled"):
        dpoints.consolidate(pts, progress=stop_in_skeleton, **SMALL)

    def boom(stage, iteration, value, elapsed):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        dpoints.consolidate(pts, progress=boom, **SMALL)
    with pytest.raises(TypeError, match="progress"):
        dpoints.consolidate(pts, progress=3)
    # the context is still good
    assert len(dpoints.consolidate(pts, **SMALL)) == 600


def _long_run_seconds():
    t = time.perf_counter()
    dpoints.consolidate(torus(20000), samples=8000)
    return time.perf_counter() - t


def test_ctrl_c_stops_a_run():
    full = _long_run_seconds()
    pts = torus(20000)
    timer = threading.Timer(0.3, os.kill, (os.getpid(), signal.SIGINT))
    t = time.perf_counter()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            dpoints.consolidate(pts, samples=8000)
            time.sleep(5)  # finished first: let the signal land here rather than in pytest
    finally:
        timer.cancel()
        timer.join()
    took = time.perf_counter() - t
    assert took < 0.3 + max(1.0, full / 2), (took, full)


def test_gil_released_during_a_run():
    ticks = []
    done = threading.Event()
    failed = []

    def run():
        try:
            dpoints.consolidate(torus(20000), samples=8000)
        except BaseException as e:  # reported below: a thread's exception would be lost
            failed.append(e)
        finally:
            done.set()

    th = threading.Thread(target=run)
    th.start()
    while not done.is_set():
        ticks.append(time.perf_counter())
        time.sleep(0.01)
    th.join()
    assert not failed, failed
    # the main thread ran all along, not only before and after
    assert len(ticks) > 20


def cli_path():
    path = os.environ.get("DPOINTS_CLI") or os.path.join(ROOT, "build", "dpoints")
    if not os.path.exists(path):
        pytest.fail("no dpoints tool at %s (set DPOINTS_CLI to the tool built from this tree)" % path)
    return path


def test_threads_change_nothing():
    pts = torus(6000, seed=3)
    one = dpoints.consolidate(pts, samples=5000, threads=1)
    two = dpoints.consolidate(pts, samples=5000, threads=2)
    for a, b in ((one.surface, two.surface), (one.skeleton, two.skeleton), (one.normals, two.normals)):
        assert np.array_equal(a, b)
    with pytest.raises(ValueError, match="threads"):
        dpoints.consolidate(pts, threads=-1)
    with pytest.raises(TypeError, match="threads"):
        dpoints.wlop(pts, threads=1.5)


def test_same_result_as_the_cli(tmp_path):
    pts = torus(4000, seed=3)
    src = tmp_path / "in.xyz"
    # %.9g: every float32 comes back exactly
    np.savetxt(src, pts, fmt="%.9g")
    out = tmp_path / "cli"
    subprocess.run([cli_path(), "consolidate", str(src), "-o", str(out), "--samples", "1000", "--seed", "7",
                    "--quiet"], check=True, stdout=subprocess.DEVNULL)
    cli = dpoints.read(out / "surface.ply")
    cli_skeleton = dpoints.read(out / "skeleton.ply")
    res = dpoints.consolidate(pts, samples=1000, wlop_seed=7)
    assert len(cli) == len(res) == 1000
    scale = np.ptp(pts, axis=0).max()
    np.testing.assert_allclose(res.surface, cli.points, atol=1e-4 * scale, rtol=0)
    np.testing.assert_allclose(res.skeleton, cli_skeleton.points, atol=1e-4 * scale, rtol=0)
    report = json.load(open(out / "report.json"))
    assert report["parameters"] == res.report["parameters"]


def test_open3d_point_cloud():
    o3d = pytest.importorskip("open3d")
    pcd = o3d.geometry.PointCloud(o3d.utility.Vector3dVector(torus().astype(np.float64)))
    res = dpoints.consolidate(np.asarray(pcd.points), **SMALL)
    assert len(res) == 600

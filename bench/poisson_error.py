#!/usr/bin/python3
"""The paper's Fig. 11 measure: screened Poisson reconstruction of points with
normals, then the mean distance from the ground-truth mesh's vertices to the
reconstructed surface, in diagonals of the ground truth's bounding box.

    /usr/bin/python3 bench/poisson_error.py GROUND_TRUTH_MESH POINTS.ply [POINTS.ply ...] [--depth 8]

Prints one JSON line per points file. Each file is reconstructed in a child
interpreter: Debian's Open3D stops some reconstructions on a failed Eigen
assertion (the abort of a whole batch, seen on 2 of 60 bunny surfaces), and
that file's line then carries "error" instead of the numbers while the
others go on; the exit status is 1 if any failed. Points without normals (a raw scan)
get PCA normals oriented consistently over a tangent-plane graph, as a user
reconstructing the raw scan would. Needs Debian's python3-open3d (a
benchmark tool only: neither the library nor the tests depend on it), hence
Debian's interpreter rather than whatever python3 is first on PATH.
"""
import argparse
import json
import os
import signal
import subprocess
import sys

import numpy as np
import open3d as o3d

# Normals of a raw scan: PCA over this many neighbours, oriented over a graph
# of as many.
RAW_NORMAL_K = 16


def poisson_error(mesh_path, points_path, depth):
    gt = o3d.io.read_triangle_mesh(mesh_path)
    if len(gt.triangles) == 0:
        sys.exit(f"poisson_error: {mesh_path}: no faces")
    pcd = o3d.io.read_point_cloud(points_path)
    if len(pcd.points) == 0:
        sys.exit(f"poisson_error: {points_path}: no points")
    estimated = not pcd.has_normals()
    if estimated:
        pcd.estimate_normals(o3d.geometry.KDTreeSearchParamKNN(RAW_NORMAL_K))
        pcd.orient_normals_consistent_tangent_plane(RAW_NORMAL_K)
    rec, _ = o3d.geometry.TriangleMesh.create_from_point_cloud_poisson(pcd, depth=depth)
    scene = o3d.t.geometry.RaycastingScene()
    scene.add_triangles(o3d.t.geometry.TriangleMesh.from_legacy(rec))
    verts = o3d.core.Tensor(np.asarray(gt.vertices, dtype=np.float32))
    dist = scene.compute_distance(verts).numpy()
    lo, hi = np.asarray(gt.vertices).min(axis=0), np.asarray(gt.vertices).max(axis=0)
    diag = float(np.linalg.norm(hi - lo))
    return {
        "bench": "poisson_error",
        "mesh": mesh_path,
        "points": points_path,
        "count": len(pcd.points),
        "normals": "estimated" if estimated else "given",
        "depth": depth,
        "mean": float(dist.mean()) / diag,
        "p95": float(np.percentile(dist, 95)) / diag,
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh")
    ap.add_argument("points", nargs="+")
    ap.add_argument("--depth", type=int, default=8)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.child:
        print(json.dumps(poisson_error(a.mesh, a.points[0], a.depth)), flush=True)
        return
    failed = 0
    for p in a.points:
        line = isolated(a.mesh, p, a.depth)
        failed += "error" in line
        print(json.dumps(line), flush=True)
    sys.exit(1 if failed else 0)


def isolated(mesh_path, points_path, depth):
    """poisson_error in a child interpreter (forking this one, whose Open3D
    has started its threads, can hang), so that an abort inside Open3D costs
    only this file's line."""
    run = subprocess.run([sys.executable, os.path.abspath(__file__), "--child", "--depth", str(depth), mesh_path,
                          points_path], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if run.returncode == 0 and run.stdout.strip():
        return json.loads(run.stdout.strip().splitlines()[-1])
    if run.returncode < 0:
        why = f"Open3D stopped the reconstruction ({signal.Signals(-run.returncode).name})"
    else:
        why = (run.stderr.strip().splitlines() or ["no result"])[-1]
    return {"bench": "poisson_error", "mesh": mesh_path, "points": points_path, "error": why}


if __name__ == "__main__":
    main()

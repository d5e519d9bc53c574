"""Spatial synthesis: cost of the constructions on large polyhedra and meshes.

* Two soft fingers over all face pairs of a polyhedron with about a thousand
  faces (the convex hull of random points on an ellipsoid): the branch and
  bound of the two-soft-finger search (``synthesize``) against solving every pair that passes
  the normal test (the exhaustive search a user would otherwise write).
* Regions for three hard fingers around a prototype on meshes of about 4k
  (pybullet's duck) and 10k to 20k triangles (subdivided ellipsoids).

    uv run python benchmarks/bench_spatial.py [--faces 1000] [--exhaustive 400]
"""

from __future__ import annotations

import argparse
import math
import os
import time

import numpy as np
import pybullet_data
import trimesh
from _tables import parse, table
from scipy.spatial import ConvexHull

from forceclosure.objects import Polyhedron
from forceclosure.objects.io import load_object
from forceclosure.synthesis import prototype_grasps, synthesize, zone_regions
from forceclosure.synthesis.spatial.two_soft import soft_pair_regions


def ellipsoid_hull(points: int, rng) -> Polyhedron:
    x = rng.normal(size=(points, 3))
    x = x / np.linalg.norm(x, axis=1, keepdims=True) * [1.0, 0.7, 0.5]
    hull = ConvexHull(x)
    return Polyhedron.from_arrays(x, hull.simplices, name=f"hull of {points} points")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--faces", type=int, default=1000)
    ap.add_argument("--exhaustive", type=int, default=400,
                    help="pairs solved one by one to time the exhaustive search")
    ap.add_argument("--mu", type=float, default=0.5)
    args = parse(ap)
    rng = np.random.default_rng(0)
    poly = ellipsoid_hull(args.faces // 2 + 2, rng)
    n = len(poly.faces)
    print(f"two soft fingers, mu {args.mu}, on a polyhedron of {n} faces "
          f"({n * (n - 1) // 2:,} face pairs)")
    t = time.process_time()
    # on faces: every face of the hull is one triangle, which "auto" would call curved
    found = synthesize(poly, 2, "soft", args.mu, top=5, method="faces").found
    bb = time.process_time() - t
    print(f"  best 5 by branch and bound: {bb:.2f} s; smallest region of the best "
          f"{found[0].min_area:.3g}, all certified: {all(r.certify().holds for r in found)}")
    normals = np.array([f.normal for f in poly.faces])
    gap = np.arccos(np.clip(-normals @ normals.T, -1, 1))
    i, j = np.nonzero(np.triu(gap < 2 * (math.atan(args.mu) - 1e-3), k=1))
    sample = rng.choice(len(i), size=min(args.exhaustive, len(i)), replace=False)
    t = time.process_time()
    for k in sample:
        soft_pair_regions(poly, int(i[k]), int(j[k]), args.mu)
    per_pair = (time.process_time() - t) / len(sample)
    full = per_pair * len(i)
    print(f"  exhaustive: {len(i):,} pairs pass the normal test, {per_pair * 1e3:.2f} ms each "
          f"-> {full:.0f} s; branch and bound is {full / bb:.0f}x faster")
    table("spatial.soft", ["two soft fingers, 1000-face polyhedron (CPU)", "time"], [
        [f"best 5 of {n * (n - 1) // 2:,} face pairs by branch and bound, certified",
         f"{bb:.2f} s"],
        [f"exhaustive: {len(i):,} pairs pass the normal test, {per_pair * 1e3:.2f} ms each",
         f"{full:.0f} s (estimated: {full / bb:.0f}× branch and bound)"]])
    rows = []
    meshes = [load_object(os.path.join(pybullet_data.getDataPath(), "duck.obj"))]
    for sub in (4, 5):
        s = trimesh.creation.icosphere(subdivisions=sub)
        meshes.append(Polyhedron.from_arrays(s.vertices * [1.0, 0.7, 0.5], s.faces,
                                             name=f"ellipsoid ({sub} subdivisions)"))
    print("three hard fingers, mu 0.5, regions grown around a sampled prototype")
    for mesh in meshes:
        t = time.process_time()
        [p] = prototype_grasps(mesh, 3, "hard", 0.5, samples=5000)
        proto = time.process_time() - t
        t = time.process_time()
        r = zone_regions(mesh, p, "hard", 0.5)
        grow = time.process_time() - t
        t = time.process_time()
        cert = r.certify()
        check = time.process_time() - t
        print(f"  {mesh.name}: {len(mesh.triangles):,} triangles; prototype {proto:.2f} s, "
              f"regions {grow:.2f} s ({sum(len(x) for x in r.regions)} patches), "
              f"certificate {check:.2f} s ({cert.holds})")
        rows.append([mesh.name, f"{len(mesh.triangles):,}", f"{proto:.2f} s", f"{grow:.2f} s",
                     f"{check:.2f} s" + ("" if cert.holds else " (**fails**)")])
    table("spatial.mesh", ["mesh (3 hard, mu 0.5; CPU)", "triangles",
                           "prototype (5000 samples)", "regions", "certificate"], rows)


if __name__ == "__main__":
    main()

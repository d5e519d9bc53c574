"""Loading and face-merging large meshes (issue: seconds, not minutes, for 100k triangles).

Two meshes of about 100k triangles, written as binary STL and loaded through
``load_object`` (parse, merge vertices, validate, orient, merge coplanar
triangles into faces): a sphere, where every triangle is its own face, and a
finely subdivided box, whose 98k triangles merge into 6 faces. trimesh's own
load with processing and its ``facets`` (which leaves one-triangle faces out
and checks no flatness) is timed in the same run for reference.

Then the convex decompositions of pybullet_data (several overlapping
shells each, reduced to their outer surface by a manifold3d union): the
first 100 ``random_urdfs`` and ``duck_vhacd.obj``, against trimesh's plain
load of the same files (which keeps the shells, inner faces and all). CPU time,
best of three (decompositions: one run).

    uv run python benchmarks/bench_objects.py [--quick]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from contextlib import suppress
from pathlib import Path

import pybullet_data
import trimesh
from _tables import parse, table

from forceclosure.errors import InputError
from forceclosure.objects.io import load_object


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.process_time()
        result = fn()
        times.append(time.process_time() - t)
    return min(times), result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="small meshes: a smoke run")
    quick = parse(parser).quick
    meshes = {
        "icosphere (curved)": trimesh.creation.icosphere(subdivisions=3 if quick else 6),
        "subdivided box": trimesh.creation.box(extents=(2, 2, 2)).subdivide_to_size(
            0.5 if quick else 0.035),
    }
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, mesh in meshes.items():
            path = Path(tmp) / "mesh.stl"
            mesh.export(path)
            ours, poly = best_of(lambda path=path: load_object(path))
            theirs, _ = best_of(lambda path=path: trimesh.load(path, process=True).facets)
            rows.append([name, f"{len(poly.triangles):,}", f"{len(poly.faces):,}",
                         f"{ours:.2f} s", f"{theirs:.2f} s"])
    table("objects", ["mesh (best of 3, CPU time)", "triangles", "faces", "forceclosure",
                      "trimesh load + `facets`"], rows)
    data = Path(pybullet_data.getDataPath())
    decompositions = {
        "`random_urdfs` 000–" + ("009" if quick else "099"): [
            data / "random_urdfs" / f"{i:03d}" / f"{i:03d}.obj"
            for i in range(10 if quick else 100)],
        "`duck_vhacd.obj`": [data / "duck_vhacd.obj"],
    }
    rows = []
    for name, paths in decompositions.items():
        def ours(paths=paths):
            loaded = []
            for p in paths:
                with suppress(InputError):  # the few with non-manifold pieces
                    loaded.append(load_object(p))
            return loaded

        t_ours, loaded = best_of(ours, repeat=1)
        t_theirs, _ = best_of(lambda paths=paths: [trimesh.load(p, force="mesh")
                                                   for p in paths], repeat=1)
        shells = sum(p.shells for p in loaded)
        rows.append([name, f"{len(paths):,}", f"{shells:,}", f"{t_ours:.2f} s",
                     f"{t_theirs:.2f} s"])
    table("objects.decompositions", ["convex decomposition (CPU time)", "files",
                                     "shells after the union", "forceclosure", "trimesh load"],
          rows)


if __name__ == "__main__":
    main()

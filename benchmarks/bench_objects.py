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
load of the same files (which keeps the shells, inner faces and all).

    uv run python benchmarks/bench_objects.py
"""

from __future__ import annotations

import tempfile
import time
from contextlib import suppress
from pathlib import Path

import pybullet_data
import trimesh

from forceclosure.errors import InputError
from forceclosure.objects.io import load_object


def best_of(fn, repeat=3):
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - t)
    return min(times), result


def main() -> None:
    meshes = {
        "sphere (curved)": trimesh.creation.icosphere(subdivisions=6),
        "subdivided box": trimesh.creation.box(extents=(2, 2, 2)).subdivide_to_size(0.035),
    }
    print(f"{'mesh':18} {'triangles':>9} {'faces':>7} {'forceclosure':>13} {'trimesh':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, mesh in meshes.items():
            path = Path(tmp) / "mesh.stl"
            mesh.export(path)
            ours, poly = best_of(lambda path=path: load_object(path))
            theirs, _ = best_of(lambda path=path: trimesh.load(path, process=True).facets)
            print(f"{name:18} {len(poly.triangles):9d} {len(poly.faces):7d} {ours:11.2f} s "
                  f"{theirs:7.2f} s")
    data = Path(pybullet_data.getDataPath())
    decompositions = {
        "random_urdfs x100": [data / "random_urdfs" / f"{i:03d}" / f"{i:03d}.obj"
                              for i in range(100)],
        "duck_vhacd": [data / "duck_vhacd.obj"],
    }
    print(f"\n{'decomposition':18} {'files':>9} {'shells':>7} {'forceclosure':>13} {'trimesh':>9}")
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
        print(f"{name:18} {len(paths):9d} {shells:7d} {t_ours:11.2f} s {t_theirs:7.2f} s")


if __name__ == "__main__":
    main()

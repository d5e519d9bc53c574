"""Loading and face-merging large meshes (issue: seconds, not minutes, for 100k triangles).

Two meshes of about 100k triangles, written as binary STL and loaded through
``load_object`` (parse, merge vertices, validate, orient, merge coplanar
triangles into faces): a sphere, where every triangle is its own face, and a
finely subdivided box, whose 98k triangles merge into 6 faces. trimesh's own
load with processing and its ``facets`` (which leaves one-triangle faces out
and checks no flatness) is timed in the same run for reference.

    uv run python benchmarks/bench_objects.py
"""

from __future__ import annotations

import tempfile
import time
from pathlib import Path

import trimesh

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


if __name__ == "__main__":
    main()

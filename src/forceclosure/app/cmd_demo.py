"""``forceclosure demo``: the bundled example grasps analysed, and a taste of synthesis."""

from __future__ import annotations

import argparse
import sys
from importlib import resources
from typing import Any

from .. import __version__
from .cmd_analyze import analyze_file

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``demo`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    d = sub.add_parser("demo", help="analyse the bundled example grasps")
    d.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ..io.grasp_file import parse_grasp_file

    examples = resources.files("forceclosure") / "examples"
    print(f"forceclosure {__version__}: Nguyen (1988) force-closure analysis on the bundled "
          "examples\n")
    status = 0
    for name in ("planar.json", "spatial.json"):
        print(f"== {name} ==")
        grasp_file = parse_grasp_file((examples / name).read_text(encoding="utf-8"), name)
        status = max(status, analyze_file(grasp_file, False, True, sys.stdout))
        print()
    _demo_objects()
    print("\nAnalyse your own grasps with: forceclosure analyze GRASPS.json [--json]")
    print("Inspect an object (a file or a bundled name): "
          "forceclosure inspect OBJECT --plot out.png")
    print("Find grasps and their regions: forceclosure synthesize OBJECT --mu 0.3 "
          "--plot out.png")
    print("  on a polyhedron or mesh: forceclosure synthesize OBJECT.stl --fingers 3 "
          "--contact hard --mu 0.5 --plot out.png --html out.html")
    print("Whole object sets, resumable, on all cores or a Dask cluster: "
          "forceclosure dataset FOLDER --out results/")
    return status


def _demo_objects() -> None:
    """Planar synthesis on the bundled polygons; two soft fingers on each polyhedron."""
    import numpy as np

    from ..analysis.closure import analyze
    from ..contacts import point_contact
    from ..objects import POLYGONS, POLYHEDRA, Polyhedron, bundled
    from ..synthesis.best import synthesize
    from ..synthesis.regions import Regions

    print("== bundled polygons: the best two-finger grasp, mu 0.3, and its independent "
          "regions ==")
    for name in POLYGONS:
        found = synthesize(bundled(name), 2, "hard", 0.3, top=1).found
        if not found:
            print(f"  {name:17} no force-closure grasp with two fingers at mu 0.3")
            continue
        r = found[0]
        assert isinstance(r, Regions)  # segments: synthesize's region sets on a polygon
        print(f"  {name:17} edges {r.edges[0]} + {r.edges[1]}: segments "
              f"{r.lengths[0]:.3g} and {r.lengths[1]:.3g} long, certified {r.certify().holds}")
    print("== bundled polyhedra: two soft fingers, mu 0.3, at the middles of the most opposed "
          "faces ==")
    for name in POLYHEDRA:
        obj = bundled(name)
        assert isinstance(obj, Polyhedron)  # POLYHEDRA names only polyhedra
        sites = [(f.to_world(np.asarray(f.polygon.centroid)), f.normal) for f in obj.faces]
        normals = np.array([n for _, n in sites])
        i, j = np.unravel_index(np.argmin(normals @ normals.T), (len(sites),) * 2)
        grasp = [point_contact(*sites[k], "soft", 0.3) for k in (i, j)]
        print(f"  {name:17} faces {i} + {j}: {analyze(grasp).verdict.value}")
    from ..synthesis import soft_pair_regions, three_hard_regions

    cube = bundled("cube")
    print("== the cube: independent regions on its faces, mu 0.5 ==")
    pair = soft_pair_regions(cube, 0, 1, 0.5)
    print(f"  two soft fingers, top and bottom (§5.2): regions of area {pair.min_area:.3g} "
          f"each; certified: {pair.certify().holds} ({pair.certify().method})")
    three = three_hard_regions(cube, (0, 1, 1), 0.5)
    print(f"  three hard fingers, one on top, two below (§5.3, class "
          f"{three.grasp_class.number}): smallest region {three.min_area:.3g}; certified: "
          f"{three.certify().holds} ({three.certify().method})")
    from .. import kernels
    from ..analysis.batch import analyze_batch
    from ..gripper.jaw import ParallelJaw
    from ..gripper.pipeline import label_poses

    # the last part compiles the batch kernels for this machine, once (the README's quick
    # start): the Theorem 1 verdict of batches too, not only after its first grasps
    kernels.COMPILE_AFTER = 0
    analyze_batch(np.array([[[1.0, 0, 0], [-1, 0.5, 0], [-1, -0.5, 0.1]]]),
                  np.array([[[1.0, 0, 0], [-1, 0, 0], [-1, 0, 0]]]), mu=0.5)
    jaw = label_poses(cube, ParallelJaw(3.0), 0.5, 20, seed=0).summary
    print(f"== the cube in a parallel-jaw hand opening 3 (docs/gripper.md), mu 0.5 ==\n"
          f"  20 poses the hand can take: closure and clear {jaw['closure_clear']}, least "
          f"friction median {jaw['least_friction_median']:.3g}")

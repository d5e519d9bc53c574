"""``forceclosure inspect OBJECT``: an object's summary (faces found, watertight, sizes),
and its picture."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from .common import check_picture, outside_meshes_option

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``inspect`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    i = sub.add_parser("inspect", help="summarise an object: polygon or polyhedron",
                       description="Load an object (a file or a bundled name), check it, and "
                                   "summarise it: edges, or planar faces found in a mesh.")
    i.add_argument("object", metavar="OBJECT",
                   help="a file (.json .geojson .svg .csv .stl .obj .ply .off .glb .gltf .urdf) "
                        "or a bundled name")
    i.add_argument("--plot", metavar="OUT", help="save a picture (.png or .svg)")
    i.add_argument("--json", action="store_true", help="print the summary as JSON")
    i.add_argument("--allow-open", action="store_true",
                   help="open or non-manifold meshes are described either way; with this "
                        "flag, without the reminder that synthesize needs it")
    i.add_argument("--part", metavar="NAME", help="the URDF link (or SVG element id) to read")
    outside_meshes_option(i)
    i.set_defaults(run=run)


def _rounded(values, size: float) -> list:
    """Coordinates for people (:func:`forceclosure.synthesis.regions.rounded`)."""
    from ..synthesis.regions import rounded

    return rounded(values, size)


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from ..objects.io import load_object
    from ..objects.polygon import in_units

    check_picture(args.plot, args.object)
    obj = load_object(args.object, allow_open=True, part=args.part,  # describe open meshes too
                      allow_outside_meshes=args.allow_outside_meshes)
    info: dict[str, Any] = obj.summary()
    unit, square = in_units(info.get("units")), in_units(info.get("units"), 2)
    if args.json:
        json.dump(info, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        for warning in info.get("warnings", []):
            print(f"forceclosure: warning: {obj.name}: {warning}", file=sys.stderr)
        lo, hi = np.asarray(info["bounds"])
        print(f"{obj.name}: {info['kind']}")
        if obj.dim == 2:
            print(f"  {info['vertices']} vertices, {info['edges']} edges, {info['holes']} holes;"
                  f" {'convex' if info['convex'] else 'non-convex'}")
            print(f"  area {info['area']:.6g}{square}, perimeter {info['perimeter']:.6g}{unit}")
        else:
            print(f"  {info['vertices']} vertices, {info['triangles']} triangles -> "
                  f"{info['faces']} planar faces ({info['merged_faces']} merged from several "
                  "triangles)")
            tight = "watertight"
            if not info["watertight"]:
                facts = [f"{info['boundary_edges']} boundary edges in {info['holes']} "
                         f"hole{'s' if info['holes'] != 1 else ''}"] if info["holes"] else []
                if info["non_manifold_edges"]:
                    facts.append(f"{info['non_manifold_edges']} non-manifold edges")
                tight = f"{'open' if info['holes'] else 'non-manifold'} (not watertight): " + (
                    ", ".join(facts))
            volume = f", volume {info['volume']:.6g}" if info["volume"] is not None else ""
            print(f"  {tight}{volume}, area {info['area']:.6g}")
            if info["defects"] and not args.allow_open:
                print(f"  the file is {' and '.join(info['defects'])}: synthesize and dataset "
                      "need --allow-open for it")
        print(f"  size {info['size']:.6g}{unit} (bounding-box diagonal), bounds "
              f"{_rounded(lo, obj.size)} to {_rounded(hi, obj.size)}")
    if args.plot:
        from ..pictures.plot import plot_object, upright_axis

        plot_object(obj, args.plot, up=upright_axis(args.object, obj))
        print(f"  picture: {args.plot}", file=sys.stderr if args.json else sys.stdout)
    return 0

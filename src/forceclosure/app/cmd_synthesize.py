"""``forceclosure synthesize OBJECT``: the best grasps and their independent regions
(:func:`forceclosure.synthesis.best.synthesize`), in words, JSON and pictures."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence
from typing import Any

from ..errors import InputError
from ..extras import require
from .common import FINGERS_HELP, check_picture, outside_meshes_option, synthesis_options

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``synthesize`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    y = sub.add_parser("synthesize", help="where to put the fingers: independent regions",
                       description="Find the best force-closure grasps on an object and the "
                                   "independent regions of contact around them (Nguyen 1988, "
                                   "§5): every choice of one point per region is "
                                   "force-closure.")
    y.add_argument("object", metavar="OBJECT",
                   help="a polygon or mesh file, or a bundled name")
    y.add_argument("--fingers", type=int, default=None, help=FINGERS_HELP)
    y.add_argument("--part", metavar="NAME", help="the URDF link (or SVG element id) to read")
    outside_meshes_option(y)
    synthesis_options(y)
    y.add_argument("--vertices", action="store_true",
                   help="also grasp with a soft finger on a convex vertex (a wider cone)")
    y.add_argument("--json", action="store_true", help="print JSON for machines")
    y.add_argument("--plot", metavar="OUT", help="save a picture (.png or .svg)")
    y.add_argument("--html", metavar="OUT",
                   help="save an interactive view (.html, self-contained, works offline)")
    y.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ..objects.io import load_object
    from ..synthesis.best import synthesize

    if args.html and not args.html.lower().endswith((".html", ".htm")):
        raise InputError(f"--html {args.html}: an interactive view is saved as .html")
    if args.html:  # before any work
        require("plotly", "the interactive HTML view", "view")
    check_picture(args.plot, args.object)
    obj = load_object(args.object, allow_open=args.allow_open, part=args.part,
                      allow_outside_meshes=args.allow_outside_meshes)
    if obj.dim == 3 and args.vertices:
        raise InputError("--vertices is for polygons; on a polyhedron every finger is on a face")
    if args.vertices and args.contact == "frictionless":
        raise InputError("--vertices puts soft fingers, with friction, on vertices; it "
                         "does not go with --contact frictionless")
    defaulted = args.fingers is None
    from tqdm import tqdm

    from ..datasets.progress import bar_size

    # a counter of the sites built, on a terminal (a long search is not silent)
    with tqdm(unit=" sites", desc="searching", file=sys.stderr, disable=None, leave=False,
              **bar_size()) as bar:
        result = synthesize(obj, args.fingers, args.contact, args.mu, top=args.top,
                            margin=args.margin, construction=args.construction,
                            method=args.method, samples=args.samples, seed=args.seed,
                            progress=bar.update)
    args.fingers = result.fingers  # the default filled in (the API's and dataset's)
    if defaulted and not args.json:
        from ..synthesis.best import default_fingers_reason

        print(f"{obj.name}: by default {default_fingers_reason(obj.dim, args.contact)} "
              "(--fingers N to choose)")
    found, mu = result.found, result.mu
    corners = []
    if args.vertices:  # the table's vertex construction, two fingers
        corners = synthesize(obj, 2, "soft", mu, top=args.top, margin=args.margin,
                             construction="vertices").found
    if args.json:
        found_record = result.to_dict()
        record = {"object": obj.name,
                  **{k: found_record.pop(k) for k in ("fingers", "contact", "mu")},
                  "size": obj.size, "units": getattr(obj, "units", None), **found_record}
        if args.vertices:
            record["vertex_grasps"] = [g.to_dict() for g in corners]
        json.dump(record, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _print_found(args, obj, result)
        if args.vertices:
            print(f"  with a soft finger on a convex vertex ({len(corners)} best):")
            for rank, g in enumerate(corners, start=1):
                vertex, where = g.describe()
                print(f"  {rank}. {vertex} with {where}; certified: {g.certify().holds}")
    _save_views(args, found, corners)
    return 0


def _print_found(args: argparse.Namespace, obj, result) -> None:
    """The region sets found, best first, for people (``--json`` has every number)."""
    from ..objects.polygon import in_units

    found, c = result.found, result.construction
    friction = ("frictionless" if args.contact == "frictionless"
                else f"{args.contact} fingers, mu {result.mu:g}")
    how = {"edges": "", "faces": f", regions on faces ({c.paper})",
           "mesh": ", regions grown on the mesh around sampled prototypes"}[result.method]
    units = getattr(obj, "units", None)
    ranked = "the shortest independent segment" if obj.dim == 2 else "the smallest region"
    print(f"{obj.name}: {len(found)} best {args.fingers}-finger grasps ({friction}){how}, "
          f"ranked by {ranked}" + (f"; coordinates in {units}" if units and " " not in units
                                   else f"; coordinates in units of {units}" if units else ""))
    if not found:
        more = f" (of {args.samples:,} random grasps: try --samples)" if \
            result.method == "mesh" or result.construction.name == "grown" else ""
        print(f"  no force-closure grasp found; searched {result.searched}{more}")
    elif result.undecided:
        print(f"  searched {result.searched}")
    for rank, r in enumerate(found, start=1):
        print(f"  {rank}. {'; '.join(r.describe())}")
        cert = r.certify()
        if obj.dim == 2:
            size = (f"shortest segment {r.min_size:.4g}{in_units(units)} "
                    f"({r.relative_min_size:.1%} of the object's size)")
        else:
            size = (f"region areas {', '.join(f'{a:.4g}' for a in r.sizes)} (smallest "
                    f"{r.relative_min_size:.2%} of size^2)")
        notes = "".join(f"; {n}" for n in r.notes())
        proof = f" ({cert.method})" if obj.dim == 3 else ""
        print(f"     {size}{notes}; certified: {cert.holds}{proof}")


def _save_views(args: argparse.Namespace, found: Sequence[Any], corners: Sequence[Any] = ()
                ) -> None:
    """The PNG still (``--plot``) and the interactive page (``--html``) of the grasps found
    and those with a soft finger on a vertex (``--vertices``), whatever their kind; a mesh
    file's object upright by its format's convention
    (:func:`forceclosure.pictures.plot.upright_axis`)."""
    say = sys.stderr if args.json else sys.stdout
    drawn = [*found, *corners]
    if not drawn or not (args.plot or args.html):
        return
    from ..pictures.plot import upright_axis

    up = upright_axis(args.object, drawn[0].object)
    if args.plot:
        from ..pictures.plot import plot_found

        plot_found(drawn, args.plot, up=up)
        print(f"  picture: {args.plot}", file=say)
    if args.html:
        from ..pictures.view import write_html

        write_html(drawn, args.html, up=up)
        print(f"  interactive view: {args.html}", file=say)

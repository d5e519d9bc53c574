"""What the commands share: the one-line error, the picture check, and the options of
several commands."""

from __future__ import annotations

import argparse
import sys

from ..errors import printable
from ..synthesis.table import DEFAULT, names

__all__ = ["FINGERS_HELP", "check_picture", "error", "outside_meshes_option", "synthesis_options"]


def error(message: str) -> None:
    """One line on standard error, safe for a terminal (names may hold escapes)."""
    print(f"forceclosure: error: {printable(message)}", file=sys.stderr)


def check_picture(path: str | None, source: str) -> None:
    """``--plot`` of a format the pictures are not saved in, or where nothing can be
    written (or onto the input file): refused before any work."""
    if path:
        from ..files.atomic import check_output
        from ..pictures.plot import check_plot_path

        check_plot_path(path)
        check_output(path, inputs=[source])


#: ``--fingers`` of synthesize and dataset: one default (synthesis.best.default_fingers).
FINGERS_HELP = ("number of fingers (default: the fewest that can hold the object: 2 with "
                "friction in the plane, 4 frictionless; in space 2 soft, 3 hard, 7 frictionless)")


def outside_meshes_option(p: argparse.ArgumentParser) -> None:
    p.add_argument("--allow-outside-meshes", action="store_true",
                   help="let a URDF name meshes outside its folder (or its package's "
                        "folder); refused by default")


def synthesis_options(p: argparse.ArgumentParser) -> None:
    """The hand and the construction: options shared by ``synthesize`` and ``dataset``."""
    p.add_argument("--contact", choices=("hard", "soft", "frictionless"), default="hard",
                   help="contact model (in the plane a soft finger acts as a hard one)")
    p.add_argument("--mu", type=float, default=0.3, help="friction coefficient (default 0.3)")
    p.add_argument("--top", type=int, default=5, help="how many grasps (default 5)")
    p.add_argument("--margin", type=float, default=1e-3,
                   help="radians: the regions stay force-closure when every contact normal "
                        "turns by up to this angle (default 1e-3; cones narrowed by it)")
    p.add_argument("--construction", choices=names(), default=DEFAULT,
                   help="a name in the table of constructions (forceclosure constructions): "
                        "maximal regions (an exact LP), the paper's two-sided cone "
                        "constructions (nguyen: §5.1, §5.2, §5.4), a soft finger on a vertex "
                        "(vertices: polygons), segments grown around sampled grasps (grown: "
                        "polygons, any hand), regions grown on the mesh (mesh: polyhedra)")
    p.add_argument("--method", choices=("auto", "faces", "mesh"), default="auto",
                   help="polyhedra: the paper's constructions on faces (two soft, three hard, "
                        "seven frictionless fingers), or regions grown over a mesh around "
                        "sampled prototype grasps (any hand); auto: faces unless the object "
                        "is curved")
    p.add_argument("--samples", type=int, default=20_000,
                   help="random grasps sampled for prototypes (polyhedra, and hands on a "
                        "polygon no paper construction serves; default 20000)")
    p.add_argument("--seed", type=int, default=0, help="random seed of the sampling")
    p.add_argument("--allow-open", action="store_true",
                   help="accept open or non-manifold meshes (scans, single-sided surfaces), "
                        "with a warning, instead of refusing them")

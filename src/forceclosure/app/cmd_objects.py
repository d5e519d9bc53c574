"""``forceclosure objects``: the bundled polygons and polyhedra."""

from __future__ import annotations

import argparse
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``objects`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    o = sub.add_parser("objects", help="list the bundled example objects")
    o.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from ..objects import POLYGONS, POLYHEDRA

    print("Bundled objects (use the name wherever a file is expected):\n")
    for kind, table in (("polygons", POLYGONS), ("polyhedra", POLYHEDRA)):
        print(f"{kind}:")
        for name, (description, _) in table.items():
            print(f"  {name:18} {description}")
    return 0

"""``forceclosure constructions``: the table of constructions synthesize chooses from."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

__all__ = ["add_parser", "run"]


def add_parser(sub: Any) -> None:
    """Register the ``constructions`` subcommand on the ``forceclosure`` subparsers ``sub``."""
    k = sub.add_parser("constructions", help="list the constructions of independent regions "
                                             "(the table synthesize chooses from)")
    k.add_argument("--json", action="store_true", help="print the table as JSON")
    k.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    import textwrap

    from ..synthesis.table import constructions

    table = constructions()
    if args.json:
        json.dump([{"dim": c.dim, "fingers": c.fingers, "contact": c.contact, "name": c.name,
                    "paper": c.paper, "method": c.method, "searched": c.described,
                    "bound": c.bound is not None, "prune": c.prune is not None}
                   for c in table], sys.stdout, indent=2)
        sys.stdout.write("\n")
        return 0
    print("The constructions synthesize chooses from (by object, --fingers, --contact and "
          "--construction;\nthe mesh method where none fits):\n")
    for c in table:
        where = "polygon" if c.dim == 2 else "polyhedron"
        fingers = "any number of" if c.fingers is None else str(c.fingers)
        contact = "" if c.contact == "any" else f" {c.contact}"
        print(f"  {where}, {fingers}{contact} fingers, {c.name}: {c.paper}")
        print(textwrap.fill(f"searches {c.described}", 96, initial_indent=" " * 6,
                            subsequent_indent=" " * 6))
    return 0

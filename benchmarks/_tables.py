"""The benchmarks' machine-readable output: markdown tables between named markers.

Every ``benchmarks/bench_*.py`` script takes ``--markdown``; with it, each result table it
prints is framed by ``<!-- table: NAME -->`` and ``<!-- /table -->`` lines, the markers
``benchmarks/regenerate.py`` looks for in its output and in docs/benchmarks.md, whose
table of the same name it replaces. Without the option the tables print unframed.
"""

from __future__ import annotations

import argparse
import contextlib
from collections.abc import Iterable, Iterator, Sequence

MARKERS = False


def parse(parser: argparse.ArgumentParser, argv: Sequence[str] | None = None):
    """``parser.parse_args`` with the ``--markdown`` option added and applied."""
    global MARKERS
    parser.add_argument("--markdown", action="store_true",
                        help="frame each result table in the markers benchmarks/regenerate.py "
                             "reads")
    args = parser.parse_args(argv)
    MARKERS = args.markdown
    return args


@contextlib.contextmanager
def block(name: str) -> Iterator[None]:
    """Frame what is printed inside (one markdown table) as the table ``name``."""
    if MARKERS:
        print(f"\n<!-- table: {name} -->", flush=True)
    yield
    if MARKERS:
        print("<!-- /table -->", flush=True)


def table(name: str, header: Sequence[str], rows: Iterable[Sequence[object]]) -> None:
    """Print one markdown table (cells as given, already formatted), framed as ``name``."""
    with block(name):
        print("\n| " + " | ".join(header) + " |")
        print("|" + "---|" * len(header))
        for row in rows:
            print("| " + " | ".join(str(cell) for cell in row) + " |", flush=True)

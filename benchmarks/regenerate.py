"""Regenerate docs/benchmarks.md's tables from the benchmark scripts (issue 26).

Each script of ``SCRIPTS`` runs as its own process with the arguments its section of
docs/benchmarks.md documents, plus ``--markdown``; every table it prints between
``<!-- table: NAME -->`` and ``<!-- /table -->`` replaces the table of that name in the
document, stamped with the date, the commit, the load average before and after, the CPU
count and the script's CPU and wall time. A table the document has for a script but the
script no longer prints is an error (stale rows go), as is a table the document lacks.

    uv run --extra bench python benchmarks/regenerate.py            # every script (~20 min)
    uv run python benchmarks/regenerate.py --only calls --only planar
    uv run python benchmarks/regenerate.py --quick --docs /tmp/b.md # smoke: small sizes
"""

from __future__ import annotations

import argparse
import datetime
import os
import re
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

# name: (the documented arguments, the --quick arguments); the script is bench_NAME.py
SCRIPTS: dict[str, tuple[list[str], list[str]]] = {
    "targets": ([], ["--quick"]),
    "calls": (["--grasps", "20", "--repeats", "3"], ["--grasps", "2", "--repeats", "1"]),
    "analysis": (["--grasps", "100"], ["--grasps", "3"]),
    "least_friction": (["--grasps", "8"], ["--grasps", "1", "--batch", "1000"]),
    "planar": ([], ["--random", "2", "--edges", "8", "--whole", "60"]),
    "mesh_synthesis": ([], ["--quick"]),
    "batch": (["--quick"], ["--quick", "--plot", str(Path(tempfile.gettempdir()) / "b.png")]),
    "startup": (["--repeat", "3"], ["--repeat", "1"]),
    "objects": ([], ["--quick"]),
    "constructions": ([], ["--repeat", "1"]),
    "epsilon_frame": (["--pad-radius", "0", "0.01"], ["--grasps", "5"]),
    "robust": (["--grasps", "100", "--samples", "50"], ["--grasps", "5", "--samples", "4"]),
    "hands": (["--count", "300"], ["--count", "20", "--objects", "2"]),
    "spatial": (["--exhaustive", "100"], ["--faces", "60", "--exhaustive", "5"]),
    "dataset": (["--objects", "50"], ["--objects", "3", "--samples", "200"]),
}

BLOCK = re.compile(r"<!-- table: (?P<name>[\w.-]+) -->\n.*?<!-- /table -->\n", re.S)


class RegenerateError(Exception):
    """A script failed, or its tables and the document's do not match."""


def commit() -> str:
    def git(*args: str) -> str:
        return subprocess.run(["git", *args], cwd=ROOT, capture_output=True,
                              text=True).stdout.strip()
    dirty = git("status", "--porcelain", "--untracked-files=no", "--", "src", "benchmarks")
    return git("rev-parse", "--short", "HEAD") + (" with local changes" if dirty else "")


def run(name: str, quick: bool) -> tuple[dict[str, str], str]:
    """Run ``bench_NAME.py``; its tables by name, and the stamp that goes under each."""
    args = [*SCRIPTS[name][quick], "--markdown"]
    command = ["python", f"benchmarks/bench_{name}.py", *args]
    print(f"$ {' '.join(command)}", flush=True)
    load0, wall0 = os.getloadavg(), time.perf_counter()
    cpu0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    done = subprocess.run([sys.executable, *command[1:]], cwd=ROOT, capture_output=True,
                          text=True)
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    wall, load1 = time.perf_counter() - wall0, os.getloadavg()
    if done.returncode != 0:
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        raise RegenerateError(f"bench_{name}.py failed (status {done.returncode}): {last}")
    cpu = (cpu1.ru_utime - cpu0.ru_utime) + (cpu1.ru_stime - cpu0.ru_stime)
    now = datetime.datetime.now(datetime.UTC).strftime("%Y-%m-%d %H:%M UTC")
    stamp = (f"*Regenerated {now}{' (--quick)' if quick else ''}, commit {commit()}: "
             f"`{' '.join(command[:2] + args[:-1])}`; load average {load0[0]:.1f} before, "
             f"{load1[0]:.1f} after; {os.cpu_count()} CPUs; the script took {cpu:.0f} s of "
             f"CPU, {wall:.0f} s wall.*")
    tables = {m["name"]: m[0].split("\n", 1)[1].rsplit("<!-- /table -->", 1)[0].strip()
              for m in BLOCK.finditer(done.stdout + "\n")}
    if not tables:
        raise RegenerateError(f"bench_{name}.py printed no table")
    return tables, stamp


def replace(document: str, name: str, tables: dict[str, str], stamp: str) -> str:
    """``document`` with the script ``name``'s tables replaced."""
    have = {m["name"] for m in BLOCK.finditer(document)}
    mine = {t for t in have if t == name or t.startswith(name + ".")}
    if missing := sorted(set(tables) - have):
        raise RegenerateError(f"docs have no marker for table(s) {', '.join(missing)}")
    if stale := sorted(mine - set(tables)):
        raise RegenerateError(f"bench_{name}.py no longer prints table(s) {', '.join(stale)}")

    def fill(m: re.Match) -> str:
        if m["name"] not in tables:
            return m[0]
        return (f"<!-- table: {m['name']} -->\n\n{tables[m['name']]}\n\n{stamp}\n\n"
                "<!-- /table -->\n")
    return BLOCK.sub(fill, document)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", action="append", choices=sorted(SCRIPTS), metavar="NAME",
                        help=f"only this script (repeatable): {', '.join(SCRIPTS)}")
    parser.add_argument("--quick", action="store_true", help="small sizes, a smoke run")
    parser.add_argument("--docs", type=Path, default=ROOT / "docs" / "benchmarks.md")
    args = parser.parse_args(argv)
    try:
        document = args.docs.read_text()
        for name in args.only or SCRIPTS:
            tables, stamp = run(name, args.quick)
            document = replace(document, name, tables, stamp)
            args.docs.write_text(document)  # each script's tables kept as soon as they exist
            print(f"  {len(tables)} table(s): {', '.join(tables)}", flush=True)
    except (RegenerateError, OSError) as error:
        print(f"regenerate: {error}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Every construction through the front door: time and result, optionally against a revision.

For each case (one per construction of the table, on bundled objects; and a regular
400-gon, whose edge pairs all tie for branch and bound),
``synthesize()`` is called once to warm up (compiling kernels on a fresh
install), then timed as the best of ``--repeat`` calls, in CPU time. With ``--against
REV`` the same cases run, in the same run, with the package as it was at git
revision ``REV`` (exported to a temporary folder, first on PYTHONPATH); the
script prints the ratio and whether the ranked grasps (their edges or faces
and smallest regions, to nine digits) are the same.

    uv run python benchmarks/bench_constructions.py [--against 271c0b5] [--repeat 3]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from _tables import parse, table

#: (label, object, synthesize keyword arguments; ``vertices``: the vertex construction, which
#: a revision before issue 27 reached by ``vertex_grasps``)
CASES = [
    ("2 hard, maximal", "frame", {"fingers": 2, "mu": 0.4}),
    ("2 hard, maximal, glyph", "glyph:&", {"fingers": 2, "mu": 0.4}),
    ("2 hard, maximal, ties", "regular:400", {"fingers": 2, "mu": 0.3}),
    ("2 hard, nguyen", "star", {"fingers": 2, "mu": 0.3, "construction": "nguyen"}),
    ("soft on vertices", "star", {"vertices": True, "mu": 0.3}),
    ("3 hard (plane)", "hexagon", {"fingers": 3, "mu": 0.6}),
    ("4 frictionless, maximal", "wrench-head", {"fingers": 4, "contact": "frictionless"}),
    ("4 frictionless, nguyen", "l-shape", {"fingers": 4, "contact": "frictionless",
                                           "construction": "nguyen"}),
    ("2 soft, maximal", "holed-block", {"fingers": 2, "contact": "soft", "mu": 0.5}),
    ("2 soft, nguyen", "l-prism", {"fingers": 2, "contact": "soft", "mu": 0.5,
                                   "construction": "nguyen"}),
    ("3 hard (space)", "cube", {"fingers": 3, "mu": 0.5}),
    ("7 frictionless", "cube", {"fingers": 7, "contact": "frictionless", "samples": 5000}),
    ("mesh, 4 hard", "cube", {"fingers": 4, "mu": 0.5, "samples": 5000}),
]

DRIVER = r"""
import json, sys, time
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis.best import synthesize
try:  # a revision before the table was the only door (issue 27)
    from forceclosure.synthesis import vertex_grasps
except ImportError:
    vertex_grasps = None

cases, repeat = json.loads(sys.argv[1]), int(sys.argv[2])
out = {}
for label, name, kwargs in cases:
    kind, _, arg = name.partition(":")
    obj = {"glyph": lambda: glyph(arg), "regular": lambda: Polygon.regular(int(arg or 0))}.get(
        kind, lambda: bundled(name))()
    kwargs = dict(kwargs)
    vertices = kwargs.pop("vertices", False)
    if vertices and vertex_grasps is not None:
        run = lambda: vertex_grasps(obj, kwargs["mu"], top=5)
    elif vertices:
        run = lambda: synthesize(obj, 2, "soft", kwargs["mu"], top=5,
                                 construction="vertices").found
    else:
        run = lambda: synthesize(obj, top=5, **kwargs).found
    run()
    best = float("inf")
    for _ in range(repeat):
        t = time.process_time()
        found = run()
        best = min(best, time.process_time() - t)
    sig = []
    for r in found:
        d = r.to_dict()
        where = d.get("edges") or d.get("faces") or [d.get("vertex"), d.get("edge"),
                                                       d.get("other_vertex")]
        size = d.get("min_length", d.get("min_area", d.get("length", 0.0)))
        sig.append([where, float(f"{size:.9g}")])
    out[label] = [best, sig]
print(json.dumps(out))
"""


def run(env: dict, repeat: int) -> dict:
    cases = json.dumps(CASES)
    done = subprocess.run([sys.executable, "-c", DRIVER, cases, str(repeat)], env=env,
                          check=True, capture_output=True, text=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", metavar="REV", help="git revision to compare with")
    parser.add_argument("--repeat", type=int, default=3)
    args = parse(parser)
    env = dict(os.environ)
    with tempfile.TemporaryDirectory() as tmp:
        old = None
        if args.against:
            root = Path(__file__).resolve().parents[1]
            archive = subprocess.run(["git", "-C", str(root), "archive", args.against, "src"],
                                     check=True, capture_output=True).stdout
            subprocess.run(["tar", "-x", "-C", tmp], input=archive, check=True)
            old = run(dict(env, PYTHONPATH=str(Path(tmp) / "src")), args.repeat)
        now = run(env, args.repeat)
    rows = []
    for label, name, _ in CASES:
        seconds, sig = now[label]
        line = f"{label:26s} {name:12s} {seconds * 1e3:9.1f} ms  {len(sig)} found"
        if old is not None:
            then, old_sig = old[label]
            line += (f"   {args.against}: {then * 1e3:9.1f} ms  {then / seconds:5.2f}x  "
                     f"same grasps: {sig == old_sig}")
            rows.append([label, name, ms(seconds), ms(then), "yes" if sig == old_sig else "**no**"])
        else:
            rows.append([label, name, ms(seconds), f"{len(sig)}"])
        print(line, flush=True)
    table("constructions", ["case", "object", "CPU, best of " + str(args.repeat)] + (
        [args.against, "same grasps"] if old is not None else ["found"]), rows)


def ms(seconds: float) -> str:
    return f"{seconds * 1e3:.1f} ms" if seconds < 1 else f"{seconds:.2f} s"


if __name__ == "__main__":
    main()

"""Any hand on a polygon (issue 25): the grown segments' search, and their corner proof
against deciding every corner grasp one by one.

For a few hands on bundled polygons it prints the search's CPU seconds (``search`` on the
table's ``grown`` construction, default 20,000 samples, top 5) and the best relative
segment; then, for the best region set, the proof two ways in one process:

* **directions**: :func:`~forceclosure.synthesis.planar.grown_segments.corner_closure`
  (exact rationals where floating point cannot tell), as ``certify`` runs it;
* **every corner grasp**: the ``2^n`` (``4^n`` frictionless with a margin) grasps at the
  segments' ends (and the fan's ends) decided by the compiled batch analysis (Theorem 1's
  LP per grasp, :func:`~forceclosure.analysis.batch_analysis.analyze_batch`), in floating
  point only: what a user would run without the module's argument.

Both must agree. The machine's load is printed beside the times. Run it with::

    uv run python benchmarks/bench_grown_planar.py
"""

from __future__ import annotations

import itertools
import math
import os
import time

import numpy as np

from forceclosure.analysis.batch_analysis import analyze_batch
from forceclosure.objects import bundled
from forceclosure.synthesis import Hand, search
from forceclosure.synthesis.planar import grown_segments as grown

HANDS = [("l-shape", 5, "frictionless", 0.0), ("hexagon", 6, "hard", 0.3),
         ("star", 8, "frictionless", 0.0), ("star", 8, "hard", 0.3)]


def corner_grasps(r):
    """Every corner grasp of a region set: points and (turned) normals, ``(C, n, 2)``."""
    polygon = r.polygon
    turn = max(r.margin, polygon.spread)
    per = []
    for e_index, (u, v) in zip(r.edges, r.segments, strict=True):
        e = polygon.edges[e_index]
        n = np.asarray(e.normal, float)
        turns = (-turn, turn) if r.mu == 0 and turn > 0 else (0.0,)
        per.append([(e.point(t), np.array([math.cos(a) * n[0] - math.sin(a) * n[1],
                                           math.sin(a) * n[0] + math.cos(a) * n[1]]))
                    for t in (u, v) for a in turns])
    combos = list(itertools.product(*per))
    P = np.array([[p for p, _ in c] for c in combos])
    N = np.array([[m for _, m in c] for c in combos])
    return P, N


def main() -> None:
    search(grown.GROWN, bundled("square"), Hand(4, "hard", 0.4, samples=500, top=1))  # warm
    for name, n, contact, mu in HANDS:
        obj = bundled(name)
        t = time.process_time()
        found = search(grown.GROWN, obj, Hand(n, contact, mu, top=5))
        cpu = time.process_time() - t
        r = found[0]
        print(f"{name}, {n} {contact}: search {cpu:.2f} s CPU, best relative segment "
              f"{r.relative_min_size:.3f}, load {os.getloadavg()[0]:.1f}")
        fresh = type(r)(r.polygon, r.edges, r.segments, r.construction, r.mu, r.margin)
        t = time.process_time()
        proof = fresh.certify()
        t_dir = time.process_time() - t
        P, N = corner_grasps(r)
        narrowed = grown.narrowed(mu, max(r.margin, r.polygon.spread)) if mu else 0.0
        model = "hard" if mu else "frictionless"
        analyze_batch(P[:1], N[:1], mu=narrowed, model=model)  # the kernel for n contacts
        t = time.process_time()
        batch = analyze_batch(P, N, mu=narrowed, model=model)
        t_all = time.process_time() - t
        every = bool(np.all(batch.force_closure))
        print(f"  proof by directions {t_dir * 1e3:.1f} ms CPU ({proof.holds}); every corner "
              f"grasp, {len(P):,} LPs, {t_all * 1e3:.1f} ms CPU ({every}); ratio "
              f"{t_all / t_dir:.1f}x, load {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()

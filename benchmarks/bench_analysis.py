"""Per-grasp cost of forceclosure's analysis against the textbook baseline.

The baseline is what a user writes by hand: one ``scipy.optimize.linprog``
per grasp asking for a combination of the wrenches with every weight >= 1
summing to zero (the second half of Theorem 1 only; no rank check, no
certificate, no exact cones). Both run in the same process, on the same
grasps, timed in CPU time; ratios, not absolute times, are the result on a shared
machine.
``analyze`` is timed twice: the verdict, rank and margin (what it computes
at once, compiled), and with its explanation read too (the reference path's
linear programs, worked out on first reading).

    uv run python benchmarks/bench_analysis.py [--grasps 200]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _tables import parse, table
from scipy.optimize import linprog

from forceclosure import Cone, analyze, generating_wrenches, kernels, point_contact
from forceclosure.analysis.two_finger import two_finger_closure


def baseline(W: np.ndarray) -> bool:
    m = W.shape[1]
    res = linprog(np.zeros(m), A_eq=W, b_eq=np.zeros(W.shape[0]), bounds=[(1, None)] * m,
                  method="highs")
    return res.status == 0


def grasps(rng, n, k, d, model, mu):
    out = []
    for _ in range(n):
        p = rng.normal(size=(k, d))
        p /= np.linalg.norm(p, axis=1, keepdims=True)
        normals = p + rng.normal(0, 0.2, (k, d))
        out.append([point_contact(p[i], normals[i], model, mu) for i in range(k)])
    return out


def timed(fn, items):
    """CPU seconds (``time.process_time``: every thread of the process) per item."""
    t = time.process_time()
    for item in items:
        fn(item)
    return (time.process_time() - t) / len(items)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--grasps", type=int, default=200)
    n = parse(ap).grasps
    rng = np.random.default_rng(0)
    cases = [
        ("planar, 2 hard fingers", grasps(rng, n, 2, 2, "hard", 0.3), "exact"),
        ("planar, 4 frictionless", grasps(rng, n, 4, 2, "frictionless", 0.0), "exact"),
        ("spatial, 3 hard, 8-edge pyramid", grasps(rng, n, 3, 3, "hard", 0.5), Cone(8)),
        ("spatial, 3 hard, exact cones", grasps(rng, n, 3, 3, "hard", 0.5), "exact"),
        ("spatial, 7 frictionless", grasps(rng, n, 7, 3, "frictionless", 0.0), "exact"),
    ]
    for gs in (cases[0][1], cases[2][1]):  # compiled (or loaded from the cache) before timing
        for _ in range(kernels.COMPILE_AFTER + 1):
            analyze(gs[0])
    rows = []
    for name, gs, cone in cases:
        ws = [generating_wrenches(g, cone if isinstance(cone, Cone) else Cone(8)).wrenches
              for g in gs]
        ours = timed(lambda g, cone=cone: analyze(g, cone=cone), gs)
        explained = timed(lambda g, cone=cone: analyze(g, cone=cone).reason, gs)
        base = timed(baseline, ws)
        rows.append([name, f"{ours * 1e6:.0f} µs", f"{explained * 1e3:.1f} ms",
                     f"{base * 1e3:.2f} ms", f"{base / ours:.0f}×"])
    table("analysis", ["case (CPU a grasp)", "analyze", "explained", "linprog",
                       "linprog / analyze"], rows)
    m = 100_000
    p, q = rng.normal(size=(m, 2)), rng.normal(size=(m, 2))
    t = time.process_time()
    two_finger_closure(p, p, q, q, 0.3)
    vec = (time.process_time() - t) / m
    loop = timed(lambda i: analyze([point_contact(p[i], p[i], "hard", 0.3),
                                    point_contact(q[i], q[i], "hard", 0.3)]), range(200))
    print(f"Corollary 3, vectorised: {1 / vec / 1e6:.1f} M pairs per CPU-second; "
          f"{loop / vec:.0f}x the per-pair general test")


if __name__ == "__main__":
    main()

"""Least friction of one grasp (issue 18): the compiled bisection against the reference.

``quality.least_friction`` on point contacts runs one compiled bisection on
the cone half-angle (each step a Theorem 1 verdict in the kernel);
``quality.least_friction_reference`` is the same bisection over full
analyses (what every grasp paid before). Both with exact cones, one grasp at
a time, as the command line computes it for each grasp of a file; the same
grasps in the same run, in CPU time:

* three hard fingers around a ball's equator (Fig. 9: any positive friction
  closes it, so the bisection runs to the tolerance band);
* random three-hard-finger grasps on a sphere, normals tilted (most close
  at some friction);
* random two-soft-finger grasps in space.

    uv run python benchmarks/bench_least_friction.py [--grasps 20]
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from _tables import parse, table

from forceclosure import Cone, point_contact
from forceclosure.analysis.batch import least_friction_batch
from forceclosure.analysis.quality import least_friction, least_friction_reference


def grasps(kind: str, count: int, rng: np.random.Generator) -> list:
    if kind == "equator":
        t = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
        p = np.c_[np.cos(t), np.sin(t), np.zeros(3)]
        return [[point_contact(q, q, "hard") for q in p]] * count
    k, model = (3, "hard") if kind == "three hard" else (2, "soft")
    out = []
    for _ in range(count):
        p = rng.normal(size=(k, 3))
        p /= np.linalg.norm(p, axis=1, keepdims=True)
        out.append([point_contact(q, q + rng.normal(scale=0.2, size=3), model) for q in p])
    return out


def timed(fn, cases) -> tuple[float, list[float]]:
    start = time.process_time()
    values = [fn(g) for g in cases]
    return (time.process_time() - start) / len(cases), values


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grasps", type=int, default=20)
    parser.add_argument("--batch", type=int, default=200_000, help="soft pairs in the batch")
    args = parse(parser)
    rng = np.random.default_rng(0)
    least_friction(grasps("equator", 1, rng)[0])  # compile or load the kernels first
    rows = []
    for kind in ("equator", "three hard", "two soft"):
        cases = grasps(kind, args.grasps, rng)
        least_friction(cases[0])  # this kind's kernel loaded
        fast, a = timed(least_friction, cases)
        # soft pairs have a closed form now, in both; "before" is the bisection over full
        # analyses that both ran until then (a pyramid of 256 edges, as exact cones end)
        before = (lambda g: least_friction_reference(g, cone=Cone(256))) if kind == "two soft" \
            else least_friction_reference
        ref, b = timed(before, cases)
        agree = sum((x == y) or (np.isfinite(y) and abs(x - y) <= 1e-4 * y) or
                    (x < 1e-4 and y < 1e-4) for x, y in zip(a, b, strict=True))
        rows.append([kind, f"{fast * 1e3:.2f} ms", f"{ref * 1e3:.0f} ms", f"{ref / fast:.0f}×",
                     f"{agree}/{len(cases)}"])
    table("least_friction", ["grasps (CPU a grasp)", "now", "before (reference)", "ratio",
                             "agree (rel 1e-4)"], rows)
    batch(args.batch, rng)


def batch(count: int, rng: np.random.Generator) -> None:
    """``least_friction_batch`` on many random spatial soft pairs: in closed form with the
    paper's torque, bisected inside the kernel with torsion coupled to the normal force."""
    P = rng.normal(size=(count, 2, 3))
    d = P[:, 1] - P[:, 0]
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    N = np.stack([-d + 0.3 * rng.normal(size=(count, 3)), d + 0.3 * rng.normal(size=(count, 3))],
                 axis=1)
    least_friction_batch(P[:2], N[:2], model="soft")
    least_friction_batch(P[:2], N[:2], model="soft", torsion=0.01)
    start = time.process_time()
    least_friction_batch(P, N, model="soft")
    each = (time.process_time() - start) / count
    m = min(count, 200)
    start = time.process_time()
    least_friction_batch(P[:m], N[:m], model="soft", torsion=0.01)
    coupled = (time.process_time() - start) / m
    table("least_friction.batch", ["`least_friction_batch`, spatial soft pairs", "CPU a pair"],
          [[f"{count:,} pairs, the paper's torque (closed form)", f"{each * 1e9:,.0f} ns"],
           [f"{m:,} pairs, torsion coupled to the normal force, 0.01 (bisection)",
            f"{coupled * 1e3:.2f} ms"]])


if __name__ == "__main__":
    main()

"""The calls a person makes (issue 26): one grasp at a time, and pairs through the public call.

Each row is timed in this one process, on the same grasps, with CPU time
(``time.process_time``: every thread of the process, so a spinning thread pool
counts) beside wall time, and the load average printed before and after: on a
shared machine the CPU column and the ratios are the result, not the wall
times. "first" is the first call of the row in this process (the first row
of a kernel also loads it from numba's disk cache); "warm" is the median of
the later calls.

Rows and their baselines (what a user writes without this library):

* ``analyze()`` of one spatial three-hard-finger grasp (exact cones): the
  feasibility LP "every weight >= 1, the wrenches sum to zero" on an 8-edge
  pyramid, by ``scipy.optimize.linprog`` (HiGHS) and by HiGHS itself with one
  solver instance reused for every grasp (SciPy's bundled HiGHS bindings,
  the API of ``highspy``); the baselines get their wrenches precomputed.
* ``least_friction()`` of one spatial three-hard-finger grasp and of one pair
  of soft fingers (exact cones): a GraspNet-style loop over 10 friction values
  (0.1, 0.2, ..., 1.0; it stops at the first that closes), each an 8-edge
  pyramid built in NumPy and one HiGHS LP (reused instance). The loop only
  brackets the answer (to 0.1, up to 1); ours is the value to ``rtol`` 1e-6.
* ``epsilon()`` (L1, 8-edge pyramids) of one closed grasp: SciPy's
  ``ConvexHull`` (Qhull) of the same wrenches, precomputed.
* ``two_finger_closure`` on 100 / 10 k / 1 M planar pairs: the public call,
  the compiled kernel it runs (its inputs prepared beforehand), and the
  squeezing test in vectorised NumPy (unit normals given, no validation).

    uv run python benchmarks/bench_calls.py [--grasps 40] [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import statistics
import time

import numpy as np
from _tables import block, parse
from scipy.optimize import linprog
from scipy.optimize._highspy import _core as highs
from scipy.spatial import ConvexHull

from forceclosure import analyze, generating_wrenches, kernels, point_contact
from forceclosure.analysis.friction import least_friction
from forceclosure.analysis.quality import epsilon
from forceclosure.analysis.two_finger import SERIAL_BELOW, two_finger_closure
from forceclosure.contacts import Cone

MUS = np.round(np.arange(1, 11) * 0.1, 1)  # GraspNet-style friction values


# --- what a user writes -----------------------------------------------------------------

def pyramid_wrenches(P: np.ndarray, N: np.ndarray, mu: float, soft: bool = False,
                     edges: int = 8) -> np.ndarray:
    """(6, m) wrenches of point contacts with an inscribed ``edges``-pyramid, in NumPy
    (torques about the origin; soft fingers add the pure torques ``±n``)."""
    n = N / np.linalg.norm(N, axis=1, keepdims=True)
    helper = np.where(np.abs(n[:, :1]) < 0.9, [[1.0, 0, 0]], [[0, 1.0, 0]])
    t1 = np.cross(n, helper)
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    t2 = np.cross(n, t1)
    th = 2 * np.pi * np.arange(edges) / edges
    f = (-n[:, None] + mu * (np.cos(th)[None, :, None] * t1[:, None]
                             + np.sin(th)[None, :, None] * t2[:, None])).reshape(-1, 3)
    p = np.repeat(P, edges, axis=0)
    W = np.hstack([f, np.cross(p, f)])
    if soft:
        W = np.vstack([W, np.hstack([np.zeros_like(n), n]), np.hstack([np.zeros_like(n), -n])])
    return W.T


def linprog_closed(W: np.ndarray) -> bool:
    m = W.shape[1]
    res = linprog(np.zeros(m), A_eq=W, b_eq=np.zeros(W.shape[0]), bounds=[(1, None)] * m,
                  method="highs")
    return res.status == 0


class ReusedHighs:
    """One HiGHS instance for every LP ("weights >= 1, W x = 0"), as a user of ``highspy``
    would keep it."""

    def __init__(self) -> None:
        self.h = highs._Highs()
        self.h.setOptionValue("output_flag", False)

    def closed(self, W: np.ndarray) -> bool:
        d, m = W.shape
        lp = highs.HighsLp()
        lp.num_col_, lp.num_row_ = m, d
        lp.col_cost_ = np.zeros(m)
        lp.col_lower_ = np.ones(m)
        lp.col_upper_ = np.full(m, highs.kHighsInf)
        lp.row_lower_ = lp.row_upper_ = np.zeros(d)
        a = lp.a_matrix_
        a.format_ = highs.MatrixFormat.kColwise
        a.start_ = np.arange(0, d * m + 1, d)
        a.index_ = np.tile(np.arange(d), m)
        a.value_ = np.ascontiguousarray(W.T).ravel()
        a.num_col_, a.num_row_ = m, d
        lp.a_matrix_ = a
        self.h.passModel(lp)
        self.h.run()
        return self.h.getModelStatus() == highs.HighsModelStatus.kOptimal


def graspnet_loop(solver: ReusedHighs, P, N, soft: bool) -> float:
    """The first of 10 friction values whose pyramid grasp closes (inf: none does)."""
    for mu in MUS:
        if solver.closed(pyramid_wrenches(P, N, mu, soft)):
            return float(mu)
    return np.inf


def numpy_pairs(p, n_p, q, n_q, mu):
    """Corollary 3's squeezing test, vectorised (unit normals given)."""
    vx, vy = q[:, 0] - p[:, 0], q[:, 1] - p[:, 1]
    length = np.sqrt(vx * vx + vy * vy)
    cos_p = -(vx * n_p[:, 0] + vy * n_p[:, 1])
    cos_q = vx * n_q[:, 0] + vy * n_q[:, 1]
    bound = length / np.sqrt(1.0 + mu * mu)
    return (cos_p > bound) & (cos_q > bound)


# --- timing -----------------------------------------------------------------------------

def timed(fn, items, repeats: int = 1):
    """(first wall, first CPU, warm wall, warm CPU): seconds per item; first = item 0's
    first call, warm = the median over the later calls (all items, ``repeats`` times)."""
    w0, c0 = time.perf_counter(), time.process_time()
    fn(items[0])
    first = (time.perf_counter() - w0, time.process_time() - c0)
    walls, cpus = [], []
    for _ in range(repeats):
        w, c = time.perf_counter(), time.process_time()
        for item in items:
            fn(item)
        walls.append((time.perf_counter() - w) / len(items))
        cpus.append((time.process_time() - c) / len(items))
    return (*first, statistics.median(walls), statistics.median(cpus))


def fmt(seconds: float) -> str:
    if seconds >= 1e-1:
        return f"{seconds:.2f} s"
    if seconds >= 1e-3:
        return f"{seconds * 1e3:.2f} ms"
    return f"{seconds * 1e6:.1f} µs"


def row(name: str, ours, base_name: str, base) -> None:
    ratio_cpu = base[3] / ours[3] if ours[3] > 0 else np.inf
    ratio_wall = base[2] / ours[2]
    print(f"| {name} | {fmt(ours[0])} / {fmt(ours[1])} | {fmt(ours[2])} / {fmt(ours[3])} | "
          f"{base_name}: {fmt(base[2])} / {fmt(base[3])} | {ratio_wall:.1f}× / "
          f"{ratio_cpu:.1f}× |", flush=True)


def sphere_grasps(rng, count: int, k: int, model: str, mu: float = 0.5):
    out = []
    for _ in range(count):
        p = rng.normal(size=(k, 3))
        p /= np.linalg.norm(p, axis=1, keepdims=True)
        out.append([point_contact(x, x + rng.normal(scale=0.2, size=3), model, mu) for x in p])
    return out


def arrays(grasp):
    return (np.array([c.point for c in grasp]), np.array([c.normal for c in grasp]))


def single_calls(rng, count: int, repeats: int) -> None:
    print("\n| call (one grasp) | ours, first: wall / CPU | ours, warm: wall / CPU | "
          "baseline, warm: wall / CPU | baseline / ours: wall / CPU |")
    print("|---|---|---|---|---|")
    solver = ReusedHighs()
    three = sphere_grasps(rng, count, 3, "hard")
    kernels.COMPILE_AFTER = 0  # the compiled kernels from the first call (cached on disk)
    ours = timed(lambda g: analyze(g).verdict, three, repeats)
    ws = [generating_wrenches(g, Cone(8)).wrenches for g in three]
    row("`analyze()`, 3 hard fingers, exact cones", ours, "linprog, 8-edge pyramid",
        timed(linprog_closed, ws, repeats))
    row("", ours, "HiGHS reused, 8-edge pyramid", timed(solver.closed, ws, repeats))

    free = sphere_grasps(rng, count, 3, "hard")
    ours = timed(least_friction, free, repeats)
    base = timed(lambda g: graspnet_loop(solver, *arrays(g), soft=False), free, repeats)
    row("`least_friction()`, 3 hard fingers, exact cones", ours,
        "GraspNet-style loop, 10 μ × HiGHS reused", base)
    t = np.array([0.0, 2 * np.pi / 3, 4 * np.pi / 3])
    ring = np.c_[np.cos(t), np.sin(t), np.zeros(3)]
    equator = [[point_contact(x, x, "hard") for x in ring]] * count
    ours = timed(least_friction, equator, repeats)
    base = timed(lambda g: graspnet_loop(solver, *arrays(g), soft=False), equator, repeats)
    row("`least_friction()`, 3 hard fingers on the equator", ours,
        "GraspNet-style loop", base)
    pairs = sphere_grasps(rng, count, 2, "soft")
    ours = timed(least_friction, pairs, repeats)
    base = timed(lambda g: graspnet_loop(solver, *arrays(g), soft=True), pairs, repeats)
    row("`least_friction()`, 2 soft fingers in space", ours, "GraspNet-style loop", base)

    closed = [g for g in sphere_grasps(rng, 8 * count, 3, "hard", 1.0)
              if analyze(g).verdict.value == "closure"][:count]
    ours = timed(lambda g: epsilon(g).value, closed, repeats)
    hull = [generating_wrenches(g, Cone(8, "inscribed")).wrenches.T for g in closed]
    row(f"`epsilon()` L1, 3 hard fingers (closed, {len(closed)})", ours,
        "Qhull `ConvexHull`", timed(ConvexHull, hull, repeats))


def pair_row(rng, n: int, repeats: int) -> None:
    """One size of the pairs table: the public call, its kernel alone, NumPy."""
    from forceclosure.kernels import kernel_array
    from forceclosure.kernels import pairs as kernel

    p, q = rng.normal(size=(n, 2)), rng.normal(size=(n, 2))
    d = q - p
    d /= np.linalg.norm(d, axis=1, keepdims=True)
    n_p = -d + 0.3 * rng.normal(size=(n, 2))
    n_q = d + 0.3 * rng.normal(size=(n, 2))
    n_p /= np.linalg.norm(n_p, axis=1, keepdims=True)
    n_q /= np.linalg.norm(n_q, axis=1, keepdims=True)
    mu = kernel_array(np.array([0.3]))
    code, least = np.empty(n, dtype=np.int8), np.empty(n)
    flat = [kernel_array(a) for a in (p, n_p, q, n_q)]

    def compiled(_):  # what two_finger_closure runs, on its prepared inputs
        kernel.pair_verdicts(*flat, mu, mu, 1e-9, False, 1e290, code, least, SERIAL_BELOW)

    reps = [None] * max(1, min(repeats * 20, 2_000_000 // n))
    public = timed(lambda _: two_finger_closure(p, n_p, q, n_q, 0.3), reps)
    alone = timed(compiled, reps)
    numpy = timed(lambda _: numpy_pairs(p, n_p, q, n_q, 0.3), reps)
    agree = np.array_equal(two_finger_closure(p, n_p, q, n_q, 0.3).code == 2,
                           numpy_pairs(p, n_p, q, n_q, 0.3))
    for name, t in (("`two_finger_closure`", public), ("its kernel alone", alone),
                    ("NumPy, vectorised" + ("" if agree else " (disagrees)"), numpy)):
        print(f"| {n:,} | {name} | {fmt(t[0])} / {fmt(t[1])} | {fmt(t[2])} / "
              f"{fmt(t[3])} | {n / t[2] / 1e6:.1f} | "
              f"{(n / t[3] / 1e6) if t[3] > 0 else np.inf:.1f} |", flush=True)
    print(f"| {n:,} | public / kernel (CPU) | | | | {public[3] / alone[3]:.2f}× |"
          if alone[3] > 0 else f"| {n:,} | public / kernel | | | | (below CPU clock) |")


def pair_calls(rng, repeats: int, sizes=(100, 10_000, 1_000_000)) -> None:
    print("\n| planar pairs | call | first: wall / CPU | warm: wall / CPU | "
          "M pairs/s (wall) | M pairs per CPU-s |")
    print("|---|---|---|---|---|---|")
    for n in sizes:
        pair_row(rng, n, repeats)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grasps", type=int, default=40)
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--only", choices=("single", "pairs"), default=None)
    args = parse(parser)
    import numba

    print(f"load average before: {os.getloadavg()}; numba threads: "
          f"{numba.config.NUMBA_NUM_THREADS}; CPUs: {os.cpu_count()}")
    rng = np.random.default_rng(0)
    if args.only != "pairs":
        with block("calls.single"):
            single_calls(rng, args.grasps, args.repeats)
    if args.only != "single":
        with block("calls.pairs"):
            pair_calls(rng, args.repeats)
    print(f"\nload average after: {os.getloadavg()}")


if __name__ == "__main__":
    main()

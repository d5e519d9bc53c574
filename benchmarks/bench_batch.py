"""The batch engine against what dataset builders run today (issue 5).

Every baseline is re-implemented here from its published algorithm and
timed in the same run, on the same grasps, as the compiled kernels:

* ``linprog``: one ``scipy.optimize.linprog`` (HiGHS) per grasp asking for
  weights >= 1 on the generating wrenches that sum to zero (Theorem 1's
  second half, no rank check);
* ``qhull`` (GraspIt! style): the convex hull of the wrenches, closure when
  every facet has the origin strictly on its inner side;
* ``min-norm QP`` (Dex-Net style): the point of the wrenches' convex hull
  nearest the origin by a ``cvxopt`` QP, closure when its norm is below
  1e-3 (needs ``--extra bench``);
* ``six-value loop`` (GraspNet-1Billion style): the two-finger angle test
  in a Python loop over grasps, re-run for friction 0.1 … 1.0 until it
  passes;
* ``Qhull epsilon`` (GraspIt! style): Ferrari–Canny's epsilon as the
  nearest facet of ``scipy.spatial.ConvexHull`` of the wrenches, per grasp.

The baselines get their wrenches precomputed (only their test is timed);
ours builds them inside the kernel. Rates are per CPU-second
(``time.process_time``: every thread of the process, a spinning pool included), and
ratios, measured in the one process, are the result on a shared machine.
Compilation is timed apart, in fresh processes with an empty cache, then
with the cache filled. The streaming run analyses an ``.npz`` of 10 M grasps
through the CLI and reports its peak resident memory.

    uv run --extra bench python benchmarks/bench_batch.py [--quick]

Prints a table and writes ``docs/bench_batch.png``. ``--quick`` is a smoke run
of small sizes (the test suite runs it).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from _tables import parse, table
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, QhullError

from forceclosure import Cone
from forceclosure.analysis.batch import analyze_batch, epsilon_batch, least_friction_batch
from forceclosure.analysis.two_finger import two_finger_closure

DOCS = Path(__file__).parents[1] / "docs"
GRASPNET_FRICTION = (0.1, 0.2, 0.4, 0.6, 0.8, 1.0)


# --- grasps -----------------------------------------------------------------------------

def sphere_grasps(rng, n, k, d=3, jitter=0.3):
    """Contacts on the unit sphere, normals the radius plus noise (sampled grasps)."""
    p = rng.normal(size=(n, k, d))
    p /= np.linalg.norm(p, axis=-1, keepdims=True)
    normal = p + rng.normal(0, jitter, (n, k, d))
    return p, normal / np.linalg.norm(normal, axis=-1, keepdims=True)


def antipodal_pairs(rng, n, d):
    """Two fingers on opposite faces of a box, normals antiparallel (parallel-jaw grasps)."""
    p = rng.uniform(-1, 1, (n, d))
    q = rng.uniform(-1, 1, (n, d))
    p[:, 0], q[:, 0] = -1.0, 1.0
    n_p = np.zeros((n, d))
    n_p[:, 0] = -1.0
    return p, n_p, q, -n_p


def pyramid_wrenches(P, N, mu, edges):
    """Hard-finger wrenches of one spatial grasp, an inscribed ``edges``-pyramid per contact."""
    cols = []
    angles = 2 * np.pi * np.arange(edges) / edges
    for p, n, m in zip(P, N, mu, strict=True):
        helper = np.eye(3)[np.argmin(np.abs(n))]
        t1 = np.cross(n, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(n, t1)
        forces = -n + m * (np.cos(angles)[:, None] * t1 + np.sin(angles)[:, None] * t2)
        cols.append(np.hstack([forces, np.cross(p, forces)]))
    return np.vstack(cols).T  # (6, k * edges)


# --- baselines ----------------------------------------------------------------------------

def linprog_closure(W):
    m = W.shape[1]
    res = linprog(np.zeros(m), A_eq=W, b_eq=np.zeros(W.shape[0]), bounds=[(1, None)] * m,
                  method="highs")
    return res.status == 0


def qhull_closure(W):
    try:
        hull = ConvexHull(W.T)
    except QhullError:  # flat wrench set: GraspIt! reports no closure
        return False
    return bool(np.all(hull.equations[:, -1] < 0))


def qhull_epsilon(W):
    try:
        hull = ConvexHull(W.T)
    except QhullError:
        return 0.0
    return max(0.0, float(np.min(-hull.equations[:, -1])))


def min_norm_qp_closure(W, regularizer=1e-10, threshold=1e-3):
    import cvxopt

    cvxopt.solvers.options["show_progress"] = False
    m = W.shape[1]
    P = cvxopt.matrix(W.T @ W + regularizer * np.eye(m))
    q = cvxopt.matrix(np.zeros(m))
    G = cvxopt.matrix(-np.eye(m))
    h = cvxopt.matrix(np.zeros(m))
    A = cvxopt.matrix(np.ones((1, m)))
    b = cvxopt.matrix(np.ones(1))
    x = np.array(cvxopt.solvers.qp(P, q, G, h, A, b)["x"]).ravel()
    return math.sqrt(max(x @ (W.T @ W) @ x, 0.0)) < threshold


def dexnet_pair(p1, n1, p2, n2, mu):
    """The two-finger angle test, one pair in Python (outward normals in, as ours)."""
    if np.array_equal(p1, p2):
        return False
    for inward, here, there in ((-n1, p1, p2), (-n2, p2, p1)):
        diff = there - here
        proj = inward @ diff / np.linalg.norm(inward)
        if proj < 0:
            return False
        if np.arccos(min(proj / np.linalg.norm(diff), 1.0)) > np.arctan(mu):
            return False
    return True


def graspnet_loop(P, Np, Q, Nq):
    """Least friction as GraspNet scored it: the first of six values that closes."""
    out = np.full(len(P), np.inf)
    for i in range(len(P)):
        for mu in GRASPNET_FRICTION:
            if dexnet_pair(P[i], Np[i], Q[i], Nq[i], mu):
                out[i] = mu
                break
    return out


# --- timing -------------------------------------------------------------------------------

def best_rate(fn, count, repeats=5):
    """Items per CPU-second of ``fn()`` handling ``count`` items, best of ``repeats``."""
    fn()  # warm: threads started, pages touched once
    best = math.inf
    for _ in range(repeats):
        t = time.process_time()
        fn()
        best = min(best, time.process_time() - t)
    return count / best


def per_item_rate(fn, items):
    t = time.process_time()
    for item in items:
        fn(item)
    return len(items) / (time.process_time() - t)


WARM = """
import time
t = time.perf_counter()
import numpy as np
from forceclosure import Cone
from forceclosure.analysis.batch import analyze_batch, epsilon_batch, least_friction_batch
from forceclosure.analysis.two_finger import two_finger_closure
P = np.random.default_rng(0).normal(size=(64, 3, 3))
two_finger_closure(P[:, 0, :2], P[:, 0, :2], P[:, 1, :2], -P[:, 1, :2], 0.3)
two_finger_closure(P[:, 0], P[:, 0], P[:, 1], -P[:, 1], 0.3)
analyze_batch(P, P, mu=0.5, cone=Cone(8))
analyze_batch(P[..., :2], P[..., :2], mu=0.5)
least_friction_batch(P, P, cone=Cone(8))
epsilon_batch(P, P, mu=0.5)
print(time.perf_counter() - t)
"""


def compile_seconds():
    """(first run with an empty cache, later run from the filled cache), fresh processes."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        runs = [float(subprocess.run([sys.executable, "-c", WARM], env=env, check=True,
                                     capture_output=True, text=True).stdout)
                for _ in range(2)]
    return runs[0], runs[1]


# Peak memory from VmHWM: it belongs to the process image, unlike ru_maxrss, which a
# child inherits from the (large) parent it was forked from.
STREAM = """
import sys
from forceclosure.app.cli import main
code = main(["analyze", sys.argv[1], "--out", sys.argv[2], "--json"])
status = open("/proc/self/status").read().split("VmHWM:")[1]
print(int(status.split()[0]) / 1024, file=sys.stderr)
sys.exit(code)
"""


def streaming(n, rng):
    """Write ``n`` three-finger grasps to an .npz, analyse it with the CLI in a fresh process."""
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "grasps.npz")
        P, N = sphere_grasps(rng, n, 3)
        np.savez(path, points=P, normals=N, mu=0.5, model="hard", cone="8-inscribed")
        size = os.path.getsize(path) / 2**30
        del P, N
        run = subprocess.run([sys.executable, "-c", STREAM, path, os.path.join(tmp, "r.npz")],
                             capture_output=True, text=True, check=True,
                             env=dict(os.environ, TQDM_DISABLE="1"))
        summary = json.loads(run.stdout)
        peak_mib = float(run.stderr.strip().splitlines()[-1])
    return summary, size, peak_mib


# --- the run -----------------------------------------------------------------------------

def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="small sizes, no compile timing, 200k streamed (a smoke run)")
    ap.add_argument("--plot", default=str(DOCS / "bench_batch.png"), metavar="PNG",
                    help="where the figure goes (default docs/bench_batch.png)")
    args = parse(ap)
    quick = args.quick
    rng = np.random.default_rng(0)
    rows = []

    def row(case, ours, unit, baseline=None, theirs=None, target=None):
        ratio = ours / theirs if theirs else None
        rows.append((case, ours, unit, baseline, theirs, ratio, target))
        text = f"{case:44} {ours:>14,.0f} {unit:9}"
        if baseline:
            text += f" {baseline:>16} {theirs:>10,.0f}/s {ratio:>9,.0f}x"
        print(text + (f"   target {target}" if target else ""), flush=True)

    if not quick:
        cold, cached = compile_seconds()
        print(f"compile: {cold:.1f} s in a fresh process with an empty cache; "
              f"{cached:.1f} s once cached (import and first calls included)")
    print(f"{'case':44} {'ours':>14} {'unit':9} {'baseline':>16} {'baseline':>12} {'ratio':>10}")

    # pairs: Corollary 3
    n = 200_000 if quick else 10_000_000
    p, n_p, q, n_q = antipodal_pairs(rng, n, 2)
    p[:, 1] += rng.normal(0, 0.3, n)  # tilt the normals a little: verdicts of all three kinds
    sample = range(2000)
    loop = per_item_rate(lambda i: dexnet_pair(p[i], n_p[i], q[i], n_q[i], 0.3), sample)
    row("planar pairs, Corollary 3", best_rate(lambda: two_finger_closure(p, n_p, q, n_q, 0.3),
                                               n), "pairs/s", "Python pair test", loop,
        ">= 100M/s")
    p3, n3p, q3, n3q = antipodal_pairs(rng, n, 3)
    row("spatial soft pairs, antiparallel normals",
        best_rate(lambda: two_finger_closure(p3, n3p, q3, n3q, 0.3), n), "pairs/s",
        "Python pair test",
        per_item_rate(lambda i: dexnet_pair(p3[i], n3p[i], q3[i], n3q[i], 0.3), sample),
        ">= 100M/s")
    m = 2_000 if quick else 20_000
    P, N = sphere_grasps(rng, m, 2)
    row("spatial soft pairs, any normals (Thm 1)",
        best_rate(lambda: two_finger_closure(P[:, 0], N[:, 0], P[:, 1], N[:, 1], 0.5), m, 2),
        "pairs/s")

    # least friction of pairs: one pass against the six-value loop
    k = 1_000_000 if not quick else 100_000
    pairs = np.stack([p[:k], q[:k]], 1), np.stack([n_p[:k], n_q[:k]], 1)
    star = least_friction_batch(*pairs)
    six = graspnet_loop(p[:3000], n_p[:3000], q[:3000], n_q[:3000])
    vectorised = best_rate(lambda: [two_finger_closure(p[:k], n_p[:k], q[:k], n_q[:k], mu,
                                                       engine="reference")
                                    for mu in GRASPNET_FRICTION], k, 2)
    rate = best_rate(lambda: least_friction_batch(*pairs), k, 3)
    row("least friction of pairs, one pass", rate, "pairs/s", "six-value loop",
        per_item_rate(lambda i: graspnet_loop(p[i:i + 1], n_p[i:i + 1], q[i:i + 1],
                                              n_q[i:i + 1]), range(3000)), ">= 50x")
    row("", rate, "pairs/s", "six NumPy passes", vectorised)
    # the loop only brackets mu*: it lands on the first listed value above it
    above = np.array([min([m_ for m_ in GRASPNET_FRICTION if m_ > s], default=np.inf)
                      for s in star[:3000]])
    clear = np.abs(star[:3000, None] - np.array(GRASPNET_FRICTION)).min(1) > 1e-6
    print(f"  six-value loop = next listed value above our mu* on "
          f"{np.mean(six[clear] == above[clear]):.1%} of 3000 pairs")

    # three hard fingers in space, 8-edge pyramids, full Theorem 1 verdict
    n = 20_000 if quick else 300_000
    P, N = sphere_grasps(rng, n, 3)
    mu = np.full((n, 3), 0.5)
    ours = analyze_batch(P[:1000], N[:1000], mu=mu[:1000], cone=Cone(8))
    rate = best_rate(lambda: analyze_batch(P, N, mu=mu, cone=Cone(8)), n, 3)
    few = 50 if quick else 400
    W = [pyramid_wrenches(P[g], N[g], mu[g], 8) for g in range(few)]
    truth = ours.code[:few] == 2
    verdicts = {}
    for name, fn, target in (("linprog", linprog_closure, ">= 300x"),
                             ("Qhull (GraspIt!)", qhull_closure, None),
                             ("min-norm QP (Dex-Net)", min_norm_qp_closure, ">= 150x")):
        try:
            for w in W[:20]:  # warm (and the import, where it fails)
                fn(w)
            theirs = per_item_rate(fn, W)
        except ImportError:
            print(f"  ({name} skipped: install the bench extra)")
            continue
        verdicts[name] = np.array([fn(w) for w in W])
        row("3 hard fingers, 8-edge pyramids", rate, "grasps/s", name, theirs, target)
    for name, v in verdicts.items():
        print(f"  {name}: same closure verdict as ours on {np.mean(v == truth):.1%} of "
              f"{len(v)} grasps ({int(np.sum(v & ~truth))} closures we refute)")

    # epsilon of closed grasps: the wrench hull in the kernel against Qhull per grasp
    m = 2_000 if quick else 40_000
    eps = epsilon_batch(P[:4 * m], N[:4 * m], mu=mu[:4 * m])
    closed = np.flatnonzero(eps > 0)[:m]
    Pc, Nc, muc = P[closed], N[closed], mu[closed]
    rate = best_rate(lambda: epsilon_batch(Pc, Nc, mu=muc), len(closed), 3)
    arms = [Pc[g] - Pc[g].mean(0) for g in range(few)]
    W = [pyramid_wrenches(a, Nc[g], muc[g], 8) for g, a in enumerate(arms)]
    for w, a in zip(W, arms, strict=True):  # the kernel's frame: torques over the grasp's size
        w[3:] /= np.linalg.norm(a, axis=1).max()
    row("epsilon of closed grasps, 3 hard, 8-edge", rate, "grasps/s", "Qhull epsilon",
        per_item_rate(qhull_epsilon, W))
    theirs = np.array([qhull_epsilon(w) for w in W])
    print(f"  epsilon differs from Qhull's by at most "
          f"{np.abs(eps[closed[:few]] - theirs).max():.1e} on {few} grasps")

    # scaling
    m = 5_000 if quick else 40_000
    scaling = {"contacts": [], "edges": [], "batch": []}
    for k in (2, 3, 4, 5, 6, 8):
        P, N = sphere_grasps(rng, m, k)
        scaling["contacts"].append((k, 1e6 / best_rate(
            lambda P=P, N=N: analyze_batch(P, N, mu=0.5, cone=Cone(8)), m, 2)))
    P, N = sphere_grasps(rng, m, 3)
    for e in (4, 6, 8, 12, 16, 32):
        scaling["edges"].append((e, 1e6 / best_rate(
            lambda e=e: analyze_batch(P, N, mu=0.5, cone=Cone(e)), m, 2)))
    P, N = sphere_grasps(rng, 10 * m, 3)
    for b in (1, 10, 100, 1_000, 10_000, 10 * m):
        scaling["batch"].append((b, 1e6 / best_rate(
            lambda b=b: analyze_batch(P[:b], N[:b], mu=0.5, cone=Cone(8)), b, 3)))
    for what, points in scaling.items():
        print(f"  CPU µs per grasp by {what}: " + ", ".join(f"{x}: {y:.2f}" for x, y in points))

    # streaming
    n = 200_000 if quick else 10_000_000
    summary, size, peak = streaming(n, rng)
    print(f"streamed {summary['grasps']:,} grasps ({size:.2f} GiB .npz) through "
          f"`forceclosure analyze`: {summary['grasps_per_second']:,} grasps/s, "
          f"peak memory {peak:,.0f} MiB")

    table("batch", ["case", "batch engine (per CPU-s)", "baseline", "baseline (per CPU-s)",
                    "ratio", "target"],
          [[case, f"{ours:,.0f} {unit.removesuffix('/s')}", baseline or "",
            f"{theirs:,.0f}" if theirs else "", f"{ratio:,.0f}×" if ratio else "", target or ""]
           for case, ours, unit, baseline, theirs, ratio, target in rows])
    plot(rows, scaling, args.plot)
    print(f"plot: {args.plot}")


def plot(rows, scaling, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(14, 7.5))
    grid = fig.add_gridspec(2, 3, height_ratios=[1.1, 1])
    bars = [(f"{case or 'least friction of pairs, one pass'} vs {baseline}", ratio)
            for case, _, _, baseline, _, ratio, _ in rows if ratio]
    ax = fig.add_subplot(grid[0, :])
    ax.barh(range(len(bars)), [r for _, r in bars], color="#3a7")
    ax.set_yticks(range(len(bars)), [b for b, _ in bars], fontsize=8)
    for i, (_, r) in enumerate(bars):
        ax.text(r, i, f" {r:,.0f}x", va="center", fontsize=8)
    ax.set_xscale("log")
    ax.invert_yaxis()
    ax.set_xlabel("speed-up of the batch engine over the baseline, same run (log scale)")
    axes = [fig.add_subplot(grid[1, i]) for i in range(3)]
    for ax, (what, label) in zip(axes, (("contacts", "hard fingers per grasp"),
                                        ("edges", "pyramid edges per contact"),
                                        ("batch", "grasps per call")), strict=True):
        x, y = zip(*scaling[what], strict=True)
        ax.plot(x, y, "o-")
        ax.set_xlabel(label)
        ax.set_ylabel("CPU µs per grasp")
        ax.set_yscale("log")
        if what == "batch":
            ax.set_xscale("log")
        ax.grid(alpha=0.3, which="both")
    axes[0].annotate("2 hard fingers in space:\nrank 5 exactly, left to\nthe reference path",
                     scaling["contacts"][0], xytext=(3.2, scaling["contacts"][0][1] / 4),
                     fontsize=8, arrowprops={"arrowstyle": "->"})
    axes[0].set_title("8-edge pyramids", fontsize=9)
    axes[1].set_title("three hard fingers", fontsize=9)
    axes[2].set_title("three hard fingers, 8 edges", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)


if __name__ == "__main__":
    main()

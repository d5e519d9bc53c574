"""Wrong "closure" verdicts on the adversarial set, beside speed (issue 26).

    uv run --extra bench python benchmarks/bench_adversarial.py [--seed 0] [--copies 21] [--check]

Runs every test on the cases of :mod:`adversarial` (798 by default: grasps on the friction
cone's edge, just inside and outside it, rank-deficient, scaled by 2**-13..2**10 and moved by
up to 9e8, each exactly the constructed grasp in floating point, so its truth is known) and
counts, per test, its **wrong closures** (``closure`` where the truth is not) split by what
the truth is, its **missed closures** (not ``closure`` where the truth is; ours may say
``marginal`` near the edge, which counts here as missed), and its speed in cases per
CPU-second (``time.process_time``, every thread), with wall time and the load average.
``--check`` first verifies every case's truth exactly in rationals (``tests/exact.py``).

The baselines, re-implemented from their papers and documentation, get their wrenches built
once, untimed: the contacts' torques about their centroid per their largest distance from it,
spatial friction cones as an inscribed 8-edge pyramid, soft fingers with the two pure torques
about the normal, planar cones exact.

* **Dex-Net pair**: Dex-Net's ``force_closure`` for two contacts, one pair at a time: each
  inward normal within ``atan(mu)`` of the line to the other contact, the projection taken in
  absolute value (its default ``use_abs_value=True``), ``alpha > atan(mu)`` rejecting.
* **GraspNet pair**: GraspNet-1Billion's antipodal angle test vectorised over all pairs, in
  its own arccos form (:func:`graspnet_passes`: both on the right side, ``<= atan(mu)``
  passing; ``bench_gripper.graspnet_labels`` compares cosines instead, which is faster and
  gives the same labels at GraspNet's ten μ values away from the cone's edge, but on the
  edge it is the arccos rounding that a GraspNet user gets).
* **Dex-Net QP**: Dex-Net's ``force_closure_qp``: the point of the wrenches' convex hull
  nearest the origin by a ``cvxopt`` QP, closure when its norm is below 1e-3.
* **GraspIt!-style hull**: Qhull's hull of the wrenches (scipy's default options), closure
  when the origin is strictly inside every facet (all offsets < 0); Qhull refusing a flat
  set is "not closure".
* **Qhull QJ**: the same with joggled input (``QJ``), which never refuses a flat set.

Ours: :func:`forceclosure.analyze` one case at a time (exact cones), ``analyze_batch`` on
the cases of one shape at once, and ``two_finger_closure`` on the pairs (Corollary 3).
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from collections import defaultdict
from collections.abc import Callable
from pathlib import Path

import numpy as np
from scipy.spatial import ConvexHull, QhullError

sys.path.insert(0, str(Path(__file__).parent))
from adversarial import BASES, TRUTHS, Case, adversarial_set
from bench_batch import min_norm_qp_closure, qhull_closure

from forceclosure import analyze, point_contact
from forceclosure.analysis.batch import analyze_batch
from forceclosure.analysis.two_finger import two_finger_closure


def tool_wrenches(case: Case, edges: int = 8) -> np.ndarray:
    """The case's wrenches as the baselines build them, ``(3 or 6, m)``."""
    P, N, mu = case.arrays()
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    ref = P.mean(axis=0)
    scale = max(np.linalg.norm(P - ref, axis=1).max(), 1e-300)
    cols = []
    for p, n in zip(P - ref, N, strict=True):
        if case.dim == 2:
            t = np.array([-n[1], n[0]])
            forces = [-n + mu * t, -n - mu * t] if mu else [-n]
            cols += [[*f, (p[0] * f[1] - p[1] * f[0]) / scale] for f in forces]
            continue
        forces = [-n]
        if mu:
            t1 = np.cross(n, np.eye(3)[np.argmin(np.abs(n))])
            t1 /= np.linalg.norm(t1)
            t2 = np.cross(n, t1)
            a = 2 * np.pi * np.arange(edges) / edges
            forces = -n + mu * (np.cos(a)[:, None] * t1 + np.sin(a)[:, None] * t2)
        cols += [[*f, *(np.cross(p, f) / scale)] for f in forces]
        if case.model == "soft":
            cols += [[0, 0, 0, *n], [0, 0, 0, *-n]]
    return np.array(cols, dtype=float).T


def dexnet_pair(case: Case, use_abs_value: bool = True) -> bool:
    """Dex-Net's ``force_closure`` of a pair (its default takes the projection's absolute
    value, for meshes whose normals are not oriented)."""
    (p1, p2), (n1, n2), mu = case.arrays()
    if np.array_equal(p1, p2):
        return False
    for inward, here, there in ((-n1, p1, p2), (-n2, p2, p1)):
        diff = there - here
        proj = inward @ diff / np.linalg.norm(inward)
        if use_abs_value:
            proj = abs(proj)
        if proj < 0:
            return False
        if np.arccos(proj / np.linalg.norm(diff)) > np.arctan(mu):
            return False
    return True


def qhull_joggle_closure(W: np.ndarray) -> bool:
    """Qhull with joggled input (``QJ``): the origin strictly inside every facet."""
    try:
        hull = ConvexHull(W.T, qhull_options="QJ")
    except QhullError:  # fewer points than a simplex needs
        return False
    return bool(np.all(hull.equations[:, -1] < 0))


def _by_shape(cases: list[Case]) -> dict[tuple, list[int]]:
    groups = defaultdict(list)
    for i, c in enumerate(cases):
        groups[(c.dim, len(c.points), c.model)].append(i)
    return groups


def ours_analyze(cases: list[Case]) -> np.ndarray:
    return np.array([analyze([point_contact(p, n, c.model, m) for p, n in zip(P, N, strict=True)])
                     .force_closure for c in cases for P, N, m in [c.arrays()]])


def ours_batch(cases: list[Case]) -> np.ndarray:
    out = np.zeros(len(cases), dtype=bool)
    for (_, _, model), idx in _by_shape(cases).items():
        P, N, mu = (np.array(v) for v in zip(*(cases[i].arrays() for i in idx), strict=True))
        out[idx] = analyze_batch(P, N, mu=mu[:, None], model=model).force_closure
    return out


def ours_pairs(cases: list[Case]) -> np.ndarray:
    out = np.zeros(len(cases), dtype=bool)
    for (d, _, model), idx in _by_shape(cases).items():
        P, N, mu = (np.array(v) for v in zip(*(cases[i].arrays() for i in idx), strict=True))
        r = two_finger_closure(P[:, 0], N[:, 0], P[:, 1], N[:, 1], mu,
                               model="soft" if model == "soft" and d == 3 else "hard")
        out[idx] = np.asarray(r.verdict) == "closure"
    return out


def graspnet_pairs(cases: list[Case]) -> np.ndarray:
    out = np.zeros(len(cases), dtype=bool)
    mus = np.array([c.mu for c in cases], dtype=float)
    for d in (2, 3):
        for mu in np.unique(mus):
            idx = [i for i, c in enumerate(cases) if c.dim == d and mus[i] == mu]
            if idx:
                P, N = (np.array(v) for v in zip(*(cases[i].arrays()[:2] for i in idx),
                                                   strict=True))
                out[idx] = graspnet_passes(P, N, mu)
    return out


def graspnet_passes(P: np.ndarray, N: np.ndarray, mu: float) -> np.ndarray:
    """GraspNet's antipodal test of ``(n, 2, d)`` contact pairs at friction ``mu``, as its
    loop writes it, vectorised: each inward normal's angle to the line to the other contact
    (``arccos`` of the normalised projection) at most ``atan(mu)``, both projections
    positive."""
    d = P[:, 1] - P[:, 0]
    length = np.linalg.norm(d, axis=1)
    proj_1 = -np.einsum("ij,ij->i", N[:, 0], d) / np.linalg.norm(N[:, 0], axis=1)
    proj_2 = np.einsum("ij,ij->i", N[:, 1], d) / np.linalg.norm(N[:, 1], axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        a1 = np.arccos(np.clip(proj_1 / length, -1, 1))
        a2 = np.arccos(np.clip(proj_2 / length, -1, 1))
    worst = np.where((proj_1 < 0) | (proj_2 < 0) | (length == 0), np.inf, np.maximum(a1, a2))
    return worst <= np.arctan(mu)


def on_wrenches(test: Callable[[np.ndarray], bool], wrenches: dict[int, np.ndarray]):
    """``test`` run case by case on the wrenches built beforehand (by ``id`` of the case)."""
    return lambda cases: np.array([test(wrenches[id(c)]) for c in cases], dtype=bool)


def by_family(cases: list[Case], verdicts: dict[str, np.ndarray]) -> None:
    """Per base case (all its placements): each baseline's wrong closures, or, where the
    truth is closure, ours' missed ones (``marginal`` near the edge or far out)."""
    names = list(verdicts)
    print("| family | truth | mu | " + " | ".join(n.split(" (")[0] for n in names) + " |")
    print("|---|---|---|" + "---|" * len(names))
    base = np.arange(len(cases)) % len(BASES)
    for b, case in enumerate(BASES):
        cells = []
        for n in names:
            said = verdicts[n][base == b]
            said = said[said >= 0]
            cells.append("" if not len(said) else str(int((said == int(not case.closure)).sum())))
        print(f"| {case.family} | {case.truth} | {case.mu} | " + " | ".join(cells) + " |")
    print("\n(cells: cases of the family, out of its placements, where the test says closure"
          " and the truth is not, or the truth is closure and it does not say so; blank: the"
          " test does not apply)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--copies", type=int, default=21, help="placements of each base case")
    parser.add_argument("--check", action="store_true",
                        help="first verify every truth exactly in rationals (tests/exact.py)")
    args = parser.parse_args()
    cases = adversarial_set(args.seed, args.copies)
    if args.check:
        sys.path.insert(0, str(Path(__file__).parents[1] / "tests"))
        from test_adversarial import check_truth

        cpu = time.process_time()
        for c in cases:
            check_truth(c)
        print(f"every truth checked exactly in rationals ({time.process_time() - cpu:.1f} CPU-s)")
    truth = np.array([c.truth for c in cases])
    pairs = np.array([len(c.points) == 2 for c in cases])
    wrenches = {id(c): tool_wrenches(c) for c in cases}
    rows = [
        ("ours: `analyze` (one at a time)", None, ours_analyze),
        ("ours: `analyze_batch`", None, ours_batch),
        ("ours: `two_finger_closure`", pairs, ours_pairs),
        ("Dex-Net pair angle test", pairs, lambda cs: np.array([dexnet_pair(c) for c in cs])),
        ("GraspNet pair angle test (vectorised)", pairs, graspnet_pairs),
        ("Dex-Net QP (min-norm < 1e-3)", None, on_wrenches(min_norm_qp_closure, wrenches)),
        ("GraspIt!-style Qhull hull", None, on_wrenches(qhull_closure, wrenches)),
        ("Qhull with joggle (QJ)", None, on_wrenches(qhull_joggle_closure, wrenches)),
    ]
    ours_wrong, verdicts = [], {}
    load = os.getloadavg()
    print(f"{len(cases)} adversarial cases (seed {args.seed}, "
          + ", ".join(f"{(truth == t).sum()} {t}" for t in TRUTHS) + "), "
          f"{pairs.sum()} of them pairs; load average {load[0]:.1f}, {os.cpu_count()} CPUs\n")
    print("| test | cases | wrong closures | on the edge | rank-deficient | outside "
          "| missed closures | cases per CPU-s | wall s |")
    print("|---|---|---|---|---|---|---|---|---|")
    for name, mask, fn in rows:
        idx = np.flatnonzero(np.ones(len(cases), bool) if mask is None else mask)
        sub = [cases[i] for i in idx]
        fn(sub[:len(sub) // 20 or 1])  # warm: kernels loaded, imports done
        wall, cpu = time.perf_counter(), time.process_time()
        said = fn(sub)
        wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
        verdicts[name] = np.full(len(cases), -1)
        verdicts[name][idx] = said
        t = truth[idx]
        wrong = said & (t != "closure")
        missed = ~said & (t == "closure")
        if name.startswith("ours"):
            ours_wrong += [(name, sub[i]) for i in np.flatnonzero(wrong)]
        print(f"| {name} | {len(sub)} | **{wrong.sum()}** | {(wrong & (t == 'boundary')).sum()} "
              f"| {(wrong & (t == 'rank-deficient')).sum()} | {(wrong & (t == 'outside')).sum()} "
              f"| {missed.sum()} | {len(sub) / max(cpu, 1e-9):,.0f} | {wall:.2f} |")
    print(f"\nload average after: {os.getloadavg()[0]:.1f}\n")
    by_family(cases, verdicts)
    for name, case in ours_wrong:
        print(f"WRONG CLOSURE OF OURS ({name}): {case}")
    sys.exit(1 if ours_wrong else 0)


if __name__ == "__main__":
    main()

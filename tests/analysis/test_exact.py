"""Theorem 1 against an exact rational check (tests/exact.py).

Rules: a ``closure`` verdict is always exactly right; a ``none`` verdict is
always exactly right; and whenever the margin and singular-value ratio are
clearly away from zero the verdict matches the exact answer.
"""

import random
from fractions import Fraction

import numpy as np
import pytest

from exact import (
    planar_hard_wrenches,
    positively_spans,
    spatial_pyramid4_wrenches,
    to_fractions,
)
from forceclosure import Cone, Verdict, analyze, point_contact, vector_closure

CLEAR = 1e-3


def assert_agrees(a, exact):
    """A grasp analysis against the exact answer: closure and none always right,
    and every verdict right when the margins are clear."""
    if a.verdict is Verdict.CLOSURE:
        assert exact
    if a.verdict is Verdict.NONE:
        assert not exact
    if a.margin is not None and abs(a.margin) > CLEAR and a.sigma_ratio > CLEAR:
        assert a.force_closure == exact


def check_against_exact(columns_fraction, W_float):
    exact = positively_spans(columns_fraction)
    r = vector_closure(W_float)
    if r.verdict is Verdict.CLOSURE:
        assert exact, "closure verdict on a set that is not exactly force-closure"
        assert r.weights is not None and np.all(r.weights > 0)
        assert np.linalg.norm(W_float @ r.weights) < 1e-9
    if r.verdict is Verdict.NONE:
        assert not exact, "none verdict on a set that is exactly force-closure"
        assert r.twist is not None
        # the certificate: no column does negative work on the twist
        U = W_float / np.linalg.norm(W_float, axis=0)
        assert np.min(U.T @ r.twist) > -1e-9
    clear = r.margin is not None and abs(r.margin) > CLEAR and r.sigma_ratio > CLEAR
    if clear or r.rank < W_float.shape[0]:
        assert (r.verdict is Verdict.CLOSURE) == exact
    return exact, r


def _random_set(rng, d, m, closed):
    cols = [[rng.randint(-3, 3) for _ in range(d)] for _ in range(m - 1)]
    if closed:  # append minus a strictly positive combination: a zero combination exists
        weights = [rng.randint(1, 3) for _ in range(m - 1)]
        cols.append([-sum(w * c[i] for w, c in zip(weights, cols, strict=True))
                     for i in range(d)])
    else:
        cols.append([rng.randint(-3, 3) for _ in range(d)])
    return [c for c in cols if any(c)] or [[1] + [0] * (d - 1)]


@pytest.mark.parametrize("d,m", [(2, 3), (2, 4), (3, 4), (3, 5), (3, 6), (6, 7), (6, 8)])
def test_random_integer_sets(d, m):
    rng = random.Random(1000 * d + m)
    counts = {True: 0, False: 0}
    for trial in range(40 if d < 6 else 12):
        cols = _random_set(rng, d, m, closed=trial % 2 == 0)
        exact, _ = check_against_exact(to_fractions(cols), np.array(cols, dtype=float).T)
        counts[exact] += 1
    assert counts[True] > 0 and counts[False] > 0  # both answers exercised


def test_rank_deficient_sets_are_none():
    # A strictly positive zero combination exists, but all columns lie in z = 0.
    cols = [[1, 0, 0], [0, 1, 0], [-1, -1, 0], [2, -1, 0]]
    exact, r = check_against_exact(to_fractions(cols), np.array(cols, float).T)
    assert not exact and r.verdict is Verdict.NONE and r.rank == 2


def test_boundary_set_is_never_closure():
    # +-x and +-y positively span the plane z = 0; the rest have z > 0, so any
    # zero combination gives them weight 0: not force-closure, on the boundary.
    cols = [[1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [1, 1, 1]]
    exact, r = check_against_exact(to_fractions(cols), np.array(cols, float).T)
    assert not exact
    assert r.verdict is not Verdict.CLOSURE
    assert r.rank == 3


def test_exact_boundary_two_finger_grasp():
    # tan(angle of PQ) = 3/10 = mu exactly: on the boundary of Corollary 3.
    pts, nrm, mu = [(-1, 0), (1, "3/5")], [(-1, 0), (1, 0)], ["3/10", "3/10"]
    exact = positively_spans(planar_hard_wrenches(pts, nrm, mu))
    grasp = [point_contact([-1, 0], [-1, 0], "hard", 0.3),
             point_contact([1, 0.6], [1, 0], "hard", 0.3)]
    assert not exact
    assert analyze(grasp).verdict is Verdict.MARGINAL


def _rational_planar_grasp(rng, k):
    units = [(1, 0), (-1, 0), (0, 1), (0, -1), ("3/5", "4/5"), ("-4/5", "3/5"),
             ("-3/5", "-4/5"), ("4/5", "-3/5")]
    pts = [(rng.randint(-4, 4) / 2, rng.randint(-4, 4) / 2) for _ in range(k)]
    nrm = [rng.choice(units) for _ in range(k)]
    mu = [rng.choice(["0", "1/4", "1/2", "1"]) for _ in range(k)]
    return pts, nrm, mu


def test_planar_contact_grasps_match_exact_wrenches():
    rng = random.Random(7)
    seen = set()
    for _ in range(60):
        k = rng.randint(2, 4)
        pts, nrm, mu = _rational_planar_grasp(rng, k)
        grasp = [point_contact(p, [float(Fraction(c)) for c in n], "hard", float(Fraction(m)))
                 for p, n, m in zip(pts, nrm, mu, strict=True)]
        a = analyze(grasp)
        assert_agrees(a, positively_spans(planar_hard_wrenches(pts, nrm, mu)))
        seen.add(a.verdict)
    assert {Verdict.CLOSURE, Verdict.NONE} <= seen


def test_spatial_contact_grasps_match_exact_wrenches():
    rng = random.Random(11)
    axes = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    seen = set()
    for _ in range(14):
        k = rng.randint(2, 3)
        nrm = [rng.choice(axes) for _ in range(k)]
        pts = [tuple(n[i] if n[i] else rng.randint(-2, 2) / 2 for i in range(3)) for n in nrm]
        mu = [rng.choice(["1/4", "1/2", "1"]) for _ in range(k)]
        grasp = [point_contact(p, n, "hard", float(Fraction(m)))
                 for p, n, m in zip(pts, nrm, mu, strict=True)]
        a = analyze(grasp, cone=Cone(4, "inscribed"))
        assert_agrees(a, positively_spans(spatial_pyramid4_wrenches(pts, nrm, mu)))
        seen.add(a.verdict)
    assert Verdict.NONE in seen

"""Issue 26's adversarial set (``benchmarks/adversarial.py``): its truths are right, checked
exactly in rationals on every case of a seed, and ours never says ``closure`` where the truth
is not, while the set does fool at least one of the baselines."""

import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest

from exact import (
    in_cone,
    planar_hard_wrenches,
    positively_spans,
    rank,
    spatial_pyramid4_wrenches,
    spatial_square_pyramid_wrenches,
)

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
from adversarial import BASES, TRUTHS, adversarial_set
from bench_adversarial import (
    dexnet_pair,
    graspnet_pairs,
    ours_analyze,
    ours_batch,
    ours_pairs,
    qhull_joggle_closure,
    tool_wrenches,
)

CASES = adversarial_set(seed=3, copies=2)


def exact_brackets(case):
    """(inscribed closed, circumscribed closed, rank, circumscribed wrenches) of the floats a
    tool receives, in rationals: the planar cones are exact, so there both are the cone."""
    P, N, mu = case.arrays()
    P = [[Fraction(x) for x in p] for p in P]
    N = [[Fraction(x) for x in n] for n in N]
    mus = [Fraction(mu)] * len(P)
    if case.dim == 2:
        inner = outer = planar_hard_wrenches(P, N, mus)
    else:
        inner, outer = (spatial_square_pyramid_wrenches(P, N, mus, case.model, circumscribed=c)
                        for c in (False, True))
    return positively_spans(inner), positively_spans(outer), rank(outer), outer


def test_square_pyramids_of_an_axis_and_of_a_3_4_5_normal():
    """The inscribed pyramid of an axis normal is the 4-edge one of tests/exact.py; a 3-4-5
    normal's edges make the same angle with it, on the circle (inscribed) or its tangent
    square (circumscribed)."""
    p, n = [[1, 2, 3]], [[0, 0, -1]]
    inner = spatial_square_pyramid_wrenches(p, n, [Fraction(3, 4)])
    assert sorted(map(tuple, inner)) == sorted(map(tuple, spatial_pyramid4_wrenches(
        p, n, [Fraction(3, 4)])))
    for circumscribed, reach in ((False, 1), (True, 2)):
        for w in spatial_square_pyramid_wrenches([[0, 0, 0]], [[3, 4, 0]], [Fraction(1, 2)],
                                                 circumscribed=circumscribed):
            f = w[:3]
            along = -(3 * f[0] + 4 * f[1]) / 5  # the force's part along -n, and across it:
            across2 = sum(x * x for x in f) - along * along
            assert along == 5 and across2 == reach * (Fraction(1, 2) * 5) ** 2


def test_every_truth_is_used_and_the_floats_are_the_exact_grasp():
    assert {c.truth for c in CASES} == set(TRUTHS)
    assert len(CASES) == 2 * len(BASES)
    moved = CASES[len(BASES):]
    # the placed copies are scaled and moved far: not the bases again
    assert sum(max(abs(x) for p in c.points for x in p) > 1000 for c in moved) > len(moved) // 2
    for c in CASES:
        P, _, mu = c.arrays()
        assert [[Fraction(x) for x in p] for p in P] == [list(p) for p in c.points]
        assert Fraction(mu) == c.mu


def line_side(case) -> int:
    """A pair's line against its friction cones, exactly: -1 strictly inside both, 0 inside
    both and on the edge of one, 1 outside one (or leaving a finger on the wrong side)."""
    P, N, _ = case.arrays()
    (p, q), (n_p, n_q) = ([[Fraction(x) for x in v] for v in a] for a in (P, N))
    sides = []
    for here, there, n in ((p, q, n_p), (q, p, n_q)):
        d = [b - a for a, b in zip(here, there, strict=True)]
        along = -sum(x * y for x, y in zip(n, d, strict=True))  # |n| |d| cos
        if along <= 0:
            return 1
        tan2 = (sum(x * x for x in d) * sum(x * x for x in n) - along**2) / along**2
        sides.append((tan2 > case.mu**2) - (tan2 < case.mu**2))
    return max(sides)


def check_truth(case) -> None:
    """Assert the case's truth exactly (also run by ``bench_adversarial.py --check``)."""
    inner, outer, r, W = exact_brackets(case)
    full = 3 if case.dim == 2 else 6
    assert outer or not inner, case  # the circumscribed pyramid contains the inscribed one
    if case.truth == "closure":
        assert inner, case
    else:
        assert not outer, case
        assert (r < full) == (case.truth == "rank-deficient"), case
    if case.truth in ("boundary", "outside"):
        if len(case.points) == 2:
            assert line_side(case) == (0 if case.truth == "boundary" else 1), case
        if case.dim == 2 or len(case.points) > 2:
            # on the edge: a non-trivial equilibrium (some -w_j in the cone), outside: none
            # (a soft pair always has one, its two torques about the normals)
            equilibrium = any(in_cone(W, [-x for x in w]) for w in W)
            assert equilibrium == (case.truth == "boundary"), case


@pytest.mark.parametrize("case", CASES, ids=lambda c: f"{c.family} ({c.truth})")
def test_truth_checked_exactly(case):
    check_truth(case)


def _clear(case) -> bool:
    """Closed, and not within about 2**-20 of the boundary (where ``marginal`` is right)."""
    return case.closure and not any(w in case.family for w in ("just", "barely", "2^-20"))


def test_ours_never_says_closure_where_the_truth_is_not():
    pairs = [c for c in CASES if len(c.points) == 2]
    for cases, said in ((CASES, ours_analyze(CASES)), (CASES, ours_batch(CASES)),
                        (pairs, ours_pairs(pairs))):
        truth = np.array([c.closure for c in cases])
        clear = np.array([_clear(c) for c in cases])
        assert not np.any(said & ~truth)
        # and not by never saying closure: every clearly closed grasp, scaled and moved too
        assert clear.sum() >= 4 and said[clear].all()


def test_the_set_is_adversarial():
    """The baselines are fooled on it: each pair test by the frictionless antipodal pair
    (and more), the joggled hull by a flat wrench set."""
    truth = np.array([c.closure for c in CASES])
    pairs = [c for c in CASES if len(c.points) == 2]
    pair_truth = np.array([c.closure for c in pairs])
    dexnet = np.array([dexnet_pair(c) for c in pairs])
    graspnet = graspnet_pairs(pairs)
    joggled = np.array([qhull_joggle_closure(tool_wrenches(c)) for c in CASES])
    for said, true in ((dexnet, pair_truth), (graspnet, pair_truth), (joggled, truth)):
        assert np.any(said & ~true)
    frictionless = [c for c in pairs if c.family == "planar pair, frictionless, antipodal"]
    assert frictionless and all(dexnet_pair(c) for c in frictionless)

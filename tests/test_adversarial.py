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
    """(inscribed closed, circumscribed closed, rank) of the floats a tool receives, in
    rationals: the planar cones are exact, so there both pyramids are the cone itself."""
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


def check_truth(case) -> None:
    """Assert the case's truth exactly (also run by ``bench_adversarial.py --check``)."""
    inner, outer, r, W = exact_brackets(case)
    full = 3 if case.dim == 2 else 6
    if case.truth == "closure":
        assert inner, case
    else:
        assert not outer, case
        assert (r < full) == (case.truth == "rank-deficient"), case
    if case.dim == 2 and case.truth in ("boundary", "outside"):
        # on the edge: some non-trivial equilibrium (a -w_j in the cone), outside: none
        assert any(in_cone(W, [-x for x in w]) for w in W) == (case.truth == "boundary"), case


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

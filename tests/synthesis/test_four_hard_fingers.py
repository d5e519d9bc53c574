"""Four hard fingers on a polygon (issue 25: the hand was refused): two pairs that each hold
the object alone. Checked independently: Corollary 3 in exact rationals for each pair on
sampled points (written here), Theorem 1 (the library's general analysis) on the four, and
a brute force over every quadruple and pairing of the two-finger search's regions."""

import itertools
from fractions import Fraction

import numpy as np
import pytest

from forceclosure import Verdict, analyze, point_contact
from forceclosure.app.cli import main
from forceclosure.objects import bundled
from forceclosure.synthesis import maximal_regions, synthesize


def _strictly_in_cone(inward, mu, w):
    """``w`` strictly inside the cone of half-angle atan(mu) about ``inward`` (exact)."""
    dot = inward[0] * w[0] + inward[1] * w[1]
    cross = inward[0] * w[1] - inward[1] * w[0]
    return dot > 0 and mu * mu * dot * dot > cross * cross


def _pair_closure(e1, p, e2, q, mu, spreading):
    """Corollary 3 exactly: squeezing, q - p inside the cone at p and p - q at q; pushing
    apart, the other way round."""
    F = Fraction
    n1 = [F(-float(e1.normal[0])), F(-float(e1.normal[1]))]
    n2 = [F(-float(e2.normal[0])), F(-float(e2.normal[1]))]
    w = [F(float(q[0])) - F(float(p[0])), F(float(q[1])) - F(float(p[1]))]
    if spreading:
        w = [-w[0], -w[1]]
    return _strictly_in_cone(n1, mu, w) and _strictly_in_cone(n2, mu, [-w[0], -w[1]])


@pytest.mark.parametrize("name", ["square", "hexagon", "l-shape", "frame", "star"])
def test_four_hard_fingers_hold_by_two_exact_pairs_and_theorem_1(name):
    obj = bundled(name)
    mu = 0.4
    s = synthesize(obj, 4, "hard", mu, top=3)
    assert s.found, name
    rng = np.random.default_rng(3)
    for r in s.found:
        assert r.certify().holds and len(set(r.edges)) == 4
        where = dict(zip(r.edges, r.segments, strict=True))
        for _ in range(30):
            t = {e: rng.uniform(*where[e]) for e in r.edges}
            pts = {e: obj.edges[e].point(t[e]) for e in r.edges}
            for (a, b), spreading in zip(r.pairs, r.spreading, strict=True):
                assert _pair_closure(obj.edges[a], pts[a], obj.edges[b], pts[b],
                                     Fraction(mu), spreading), (name, r.edges)
            grasp = [point_contact(pts[e], obj.edges[e].normal, "hard", mu) for e in r.edges]
            assert analyze(grasp).verdict is Verdict.CLOSURE


@pytest.mark.parametrize("name", ["hexagon", "l-shape", "wrench-head"])
def test_four_hard_fingers_best_is_the_brute_force_over_pairings(name):
    """The best quadruple's shorter segment is the largest, over every four edges and
    pairing, of the smaller of its two pairs' maximal two-finger regions."""
    obj = bundled(name)
    mu, n = 0.4, len(obj.edges)
    pair = {}
    for i, j in itertools.combinations(range(n), 2):
        r = maximal_regions(obj, i, j, mu)
        pair[i, j] = r.min_length if r is not None else 0.0
    brute = 0.0
    for quad in itertools.combinations(range(n), 4):
        for (p, q), (u, v) in (((0, 1), (2, 3)), ((0, 2), (1, 3)), ((0, 3), (1, 2))):
            brute = max(brute, min(pair[quad[p], quad[q]], pair[quad[u], quad[v]]))
    best = synthesize(obj, 4, "hard", mu, top=1).found
    if brute == 0:
        assert not best
    else:
        assert best[0].min_length == pytest.approx(brute, rel=1e-6)


def test_the_cli_serves_four_hard_fingers(capsys):
    assert main(["synthesize", "square", "--fingers", "4", "--contact", "hard", "--mu", "0.4",
                 "--top", "1"]) == 0
    out = capsys.readouterr().out
    assert "edges 0 + 2 and edges 1 + 3 each hold the object alone" in out
    assert main(["synthesize", "square", "--fingers", "1", "--contact", "hard"]) == 2
    assert "at least 2 hard fingers" in capsys.readouterr().err


def test_three_fingers_say_whether_the_third_finger_is_idle():
    """On the L a pair of opposite edges holds alone (the third finger idle: its segment is
    its whole edge, and the pair alone passes Corollary 3 exactly); on the triangle no two
    edges face each other closely enough at mu 0.5 (the cones are 26.6 degrees, the normals
    120 apart), so all three bear load."""
    for r in synthesize(bundled("l-shape"), 3, "hard", 0.5, top=3).found:
        assert r.pair is not None
        (a, b), free = r.pair, next(e for e in r.edges if e not in r.pair)
        assert f"the finger on edge {free} is idle" in r.notes()[0]
        assert r.segments[r.edges.index(free)] == (0.0, bundled("l-shape").edges[free].length)
        obj = bundled("l-shape")
        where = dict(zip(r.edges, r.segments, strict=True))
        for ta in where[a]:
            for tb in where[b]:
                assert _pair_closure(obj.edges[a], obj.edges[a].point(ta), obj.edges[b],
                                     obj.edges[b].point(tb), Fraction(1, 2), r.spreading)
    [r] = synthesize(bundled("triangle"), 3, "hard", 0.5, top=1).found
    assert r.pair is None and "all three fingers bear load" in r.notes()[0]

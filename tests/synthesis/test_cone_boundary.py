"""The two-finger search is complete on the boundary of the friction cones (issue 25).

Polygons built so that the best pairs of segments end exactly on a cone's boundary (parallel
edges as far apart as their overlap, mu = 1: the line between the segments' ends at 45
degrees), at tiny margins. The reference is a linear program written here, independently of
the library: for every pair of edges and both orientations, the largest ``z`` such that
segments ``[u1, u1 + z]`` and ``[u2, u2 + z]`` have every corner pair strictly inside both
narrowed cones (scipy's HiGHS). The search must return the reference's best pair first, and
the full ranking must be the reference's.
"""

import itertools
import math

import numpy as np
import pytest
from scipy.optimize import linprog

from forceclosure.objects import Polygon
from forceclosure.synthesis import synthesize

NOTCH = [[0, 0], [4, 0], [4, 1], [2.5, 1], [2.5, 1.0000015], [1.5, 1.5], [0, 1.5]]
POLYGONS = {
    "notch": NOTCH,
    # bottom and top 1.5 apart and 1.5 long, overlapping exactly: at mu = 1 the diagonal
    # between their far ends is the cone's boundary
    "square-gap": [[0, 0], [1.5, 0], [1.5, 1.5], [0, 1.5]],
    # the slanted sides are at 45 degrees: parallel to the cone's boundary
    "parallelogram": [[0, 0], [2, 0], [3, 1], [1, 1]],
    # a slot 1 wide and 1 deep: the fingers push its walls apart, on the boundary at mu = 1
    "slot": [[0, 0], [3, 0], [3, 2], [2, 2], [2, 1], [1, 1], [1, 2], [0, 2]],
}


def _reference(points, mu, margin):
    """``{(i, j, spreading): z}``: the largest equal segments on every pair (an LP per pair)."""
    pts = np.asarray(points, float)
    n = len(pts)
    # counter-clockwise outline (the polygons above are), inward normal = left of the edge
    starts, ends = pts, np.roll(pts, -1, axis=0)
    dirs = ends - starts
    lengths = np.hypot(dirs[:, 0], dirs[:, 1])
    dirs = dirs / lengths[:, None]
    inward = np.stack([-dirs[:, 1], dirs[:, 0]], axis=1)
    k = math.tan(math.atan(mu) - margin)
    out = {}
    for i in range(n):
        for j in range(i + 1, n):
            for spreading in (False, True):
                sign = -1.0 if spreading else 1.0
                rows, rhs = [], []
                # corner (a, b): p = s_i + (u1 + a z) d_i, q = s_j + (u2 + b z) d_j;
                # w = sign (q - p) = w0 + W @ (u1, u2, z)
                for a in (0, 1):
                    for b in (0, 1):
                        w0 = sign * (starts[j] - starts[i])
                        W = sign * np.stack([-dirs[i], dirs[j], b * dirs[j] - a * dirs[i]],
                                            axis=1)  # (2, 3)
                        for m, s in ((inward[i], 1.0), (inward[j], -1.0)):
                            # s w inside the cone about m: k (m . s w) -+ cross(m, s w) >= 0
                            perp = np.array([-m[1], m[0]])  # cross(m, v) = perp . v
                            for t in (1.0, -1.0):
                                ell = s * (k * m - t * perp)
                                rows.append(-(ell @ W))
                                rhs.append(ell @ w0)
                for col, L in ((0, lengths[i]), (1, lengths[j])):
                    row = np.zeros(3)
                    row[col], row[2] = 1.0, 1.0
                    rows.append(row)
                    rhs.append(L)
                res = linprog([0, 0, -1], A_ub=np.array(rows), b_ub=np.array(rhs),
                              bounds=[(0, None)] * 3, method="highs")
                if res.status == 0:
                    out[(i, j, spreading)] = float(res.x[2])
    return out


@pytest.mark.parametrize("margin", [1e-9, 1e-13, 1e-3])
@pytest.mark.parametrize("name", list(POLYGONS))
def test_top_and_ranking_match_a_reference_lp(name, margin):
    points = POLYGONS[name]
    polygon = Polygon.from_points(points, name=name)
    assert len(polygon.edges) == len(points)
    size = polygon.size
    ref = _reference(points, 1.0, margin)
    real = {key: z for key, z in ref.items() if z > 1e-6 * size}
    found = synthesize(polygon, 2, "hard", 1.0, top=100, margin=margin).found
    got = {(*r.edges, r.spreading): r.min_length for r in found}
    assert all(r.certify().holds for r in found)
    # every pair with regions is found, as large as the reference's (to the cuts that
    # rounding needs) and never larger
    assert set(real) <= set(got), set(real) - set(got)
    for key, z in got.items():
        assert key in ref
        assert z <= ref[key] + 1e-9 * size
        assert z >= ref[key] - 1e-7 * size, (key, z, ref[key])
    # the best first, and the ranking the reference's (equal sizes in any order)
    best = max(real.values())
    assert found[0].min_length >= best - 1e-7 * size
    assert (*found[0].edges, found[0].spreading) in {k for k, z in real.items()
                                                     if z >= best - 1e-7 * size}
    sizes = [r.min_length for r in found]
    assert all(a >= b - 1e-7 * size for a, b in itertools.pairwise(sizes))


def _tangential(n, turn):
    """A polygon of ``n`` (a multiple of 4) sides tangent to the unit circle, the angles
    between its points of contact ``2 pi / n`` less, less, more, more ``turn``, in turn:
    opposite sides parallel and 2 apart, sides of three lengths (``turn`` 0: regular)."""
    gaps = 2 * np.pi / n + turn * np.resize([-1.0, -1.0, 1.0, 1.0], n)
    phi = np.r_[0.0, np.cumsum(gaps)[:-1]]
    a, b = phi, np.roll(phi, -1)  # the corner between the tangents at a and b
    r = 1 / np.cos((b - a) / 2)
    return np.c_[r * np.cos((a + b) / 2), r * np.sin((a + b) / 2)]


@pytest.mark.parametrize("n,turn,grow,mu,top", [
    (24, 0.0, 0.0, 0.3, 5), (24, 0.0, 2e-8, 0.3, 4),
    (16, 0.1, 0.0, 0.1, 3), (8, 0.15, 0.0, 0.1, 2)])
def test_ties_go_to_the_lowest_edge_pairs(n, turn, grow, mu, top):
    """Many pairs of equal regions: whole edges on a regular polygon (with ``grow``, each
    corner ``grow`` farther out than the one before: edges longer by ~1e-7 of their length
    as their index grows, so that the bound, the shorter edge, puts the highest pairs
    first, while their regions tie); on one with sides of three lengths, opposite sides at
    low friction give regions as long as the cone allows, equal for all. The search stops
    early on ties; it must still return the reference's largest, and among equal sizes the
    lowest pairs (i, j, spreading) in that order, the rule of ties."""
    points = _tangential(n, turn) * (1 + grow * np.arange(n))[:, None]
    polygon = Polygon.from_points(points)
    margin = 1e-3
    ref = _reference(points, mu, margin)
    best = max(ref.values())
    # equal within 1e-6 of their length: the library's rule of ties, far wider than the
    # reference LP's error
    tied = sorted(k for k in ref if ref[k] >= best * (1 - 1e-6) + 1e-12)
    assert len(tied) > top  # the case is one of ties
    found = synthesize(polygon, 2, "hard", mu, top=top, margin=margin).found
    assert [(*r.edges, r.spreading) for r in found] == tied[:top]


def test_the_notch_gives_bottom_and_top_first_at_every_margin():
    polygon = Polygon.from_points(NOTCH, name="notch")
    for margin in (1e-13, 1e-9, 1e-6, 1e-3):
        best = synthesize(polygon, 2, "hard", 1.0, top=1, margin=margin).found[0]
        assert best.edges == (0, 5)
        # the segments are x in [0, 1.5] on both edges, less what the margin takes
        assert best.min_length == pytest.approx(1.5 * math.tan(math.pi / 4 - margin), abs=1e-7)


def _corners_hold_in_rationals(polygon, regions):
    """Corollary 3 at the four corners, in fractions only, from the polygon's vertices and the
    points as floats (this test's own arithmetic, not the library's)."""
    from fractions import Fraction as F

    from forceclosure.synthesis.regions import narrowed

    e1, e2 = (polygon.edges[k] for k in regions.edges)

    def inward(e):
        return [-(F(float(e.end[1])) - F(float(e.start[1]))),
                F(float(e.end[0])) - F(float(e.start[0]))]

    def cone(m, mu, w):
        dot, cross = m[0] * w[0] + m[1] * w[1], m[0] * w[1] - m[1] * w[0]
        return mu * dot > cross and mu * dot > -cross

    mus = [F(float(narrowed(m, polygon.spread))) for m in regions.mu]
    for t1 in regions.segments[0]:
        for t2 in regions.segments[1]:
            p, q = ([F(float(x)) for x in e.point(t)] for e, t in ((e1, t1), (e2, t2)))
            w = [q[0] - p[0], q[1] - p[1]]
            if regions.spreading:
                w = [-w[0], -w[1]]
            if not (cone(inward(e1), mus[0], w) and cone(inward(e2), mus[1], [-w[0], -w[1]])):
                return False
    return True


@pytest.mark.parametrize("offset", [0.0, 1e8])
def test_corner_proof_agrees_with_rationals_a_few_doubles_from_the_boundary(offset):
    """The corner proof decides in doubles where an error bound allows and in rationals
    elsewhere. On a square of side 1.5 turned by a random angle, whole opposite sides at
    friction ``1 + k 2^-52`` put the diagonal between the far corners within a few doubles
    of the cone's boundary, where doubles alone get the sign wrong: the proof must give the
    rationals' answer every time, near the origin and far from it."""
    from fractions import Fraction as F

    from forceclosure.synthesis.planar.edge_pair import IndependentRegions

    rng = np.random.default_rng(3)
    both = set()
    for _ in range(400):
        turn = rng.uniform(0, 2 * np.pi)
        c, s = np.cos(turn), np.sin(turn)
        square = Polygon.from_points(np.array(POLYGONS["square-gap"]) @ [[c, s], [-s, c]]
                                     + offset)
        whole = ((0.0, square.edges[0].length), (0.0, square.edges[2].length))
        # the friction that puts the far corners' diagonal on the first cone's boundary,
        # in rationals, then a few doubles either side of it
        e1, e2 = square.edges[0], square.edges[2]
        m = [-(F(float(e1.end[1])) - F(float(e1.start[1]))),
             F(float(e1.end[0])) - F(float(e1.start[0]))]
        p, q = ([F(float(x)) for x in e.point(t)] for e, t in ((e1, 0.0), (e2, 0.0)))
        w = [q[0] - p[0], q[1] - p[1]]
        edge = abs(m[0] * w[1] - m[1] * w[0]) / (m[0] * w[0] + m[1] * w[1])
        mu = float(edge)
        for _ in range(int(rng.integers(-3, 4))):
            mu = float(np.nextafter(mu, np.inf if mu < 2 else 0))
        mu = float(np.nextafter(mu, 0)) if rng.uniform() < 0.3 else mu  # below it too
        r = IndependentRegions(square, (0, 2), whole, "test", (mu, mu))
        want = _corners_hold_in_rationals(square, r)
        assert r.certify().holds is want, (turn, mu)
        both.add(want)
    assert both == {True, False}  # the cases straddle the boundary

"""Planar synthesis (Lemma 1, maximal independent regions) against independent checks."""

import itertools
import math

import numpy as np
import pytest
import shapely

from forceclosure import InputError, Verdict, analyze, point_contact
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis import best_regions, maximal_regions, pair_grasps
from forceclosure.synthesis.planar import ANGLE_MARGIN
from forceclosure.two_finger import two_finger_closure


def _random_convex(seed, n=7):
    rng = np.random.default_rng(seed)
    hull = shapely.MultiPoint(rng.normal(size=(n * 3, 2))).convex_hull
    return Polygon.from_shapely(hull, name=f"random convex {seed}")


OBJECTS = [bundled(n) for n in ("square", "hexagon", "l-shape", "star", "frame",
                                "wrench-head", "bracket")] + [_random_convex(s) for s in (1, 2)]


def _closed_form(polygon, i, j, t1, t2, mu):
    e1, e2 = polygon.edges[i], polygon.edges[j]
    return two_finger_closure(e1.point(t1), e1.normal, e2.point(t2), e2.normal, mu)


@pytest.mark.parametrize("polygon", OBJECTS, ids=lambda p: p.name)
def test_lemma_1_is_the_set_of_force_closure_grasps(polygon):
    rng = np.random.default_rng(0)
    mu = 0.4
    nonempty = 0
    for i in range(len(polygon.edges)):
        for j in range(i + 1, len(polygon.edges)):
            g = pair_grasps(polygon, i, j, mu)
            e1, e2 = polygon.edges[i], polygon.edges[j]
            t1 = rng.uniform(0, e1.length, 400)
            t2 = rng.uniform(0, e2.length, 400)
            truth = _closed_form(polygon, i, j, t1, t2, mu)
            # Lemma 1's set is the squeezing grasps (PQ): the fingers pushing apart inside a
            # slot (QP, Corollary 3's other case) are not searched (docs/synthesis.md)
            worst = np.maximum(truth.angle_p, truth.angle_q)
            squeezing = worst < math.atan(mu)
            clear = np.abs(worst - math.atan(mu)) > 1e-9
            assert np.array_equal(truth.force_closure[clear & squeezing],
                                  np.ones(np.sum(clear & squeezing), bool))
            np.testing.assert_array_equal(g.contains(t1, t2)[clear], squeezing[clear])
            if g.empty:
                assert not squeezing[clear].any()
            else:
                nonempty += 1
                inside = shapely.Polygon(g.region)
                pts = shapely.points(np.stack([t1, t2], 1))
                far = shapely.distance(inside.boundary, pts) > 1e-9
                np.testing.assert_array_equal(shapely.contains(inside, pts)[far & clear],
                                              squeezing[far & clear])
    assert nonempty > 0


def _sample_box(regions, rng, n):
    (u1, v1), (u2, v2) = regions.segments
    t1 = np.concatenate([[u1, u1, v1, v1], rng.uniform(u1, v1, n)])
    t2 = np.concatenate([[u2, v2, u2, v2], rng.uniform(u2, v2, n)])
    return t1, t2


@pytest.mark.parametrize("polygon", [*OBJECTS, glyph("A"), glyph("e")], ids=lambda p: p.name)
def test_every_pair_in_every_region_is_force_closure(polygon):
    rng = np.random.default_rng(1)
    mu = 0.35
    results = best_regions(polygon, mu, top=4)
    assert results, polygon.name
    for r in results:
        assert r.certify().holds
        i, j = r.edges
        t1, t2 = _sample_box(r, rng, 3000)
        assert np.all(_closed_form(polygon, i, j, t1, t2, mu).force_closure)
        for k in range(12):  # the general test, Theorem 1, on some of them
            e1, e2 = polygon.edges[i], polygon.edges[j]
            grasp = [point_contact(e1.point(t1[k]), e1.normal, "hard", mu),
                     point_contact(e2.point(t2[k]), e2.normal, "hard", mu)]
            assert analyze(grasp).verdict is Verdict.CLOSURE
    lengths = [r.min_length for r in results]
    assert all(a >= b - 1e-12 for a, b in itertools.pairwise(lengths))  # best first


@pytest.mark.parametrize("name,i,j,gap", [("square", 0, 2, 2.0), ("hexagon", 0, 3, math.sqrt(3)),
                                          ("frame", 0, 2, 4.0)])
@pytest.mark.parametrize("mu", [0.1, 0.3, 0.6])
def test_parallel_edges_closed_form(name, i, j, gap, mu):
    """Facing parallel edges a distance h apart: aligned segments of length
    h tan(atan(mu) - margin), unless the edges are shorter."""
    polygon = bundled(name)
    r = maximal_regions(polygon, i, j, mu)
    want = min(gap * math.tan(math.atan(mu) - ANGLE_MARGIN), polygon.edges[i].length)
    assert r.min_length == pytest.approx(want, rel=1e-6)


def test_maximal_regions_beat_a_grid_search():
    """No pair of segments on a grid of endpoints does better than the LP."""
    rng = np.random.default_rng(5)
    polygon = _random_convex(3, n=6)
    mu = 0.5
    shrunk = math.tan(math.atan(mu) - ANGLE_MARGIN)
    checked = 0
    for i in range(len(polygon.edges)):
        for j in range(i + 1, len(polygon.edges)):
            r = maximal_regions(polygon, i, j, mu)
            e1, e2 = polygon.edges[i], polygon.edges[j]
            g1 = np.linspace(0, e1.length, 11)
            g2 = np.linspace(0, e2.length, 11)
            u1, v1, u2, v2 = np.meshgrid(g1, g1, g2, g2, indexing="ij")
            ok = (v1 > u1) & (v2 > u2)
            for a, b in ((u1, u2), (u1, v2), (v1, u2), (v1, v2)):
                ok &= _closed_form(polygon, i, j, a, b, shrunk).force_closure
            best = np.max(np.where(ok, np.minimum(v1 - u1, v2 - u2), 0.0))
            assert (0.0 if r is None else r.min_length) >= best - 1e-9
            checked += best > 0
    assert checked > 0
    del rng


def test_no_regions_and_bad_input():
    square = bundled("square")
    g = pair_grasps(square, 0, 1, 0.3)  # perpendicular sides: cones cannot counter-overlap
    assert g.empty and "do not counter-overlap" in g.reason
    assert maximal_regions(square, 0, 1, 0.3) is None
    assert maximal_regions(square, 0, 2, 0.0) is None  # frictionless pairs never close
    with pytest.raises(InputError, match="no edge 9"):
        pair_grasps(square, 0, 9, 0.3)
    with pytest.raises(InputError, match="two different edges"):
        maximal_regions(square, 1, 1, 0.3)
    with pytest.raises(InputError, match="friction coefficient"):
        pair_grasps(square, 0, 2, -1)


def test_synthesize_command(tmp_path, capsys):
    import json

    from forceclosure.cli import main

    picture = tmp_path / "regions.png"
    assert main(["synthesize", "frame", "--mu", "0.3", "--top", "3", "--json",
                 "--plot", str(picture)]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["object"] == "frame" and len(out["grasps"]) == 3
    best = out["grasps"][0]
    assert best["certificate"]["holds"] is True
    assert best["min_length"] == pytest.approx(4 * math.tan(math.atan(0.3) - ANGLE_MARGIN))
    assert np.asarray(best["points"]).shape == (2, 2, 2)
    assert picture.read_bytes()[:4] == b"\x89PNG"
    assert main(["synthesize", "l-shape"]) == 0
    assert "1. edge " in capsys.readouterr().out


@pytest.mark.parametrize("argv,message", [
    (["synthesize", "cube", "--contact", "hard", "--fingers", "2"], "at least 3 hard fingers"),
    (["synthesize", "cube", "--fingers", "6", "--contact", "frictionless"],
     "at least 7 frictionless fingers"),
    (["synthesize", "cube", "--fingers", "4", "--method", "faces"], "use --method mesh"),
    (["synthesize", "cube", "--fingers", "3", "--construction", "nguyen"],
     "two soft fingers"),
    (["synthesize", "square", "--fingers", "4"], "implemented so far are two or three"),
    (["synthesize", "square", "--contact", "frictionless", "--fingers", "2"],
     "the plane needs four"),
    (["synthesize", "square", "--mu", "-1"], "--mu must be a positive number"),
    (["synthesize", "square", "--top", "0"], "'top' must be a positive integer"),
    (["synthesize", "square", "--margin", "-0.1"], "margin must be an angle in radians"),
])
def test_synthesize_refusals(argv, message, capsys):
    from forceclosure.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("polygon", [*OBJECTS, glyph("B")], ids=lambda p: p.name)
def test_nguyen_regions_hold_and_never_beat_the_maximal_ones(polygon):
    from forceclosure.synthesis import nguyen_regions

    rng = np.random.default_rng(2)
    mu = 0.35
    built = 0
    for i in range(len(polygon.edges)):
        for j in range(i + 1, len(polygon.edges)):
            n = nguyen_regions(polygon, i, j, mu)
            if n is None:
                continue
            built += 1
            assert n.certify().holds
            t1, t2 = _sample_box(n, rng, 500)
            assert np.all(_closed_form(polygon, i, j, t1, t2, mu).force_closure)
            m = maximal_regions(polygon, i, j, mu)
            assert m is not None and m.min_length >= n.min_length * (1 - 1e-9) - 1e-12
    assert built > 0


def test_vectorised_solver_matches_an_lp_solver():
    """max_min_segments against scipy's HiGHS on the same LP written out in five
    variables (u1, v1, u2, v2, z), on random instances, infeasible ones included."""
    from scipy.optimize import linprog

    from forceclosure.synthesis.planar import max_min_segments

    rng = np.random.default_rng(7)
    P = 400
    A = rng.normal(size=(P, 4, 2))
    b = rng.normal(size=(P, 4)) + 1.0
    L1, L2 = rng.uniform(0.1, 3, P), rng.uniform(0.1, 3, P)
    z, u1, u2 = max_min_segments(A, b, L1, L2)
    infeasible = 0
    for p in range(P):
        rows, rhs = [], []
        for (a1, a2), off in zip(A[p], b[p], strict=True):
            row = np.zeros(5)
            row[0 if a1 >= 0 else 1] -= a1
            row[2 if a2 >= 0 else 3] -= a2
            rows.append(row)
            rhs.append(off)
        rows += [[1, -1, 0, 0, 1], [0, 0, 1, -1, 1]]
        rhs += [0, 0]
        res = linprog([0, 0, 0, 0, -1], A_ub=np.array(rows), b_ub=rhs,
                      bounds=[(0, L1[p])] * 2 + [(0, L2[p])] * 2 + [(0, None)], method="highs")
        if res.status == 2:
            infeasible += 1
            assert z[p] == -np.inf or z[p] <= 1e-12
            continue
        assert z[p] == pytest.approx(res.x[4], abs=1e-9)
        corners = [(u1[p] + a, u2[p] + c) for a in (0, z[p]) for c in (0, z[p])]
        for t in corners:  # the returned segments satisfy the conditions
            assert np.all(A[p] @ np.array(t) + b[p] >= -1e-9)
    assert 0 < infeasible < P


def test_nguyen_construction_from_the_command(tmp_path, capsys):
    import json

    from forceclosure.cli import main
    from forceclosure.synthesis import best_frictionless_regions

    assert main(["synthesize", "wrench-head", "--construction", "nguyen", "--json",
                 "--plot", str(tmp_path / "cone.png")]) == 0
    out = json.loads(capsys.readouterr().out)
    best = out["grasps"][0]
    assert best["construction"].startswith("Nguyen") and best["certificate"]["holds"]
    apex = np.array(best["apex"])
    # the two-sided cone's vertex lies between the two segments
    ends = np.array(best["points"]).reshape(-1, 2)
    assert ends[:, 1].min() < apex[1] < ends[:, 1].max()
    assert (tmp_path / "cone.png").stat().st_size > 5000
    four = best_frictionless_regions(bundled("bracket"), top=1, construction="nguyen")
    assert four[0].construction.startswith("Nguyen") and four[0].certify().holds
    with pytest.raises(InputError, match="construction must be"):
        best_regions(bundled("square"), 0.3, construction="other")
    assert main(["synthesize", "square", "--fingers", "3", "--construction", "nguyen"]) == 2

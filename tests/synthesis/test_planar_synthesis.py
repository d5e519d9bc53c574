"""Planar synthesis (Lemma 1, maximal independent regions) against independent checks."""

import itertools
import math

import numpy as np
import pytest
import shapely

from forceclosure import InputError, Verdict, analyze, point_contact
from forceclosure.analysis.two_finger import two_finger_closure
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis import maximal_regions, pair_grasps, synthesize
from forceclosure.synthesis.planar.two_fingers import ANGLE_MARGIN


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
    """pair_grasps against Corollary 3 in closed form (two_finger_closure: squeezing, PQ, or
    pushing apart, QP), away from the boundary of closure: its pieces, as shapely polygons,
    hold exactly the force-closure grasps, each piece those of its orientation."""
    rng = np.random.default_rng(0)
    mu = 0.4
    nonempty = {False: 0, True: 0}
    for i in range(len(polygon.edges)):
        for j in range(i + 1, len(polygon.edges)):
            g = pair_grasps(polygon, i, j, mu)
            e1, e2 = polygon.edges[i], polygon.edges[j]
            t1 = rng.uniform(0, e1.length, 400)
            t2 = rng.uniform(0, e2.length, 400)
            truth = _closed_form(polygon, i, j, t1, t2, mu)
            closure = truth.force_closure
            # a spreading grasp has both angles above 90 degrees; away from both boundaries
            worst = {False: np.maximum(truth.angle_p, truth.angle_q),
                     True: np.maximum(np.pi - truth.angle_p, np.pi - truth.angle_q)}
            clear = np.all([np.abs(w - math.atan(mu)) > 1e-9 for w in worst.values()], axis=0)
            np.testing.assert_array_equal(g.contains(t1, t2)[clear], closure[clear])
            if g.empty:
                assert not closure[clear].any()
            assert [p.spreading for p in g.pieces] == [False, True]
            pts = shapely.points(np.stack([t1, t2], 1))
            for piece in g.pieces:
                way = worst[piece.spreading] < math.atan(mu)
                if len(piece.region) < 3:
                    assert not (closure & way)[clear].any()
                    continue
                nonempty[piece.spreading] += 1
                inside = shapely.Polygon(piece.region)
                far = (shapely.distance(inside.boundary, pts) > 1e-9) & clear
                np.testing.assert_array_equal(shapely.contains(inside, pts)[far],
                                              (closure & way)[far])
    assert nonempty[False] > 0
    # fingers pushing apart exist only where the outline turns both ways
    assert (nonempty[True] > 0) == (polygon.name in ("frame", "wrench-head")), nonempty


def _sample_box(regions, rng, n):
    (u1, v1), (u2, v2) = regions.segments
    t1 = np.concatenate([[u1, u1, v1, v1], rng.uniform(u1, v1, n)])
    t2 = np.concatenate([[u2, v2, u2, v2], rng.uniform(u2, v2, n)])
    return t1, t2


@pytest.mark.parametrize("polygon", [*OBJECTS, glyph("A"), glyph("e")], ids=lambda p: p.name)
def test_every_pair_in_every_region_is_force_closure(polygon):
    rng = np.random.default_rng(1)
    mu = 0.35
    results = synthesize(polygon, 2, "hard", mu, top=4).found
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

    from forceclosure.app.cli import main

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
     "for 2 soft fingers"),
    (["synthesize", "square", "--fingers", "9"], "at most 8 fingers"),
    (["synthesize", "square", "--contact", "frictionless", "--fingers", "3"],
     "at least 4 frictionless fingers"),
    (["synthesize", "square", "--contact", "frictionless", "--fingers", "2"],
     "the plane needs four"),
    (["synthesize", "square", "--mu", "-1"], "--mu must be a positive number"),
    (["synthesize", "square", "--top", "0"], "--top must be a positive integer"),
    (["synthesize", "square", "--margin", "-0.1"], "margin must be an angle in radians"),
])
def test_synthesize_refusals(argv, message, capsys):
    from forceclosure.app.cli import main

    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


@pytest.mark.parametrize("kwargs,argv,api,cli", [
    ({"fingers": 2, "contact": "hard"}, ["--fingers", "2", "--contact", "hard"],
     "fingers=2, contact='hard': a spatial grasp needs at least 3 hard fingers",
     "--fingers 2 --contact hard: a spatial grasp needs at least 3 hard fingers"),
    ({"fingers": 4, "method": "faces"}, ["--fingers", "4", "--method", "faces"],
     "method='faces': the paper constructs", "--method faces: the paper constructs"),
    ({"fingers": 3, "construction": "nguyen"}, ["--fingers", "3", "--construction", "nguyen"],
     "construction='nguyen': in space", "--construction nguyen: in space"),
    ({"mu": -1.0}, ["--mu", "-1"], "mu must be a positive number, got -1",
     "--mu must be a positive number, got -1"),
    ({"contact": "soft", "top": 0}, ["--contact", "soft", "--top", "0"],
     "top must be a positive integer, got 0", "--top must be a positive integer, got 0"),
])
def test_refusals_name_parameters_to_callers_and_flags_on_the_command_line(kwargs, argv, api,
                                                                            cli, capsys):
    """The same refusal, worded for who asked: the API names its parameters, the command line
    its flags (one table in cli.py maps the one to the other)."""
    from forceclosure import synthesize
    from forceclosure.app.cli import main

    with pytest.raises(InputError) as raised:
        synthesize(bundled("cube"), **kwargs)
    said = str(raised.value)
    assert "--" not in said and said.startswith(api), said
    code = main(["synthesize", "cube", *argv])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1
    assert err.startswith("forceclosure: error: " + cli), err


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

    from forceclosure.synthesis.planar.two_fingers import max_min_segments

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

    from forceclosure.app.cli import main

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
    four = synthesize(bundled("bracket"), 4, "frictionless", top=1, construction="nguyen").found
    assert four[0].construction.startswith("Nguyen") and four[0].certify().holds
    with pytest.raises(InputError, match="construction must be"):
        synthesize(bundled("square"), 2, "hard", 0.3, construction="other")
    assert main(["synthesize", "square", "--fingers", "3", "--construction", "nguyen"]) == 2


def _slot_in_a_triangle():
    """An equilateral triangle 6 wide with a slot 1 wide and 2 deep cut up from its base (a
    U-shaped opening). At mu 0.2 no two of its edges but the slot's walls have friction
    cones that counter-overlap (the triangle's normals are 120 degrees apart, the walls'
    30 or 90 degrees from the others'), and the walls face each other across the slot:
    every two-finger grasp pushes the walls apart."""
    h = 3 * math.sqrt(3)
    return Polygon.from_points([(-3, 0), (-0.5, 0), (-0.5, 2), (0.5, 2), (0.5, 0), (3, 0),
                                (0, h)], name="slot in a triangle")


def _analyzed(polygon, regions, rng, n):
    """Theorem 1's general test (analyze) on n random pairs and the corners of a region
    set; also whether each pair spreads (p - q points into the object at p)."""
    i, j = regions.edges
    e1, e2 = polygon.edges[i], polygon.edges[j]
    t1, t2 = _sample_box(regions, rng, n)
    verdicts, spreads = [], []
    for a, b in zip(t1, t2, strict=True):
        p, q = e1.point(a), e2.point(b)
        grasp = [point_contact(p, e1.normal, "hard", regions.mu[0]),
                 point_contact(q, e2.normal, "hard", regions.mu[1])]
        verdicts.append(analyze(grasp).verdict)
        spreads.append(float((p - q) @ -e1.normal) > 0)
    return verdicts, spreads


def test_grasps_in_a_slot_push_apart_and_are_found():
    polygon = _slot_in_a_triangle()
    mu = 0.2
    rng = np.random.default_rng(3)
    # the truth, independent of the synthesis: Corollary 3 on dense samples of every pair
    closing = {}
    for i, j in itertools.combinations(range(len(polygon.edges)), 2):
        e1, e2 = polygon.edges[i], polygon.edges[j]
        t1, t2 = rng.uniform(0, e1.length, 4000), rng.uniform(0, e2.length, 4000)
        truth = _closed_form(polygon, i, j, t1, t2, mu)
        if truth.force_closure.any():
            closing[(i, j)] = truth
    assert set(closing) == {(1, 3)}  # only the slot's walls
    truth = closing[(1, 3)]
    assert np.all(truth.angle_p[truth.force_closure] > np.pi / 2)  # all pushing apart
    found = synthesize(polygon, 2, "hard", mu, top=5).found
    assert [(r.edges, r.spreading) for r in found] == [((1, 3), True)]
    r = found[0]
    assert r.certify().holds and "pushing apart" in r.certify().detail
    # facing walls 1 apart: aligned segments of length tan(atan(mu) - margin)
    assert r.min_length == pytest.approx(math.tan(math.atan(mu) - ANGLE_MARGIN), rel=1e-6)
    verdicts, spreads = _analyzed(polygon, r, rng, 1000)
    assert set(verdicts) == {Verdict.CLOSURE} and all(spreads)
    # the same regions checked as squeezing ones are refused: the proof has an orientation
    import dataclasses

    assert not dataclasses.replace(r, spreading=False).certify().holds
    n = synthesize(polygon, 2, "hard", mu, top=5, construction="nguyen").found
    assert [(x.edges, x.spreading) for x in n] == [((1, 3), True)] and n[0].certify().holds
    assert n[0].min_length <= r.min_length * (1 + 1e-9)
    assert set(_analyzed(polygon, n[0], rng, 500)[0]) == {Verdict.CLOSURE}


@pytest.mark.parametrize("polygon", [bundled("frame"), bundled("wrench-head"),
                                     _slot_in_a_triangle()], ids=lambda p: p.name)
@pytest.mark.parametrize("construction", ["maximal", "nguyen"])
def test_spreading_regions_hold_under_the_general_test(polygon, construction):
    """Every region set two fingers are given (both orientations ranked together, best
    first) is certified, and 300 random pairs and the corners of each pass Theorem 1's
    general test, in the orientation it claims."""
    rng = np.random.default_rng(4)
    mu = 0.4 if polygon.name != "slot in a triangle" else 0.2
    found = synthesize(polygon, 2, "hard", mu, top=12, construction=construction).found
    assert any(r.spreading for r in found)
    for r in found:
        assert r.certify().holds
        verdicts, spreads = _analyzed(polygon, r, rng, 300)
        assert set(verdicts) == {Verdict.CLOSURE}, r
        assert set(spreads) == {r.spreading}, r
    lengths = [r.min_length for r in found]
    assert all(a >= b - 1e-12 for a, b in itertools.pairwise(lengths))


def test_frame_grasps_inside_its_hole(capsys):
    """The frame (a 4 x 4 square with a 2 x 2 hole): at mu 0.4 the best grasps squeeze its
    outer sides, 4 apart (segments 4 tan(atan(mu) - margin), closed form), then push the
    hole's sides apart, 2 apart (half as long)."""
    import json

    from forceclosure.app.cli import main

    assert main(["synthesize", "frame", "--fingers", "2", "--mu", "0.4", "--json"]) == 0
    grasps = json.loads(capsys.readouterr().out)["grasps"]
    got = [(tuple(g["edges"]), g["spreading"]) for g in grasps[:4]]
    assert got == [((0, 2), False), ((1, 3), False), ((4, 6), True), ((5, 7), True)]
    cone = math.tan(math.atan(0.4) - ANGLE_MARGIN)
    for g, gap in zip(grasps[:4], (4, 4, 2, 2), strict=True):
        assert g["min_length"] == pytest.approx(gap * cone, rel=1e-9)
        assert g["certificate"]["holds"]


@pytest.mark.parametrize("polygon", [bundled("frame"), bundled("wrench-head"), glyph("e"),
                                     _slot_in_a_triangle()], ids=lambda p: p.name)
def test_pruning_keeps_every_pair_that_pushes_apart(polygon):
    """The two-finger search prunes the spreading LP to edges that reach outside each other's lines;
    every pair whose own LP (maximal_regions, no pruning) gives spreading regions is among
    its results, as long."""
    mu = 0.6
    want = {}
    for i, j in itertools.combinations(range(len(polygon.edges)), 2):
        r = maximal_regions(polygon, i, j, mu, spreading=True)
        if r is not None:
            assert r.spreading and r.certify().holds
            want[(i, j)] = r.min_length
    got = {r.edges: r.min_length
           for r in synthesize(polygon, 2, "hard", mu, top=10_000).found if r.spreading}
    assert set(got) == set(want) and want, (got, want)
    for k, length in want.items():
        assert got[k] == pytest.approx(length, rel=1e-12)

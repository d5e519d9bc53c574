"""Any hand on a polygon (issue 25): segments grown around sampled prototypes, the table's
planar fallback. Checked independently: Theorem 1 in exact rationals (``tests/exact.py``,
no linear programming, written apart from the library) on grasps drawn exactly from the
segments, with the wrenches built here from the edges' exact endpoints; the corner proof
checked against the same exact test at the corners (it must say "holds" exactly when every
corner combination is force-closure, and then every drawn grasp is)."""

import itertools
import json
import math
from fractions import Fraction

import numpy as np
import pytest

from exact import positively_spans
from forceclosure.app.cli import main
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis import Hand, search, synthesize
from forceclosure.synthesis.planar.grown_segments import GROWN, GrownRegions, corner_closure
from forceclosure.synthesis.table import construction_for

F = Fraction


def _inward(e):
    """The inward normal, unnormalised, from the edge's endpoints exactly."""
    dx, dy = (F(float(b)) - F(float(a)) for a, b in zip(e.start, e.end, strict=True))
    return [-dy, dx]


def _forces(e, mu, turn):
    """Hard: the two cone edges at ``mu`` (the user's, not narrowed); frictionless: the
    normal turned by the rational angle ``2 atan(turn)``."""
    m = _inward(e)
    q = [-m[1], m[0]]
    if mu:
        return [[m[0] + s * mu * q[0], m[1] + s * mu * q[1]] for s in (1, -1)]
    c, s = 1 - turn * turn, 2 * turn  # (cos, sin) times 1 + turn^2
    return [[c * m[0] + s * q[0], c * m[1] + s * q[1]]]


def _exactly_closed(polygon, edges, points, mu, turns):
    cols = []
    for e_index, p, turn in zip(edges, points, turns, strict=True):
        for f in _forces(polygon.edges[e_index], mu, turn):
            cols.append([f[0], f[1], p[0] * f[1] - p[1] * f[0]])
    return positively_spans(cols)


def _drawn(r, rng, count):
    """Grasps drawn exactly from the segments (rational points between the printed ends):
    ``count // 2`` random combinations of the ends, then random points; each frictionless
    finger's force turned by a random rational angle within 90 % of the margin."""
    ends = [[[F(float(x)) for x in p] for p in seg] for seg in r.points]
    half = math.tan(0.45 * r.margin)
    for k in range(count):
        if k < count // 2:
            lam = [F(int(b)) for b in rng.integers(0, 2, len(ends))]
        else:
            lam = [F(int(rng.integers(0, 10**6)), 10**6) for _ in ends]
        pts = [[a + x * (b - a) for a, b in zip(A, B, strict=True)]
               for (A, B), x in zip(ends, lam, strict=True)]
        turns = [F(float(rng.uniform(-half, half))) if r.mu == 0 else F(0) for _ in ends]
        yield pts, turns


def _check_exactly(r, count=20, seed=0):
    assert isinstance(r, GrownRegions) and r.certify().holds
    rng = np.random.default_rng(seed)
    mu = F(r.mu)
    for pts, turns in _drawn(r, rng, count):
        assert _exactly_closed(r.polygon, r.edges, pts, mu, turns), (r.describe(), pts)


def _l_shape():
    return bundled("l-shape")


@pytest.mark.parametrize("name, fingers, contact, mu", [
    ("square", 4, "hard", 0.4), pytest.param("l-shape", 4, "hard", 0.4, marks=pytest.mark.long),
    ("l-shape", 5, "frictionless", 0.0),
    pytest.param("square", 5, "frictionless", 0.0, marks=pytest.mark.long),
    pytest.param("star", 5, "frictionless", 0.0, marks=pytest.mark.long),
    pytest.param("triangle", 5, "frictionless", 0.0, marks=pytest.mark.long),
])
def test_every_grown_region_holds_by_theorem_1_in_exact_rationals(name, fingers, contact, mu):
    """Four hard and five frictionless fingers: every returned region set, at every
    combination of its ends and at random points, force-closure exactly (five frictionless
    fingers on a triangle too: every polygon can be held by four, Markenscoff et al. 1990)."""
    obj = bundled(name)
    found = search(GROWN, obj, Hand(fingers, contact, mu, samples=3000, top=2))
    assert len(found) == 2, name
    for r in found:
        assert len(r.edges) == fingers and r.object is obj
        for e, (u, v) in zip(r.edges, r.segments, strict=True):
            assert 0 <= u < v <= obj.edges[e].length
    _check_exactly(found[0])


@pytest.mark.long
def test_five_frictionless_fingers_on_a_glyph_with_a_hole():
    a = glyph("A")
    s = synthesize(a, 5, "frictionless", top=1, samples=3000)
    assert s.construction.name == "grown" and s.complete is False
    [r] = s.found
    _check_exactly(r, count=40)


@pytest.mark.parametrize("fingers, mu, boxes", [(5, 0.0, 30), (4, 0.3, 10)])
def test_the_corner_proof_holds_exactly_when_every_corner_combination_does(fingers, mu, boxes):
    """Random segments on the L (five frictionless or four hard fingers, some sharing an
    edge; no margin): the proof holds iff the exact test passes at every combination of
    segment ends; when it holds, grasps drawn inside hold too (the corners decide the box)."""
    obj = _l_shape()
    rng = np.random.default_rng(11)
    seen = {True: 0, False: 0}
    for _ in range(boxes):
        edges = tuple(sorted(rng.choice(len(obj.edges), fingers).tolist()))
        segments = []
        for e in edges:
            u, v = np.sort(rng.uniform(0, obj.edges[e].length, 2))
            segments.append((float(u), float(v)))
        r = GrownRegions(obj, edges, tuple(segments), "test", mu, 0.0)
        corners = [[[F(float(x)) for x in p] for p in seg] for seg in r.points]
        every = all(_exactly_closed(obj, edges, [corners[i][c] for i, c in enumerate(choice)],
                                    F(mu), [F(0)] * fingers)
                    for choice in itertools.product((0, 1), repeat=fingers))
        assert r.certify().holds is every
        seen[every] += 1
        if every and seen[True] == 1:
            _check_exactly(r)
    assert seen[True] and seen[False]  # both outcomes met


@pytest.mark.parametrize("name, fingers, boxes", [
    ("square", 4, 60), ("hexagon", 3, 120),
    pytest.param("square", 4, 1000, marks=pytest.mark.long),
    pytest.param("hexagon", 3, 1000, marks=pytest.mark.long)])
def test_the_proof_never_holds_where_a_corner_combination_fails(name, fingers, boxes):
    """Hard fingers at mu 0.3 on random segments of the square and the hexagon, edges drawn
    with repeats: whenever the proof holds, every combination of segment ends is
    force-closure by the exact test. (A pair's own two wrenches once took the sign of
    their rounding, about 1e-16, and two such boxes in 480 were proved wrongly.)"""
    obj = bundled(name)
    rng = np.random.default_rng(5)
    held = 0
    for _ in range(boxes):
        edges = tuple(sorted(rng.choice(len(obj.edges), fingers).tolist()))
        segments = tuple(tuple(float(x) for x in np.sort(rng.uniform(0, obj.edges[e].length, 2)))
                         for e in edges)
        r = GrownRegions(obj, edges, segments, "test", 0.3, 0.0)
        if not r.certify().holds:
            continue
        held += 1
        corners = [[[F(float(x)) for x in p] for p in seg] for seg in r.points]
        for choice in itertools.product((0, 1), repeat=fingers):
            assert _exactly_closed(obj, edges, [corners[i][c] for i, c in enumerate(choice)],
                                   F(0.3), [F(0)] * fingers), (edges, segments, choice)
    assert held  # the proof was put to the test


def test_three_single_wrenches_never_positively_span_space():
    """Three wrenches cannot positively span R^3 (four at least), whatever their signs: the
    corner proof refuses every such hand, its pairs' own wrenches counted exactly zero."""
    rng = np.random.default_rng(3)
    for _ in range(300):
        W = [[F(float(v)) for v in rng.normal(size=3)] for _ in range(3)]
        assert corner_closure([[[w]] for w in W])[0] is False, W


@pytest.mark.parametrize("fingers, contact", [(5, "frictionless"), (3, "frictionless"),
                                              (6, "hard"), (5, "soft")])
def test_the_table_serves_every_planar_hand_with_the_grown_regions(fingers, contact):
    assert construction_for(2, fingers, contact).name == "grown"
    assert construction_for(2, 2, "hard").name == "maximal"
    assert construction_for(2, 4, "frictionless").name == "maximal"


@pytest.mark.parametrize("argv, message", [
    (["--fingers", "3", "--contact", "frictionless"], "at least 4 frictionless fingers"),
    (["--fingers", "1"], "at least 2 hard fingers"),
    (["--fingers", "9"], "at most 8 fingers"),
    (["--fingers", "5", "--construction", "nguyen"], "construction nguyen"),
])
def test_a_hand_that_cannot_close_is_refused_in_one_line(argv, message, capsys):
    assert main(["synthesize", "square", *argv]) == 2
    err = capsys.readouterr().err.strip()
    assert message in err and len(err.splitlines()) == 1


def test_the_cli_prints_certified_regions_for_five_frictionless_fingers(tmp_path, capsys):
    ring = [[0, 0], [3, 0], [3, 1], [1, 1], [1, 3], [0, 3], [0, 0]]
    path = tmp_path / "l.geojson"
    path.write_text(json.dumps({"type": "Polygon", "coordinates": [ring]}))
    argv = ["synthesize", str(path), "--fingers", "5", "--contact", "frictionless", "--top",
            "2", "--samples", "1500"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "1. edge " in out and "2. edge " in out
    assert out.count("certified: True") == 2
    assert main([*argv, "--json"]) == 0
    record = json.loads(capsys.readouterr().out)
    assert record["complete"] is False and len(record["grasps"]) == 2
    polygon = Polygon.from_points(ring[:-1])
    for g in record["grasps"]:
        assert g["certificate"]["holds"] is True and len(g["edges"]) == 5
    g = record["grasps"][0]
    r = GrownRegions(polygon, tuple(g["edges"]), tuple(map(tuple, g["segments"])), "cli", 0.0,
                     g["margin"])
    _check_exactly(r, count=10)


def test_a_moved_copy_gets_the_same_regions_in_the_same_places():
    obj = _l_shape()
    offset = np.array([1e8, -1e8])
    moved = Polygon.from_points(obj.outer + offset)
    hand = Hand(5, "frictionless", 0.0, samples=1500, top=2)
    here, there = search(GROWN, obj, hand), search(GROWN, moved, hand)
    assert len(here) == len(there) == 2
    for a, b in zip(here, there, strict=True):
        assert a.edges == b.edges
        np.testing.assert_allclose(b.points - offset, a.points, atol=1e-6 * obj.size)


def test_a_grown_segment_past_its_edge_is_not_certified():
    import dataclasses

    [r] = search(GROWN, bundled("square"), Hand(5, "frictionless", 0.0, samples=2000, top=1))
    k = next(i for i, (u, v) in enumerate(r.segments)
             if v < r.polygon.edges[r.edges[i]].length)
    length = r.polygon.edges[r.edges[k]].length
    segments = list(r.segments)
    segments[k] = (segments[k][0], length * (1 + 1e-15))
    cert = dataclasses.replace(r, segments=tuple(segments)).certify()
    assert not cert.holds and f"not within edge {r.edges[k]}" in cert.detail


@pytest.mark.long
def test_a_wide_margin_holds_for_every_direction_in_the_fan():
    """Margin 0.2 rad on five frictionless fingers: smaller regions than at 1e-3, and every
    drawn grasp force-closure exactly with each force turned by a random rational angle up
    to 0.18 rad (the fan the proof covers)."""
    obj = _l_shape()
    small = synthesize(obj, 5, "frictionless", top=1, margin=1e-3, samples=3000).found
    large = synthesize(obj, 5, "frictionless", top=1, margin=0.2, samples=3000).found
    assert large and large[0].min_length < 0.99 * small[0].min_length
    _check_exactly(large[0], count=40)


def test_three_frictionless_fingers_find_nothing_to_grow():
    """The front door refuses them (above); the construction itself, asked directly, finds no
    prototype to grow on the L either: three frictionless contacts never hold a polygon
    (the plane needs four, Reuleaux)."""
    found = search(GROWN, _l_shape(), Hand(3, "frictionless", 0.0, samples=2000, top=2))
    assert list(found) == [] and found.undecided == 0

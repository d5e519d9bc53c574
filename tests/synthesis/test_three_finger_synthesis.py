"""Three fingers with friction (a common centre, around a prototype, a pair plus a free
finger), checked by Theorem 1."""

import itertools
import math

import numpy as np
import pytest

from forceclosure import InputError, Verdict, analyze, point_contact
from forceclosure.app.cli import main
from forceclosure.objects import Polygon, bundled, glyph
from forceclosure.synthesis import synthesize, three_finger_regions
from forceclosure.synthesis.planar.three_fingers import GRID, SEARCHED
from forceclosure.synthesis.planar.two_fingers import maximal_regions


@pytest.mark.parametrize("polygon", [bundled(n) for n in ("triangle", "hexagon", "star",
                                                          "wrench-head", "bracket")]
                         + [glyph("A")], ids=lambda p: p.name)
def test_every_triple_in_every_region_is_force_closure(polygon):
    rng = np.random.default_rng(4)
    mu = 0.3
    found = synthesize(polygon, 3, "hard", mu, top=3).found
    for r in found:
        assert r.certify().holds
        es = [polygon.edges[k] for k in r.edges]
        samples = list(itertools.product(*r.segments)) + [
            tuple(rng.uniform(u, v) for u, v in r.segments) for _ in range(80)]
        for ts in samples:
            grasp = [point_contact(e.point(t), e.normal, "hard", mu)
                     for e, t in zip(es, ts, strict=True)]
            assert analyze(grasp).verdict is Verdict.CLOSURE, (polygon.name, r.edges, ts)
    if polygon.name in ("triangle", "hexagon", "wrench-head"):
        assert found


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.5])
def test_regular_polygons_closed_form(mu):
    """Around a regular n-gon with inradius r, lines meeting at the centre allow each
    finger 2 r tan(atan(mu) - margin), up to the side's length."""
    for n, edges in ((3, (0, 1, 2)), (6, (0, 2, 4))):
        polygon = Polygon.regular(n)
        r = three_finger_regions(polygon, edges, mu)
        inradius = math.cos(math.pi / n)
        want = min(2 * inradius * math.tan(math.atan(mu) - 1e-3), polygon.edges[0].length)
        if mu >= math.tan(math.pi / 6):  # (b) fails: a choice of directions fits a half-plane
            assert r is None
        else:
            assert r.min_length == pytest.approx(want, rel=1e-3)
            np.testing.assert_allclose(r.centre, [0, 0], atol=1e-6)


def test_refusals_and_command(capsys, tmp_path):
    with pytest.raises(InputError, match="three different edges"):
        three_finger_regions(bundled("triangle"), (0, 0, 1), 0.3)
    picture = tmp_path / "three.png"
    assert main(["synthesize", "triangle", "--fingers", "3", "--mu", "0.3",
                 "--plot", str(picture)]) == 0
    assert "1. edge 0" in capsys.readouterr().out
    assert picture.read_bytes()[:4] == b"\x89PNG"


# --- the three families (issue 16, item 6): every region set checked by Theorem 1 ------------

def _assert_every_choice_closes(polygon, r, mu, rng, random=60):
    """Theorem 1 (`analyze`, an LP of its own) at every corner of the segments' box (the
    segments' ends) and at random points in them: independent of the certificates."""
    assert r.certify().holds
    es = [polygon.edges[k] for k in r.edges]
    for (u, v), e in zip(r.segments, es, strict=True):
        assert -1e-12 <= u < v <= e.length + 1e-12
    samples = list(itertools.product(*r.segments)) + [
        tuple(rng.uniform(u, v) for u, v in r.segments) for _ in range(random)]
    for ts in samples:
        grasp = [point_contact(e.point(t), e.normal, "hard", mu)
                 for e, t in zip(es, ts, strict=True)]
        assert analyze(grasp).verdict is Verdict.CLOSURE, (polygon.name, r.edges, ts)


@pytest.mark.parametrize("mu", [0.3, 0.8])
def test_square_three_fingers(mu):
    """The square of side 2 at any friction: fingers on opposite sides facing each other are
    force-closure (Corollary 3), and a third finger anywhere only adds wrenches. Segments of
    length z on opposite sides, aligned, stay closed while z / 2 < tan(atan(mu) - margin), so
    every triple of the square's edges has regions at least that long (the third edge whole).
    The search before this change said that no triple admits a grasp."""
    square = bundled("square")
    rng = np.random.default_rng(16)
    found = synthesize(square, 3, "hard", mu, top=10).found
    assert sorted(r.edges for r in found) == list(itertools.combinations(range(4), 3))
    head_on = 2 * math.tan(math.atan(mu) - 1e-3)
    for r in found:
        assert head_on * (1 - 1e-6) <= r.min_length <= 2
        _assert_every_choice_closes(square, r, mu, rng)
    r = three_finger_regions(square, (0, 1, 2), mu)
    assert r.pair == (0, 2) and r.segments[1] == (0.0, 2.0) and r.centre is None
    record = r.to_dict()
    assert record["centre"] is None and record["pair"] == [0, 2]
    assert "only adds wrenches" in r.certify().detail


@pytest.mark.parametrize("mu", [0.3, 0.8])
@pytest.mark.parametrize("polygon", [bundled(n) for n in ("triangle", "hexagon", "star",
                                                          "frame", "l-shape")]
                         + [glyph("A")], ids=lambda p: p.name)
def test_every_family_checked_by_theorem_1(polygon, mu):
    rng = np.random.default_rng(6)
    found = synthesize(polygon, 3, "hard", mu, top=4).found
    assert found  # every polygon here has three-finger grasps at these frictions
    for r in found:
        _assert_every_choice_closes(polygon, r, mu, rng, random=30)


def test_around_a_prototype_where_nothing_else_applies():
    """On the star at mu 0.8 the whole cones are too wide for the common centre's condition
    (b), and no two of the edges 0, 1, 5 hold the star alone; regions grown around a
    force-closure prototype do."""
    star, mu = bundled("star"), 0.8
    for i, j in itertools.combinations((0, 1, 5), 2):
        assert maximal_regions(star, i, j, mu) is None
    r = three_finger_regions(star, (0, 1, 5), mu)
    assert r.sectors is not None and r.pair is None
    assert r.min_length > 0.01 * star.size
    assert min(r.signs) == -1  # the lines of force meet behind a finger
    _assert_every_choice_closes(star, r, mu, np.random.default_rng(1), random=200)


def test_no_grasp_on_three_consecutive_sides_of_a_hexagon():
    """By hand: consecutive outward normals of the regular hexagon are 60 degrees apart, so
    the pushing directions -n of edges 0, 1, 2 span 120 degrees, and with friction 0.3 every
    force lies within atan(0.3) = 16.7 degrees of them: all inside an arc of 153.4 < 180
    degrees, an open half-plane. Positive forces there never sum to zero, so no equilibrium
    and (Theorem 1) no force closure, wherever the fingers are."""
    hexagon, mu = Polygon.regular(6), 0.3
    assert three_finger_regions(hexagon, (0, 1, 2), mu) is None
    found = synthesize(hexagon, 3, "hard", mu, top=100).found
    assert found and all(sorted((k - min(r.edges)) % 6 for k in r.edges) != [0, 1, 2]
                         for r in found)
    rng = np.random.default_rng(3)
    es = hexagon.edges[:3]
    for _ in range(200):  # the independent check agrees: never closure
        grasp = [point_contact(e.point(rng.uniform(0, e.length)), e.normal, "hard", mu)
                 for e in es]
        assert analyze(grasp).verdict is not Verdict.CLOSURE


# The triples the search found before the three families (commit 271c0b5, mu 0.3) and their
# shortest segments then: each still has regions, at least as long.
OLD = {"triangle": {(0, 1, 2): 0.2989}, "hexagon": {(0, 2, 4): 0.5177, (1, 3, 5): 0.5177},
       "star": {(0, 4, 9): 0.0186, (0, 5, 6): 0.0186, (0, 5, 9): 0.0186, (1, 2, 6): 0.0186,
                (1, 2, 7): 0.0186},
       "wrench-head": {(0, 3, 7): 1.0, (3, 6, 8): 1.0, (3, 7, 8): 1.0, (0, 5, 7): 0.7404,
                       (1, 6, 8): 0.7404},
       "glyph A": {(0, 3, 6): 1.0817, (0, 1, 6): 0.3553, (0, 5, 6): 0.3501}}


@pytest.mark.parametrize("name", list(OLD))
def test_old_triples_still_found(name):
    polygon = glyph("A") if name == "glyph A" else bundled(name)
    for edges, length in OLD[name].items():
        r = three_finger_regions(polygon, edges, 0.3)
        assert r is not None and r.min_length >= length - 1e-4, (name, edges)


def test_what_was_searched_is_said():
    assert f"{GRID} x {GRID} x {GRID}" in SEARCHED and "does not prove" in SEARCHED
    for family in ("common centre", "prototype", "Corollary 3"):
        assert family in SEARCHED


def test_prototype_whose_lines_meet_at_a_finger():
    """A finger under the frame's hole at x = -1 and one on the hole's left side, also at
    x = -1: the largest-margin equilibrium pushes the bottom finger straight up, through the
    side finger, so its lines meet at a finger and no sector can hold them. Another
    equilibrium of the same prototype (a step in the null space of its wrenches) gives
    regions, which Theorem 1 confirms."""
    from forceclosure.synthesis.planar.three_fingers import _around
    from forceclosure.synthesis.regions import MARGIN, narrowed

    frame, mu = bundled("frame"), 0.3
    points = np.array([[-1.0, -2.0], [-1.0, -0.5], [1.0, -5 / 6]])  # on edges 0, 4, 6
    r = _around(frame, (0, 4, 6), mu, narrowed(mu, MARGIN), points)
    assert r is not None and r.sectors is not None
    assert min(np.linalg.norm(np.asarray(r.centre) - points, axis=1)) > 0.02 * frame.size
    _assert_every_choice_closes(frame, r, mu, np.random.default_rng(2), random=100)

"""The search by levels of one bound (issue 26: a 5000-edge polygon, 3 hard or 4 frictionless
fingers, in seconds rather than a loop over every tuple of edges).

``edge_sites.by_shortest_edge`` gives steps 1 to 3 at once, lazily. Its sites must come in the
order of the full search (every tuple listed, pruned, sorted by its rounded bound, ties by
site), each level's ``later`` must not exceed any site still to come, and the region sets
found must be the full search's, on fine arcs, regular polygons (every bound tied), random
ones and letters of a real font; the full search without a bound (as four frictionless
fingers searched before) finds the same. The regions found are checked by Theorem 1 at the
ends and middles of every region, the 5003-edge arc's too.
"""

import dataclasses
import itertools

import numpy as np
import pytest
import shapely
from matplotlib.font_manager import FontProperties
from matplotlib.textpath import TextPath

from forceclosure import Verdict, analyze, point_contact
from forceclosure.objects import POLYGONS, Polygon, bundled
from forceclosure.synthesis import Hand, search, synthesize
from forceclosure.synthesis.planar.edge_sites import _using
from forceclosure.synthesis.ranked_search import candidate_sites
from forceclosure.synthesis.regions import tie_rounded
from forceclosure.synthesis.table import construction_for

HANDS = {3: Hand(3, "hard", 0.3, top=3), 4: Hand(4, "frictionless", 0.0, top=3)}


def fine_arc(chords: int) -> Polygon:
    """Issue 26's square whose bottom is a ``chords``-chord half-ellipse."""
    t = np.linspace(np.pi, 2 * np.pi, chords + 1)
    return Polygon.from_points(np.r_[np.c_[np.cos(t), 0.3 * np.sin(t)], [[1, 1], [-1, 1]]])


def regular(n: int) -> Polygon:
    t = 2 * np.pi * np.arange(n) / n
    return Polygon.from_points(np.c_[np.cos(t), np.sin(t)])


def wobbly(seed: int, n: int) -> Polygon:
    t = np.sort(np.random.default_rng(seed).uniform(0, 2 * np.pi, n))
    r = 1 + 0.15 * np.sin(3 * t)
    return Polygon.from_points(np.c_[r * np.cos(t), r * np.sin(t)])


def glyph(letter: str) -> Polygon:
    """The outline of a letter of matplotlib's DejaVu Sans (its largest piece): a real
    outline nobody here drew."""
    path = TextPath((0, 0), letter, size=10, prop=FontProperties(family="DejaVu Sans"))
    shape = shapely.Polygon()
    for ring in path.to_polygons():
        if len(ring) >= 4:
            shape = shape.symmetric_difference(shapely.Polygon(ring))  # even-odd fill
    shape = max(getattr(shape, "geoms", [shape]), key=lambda piece: piece.area)
    return Polygon.from_points(np.asarray(shape.exterior.coords)[:-1])


OBJECTS = {**{name: (lambda name=name: bundled(name)) for name in POLYGONS},
           "arc-9": lambda: fine_arc(9), "arc-16": lambda: fine_arc(16),
           "regular-7": lambda: regular(7), "wobbly-11": lambda: wobbly(3, 11),
           "glyph-S": lambda: glyph("S"), "glyph-&": lambda: glyph("&")}


def _holds_at_corners(polygon, found, fingers, mu) -> None:
    """Theorem 1 (``analyze``, the general test) on every region set: each finger at either
    end or the middle of its region, every combination, on the polygon as given."""
    contact = "hard" if fingers == 3 else "frictionless"
    for r in found:
        corners = np.array([[polygon.edges[e].point(t) for t in (u, (u + v) / 2, v)]
                            for e, (u, v) in zip(r.edges, r.segments, strict=True)])
        normals = [polygon.edges[e].normal for e in r.edges]
        for choice in np.ndindex(*[3] * fingers):
            grasp = [point_contact(corners[i, k], normals[i], contact, mu)
                     for i, k in enumerate(choice)]
            assert analyze(grasp).verdict == Verdict.CLOSURE, (r.edges, choice)


def _full_order(c, polygon, hand):
    """Every site, pruned, by decreasing rounded bound, ties by site order, as the full
    search orders them."""
    sites = candidate_sites(c, polygon, hand)
    if not len(sites):
        return []
    bound = np.array([tie_rounded(b) for b in c.bound(polygon, sites, hand)])
    return [(float(bound[k]), tuple(int(e) for e in sites[k]))
            for k in np.argsort(-bound, kind="stable")]


@pytest.mark.parametrize("fingers", [3, 4])
@pytest.mark.parametrize("name", list(OBJECTS))
def test_levels_are_the_full_search_order(fingers, name):
    polygon, hand = OBJECTS[name](), HANDS[fingers]
    c = construction_for(2, fingers, hand.contact)
    levels = list(c.levels(polygon, hand, c.prune))
    ours = [(level.bound, tuple(int(e) for e in row)) for level in levels
            for row in level.sites]
    assert ours == _full_order(c, polygon, hand)
    # nothing after a level comes before its ``later``
    at = 0
    for level in levels:
        at += len(level.sites)
        assert all(level.later <= site for _, site in ours[at:])


def test_tuples_using_an_edge_of_the_level_are_all_of_them_in_order():
    """``_using`` lists exactly the tuples a filter of every combination keeps, in the same
    (lexicographic) order."""
    rng = np.random.default_rng(5)
    for _ in range(400):
        edges = sorted(rng.choice(30, rng.integers(0, 11), replace=False).tolist())
        own = set(rng.choice(edges, rng.integers(0, len(edges) + 1), replace=False).tolist()) \
            if edges else set()
        count = int(rng.integers(1, 5))
        assert list(_using(edges, own, count)) == [
            c for c in itertools.combinations(edges, count) if own & set(c)]


def _found(c, polygon, hand):
    found = search(c, polygon, hand)
    return ([(r.edges, r.segments, r.relative_min_size) for r in found],
            [tuple(int(e) for e in site) for site, _ in found.undecided_sites])


@pytest.mark.parametrize("fingers", [3, 4])
@pytest.mark.parametrize("name", ["arc-9", "arc-16", "regular-7", "wobbly-11", "hexagon",
                                  "square", "l-shape", "glyph-S", "glyph-&"])
def test_a_search_by_levels_finds_what_the_full_search_finds(fingers, name):
    polygon, hand = OBJECTS[name](), HANDS[fingers]
    c = construction_for(2, fingers, hand.contact)
    ours = _found(c, polygon, hand)
    assert ours == _found(dataclasses.replace(c, levels=None), polygon, hand)
    _holds_at_corners(polygon, search(c, polygon, hand), fingers, hand.mu)
    if fingers == 4 and name in ("arc-9", "square", "hexagon"):
        # four frictionless fingers had no bound: every site built
        assert ours == _found(dataclasses.replace(c, levels=None, bound=None), polygon, hand)


@pytest.mark.parametrize("fingers", [3, 4])
def test_the_5003_edge_arc_is_searched_in_levels(fingers):
    """Issue 26's fine arc: the search now ends (it built every tuple of 5003 edges before).
    Its region sets hold by Theorem 1 at every corner (each finger at either end of its
    region), and the best uses the arc's longest chords, where the arc is flattest."""
    polygon, hand = fine_arc(5000), HANDS[fingers]
    taken: list[int] = []
    result = synthesize(polygon, fingers, hand.contact, hand.mu, top=3, progress=taken.append)
    assert len(result.found) == 3 and result.undecided == 0
    # the progress counts each site taken up: the three found among a few dozen of the
    # 2.1e10 triples (2.6e13 quadruples)
    assert set(taken) == {1} and 3 <= len(taken) <= 200
    chords = [e for r in result.found for e in r.edges if e < 5000]
    assert chords and all(abs(e - 2499) <= 2 for e in chords)
    _holds_at_corners(polygon, result.found, fingers, hand.mu)

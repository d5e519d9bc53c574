"""Every construction of the table on every bundled object it serves (issue 16's conformance).

For each entry of the table of constructions and each bundled object of its
dimension, the search's result is empty or made of certified region sets,
ranked by the one rule; each survives an independent check (Theorem 1's
general test, ``analyze``, on points drawn from every region, the regions'
ends and corners included); each record follows ``forceclosure/schemas/regions.schema.json``
and round-trips through JSON; a construction's bound is an upper bound; and
pruning never removes a site on which the construction builds certified
regions. A new construction is tested by its line in the table (synthesis/table.py).
"""

import itertools
import json
import pickle

import jsonschema
import numpy as np
import pytest

from forceclosure import Verdict, analyze, point_contact, vertex_contact
from forceclosure.objects import POLYGONS, POLYHEDRA, bundled
from forceclosure.schemas import load_schema
from forceclosure.synthesis import (
    Hand,
    RegionSet,
    constructions,
    search,
)
from forceclosure.synthesis.construction import Undecided
from forceclosure.synthesis.ranked_search import TIE, candidate_sites
from forceclosure.synthesis.regions import tie_rounded
from forceclosure.synthesis.spatial.patches import sampling_check

SCHEMA = load_schema("regions")

#: The hand each construction is tried with (frictions where every bundled object has grasps
#: for most of them), and the region sets asked for.
HANDS = {
    (2, 2, "hard"): Hand(2, "hard", 0.4, top=3),
    (2, 3, "hard"): Hand(3, "hard", 0.6, top=2),
    (2, 4, "frictionless"): Hand(4, "frictionless", 0.0, top=2),
    (2, 4, "hard"): Hand(4, "hard", 0.4, top=2),
    (3, 2, "soft"): Hand(2, "soft", 0.5, top=2),
    (3, 3, "hard"): Hand(3, "hard", 0.5, top=1),
    (3, 7, "frictionless"): Hand(7, "frictionless", 0.0, samples=5000, top=1),
    (3, None, "any"): Hand(3, "hard", 0.5, samples=3000, top=1),
    (2, None, "any"): Hand(5, "frictionless", 0.0, samples=2000, top=1),
}
#: Constructions that sample prototypes or build slowly: every bundled object in the long
#: profile, the cube (the square in the plane) in the default one.
SLOW = {(3, 3, "hard"), (3, 7, "frictionless"), (3, None, "any"), (2, None, "any")}
#: And single cases over two seconds: Nguyen's two-sided cones between the larger faces.
SLOW_CASES = {((3, 2, "soft", "nguyen"), "holed-block"), ((3, 2, "soft", "nguyen"), "l-prism")}


def _hand(c):
    hand = HANDS[(c.dim, c.fingers, c.contact)]
    return Hand(hand.fingers, "soft", 0.3, top=3) if c.name == "vertices" else hand


def _cases():
    for c in constructions():
        names = POLYGONS if c.dim == 2 else POLYHEDRA
        for name in names:
            slow = (((c.dim, c.fingers, c.contact) in SLOW and name not in ("cube", "square"))
                    or (c.key, name) in SLOW_CASES)
            yield pytest.param(c, name, id=f"{c.dim}d-{c.fingers}-{c.contact}-{c.name}-{name}",
                               marks=[pytest.mark.long] if slow else [])


CASES = list(_cases())


def test_the_table_has_every_construction_of_the_paper():
    keys = {c.key for c in constructions()}
    assert {(2, 2, "hard", "maximal"), (2, 2, "hard", "nguyen"), (2, 2, "hard", "vertices"),
            (2, 3, "hard", "maximal"), (2, 4, "frictionless", "maximal"),
            (2, 4, "frictionless", "nguyen"), (3, 2, "soft", "maximal"),
            (3, 2, "soft", "nguyen"), (3, 3, "hard", "maximal"),
            (3, 7, "frictionless", "maximal"), (3, None, "any", "mesh"),
            (2, None, "any", "grown")} <= keys
    for c in constructions():
        assert c.paper and c.searched and c.method in ("edges", "faces", "mesh")
        assert (c.dim, c.fingers, c.contact) in HANDS, f"no test hand for {c.key}"


def _planar_grasps(r, rng, count):
    """Grasps drawn from a region set on a polygon: every finger at either end of its
    segment (all combinations), then ``count`` random choices; as contacts."""
    polygon = r.object
    if hasattr(r, "vertex"):  # a soft finger on a convex vertex, and an edge or a vertex
        (_, a, b), *other = [polygon.convex_corners[k] for k in
                             (r.vertex, *([r.other[1]] if r.other[0] == "vertex" else []))]
        edges = polygon.edges
        finger = vertex_contact(r.point, [edges[a].normal, edges[b].normal], "soft", r.mu)
        if other:
            (_, a2, b2), = other
            return [[finger, vertex_contact(edges[a2].end, [edges[a2].normal, edges[b2].normal],
                                            "soft", r.mu)]]
        e = edges[r.other[1]]
        ts = np.r_[r.segment, rng.uniform(*r.segment, count)]
        return [[finger, point_contact(e.point(t), e.normal, "hard", r.mu)] for t in ts]
    k = len(r.edges)
    ends = np.array(np.meshgrid(*[[0.0, 1.0]] * k)).reshape(k, -1).T
    fractions = np.vstack([ends, rng.uniform(size=(count, k))])
    grasps = []
    for f in fractions:
        grasp = []
        for e_index, (u, v), mu, x in zip(r.edges, r.segments, r.friction(), f, strict=True):
            e = polygon.edges[e_index]
            model = "hard" if mu > 0 else "frictionless"
            grasp.append(point_contact(e.point(u + x * (v - u)), e.normal, model, mu))
        grasps.append(grasp)
    return grasps


@pytest.mark.parametrize("construction, name", CASES)
def test_a_construction_returns_only_certified_regions_that_hold(construction, name):
    obj, hand = bundled(name), _hand(construction)
    found = search(construction, obj, hand)
    assert len(found) <= hand.top
    ranks = [r.relative_min_size for r in found]
    # the one ranking rule: larger first, sizes within TIE of each other tied
    assert all(b <= a * (1 + TIE) for a, b in itertools.pairwise(ranks))
    rng = np.random.default_rng(7)
    for r in found:
        assert isinstance(r, RegionSet) and r.object is obj
        assert len(r.kinds) == len(r.sizes) == (construction.fingers or hand.fingers)
        assert all((k == "vertex") == (s == 0) for k, s in zip(r.kinds, r.sizes, strict=True))
        assert r.certify().holds
        assert r.min_size == pytest.approx(min(s for s in r.sizes if s > 0) if any(r.sizes)
                                           else 0.0)
        if obj.dim == 2 and not hasattr(r, "vertex"):  # segments on the object as given
            for e, (u, v) in zip(r.edges, r.segments, strict=True):
                assert 0 <= u < v <= obj.edges[e].length
        # independent: Theorem 1's general test on points drawn from every region
        if obj.dim == 2:
            for grasp in _planar_grasps(r, rng, 20):
                assert analyze(grasp).verdict is Verdict.CLOSURE, (r.describe(), grasp)
        else:
            check = sampling_check(r, samples=150)
            assert check.holds, check.detail
        record = r.to_dict()
        jsonschema.validate(record, SCHEMA)
        assert json.loads(json.dumps(record)) == record
        assert (record["min_size"], record["sizes"]) == (r.min_size, list(r.sizes))
        assert record["relative_min_size"] == r.relative_min_size
        assert record["certificate"]["holds"] is True
        again = pickle.loads(pickle.dumps(r))  # with its proof kept (process pools pickle it)
        assert again.certify() == r.certify() and again.sizes == r.sizes


def _pruned_cases():
    """Every case with a prune or a bound; on polyhedra, all but the cube in the long
    profile (each build there costs a second)."""
    for case in CASES:
        c, name = case.values
        if c.prune or c.bound:
            long = c.dim == 3 and name != "cube"
            yield pytest.param(c, name, id=case.id,
                               marks=[pytest.mark.long] if long else case.marks)


@pytest.mark.parametrize("construction, name", list(_pruned_cases()))
def test_pruning_and_bounds_lose_no_regions(construction, name):
    """Sites the prune removes give no certified regions (a sample of them on the slow
    constructions); the bound is above the regions each site gives."""
    obj, hand = bundled(name), _hand(construction)
    every = candidate_sites(construction, obj, hand, prune=False)
    kept = candidate_sites(construction, obj, hand)
    key = (lambda s: tuple(int(x) for x in s)) if isinstance(every, np.ndarray) else tuple
    kept_keys = {key(s) for s in kept}
    removed = [s for s in every if key(s) not in kept_keys]
    assert len(kept) + len(removed) == len(every)
    limit = 40 if construction.dim == 2 else 6
    rng = np.random.default_rng(1)
    picks = rng.permutation(len(removed))[:limit] if removed else []
    for k in picks:
        r = construction.build(obj, removed[k], hand)
        assert r is None or isinstance(r, Undecided) or not r.certify().holds, (name,
                                                                                  removed[k])
    if construction.bound is not None and len(kept):
        bound = construction.bound(obj, kept, hand)
        for k in rng.permutation(len(kept))[:limit]:
            r = construction.build(obj, kept[k], hand)
            if r is not None and not isinstance(r, Undecided):
                assert tie_rounded(r.relative_min_size) <= tie_rounded(bound[k]), kept[k]


def test_synthesize_is_the_table_lookup():
    """The front door picks the table's entry (the mesh method where none fits) and returns
    what the search on that entry returns."""
    from forceclosure.synthesis import construction_for, synthesize

    s = synthesize("hexagon", 2, "hard", 0.4, top=3)
    assert s.construction is construction_for(2, 2, "hard")
    assert [r.edges for r in s.found] == [r.edges for r in
                                          search(s.construction, bundled("hexagon"),
                                                 Hand(2, "hard", 0.4, top=3))]
    assert synthesize("cube", 4, "hard", 0.5, top=1, samples=2000).construction.name == "mesh"


def test_the_command_lists_the_table(capsys):
    from forceclosure.app.cli import main

    assert main(["constructions", "--json"]) == 0
    table = json.loads(capsys.readouterr().out)
    assert [(c["dim"], c["fingers"], c["contact"], c["name"]) for c in table] == [
        c.key for c in constructions()]
    assert main(["constructions"]) == 0
    out = capsys.readouterr().out
    assert "polyhedron, 2 soft fingers, maximal: §5.2" in out and "Lemma 1" in out


def test_a_segment_past_its_edge_is_not_certified():
    """The proof checks that each segment lies within its edge (a region 4e-15 past the end of
    an edge was once certified), whatever the cones say."""
    import dataclasses

    from forceclosure.synthesis import maximal_regions

    r = maximal_regions(bundled("square"), 0, 2, 0.3)
    length = bundled("square").edges[0].length
    (u, v), other = r.segments
    assert r.certify().holds and v < length
    past = dataclasses.replace(r, segments=((u, length * (1 + 1e-15)), other))
    cert = past.certify()
    assert not cert.holds and "not within edge 0" in cert.detail

"""The table of constructions is the one door (issue 27): every entry is reached through
``synthesize``, any other name is refused in one line listing the table, the lookup serves
wildcard entries, and a search keeps no state between calls.

The geometry of each construction's regions is tested against independent truth in the
other files of this folder (and every entry by ``test_constructions.py``); here only which
construction answers.
"""

from __future__ import annotations

import dataclasses
import json

import pytest

from forceclosure.errors import InputError
from forceclosure.objects import bundled
from forceclosure.synthesis import Hand, search, synthesize
from forceclosure.synthesis.table import TABLE, construction_for, constructions, names

#: A hand and object for each entry, and synthesize's settings.
REACH = {
    (2, 2, "hard", "maximal"): ("hexagon", 2, "hard", 0.4, {}),
    (2, 2, "hard", "nguyen"): ("hexagon", 2, "hard", 0.4, {}),
    (2, 2, "hard", "vertices"): ("triangle", 2, "soft", 0.3, {}),
    (2, 3, "hard", "maximal"): ("triangle", 3, "hard", 0.6, {}),
    (2, 4, "frictionless", "maximal"): ("square", 4, "frictionless", 0.0, {}),
    (2, 4, "frictionless", "nguyen"): ("square", 4, "frictionless", 0.0, {}),
    (2, 4, "hard", "maximal"): ("square", 4, "hard", 0.4, {}),
    (3, 2, "soft", "maximal"): ("cube", 2, "soft", 0.5, {}),
    (3, 2, "soft", "nguyen"): ("cube", 2, "soft", 0.5, {}),
    (3, 3, "hard", "maximal"): ("cube", 3, "hard", 0.5, {}),
    (3, 7, "frictionless", "maximal"): ("cube", 7, "frictionless", 0.0, {}),
    (2, None, "any", "grown"): ("square", 5, "frictionless", 0.0, {"samples": 500}),
    (3, None, "any", "mesh"): ("cube", 3, "hard", 0.5, {"samples": 500}),
}


def test_the_table_is_one_list_whose_entries_are_their_constructions():
    keys = [e.key for e in TABLE]
    assert len(set(keys)) == len(keys)
    assert [c.key for c in constructions()] == keys
    assert names() == tuple(dict.fromkeys(k[3] for k in keys))
    assert set(REACH) == set(keys), "a new entry needs a hand here"


@pytest.mark.parametrize("entry", TABLE, ids=lambda e: "-".join(map(str, e.key)))
def test_synthesize_reaches_every_entry_by_its_name(entry, monkeypatch):
    """Which construction ``synthesize`` hands to the search (the search itself, on every
    entry, is test_constructions.py's: here it is replaced by one that records)."""
    from forceclosure.synthesis import best
    from forceclosure.synthesis.ranked_search import Found

    given = []
    monkeypatch.setattr(best, "search",
                        lambda c, obj, hand, progress=None: given.append(c) or Found())
    obj, fingers, contact, mu, settings = REACH[entry.key]
    s = synthesize(obj, fingers, contact, mu, top=1, construction=entry.name, **settings)
    assert [c.key for c in given] == [entry.key] and s.construction is given[0]
    assert s.method == s.construction.method


def test_the_vertex_construction_once_out_of_reach_answers_through_the_door():
    """A triangle has no two-finger grasp on its edges at mu 0.3 (its angles are 60°), but
    a soft finger on a vertex and one on the opposite edge hold it."""
    assert synthesize("triangle", 2, "soft", 0.3, top=1).found == []
    (g,) = synthesize("triangle", 2, "soft", 0.3, top=1, construction="vertices").found
    assert g.other[0] == "edge" and g.certify().holds


def test_synthesize_takes_a_construction_of_ones_own():
    """The table's four-frictionless search with its name changed is run as given: the same
    regions as the table's entry (a square's four sides)."""
    mine = dataclasses.replace(construction_for(2, 4, "frictionless"), name="mine")
    s = synthesize("square", 4, "frictionless", top=1, construction=mine)
    assert s.construction is mine
    assert sorted(s.found[0].edges) == [0, 1, 2, 3]
    with pytest.raises(InputError, match="does not serve 2 hard fingers on a polygon"):
        synthesize("square", 2, "hard", construction=mine)


@pytest.mark.parametrize("obj,fingers,contact,name,message", [
    ("square", 2, "hard", "bogus", "construction must be one of maximal, nguyen, vertices, "
                                   "grown, mesh (the table's names), got 'bogus'"),
    ("cube", 3, "hard", "bogus", "construction must be one of maximal, nguyen, vertices, grown, "
                                 "mesh"),
    ("cube", 3, "hard", "vertices", "construction='vertices': none for 3 hard fingers on a "
                                    "polyhedron; the table has maximal or mesh for them"),
    ("cube", 4, "hard", "vertices", "the table has mesh for them"),
    ("square", 3, "hard", "mesh", "construction='mesh': none for 3 hard fingers on a polygon; "
                                  "the table has maximal or grown for them"),
    ("square", 4, "frictionless", "vertices", "the table has maximal, nguyen or grown for "
                                              "them"),
])
def test_a_name_the_table_has_not_for_the_hand_is_refused_listing_those_it_has(
        obj, fingers, contact, name, message):
    """Once silently the mesh method on a polyhedron; now one line naming the table's."""
    with pytest.raises(InputError) as raised:
        synthesize(obj, fingers, contact, 0.5, construction=name)
    said = str(raised.value)
    assert message in said and "\n" not in said


def test_the_command_line_offers_the_table_and_refuses_others_in_one_line(capsys):
    from forceclosure.app.cli import main

    with pytest.raises(SystemExit) as done:
        main(["synthesize", "--help"])
    assert done.value.code == 0
    out = " ".join(capsys.readouterr().out.split())
    assert "{" + ",".join(names()) + "}" in out
    with pytest.raises(SystemExit) as done:
        main(["synthesize", "square", "--construction", "bogus"])
    assert done.value.code == 2
    err = capsys.readouterr().err.strip()
    assert "invalid choice: 'bogus'" in err and len(err.splitlines()) == 1
    assert main(["synthesize", "cube", "--construction", "vertices"]) == 2
    err = capsys.readouterr().err.strip()
    assert "the table has maximal or mesh for them" in err and len(err.splitlines()) == 1


def test_a_wildcard_entry_serves_the_hands_no_entry_names():
    """``fingers=None, contact="any"`` in either dimension: the fallback is a table entry
    (the grown segments on a polygon, the mesh method in space)."""
    grown = construction_for(2, 5, "hard")                      # the default name falls back
    assert grown.key == (2, None, "any", "grown")
    assert construction_for(2, 5, "soft", "grown") is grown
    assert construction_for(2, 2, "hard").name == "maximal"     # a named hand keeps its own
    assert construction_for(2, 2, "hard", "grown") is grown
    with pytest.raises(InputError, match="none for 5 hard fingers on a polygon; the table "
                                         "has grown for them"):
        construction_for(2, 5, "hard", "nguyen")
    assert construction_for(3, 5, "soft").name == "mesh"       # space: the mesh entry


def test_a_search_keeps_no_state_between_calls():
    """What a construction's steps share (the bound's solve) lives in the search's own memo:
    the hand given is left as it was, and a search on a second polygon with the same hand
    finds that polygon's grasps, not the first's."""
    c, hand = construction_for(2, 2, "hard"), Hand(2, "hard", 0.4, top=1)
    first = search(c, bundled("hexagon"), hand)
    assert hand.memo == {}
    second = search(c, bundled("square"), hand)
    assert [r.edges for r in first] == [(0, 3)] and [r.edges for r in second] == [(0, 2)]


def test_the_dataset_goes_through_the_same_door(tmp_path):
    """``dataset --construction vertices``: the triangle, which no two fingers on edges hold
    at mu 0.3, is held by a soft finger on a vertex and one on the opposite edge (the edge
    not meeting the vertex), and its row says so."""
    import pyarrow.parquet as pq

    from forceclosure.app.cli import main

    out = tmp_path / "out"
    assert main(["dataset", "triangle", "--construction", "vertices", "--out", str(out),
                 "--workers", "1"]) == 0
    (where,) = pq.read_table(out / "results.parquet").column("best_faces").to_pylist()
    best = json.loads(where)
    triangle = bundled("triangle")
    _, a, b = triangle.convex_corners[best["vertex"]]
    assert best["edge"] not in (a, b)

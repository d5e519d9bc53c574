"""Soft fingers on convex vertices, against the analysis core's vertex contact model."""

import numpy as np
import pytest

from forceclosure import Verdict, analyze, point_contact, vertex_contact
from forceclosure.app.cli import main
from forceclosure.objects import bundled, glyph
from forceclosure.synthesis import synthesize
from forceclosure.synthesis.planar.vertex_grasps import convex_vertices


def vertex_grasps(polygon, mu, top=5):
    """The table's vertex construction, through the one door."""
    return synthesize(polygon, 2, "soft", mu, top=top, construction="vertices").found


def test_convex_vertices():
    assert len(convex_vertices(bundled("square"))) == 4
    assert len(convex_vertices(bundled("l-shape"))) == 5  # one reflex corner
    assert len(convex_vertices(bundled("star"))) == 5  # the five tips
    assert len(convex_vertices(bundled("frame"))) == 4  # the hole's corners are reflex


@pytest.mark.parametrize("polygon", [bundled(n) for n in ("triangle", "square", "star",
                                                          "l-shape", "frame", "wrench-head")]
                         + [glyph("A")], ids=lambda p: p.name)
def test_every_vertex_grasp_is_force_closure(polygon):
    rng = np.random.default_rng(3)
    mu = 0.3
    found = vertex_grasps(polygon, mu, top=6)
    assert found
    for g in found:
        assert g.certify().holds
        corners = convex_vertices(polygon)
        _, a, b = corners[g.vertex]
        finger = vertex_contact(g.point, [polygon.edges[a].normal, polygon.edges[b].normal],
                                "soft", mu)
        kind, k = g.other
        if kind == "edge":
            e = polygon.edges[k]
            ts = np.r_[g.segment, rng.uniform(*g.segment, 15)]
            others = [point_contact(e.point(t), e.normal, "hard", mu) for t in ts]
        else:
            _, a2, b2 = corners[k]
            others = [vertex_contact(polygon.edges[a2].end,
                                     [polygon.edges[a2].normal, polygon.edges[b2].normal],
                                     "soft", mu)]
        for other in others:
            assert analyze([finger, other]).verdict is Verdict.CLOSURE, (g.vertex, g.other)


def test_the_triangle_needs_a_vertex():
    """No two fingers on edges hold the triangle at mu 0.3; a finger on a corner does."""
    triangle = bundled("triangle")
    assert synthesize(triangle, 2, "hard", 0.3).found == []
    best = vertex_grasps(triangle, 0.3, top=1)[0]
    assert best.other[0] == "edge" and best.min_length > 0.5


def test_synthesize_with_vertices(capsys):
    import json

    assert main(["synthesize", "triangle", "--vertices", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["grasps"] == [] and out["vertex_grasps"][0]["certificate"]["holds"]
    assert main(["synthesize", "triangle", "--vertices"]) == 0
    assert "with a soft finger on a convex vertex" in capsys.readouterr().out
    assert main(["synthesize", "square", "--vertices", "--fingers", "4",
                 "--contact", "frictionless"]) == 2

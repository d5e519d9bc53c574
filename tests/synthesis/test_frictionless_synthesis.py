"""Four frictionless fingers (§5.4) against exact and independent checks."""

import itertools
from fractions import Fraction

import numpy as np
import pytest

from forceclosure import InputError, Verdict, analyze, point_contact
from forceclosure.objects import bundled
from forceclosure.synthesis import synthesize
from forceclosure.synthesis.planar.four_frictionless import (
    cofactors,
    maximal_frictionless_regions,
)


def test_cofactors_are_the_null_vector_exactly():
    rng = np.random.default_rng(0)
    for _ in range(20):
        pts = [[Fraction(int(x), 4) for x in rng.integers(-8, 8, 2)] for _ in range(4)]
        fs = [[Fraction(int(x), 3) for x in rng.integers(-6, 6, 2)] for _ in range(4)]
        c = cofactors(pts, fs)
        wrenches = [[*f, p[0] * f[1] - p[1] * f[0]] for p, f in zip(pts, fs, strict=True)]
        for row in range(3):
            assert sum(ci * w[row] for ci, w in zip(c, wrenches, strict=True)) == 0


def test_cofactor_signs_decide_closure_like_theorem_1():
    rng = np.random.default_rng(1)
    seen = set()
    for _ in range(300):
        pts = rng.uniform(-1, 1, (4, 2))
        angles = rng.uniform(0, 2 * np.pi, 4)
        normals = np.stack([np.cos(angles), np.sin(angles)], 1)
        c = np.array(cofactors(list(pts), list(-normals)))
        same_sign = np.all(c > 0) or np.all(c < 0)
        a = analyze([point_contact(p, n, "frictionless") for p, n in zip(pts, normals,
                                                                         strict=True)])
        if np.min(np.abs(c)) > 1e-3:
            assert (a.verdict is Verdict.CLOSURE) == same_sign
            seen.add(same_sign)
    assert seen == {True, False}


@pytest.mark.parametrize("name", ["square", "hexagon", "l-shape", "frame", "star",
                                  "wrench-head", "bracket"])
def test_every_quadruple_in_every_region_is_force_closure(name):
    polygon = bundled(name)
    rng = np.random.default_rng(2)
    found = synthesize(polygon, 4, "frictionless", top=3).found
    assert found
    for r in found:
        assert r.certify().holds
        edges = [polygon.edges[k] for k in r.edges]
        corners = list(itertools.product(*r.segments))
        samples = corners + [tuple(rng.uniform(u, v) for u, v in r.segments)
                             for _ in range(40)]
        for ts in samples:
            grasp = [point_contact(e.point(t), e.normal, "frictionless")
                     for e, t in zip(edges, ts, strict=True)]
            assert analyze(grasp).verdict is Verdict.CLOSURE, (name, r.edges, ts)
        # thousands more, by Theorem 1 computed another way: the null vector of the
        # 3 x 4 wrench matrix (batched SVD) has one strict sign and the rank is 3
        t = np.stack([rng.uniform(u, v, 3000) for u, v in r.segments], axis=1)
        pts = np.stack([e.start + t[:, [k]] * e.direction for k, e in enumerate(edges)], 1)
        forces = -np.array([e.normal for e in edges])
        torque = pts[..., 0] * forces[:, 1] - pts[..., 1] * forces[:, 0]
        W = np.concatenate([np.broadcast_to(forces.T, (len(t), 2, 4)), torque[:, None, :]], 1)
        _, sv, vh = np.linalg.svd(W)
        null = vh[:, -1, :]
        assert np.all(sv[:, 2] > 1e-9)
        assert np.all(np.all(null > 0, axis=1) | np.all(null < 0, axis=1))
    lengths = [r.min_length for r in found]
    assert all(a >= b - 1e-12 for a, b in itertools.pairwise(lengths))


def test_square_pinwheel_is_half_of_each_side():
    """With no room for turned normals, the pinwheel's half sides (less what keeps the
    cofactors STRICT * size from zero)."""
    from forceclosure.synthesis.planar.four_frictionless import STRICT

    r = maximal_frictionless_regions(bundled("square"), (0, 1, 2, 3), margin=1e-12)
    want = 1 - STRICT * bundled("square").size / 2
    assert r.min_length == pytest.approx(want, rel=1e-6)


@pytest.mark.parametrize("margin", [1e-3, 0.05, 0.2])
def test_regions_hold_for_every_normal_within_the_margin(margin):
    """The margin's one meaning: every quadruple in the regions, with every pushing
    direction turned by up to ``margin``, is force-closure (Theorem 1, independently, at the
    corners with the extreme turns and at random points and turns); the regions shrink as
    the margin grows; a grasp just outside the turned normals' reach is not claimed."""
    square = bundled("square")
    rng = np.random.default_rng(7)
    r = maximal_frictionless_regions(square, (0, 1, 2, 3), margin=margin)
    assert r.certify().holds and r.margin == margin
    assert r.min_length < maximal_frictionless_regions(square, (0, 1, 2, 3),
                                                       margin=margin / 2).min_length
    edges = [square.edges[k] for k in r.edges]

    def closed(ts, turns):
        grasp = []
        for e, t, a in zip(edges, ts, turns, strict=True):
            c, s = np.cos(a), np.sin(a)
            n = np.array([c * e.normal[0] - s * e.normal[1], s * e.normal[0] + c * e.normal[1]])
            grasp.append(point_contact(e.point(t), n, "frictionless"))
        return analyze(grasp).verdict is Verdict.CLOSURE

    for ts in itertools.product(*r.segments):
        for turns in itertools.product((-margin, margin), repeat=4):
            assert closed(ts, turns)
    for _ in range(200):
        ts = [rng.uniform(u, v) for u, v in r.segments]
        assert closed(ts, rng.uniform(-margin, margin, 4))


def test_refusals_and_empty_cases():
    square = bundled("square")
    with pytest.raises(InputError, match="four different edges"):
        maximal_frictionless_regions(square, (0, 0, 1, 2))
    with pytest.raises(InputError, match="no edge 7"):
        maximal_frictionless_regions(square, (0, 1, 2, 7))
    assert synthesize(bundled("triangle"), 4, "frictionless").found == []  # three edges only


@pytest.mark.parametrize("name", ["square", "hexagon", "l-shape", "frame", "star",
                                  "wrench-head", "bracket"])
def test_nguyen_construction_holds_and_never_beats_the_maximal_regions(name):
    from forceclosure.synthesis import nguyen_frictionless_regions

    polygon = bundled(name)
    rng = np.random.default_rng(6)
    built = 0
    for quad in itertools.combinations(range(len(polygon.edges)), 4):
        g = nguyen_frictionless_regions(polygon, quad)
        if g is None:
            continue
        built += 1
        assert g.certify().holds
        edges = [polygon.edges[k] for k in g.edges]
        ts = tuple(rng.uniform(u, v) for u, v in g.segments)
        grasp = [point_contact(e.point(t), e.normal, "frictionless")
                 for e, t in zip(edges, ts, strict=True)]
        assert analyze(grasp).verdict is Verdict.CLOSURE
        # a certified box is feasible for the maximal LP with a negligible margin
        m = maximal_frictionless_regions(polygon, quad, margin=1e-9)
        assert m.min_length >= g.min_length - 1e-8 * polygon.size
    assert built > 0


def test_four_finger_command_draws(tmp_path, capsys):
    from forceclosure.app.cli import main

    picture = tmp_path / "four.svg"
    assert main(["synthesize", "bracket", "--fingers", "4", "--contact", "frictionless",
                 "--plot", str(picture)]) == 0
    assert "certified: True" in capsys.readouterr().out
    assert picture.read_text().lstrip().startswith("<?xml")


def test_the_float_filter_defers_boundary_cases_to_rationals():
    """The square's pinwheel up to the side's midpoint: there the four pushes pass through
    one point and the cofactors are exactly zero, which floating point cannot tell from a
    tiny number of either sign. The filter must defer it, and the rationals refuse it;
    a hair shorter, every sign is proved."""
    from forceclosure.synthesis.planar.four_frictionless import FrictionlessRegions

    square = bundled("square")
    r = maximal_frictionless_regions(square, (0, 1, 2, 3), margin=1e-12)
    edges = r.edges
    at_centre = FrictionlessRegions(square, edges, ((0.0, 1.0), (1.0, 2.0), (0.0, 1.0),
                                                    (1.0, 2.0)), "test")
    assert not at_centre.certify().holds
    inside = FrictionlessRegions(square, edges, ((0.0, 0.99), (1.01, 2.0), (0.0, 0.99),
                                                 (1.01, 2.0)), "test")
    assert inside.certify().holds
    # the same boxes decided by the rationals alone (the filter's bound made useless)
    import forceclosure.synthesis.planar.four_frictionless as module

    real = module._cofactors_with_bounds
    try:
        module._cofactors_with_bounds = lambda P, F: (real(P, F)[0], np.full(
            real(P, F)[0].shape, np.inf))
        assert not at_centre.certify().holds and inside.certify().holds
        assert r.certify().holds
    finally:
        module._cofactors_with_bounds = real

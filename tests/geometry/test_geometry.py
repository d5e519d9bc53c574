"""forceclosure.geometry against closed forms and shapely.

* counter_overlap: the angle between ``-n_i`` and ``n_j`` set by construction
  (a rotation of known angle), against ``atan(mu_i) + atan(mu_j)``; at right
  angles the closed form ``mu_i mu_j > 1`` (``tan(a + b)`` is infinite when
  ``tan a tan b = 1``); three fingers 120 degrees apart need ``mu > tan 30``.
* friction_forces: unit normal component, edges at the pyramid's radius from
  the axis, circumscribed faces tangent to the cone (``r cos(pi / k) = mu``).
* clip: areas against shapely's intersection with the half-plane.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely
from hypothesis import assume, given
from hypothesis import strategies as st

from forceclosure.geometry import (
    angle_between,
    clip,
    counter_overlap,
    counter_overlap_angle,
    friction_forces,
    pyramid_radius,
)
from forceclosure.synthesis.planar.two_fingers import counter_overlapping_sector
from forceclosure.synthesis.spatial.three_hard import counter_overlap as three_hard_counter_overlap
from forceclosure.synthesis.spatial.two_soft import counter_overlapping_cone

angles = st.floats(0.0, math.pi)
#: Frictionless, or wide enough that a cone's width is more than rounding.
frictions = st.one_of(st.just(0.0), st.floats(1e-6, 20.0))
#: Cases closer than this (radians) to the boundary are not asserted: the closed form is
#: exact, the floating-point angle is not.
EDGE = 1e-9


def _spatial_pair(phi: float, psi: float, tilt: float) -> tuple[np.ndarray, np.ndarray]:
    """Normals with angle(-n_i, n_j) = phi: n_i = -a and n_j = R a', where a' is ``a``
    rotated by phi about an axis perpendicular to it (chosen by psi), and the pair is
    rotated as a whole about x by tilt."""
    a = np.array([0.0, 0.0, 1.0])
    b = np.array([math.sin(phi) * math.cos(psi), math.sin(phi) * math.sin(psi), math.cos(phi)])
    c, s = math.cos(tilt), math.sin(tilt)
    R = np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    return -(R @ a), R @ b


@given(angles, st.floats(0, 2 * math.pi), st.floats(0, 2 * math.pi), frictions, frictions)
def test_spatial_cones_overlap_when_their_angle_is_below_the_half_angles(phi, psi, tilt, m1,
                                                                         m2):
    n_i, n_j = _spatial_pair(phi, psi, tilt)
    assert float(counter_overlap_angle(n_i, n_j)) == pytest.approx(phi, abs=1e-12)
    half_angles = math.atan(m1) + math.atan(m2)
    assume(abs(phi - half_angles) > EDGE)
    expected = phi < half_angles and m1 > 0 and m2 > 0  # a ray has no interior
    assert bool(counter_overlap(n_i, n_j, m1, m2)) == expected
    # unnormalised normals, and the three_hard name, give the same answer
    assert bool(counter_overlap(3.0 * n_i, 0.25 * n_j, m1, m2)) == expected
    assert three_hard_counter_overlap(n_i, n_j, m1, m2) == expected
    # the largest cone in C_i ∩ -C_j exists exactly when they counter-overlap
    assert (counter_overlapping_cone(n_i, m1, n_j, m2) is not None) == expected


@given(st.floats(-math.pi, math.pi), angles, frictions, frictions)
def test_planar_cones_overlap_when_their_angle_is_below_the_half_angles(theta, phi, m1, m2):
    n_i = np.array([math.cos(theta), math.sin(theta)])
    turn = theta + math.pi + phi  # -n_i turned by phi
    n_j = np.array([math.cos(turn), math.sin(turn)])
    half_angles = math.atan(m1) + math.atan(m2)
    assume(abs(phi - half_angles) > EDGE)
    expected = phi < half_angles and m1 > 0 and m2 > 0  # a ray has no interior
    assert bool(counter_overlap(n_i, n_j, m1, m2)) == expected
    # Lemma 1's exact sector is non-empty exactly then
    assert (counter_overlapping_sector(n_i, m1, n_j, m2) is not None) == expected


@given(frictions, frictions)
def test_at_right_angles_the_cones_overlap_iff_the_product_of_frictions_exceeds_one(m1, m2):
    assume(abs(m1 * m2 - 1.0) > 1e-9)
    expected = m1 * m2 > 1.0
    assert bool(counter_overlap([0.0, 0.0, 1.0], [1.0, 0.0, 0.0], m1, m2)) == expected
    assert bool(counter_overlap([0.0, 1.0], [1.0, 0.0], m1, m2)) == expected


def test_hand_derived_cases():
    up, down = [0.0, 0.0, 1.0], [0.0, 0.0, -1.0]
    assert counter_overlap(up, down, 1e-6)          # opposite faces: any friction
    assert not counter_overlap(up, down, 0.0)       # ... but frictionless cones have no interior
    assert not counter_overlap(up, up, 1e9)         # one face: pi is never below the sum
    # three fingers 120 degrees apart: -n_i and n_j are 60 degrees apart, so each pair
    # needs 2 atan(mu) > 60 degrees, mu > tan 30 = 0.57735
    t = np.radians([90.0, 210.0])
    ring = np.column_stack([np.cos(t), np.sin(t)])
    assert math.degrees(float(counter_overlap_angle(ring[0], ring[1]))) == pytest.approx(60.0)
    assert not counter_overlap(ring[0], ring[1], 0.577)
    assert counter_overlap(ring[0], ring[1], 0.578)


def test_vectorised_rows_match_single_pairs():
    rng = np.random.default_rng(5)
    for d in (2, 3):
        n_i, n_j = rng.normal(size=(50, d)), rng.normal(size=(50, d))
        mu_i, mu_j = rng.uniform(0, 2, 50), rng.uniform(0, 2, 50)
        rows = counter_overlap(n_i, n_j, mu_i, mu_j)
        assert rows.shape == (50,)
        assert rows.tolist() == [bool(counter_overlap(a, b, x, y))
                                 for a, b, x, y in zip(n_i, n_j, mu_i, mu_j, strict=True)]


def test_angle_between_closed_forms():
    assert float(angle_between([1.0, 0.0], [0.0, 3.0])) == pytest.approx(math.pi / 2)
    assert float(angle_between([1.0, 1.0, 0.0], [1.0, 0.0, 0.0])) == pytest.approx(math.pi / 4)
    assert float(angle_between([1.0, 0.0, 0.0], [-2.0, 0.0, 0.0])) == math.pi
    # stable near 0, where acos of a rounded cosine is not: 1e-9 rad is seen
    assert float(angle_between([1.0, 0.0], [1.0, 1e-9])) == pytest.approx(1e-9, rel=1e-12)


@given(st.integers(3, 64), st.floats(0.0, 5.0), st.booleans())
def test_the_pyramid_has_its_edges_on_its_radius_and_its_faces_on_the_cone(edges, mu, outer):
    normal = np.array([[2.0, -1.0, 0.5]]) / math.sqrt(5.25)
    radius = pyramid_radius(mu, edges, outer)
    f = friction_forces(normal, radius, edges)[0]
    assert f.shape == (edges, 3)
    assert np.allclose(f @ -normal[0], 1.0)  # unit normal component
    tangential = f + normal[0]
    assert np.allclose(np.linalg.norm(tangential, axis=1), radius)
    # the midpoints of neighbouring edges: on the cone (radius mu) when circumscribed,
    # inside it by cos(pi / edges) when inscribed
    mid = 0.5 * (tangential + np.roll(tangential, -1, axis=0))
    expected = mu if outer else mu * math.cos(math.pi / edges)
    assert np.allclose(np.linalg.norm(mid, axis=1), expected)
    # successive edges turn by 2 pi / edges about the axis
    if mu > 1e-6:
        turn = angle_between(tangential, np.roll(tangential, -1, axis=0))
        assert np.allclose(turn, 2 * math.pi / edges)


def test_planar_cone_is_exact():
    f = friction_forces(np.array([[0.0, 1.0]]), 0.5)[0]
    assert f.tolist() == [[-0.5, -1.0], [0.5, -1.0]]
    assert friction_forces(np.array([[0.0, 1.0]]), None).tolist() == [[[-0.0, -1.0]]]


convex = st.integers(3, 12).flatmap(
    lambda k: st.lists(st.floats(0, 2 * math.pi), min_size=k, max_size=k, unique=True))


@given(convex, st.floats(0, 2 * math.pi), st.floats(-1.2, 1.2))
def test_clip_matches_shapely(thetas, direction, offset):
    ring = np.column_stack([np.cos(sorted(thetas)), np.sin(sorted(thetas))])
    polygon = shapely.Polygon(ring)
    assume(polygon.area > 1e-6)
    a = np.array([[math.cos(direction), math.sin(direction)]])
    out = clip(ring, a, np.array([offset]))
    # the half-plane a . y >= offset, as a large box
    u, v = a[0], np.array([-a[0, 1], a[0, 0]])
    box = shapely.Polygon([offset * u - 10 * v, offset * u + 10 * v,
                           (offset + 10) * u + 10 * v, (offset + 10) * u - 10 * v])
    truth = polygon.intersection(box).area
    got = shapely.Polygon(out).area if len(out) >= 3 else 0.0
    assert got == pytest.approx(truth, abs=1e-9)


def test_signed_area_closed_forms_and_shapely():
    """The one polygon area (geometry.rings): a regular n-gon of circumradius r is
    (n/2) r^2 sin(2 pi / n), anticlockwise positive, clockwise negative, unchanged by a
    translation far from the origin; and it agrees with shapely (GEOS) on glyph outlines."""
    from matplotlib.textpath import TextPath

    from forceclosure.geometry import signed_area

    for n in (3, 4, 7, 40):
        t = 2 * np.pi * np.arange(n) / n
        ring = 2.0 * np.column_stack([np.cos(t), np.sin(t)])
        expected = n / 2 * 4.0 * np.sin(2 * np.pi / n)
        assert signed_area(ring) == pytest.approx(expected, rel=1e-12)
        assert signed_area(ring[::-1]) == pytest.approx(-expected, rel=1e-12)
        assert signed_area(ring + 1e8) == pytest.approx(expected, rel=1e-6)
    assert signed_area(np.zeros((2, 2))) == 0.0 and signed_area(np.zeros((0, 2))) == 0.0
    for glyph in "SQ&":
        for loop in TextPath((0, 0), glyph, size=10).to_polygons():
            ring = loop[:-1]  # the path repeats its first point
            assert signed_area(ring) == pytest.approx(
                shapely.Polygon(ring).area * np.sign(signed_area(ring)), rel=1e-9, abs=1e-9)

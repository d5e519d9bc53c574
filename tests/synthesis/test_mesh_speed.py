"""The fast paths for large meshes (issue 18) against independent truth.

The shortcuts taken for curved meshes (a one-triangle face's outline without
building its polygon, the search-zone proof checked in one pass, the
generators of many faces in one call, cached sizes) must give what the slow
paths and independent tools give: the polygon validated through shapely,
trimesh's bounding box, closed-form distances, and the general analysis of
sampled grasps with exact cones (``sampling_check``).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pybullet_data
import pytest
import trimesh

from forceclosure.objects import Polyhedron, bundled
from forceclosure.objects.io import load_object
from forceclosure.objects.polyhedron import _member
from forceclosure.synthesis.spatial.patches import _ccw, convex_pieces, sampling_check
from forceclosure.synthesis.spatial.zones import (
    _affine_batch,
    _generators,
    _segment_distances,
    _zone_conditions,
    _zone_conditions_one_by_one,
    finger_generators,
    prototype_grasps,
    zone_regions,
)

DUCK = Path(pybullet_data.getDataPath()) / "duck.obj"


@pytest.fixture(scope="module")
def duck() -> Polyhedron:
    return load_object(DUCK)


def test_triangle_outline_is_the_validated_polygon(duck):
    """On a real mesh nobody here wrote, every one-triangle face's shortcut outline is,
    to the last bit, the outer ring the shapely-validated polygon holds, and the convex
    piece is the ring shapely gives back; its size is the polygon's."""
    fast = 0
    for face in duck.faces:
        ring = face.triangle_outline
        if ring is None:
            assert len(face.triangles) > 1 or face.plane_size == face.polygon.size
            continue
        fast += 1
        assert np.array_equal(ring, face.polygon.outer)
        assert face.plane_size == face.polygon.size
        slow = _ccw(np.asarray(face.polygon.to_shapely().exterior.coords)[:-1])
        [piece] = convex_pieces(face)
        assert np.array_equal(piece, slow)
    assert fast > 0.9 * len(duck.faces)  # the duck is curved: nearly all faces one triangle


def test_size_and_area_match_trimesh(duck):
    """The cached object size is the bounding-box diagonal and the area the surface area,
    as trimesh measures them on the same file."""
    mesh = trimesh.load(DUCK, force="mesh")
    assert duck.size == pytest.approx(float(np.linalg.norm(mesh.extents)), rel=1e-12)
    assert duck.area == pytest.approx(float(mesh.area), rel=1e-9)
    assert duck.size is duck.size  # computed once


def test_member_is_isin():
    rng = np.random.default_rng(0)
    x, of = rng.integers(0, 10**12, 5000), rng.integers(0, 10**12, 7000)
    x[::3] = of[: len(x[::3])]  # a third present
    assert np.array_equal(_member(x, of), np.isin(x, of))


def test_segment_distances_closed_form():
    """Distances to the unit square's outline in the plane z = 0, by hand."""
    square = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], dtype=float)
    points = np.array([[0.5, 0.5, 0], [2, 0.5, 0], [2, 2, 0], [0.5, 0.2, 3], [1, 1, 0]])
    expected = [0.5, 1.0, np.sqrt(2), np.sqrt(0.2**2 + 9), 0.0]
    np.testing.assert_allclose(_segment_distances(points, square), expected, atol=1e-15)


def test_affine_generators_of_many_faces(duck):
    """The affine form of each face's generators, computed for many faces in one call,
    gives the generators computed directly at points of the face."""
    p = np.array([[0.0, 0.0, 1.0], [0.3, 0.3, -1.0], [-0.3, -0.3, -1.0]])
    zones = zone_regions(bundled("cube"), p, "hard", 0.5, grow=False).zones
    faces = list(duck.faces[::97])
    uv = np.array([0.3, -0.7])
    for face, (w0, wu, wv) in zip(faces, _affine_batch(faces, zones, "hard", 0.5, 8),
                                  strict=True):
        at = _generators(face.to_world(uv)[None], face.normal[None], "hard", 0.5, 8,
                         zones.reference, zones.length_scale)[0]
        np.testing.assert_allclose(w0 + uv[0] * wu + uv[1] * wv, at, atol=1e-12)


@pytest.mark.parametrize("fingers, model", [(3, "hard"), (2, "soft")])
def test_grown_regions_hold_on_a_curved_mesh(fingers, model):
    """Regions grown over a 5120-triangle sphere: the proof holds, checked in one pass
    and condition by condition alike, and thousands of point tuples drawn from the
    regions are force-closure by the general analysis with exact cones."""
    sphere = Polyhedron.from_trimesh(trimesh.creation.icosphere(subdivisions=4))
    [proto] = prototype_grasps(sphere, fingers, model, 0.5, samples=2000)
    r = zone_regions(sphere, proto, model, 0.5)
    assert sum(len(region) for region in r.regions) > 3 * fingers  # grown over faces
    cert = r.certify()
    assert cert.holds, cert.detail
    assert r.certify() is cert  # proved once
    model_, mu, every = finger_generators(r.model, r.mu, r.margin, r.edges)
    failed, counted = _zone_conditions_one_by_one(r, r.zones, model_, mu, every)
    assert failed is None and counted == _zone_conditions(r, r.zones, model_, mu, every) > 0
    check = sampling_check(r, samples=1000)
    assert check.holds, check.detail

"""The outer surface of multi-part meshes, and regions of contact that stay on it.

Ground truth nobody here computed: closed forms for unions of boxes, the ORIGINAL
files' triangles (read by trimesh) with winding numbers written out in the tests, and
trimesh's closest points.
"""

from __future__ import annotations

import os

import numpy as np
import pybullet_data
import pytest
import trimesh
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from forceclosure.objects import Polyhedron
from forceclosure.objects.io import load_object
from forceclosure.synthesis.best import synthesize

DATA = pybullet_data.getDataPath()


def winding_number(V, T, points):
    """Generalised winding numbers of points (Van Oosterom-Strackee solid angles)."""
    points = np.atleast_2d(points)
    out = []
    for chunk in np.array_split(points, max(1, len(points) * len(T) // 1_000_000)):
        a, b, c = (V[T[:, i]][None] - chunk[:, None] for i in range(3))
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        num = np.einsum("kij,kij->ki", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("kij,kij->ki", a, b) * lc
               + np.einsum("kij,kij->ki", b, c) * la + np.einsum("kij,kij->ki", c, a) * lb)
        out.append(np.sum(2 * np.arctan2(num, den), axis=1) / (4 * np.pi))
    return np.concatenate(out)


def distance_to_triangles(p, tris):
    """Distance from point p to each triangle (k, 3, 3): to the plane where p projects
    inside, else to the nearest edge. (trimesh's closest points go wrong on the sliver
    triangles of VHACD's hulls, by up to 1e-4 of the teddy's size.)"""
    a, b, c = tris[:, 0], tris[:, 1], tris[:, 2]
    n = np.cross(b - a, c - a)
    length = np.linalg.norm(n, axis=1)
    flat = length > 0
    n = n / np.where(flat, length, 1)[:, None]
    height = np.einsum("ij,ij->i", p - a, n)
    foot = p - height[:, None] * n
    inside = flat.copy()
    edge = np.full(len(a), np.inf)
    for x, y in ((a, b), (b, c), (c, a)):
        d = y - x
        inside &= np.einsum("ij,ij->i", np.cross(d, foot - x), n) >= 0
        s = np.clip(np.einsum("ij,ij->i", p - x, d) / np.einsum("ij,ij->i", d, d), 0, 1)
        edge = np.minimum(edge, np.linalg.norm(x + s[:, None] * d - p, axis=1))
    return np.where(inside, np.abs(height), edge)


def original_pieces(path):
    """The file's triangles as trimesh reads them, split into connected pieces, each turned
    to face out by its own signed volume."""
    mesh = trimesh.load(path, force="mesh")  # trimesh merges the duplicated vertices
    m = len(mesh.faces)
    rows = np.repeat(np.arange(m), 3)
    graph = coo_matrix((np.ones(3 * m), (rows, m + mesh.faces.reshape(-1))),
                       shape=(m + len(mesh.vertices),) * 2)
    label = connected_components(graph, directed=False)[1][:m]
    pieces = []
    for k in np.unique(label):
        piece = trimesh.Trimesh(mesh.vertices, mesh.faces[label == k], process=False)
        if piece.volume < 0:
            piece.invert()
        pieces.append(piece)
    return mesh, pieces


def _box(lo, hi):
    box = trimesh.creation.box(bounds=[lo, hi])
    return box.vertices, box.faces


def _boxes(*bounds):
    V, T, n = [], [], 0
    for lo, hi in bounds:
        v, t = _box(lo, hi)
        V.append(v)
        T.append(t + n)
        n += len(v)
    return np.vstack(V), np.vstack(T)


def test_a_plus_of_two_crossing_bars():
    """Two 3x1x1 bars crossing at right angles: a plus-shaped prism, 5 in volume; its top
    and bottom are one plus-shaped face each (area 5, with new corners where the bars
    cross), and 12 unit squares around."""
    V, T = _boxes(([-1.5, -0.5, -0.5], [1.5, 0.5, 0.5]), ([-0.5, -1.5, -0.5], [0.5, 1.5, 0.5]))
    plus = Polyhedron.from_arrays(V, T, name="plus")
    assert plus.warnings == ("merged 2 overlapping shells into their outer surface",)
    assert plus.watertight and plus.shells == 1
    assert plus.volume == pytest.approx(5.0, rel=1e-12)
    assert plus.area == pytest.approx(2 * 5 + 12, rel=1e-12)
    assert len(plus.faces) == 14
    caps = sorted(f.area for f in plus.faces if abs(f.normal[2]) > 0.5)
    assert caps == pytest.approx([5.0, 5.0], rel=1e-12)
    assert sorted(len(f.polygon.outer) for f in plus.faces if abs(f.normal[2]) > 0.5) == [12, 12]


def test_touching_and_nested_and_apart():
    """Two unit cubes pressed together over half a face (no vertex shared) are one solid:
    volume 2, area 12 - 2 x 0.5, 10 planar faces (one bottom, one top); a cube inside
    another vanishes; cubes apart stay as they are, with no warning."""
    touching = Polyhedron.from_arrays(*_boxes(([0, 0, 0], [1, 1, 1]),
                                              ([1, 0.5, 0], [2, 1.5, 1])))
    assert touching.shells == 1 and touching.watertight
    assert (len(touching.faces), touching.area, touching.volume) == (10, pytest.approx(11),
                                                                     pytest.approx(2))
    nested = Polyhedron.from_arrays(*_boxes(([0, 0, 0], [3, 3, 3]), ([1, 1, 1], [2, 2, 2])))
    assert (len(nested.faces), nested.area, nested.volume) == (6, pytest.approx(54),
                                                               pytest.approx(27))
    apart = Polyhedron.from_arrays(*_boxes(([0, 0, 0], [1, 1, 1]), ([2, 0, 0], [3, 1, 1])))
    assert apart.warnings == () and apart.shells == 2 and len(apart.triangles) == 24


def test_an_open_shell_inside_a_closed_one_is_dropped():
    """A cube with its lid missing (open), inside a larger closed cube, is not on the
    surface: its hole is inside, so it is capped and swallowed by the union; a flat sheet
    inside has no volume to join and is dropped. Moved up to stick out of the lid, only
    the open cube's bottom (2 triangles) is inside; its 8 side triangles cross the lid:
    partly inside, they are dropped too (a region on them could reach into the solid), and
    said so."""
    big_v, big_t = _box([-2, -2, -2], [2, 2, 2])
    V, T = _box([-1, -1, -1], [1, 1, 1])
    top = np.flatnonzero(V[T][:, :, 2].min(axis=1) > 0.99)
    inner = np.delete(T, top, axis=0)
    poly = Polyhedron.from_arrays(np.vstack([big_v, V]), np.vstack([big_t, inner + 8]),
                                  allow_open=True)
    assert len(poly.triangles) == 12 and poly.watertight and poly.volume == pytest.approx(64)
    assert any("capped 1 holes" in w for w in poly.warnings)
    sheet = Polyhedron.from_arrays(np.vstack([big_v, [[0, 0, 0], [1, 0, 0], [1, 1, 0],
                                                      [0, 1, 0]]]),
                                   np.vstack([big_t, [[8, 9, 10], [8, 10, 11]]]),
                                   allow_open=True)
    assert len(sheet.triangles) == 12 and sheet.watertight
    assert any("dropped 2 triangles" in w for w in sheet.warnings)
    out = Polyhedron.from_arrays(np.vstack([big_v, V + np.array([0, 0, 2.5])]),
                                 np.vstack([big_t, inner + 8]), allow_open=True)
    assert len(out.triangles) == 12 and out.volume == pytest.approx(64)
    assert any("dropped 2 triangles" in w for w in out.warnings)
    assert any(w.startswith("dropped 8 triangles") and "cross into a closed shell" in w
               for w in out.warnings)


@pytest.mark.parametrize("name", ["random_urdfs/000/000.obj", "duck_vhacd.obj",
                                  "teddy2_VHACD_CHs.obj", "random_urdfs/357/357.obj"])
def test_union_triangles_keep_the_original_planes(name):
    """Every triangle of the outer surface lies on an original triangle (its centroid at
    distance ~0) with the same outward normal: the union adds vertices on the curves where
    pieces cross, never a new plane."""
    path = os.path.join(DATA, name)
    poly = load_object(path)
    assert any("merged" in w for w in poly.warnings)
    _, pieces = original_pieces(path)
    tris = np.vstack([p.triangles for p in pieces])
    normals = np.vstack([p.face_normals for p in pieces])
    V, T = poly.vertices, poly.triangles
    centres = V[T].mean(axis=1)
    cross = np.cross(V[T[:, 1]] - V[T[:, 0]], V[T[:, 2]] - V[T[:, 0]])
    big = np.linalg.norm(cross, axis=1) > 1e-9 * poly.size**2  # slivers have no normal
    own = cross[big] / np.linalg.norm(cross[big], axis=1, keepdims=True)
    for c, n in zip(centres[big], own, strict=True):
        on = distance_to_triangles(c, tris) <= 1e-9 * poly.size
        assert on.any()
        assert np.max(normals[on] @ n) > 1 - 1e-9


def check_regions_on_outer_surface(path, found, samples=2000):
    """Each region's points lie on the ORIGINAL file's surface, a step outward along the
    face's normal is outside every original piece, and a step inward inside one."""
    mesh, pieces = original_pieces(path)
    size = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    eps = 1e-7 * size
    for r in found:
        points, normals = r.sample(samples, seed=1)
        p, n = points.reshape(-1, 3), normals.reshape(-1, 3)
        distance = [distance_to_triangles(q, mesh.triangles).min() for q in p]
        assert np.max(distance) <= 1e-9 * size
        outside = p + eps * n
        inside = p - eps * n
        deepest = np.zeros(len(p))
        for piece in pieces:
            assert np.all(winding_number(piece.vertices, piece.faces, outside) < 0.5)
            deepest = np.maximum(deepest, winding_number(piece.vertices, piece.faces, inside))
        assert np.all(deepest > 0.5)


@pytest.mark.parametrize("name,fingers,contact,samples,seed", [
    ("random_urdfs/000/000.obj", 2, "soft", 4000, 1),  # the reproduction
    pytest.param("duck_vhacd.obj", 2, "soft", 4000, 0, marks=pytest.mark.long),  # 5 s
    pytest.param("random_urdfs/001/001.obj", 3, "hard", 3000, 0, marks=pytest.mark.long),  # 7 s
    pytest.param("random_urdfs/357/357.obj", 2, "soft", 3000, 0, marks=pytest.mark.long),
])
def test_synthesized_regions_lie_on_the_outer_surface(name, fingers, contact, samples, seed):
    path = os.path.join(DATA, name)
    result = synthesize(load_object(path), fingers, contact, 0.5, top=2, samples=samples,
                        seed=seed)
    assert result.found and all(r.certify().holds for r in result.found)
    check_regions_on_outer_surface(path, result.found)


def test_a_cap_whose_rim_leaves_the_closed_shell_is_not_made():
    """An open-topped box wider than the closed cube it pokes into: capping its rim would
    invent a lid over the 0.1-wide gap between the two, where there is no material. It is
    not capped; its triangles inside the cube go, and no region lies on an invented lid:
    every sampled region point is on a triangle of the input."""
    cube_v, cube_t = _box([0, 0, 0], [1, 1, 1])
    V, T = _box([-0.1, -0.1, -1], [1.1, 1.1, 0.5])
    lid = np.flatnonzero(V[T][:, :, 2].min(axis=1) > 0.49)
    cup = np.delete(T, lid, axis=0)
    verts = np.vstack([cube_v, V])
    tris = np.vstack([cube_t, cup + 8])
    poly = Polyhedron.from_arrays(verts, tris, allow_open=True)
    assert not any("capped" in w for w in poly.warnings)
    tops = [f for f in poly.faces if f.normal[2] > 0.99]
    assert all(abs(f.origin[2] - 1.0) < 1e-9 for f in tops)  # only the cube's own top
    for r in synthesize(poly, 2, "soft", 0.5, top=3).found:
        points, _ = r.sample(200, seed=1)
        for q in points.reshape(-1, 3):
            assert distance_to_triangles(q, verts[tris]).min() <= 1e-9

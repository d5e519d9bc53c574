"""Moved and scaled polyhedra and meshes keep their regions, in the same places, on the outer
surface (issue 25, item 3).

Every bundled polyhedron and three meshes of pybullet_data (two convex decompositions,
``random_urdfs/000`` and ``duck_vhacd``, and ``cube.obj``), built from the very triangles of
the file moved by 1e4, 1e8, 1e12 or scaled by 1e-4, 1e3: the regions of the copy, mapped back,
are the original's (each finger's area and area-weighted centre, to 1e-6 of the size plus a
few spacings of the doubles where the copy stands), or the search says which sites it could not
decide, or (where doubles there are coarser than 1e-4 of the size) the object is refused in one
line. The moved regions are checked against the file, with code written here: points sampled
on them lie on the file's triangles, and pushed outward by 1e-6 of the size (or the doubles'
spacing there, if larger) they are outside every shell of the file (a generalised winding
number, Van Oosterom and Strackee's solid angles, summed over the file's triangles).

Two cases test what the rounding of a far copy must not change: three hard fingers on the
hexagonal prism at 1e12 (its corners rounded by 4e-5 of its size, its symmetric faces no longer
equal: faces numbered and ranked as at the origin, ties within the rounding to the lower index)
and the mesh method on random_urdfs/000 at 1e8 (the union's small triangles, whose normals the
doubles there turn by up to 1e-2 rad, merged with the faces around them allowing for that, and
a face's straight corner made reflex by the rounding not cut into convex pieces).
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pybullet_data
import pytest

from forceclosure import InputError
from forceclosure.objects import POLYHEDRA, Polyhedron, bundled
from forceclosure.synthesis import synthesize
from forceclosure.synthesis.spatial.patches import convex_pieces

MOVES = [(1e4, 1.0), (1e8, 1.0), (1e12, 1.0), (0.0, 1e-4), (0.0, 1e3)]
HANDS = {"2-soft": (2, "soft", 0.5, "faces"), "3-hard": (3, "hard", 0.5, "faces"),
         "7-frictionless": (7, "frictionless", 0.0, "faces"), "3-hard-mesh": (3, "hard", 0.5,
                                                                             "mesh")}
#: pybullet_data meshes and the scale their URDF gives them.
MESHES = {"random_urdfs/000/000.obj": 0.015, "duck_vhacd.obj": 0.05, "cube.obj": 1.0}
#: The coarsest doubles, relative to the size, that synthesis accepts (best.RESOLUTION).
RESOLUTION = 1e-4


def read_obj(path: Path, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The vertices and triangles of an OBJ file as written (polygons fanned), scaled."""
    V, F = [], []
    for line in path.read_text().splitlines():
        p = line.split()
        if p and p[0] == "v":
            V.append([float(x) for x in p[1:4]])
        elif p and p[0] == "f":
            idx = [int(x.split("/")[0]) for x in p[1:]]
            idx = [i - 1 if i > 0 else len(V) + i for i in idx]
            F += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    return np.array(V) * scale, np.array(F)


def point_triangle_distance(P, A, B, C, block=64):
    """Distance from each point to the nearest triangle: the height where the point's
    projection falls inside a triangle, else the nearest of the edges."""
    n = np.cross(B - A, C - A)
    n /= np.linalg.norm(n, axis=1)[:, None]
    out = np.empty(len(P))

    def segment(p, a, b):
        ab = b - a
        t = np.clip(np.einsum("pij,ij->pi", p[:, None] - a, ab) / np.einsum("ij,ij->i", ab, ab),
                    0, 1)
        return np.linalg.norm(p[:, None] - (a + t[..., None] * ab), axis=2)

    for s in range(0, len(P), block):
        p = P[s:s + block]
        h = np.einsum("pij,ij->pi", p[:, None] - A, n)
        q = p[:, None] - h[..., None] * n
        inside = np.ones(h.shape, bool)
        for a, b in ((A, B), (B, C), (C, A)):
            inside &= np.einsum("pij,ij->pi", np.cross(b - a, q - a), n) >= 0
        d = np.where(inside, np.abs(h), np.inf)
        for a, b in ((A, B), (B, C), (C, A)):
            d = np.minimum(d, segment(p, a, b))
        out[s:s + block] = d.min(axis=1)
    return out


def winding(P, A, B, C, block=64):
    """The generalised winding number of the triangles (A, B, C) at each point: the sum of
    their signed solid angles over 4 pi (1 inside a closed outward shell, 0 outside)."""
    out = np.empty(len(P))
    for s in range(0, len(P), block):
        a, b, c = (X[None] - P[s:s + block, None] for X in (A, B, C))
        la, lb, lc = (np.linalg.norm(x, axis=2) for x in (a, b, c))
        det = np.einsum("pij,pij->pi", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("pij,pij->pi", a, b) * lc
               + np.einsum("pij,pij->pi", b, c) * la + np.einsum("pij,pij->pi", c, a) * lb)
        out[s:s + block] = 2 * np.arctan2(det, den).sum(axis=1) / (4 * np.pi)
    return out


_WANT: dict = {}


def _at_the_origin(name, hand, top, samples, V, T):
    """The synthesis of the object as given, once per object and hand."""
    key = (name, hand, top, samples)
    if key not in _WANT:
        fingers, contact, mu, method = HANDS[hand]
        _WANT[key] = synthesize(Polyhedron.from_arrays(V, T, name), fingers, contact, mu,
                                top=top, method=method, samples=samples)
    return _WANT[key]


def _places(r, offset, scale):
    """Each finger's area and area-weighted centre, mapped back to the original's frame."""
    out = []
    for region in r.regions:
        areas = np.array([p.area for p in region])
        centres = np.array([p.points.mean(axis=0) for p in region])  # convex: fine for
        out.append((areas.sum() / scale**2,                           # comparing places
                    ((areas @ centres) / areas.sum() - offset) / scale))
    return out


def _check(V, T, name, hand, offset, scale, top=3, samples=2000, surface=False,
           places=True):
    fingers, contact, mu, method = HANDS[hand]
    kw = dict(top=top, method=method, samples=samples)
    size = float(np.linalg.norm(np.ptp(V[np.unique(T)], axis=0)))
    spacing = float(np.spacing(abs(offset) + size * scale))  # the doubles where the copy is
    try:
        moved = Polyhedron.from_arrays(V * scale + offset, T, name)
        got = synthesize(moved, fingers, contact, mu, **kw)
    except InputError as e:  # only where doubles cannot resolve the object, in one line
        assert spacing > RESOLUTION * size * scale, (name, hand, offset, scale, str(e))
        assert "\n" not in str(e)
        return None
    assert all(r.certify().holds for r in got.found)
    assert not got.complete or got.undecided == 0
    if surface:
        _on_the_outer_surface(got, V, T, offset, scale, size, spacing)
    if got.undecided:  # allowed, said so, only where the copy's corners are rounded
        assert not got.complete and offset >= 1e12, (name, hand, offset, scale)
        return got
    if not places:
        return got
    want = _at_the_origin(name, hand, top, samples, V, T)
    assert want.undecided == 0
    assert len(got.found) == len(want.found), (name, hand, offset, scale)
    tol = 1e-6 * size + 64 * spacing / scale
    for g, w in zip(got.found, want.found, strict=True):
        for (ga, gc), (wa, wc) in zip(_places(g, offset, scale), _places(w, 0.0, 1.0),
                                      strict=True):
            np.testing.assert_allclose(gc, wc, rtol=0, atol=tol, err_msg=f"{name} {hand}")
            assert abs(ga - wa) <= 1e-6 * wa + 8 * tol * np.sqrt(wa), (name, hand, ga, wa)
    return got


def _on_the_outer_surface(got, V, T, offset, scale, size, spacing):
    A, B, C = V[T[:, 0]], V[T[:, 1]], V[T[:, 2]]
    for r in got.found:
        points, normals = r.sample(150, seed=1)
        points, normals = points.reshape(-1, 3), normals.reshape(-1, 3)
        back = (points - offset) / scale
        # on the file's triangles: within the flatness the library merges faces by (1e-6 of
        # the size) and the doubles where the copy stands
        off = point_triangle_distance(back, A, B, C)
        assert off.max() <= 1e-6 * size + 4 * spacing / scale, off.max() / size
        push = max(1e-6 * size * scale, 4 * spacing)
        outside = (points + push * normals - offset) / scale
        assert winding(outside, A, B, C).max() < 0.5


OBJECTS = list(POLYHEDRA)


#: The default run's moves (1.6 s of CPU for two fingers on every polyhedron); the rest long.
CHEAP = [(1e8, 1.0), (0.0, 1e-4)]


@pytest.mark.parametrize("offset,scale", [
    pytest.param(*m, marks=() if m in CHEAP else pytest.mark.long) for m in MOVES])
@pytest.mark.parametrize("name", OBJECTS)
def test_two_soft_fingers_same_places(name, offset, scale):
    obj = bundled(name)
    _check(obj.vertices, obj.triangles, name, "2-soft", offset, scale)


@pytest.mark.parametrize("offset", [1e4, 1e8, 1e12])
@pytest.mark.parametrize("name", OBJECTS)
def test_faces_numbered_as_at_the_origin(name, offset):
    """A moved polyhedron has the original's faces under the same numbers: each face the
    same triangles (the file's, in the file's order) and, to the rounding there, the same
    normal (at 1e12 the hexagonal prism's top was once numbered after its sides)."""
    obj = bundled(name)
    moved = Polyhedron.from_arrays(obj.vertices + offset, obj.triangles, name)
    np.testing.assert_array_equal(moved.triangles, obj.triangles)
    np.testing.assert_array_equal(moved.face_of_triangle, obj.face_of_triangle)
    spacing = float(np.spacing(offset + obj.size))
    for f, g in zip(moved.faces, obj.faces, strict=True):
        assert np.linalg.norm(f.normal - g.normal) <= 64 * spacing / obj.size, (name, f.index)


def test_a_straight_corner_rounded_reflex_does_not_cut_a_face():
    """A wedge whose top is the triangle (0,0), (1,0), (0.7,0.9) with a fourth corner at
    the middle of its slanted side: convex, one piece. Moved by 3e8, that corner rounds
    off the line, reflex by a few spacings there; allowing for the rounding (as the
    search does), each face is still one convex piece."""
    P = np.array([[0, 0], [1, 0], [0.7, 0.9], [0.35, 0.45]])
    V = np.vstack([np.column_stack([P, np.zeros(4)]), np.column_stack([P, np.ones(4)])])
    T = [[1, 0, 3], [1, 3, 2], [5, 6, 7], [5, 7, 4]]
    T += [t for i in range(4) for t in ([i, (i + 1) % 4, 4 + (i + 1) % 4],
                                       [i, 4 + (i + 1) % 4, 4 + i])]
    moved = Polyhedron.from_arrays(V + 3e8, T, "wedge")
    spacing = float(np.spacing(3e8))
    top = max(moved.faces, key=lambda f: f.normal[2])
    assert len(convex_pieces(top)) == 2  # the rounding made the corner reflex
    assert [len(convex_pieces(f, spacing)) for f in moved.faces] == [1] * 5


@pytest.mark.parametrize("offset,scale", [(1e8, 1.0), (1e6, 1e-3)])
def test_a_far_decomposition_is_searched_on_its_outer_surface(offset, scale):
    """random_urdfs/000 (three overlapping shells and two apart) moved by 1e8, or scaled by
    1e-3 at 1e6 (the issue's two cases): all three region sets, every site decided, on the
    file's triangles, none reaching into the solid."""
    V, T = read_obj(Path(pybullet_data.getDataPath()) / "random_urdfs/000/000.obj", 0.015)
    got = _check(V, T, "000", "3-hard-mesh", offset, scale, surface=True, places=False)
    assert got is not None and len(got.found) == 3 and got.undecided == 0


#: Every move with FORCECLOSURE_ALL_MOVES=1 (about 16 CPU-minutes); the long profile takes the
#: far ones for each hand (seven frictionless fingers, seconds a search, at 1e8 only).
ALL_MOVES = os.environ.get("FORCECLOSURE_ALL_MOVES") == "1"
LONG_MOVES = {"3-hard": [(1e8, 1.0), (1e12, 1.0)], "7-frictionless": [(1e8, 1.0)],
              "3-hard-mesh": [(1e8, 1.0), (1e12, 1.0)],
              "pybullet": [(1e8, 1.0), (1e12, 1.0), (0.0, 1e-4)]}


def _moves(hand: str) -> list[tuple[float, float]]:
    return MOVES if ALL_MOVES else LONG_MOVES[hand]


@pytest.mark.long  # minutes: the faces' constructions take seconds each
@pytest.mark.parametrize("name,hand,offset,scale", [
    (name, hand, offset, scale) for name in OBJECTS
    for hand in ("3-hard", "7-frictionless", "3-hard-mesh") for offset, scale in _moves(hand)])
def test_other_hands_same_places(name, hand, offset, scale):
    obj = bundled(name)
    _check(obj.vertices, obj.triangles, name, hand, offset, scale)


@pytest.mark.long
@pytest.mark.parametrize("mesh,offset,scale", [
    (mesh, offset, scale) for mesh in MESHES for offset, scale in _moves("pybullet")])
def test_pybullet_meshes_same_places_on_the_outer_surface(mesh, offset, scale):
    V, T = read_obj(Path(pybullet_data.getDataPath()) / mesh, MESHES[mesh])
    _check(V, T, mesh, "3-hard-mesh", offset, scale, surface=True, places=False)
    _check(V, T, mesh, "3-hard-mesh", offset, scale)

"""Independent regions on polyhedra: patches of faces, and their proof by sampling.

A finger's region on a polyhedron is a set of :class:`FacePatch` objects,
convex polygons on planar faces (one patch for the paper's constructions on
faces, §5.2–§5.5; several across neighbouring faces for regions grown on a
mesh). :class:`SpatialRegions` holds one region per finger; each
construction subclasses it with its own exact :meth:`~SpatialRegions.certify`.
:func:`sampling_check` is the independent check every construction must
also survive: thousands of point tuples drawn from the regions, each
analysed with exact friction cones by the general analysis (§3).
"""

from __future__ import annotations

import builtins  # builtins.object in annotations inside classes with an `object` property
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import shapely
from numpy.typing import NDArray

from ...errors import InputError
from ...geometry.clip import clip
from ...geometry.rings import signed_area
from ...objects.polyhedron import PlanarFace, Polyhedron
from ...verdicts import VerdictCode
from ..regions import Certificate, RegionSet

__all__ = ["CONVEX_RTOL", "FacePatch", "SpatialRegions", "clip", "convex_pieces", "sampling_check",
           "uniform_in_triangles"]

#: Relative tolerance (of the face's size) for calling a union of triangles convex.
CONVEX_RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class FacePatch:
    """A convex polygon on a planar face: where one finger may touch.

    Attributes
    ----------
    face : int
        Index of the face in ``Polyhedron.faces``.
    uv : (k, 2) array
        Vertices in the face's own frame, counter-clockwise seen from outside.
    points : (k, 3) array
        The same vertices in object coordinates.
    """

    face: int
    uv: NDArray[np.float64]
    points: NDArray[np.float64]

    @classmethod
    def on(cls, face: PlanarFace, uv) -> FacePatch:
        """The patch with plane coordinates ``uv`` on ``face``."""
        uv = _corners(np.asarray(uv, dtype=float), 1e-12 * face.plane_size)
        return cls(face.index, uv, face.to_world(uv))

    @property
    def area(self) -> float:
        """Area of the patch."""
        return abs(signed_area(self.uv))

    def sample(self, count: int, rng: np.random.Generator) -> NDArray[np.float64]:
        """``count`` points uniformly distributed over the patch, in object coordinates."""
        k = len(self.points)
        fan = self.points[np.column_stack([np.zeros(k - 2, dtype=int), np.arange(1, k - 1),
                                           np.arange(2, k)])]
        return uniform_in_triangles(fan[:, 0], fan[:, 1], fan[:, 2], count, rng)[0]

    def to_dict(self) -> dict[str, object]:
        """The JSON record: face, polygon in object coordinates, area."""
        return {"face": self.face, "polygon": self.points.tolist(), "area": self.area}


def _weights(areas: NDArray, what: str) -> NDArray[np.float64]:
    """Probabilities proportional to ``areas``, or a one-line refusal where there are none
    (every area zero, or not finite) instead of numpy's 'probabilities contain NaN'."""
    total = float(np.sum(areas))
    if not (np.all(np.isfinite(areas)) and total > 0):
        raise InputError(f"{what}: nothing to sample from (areas {total:g} in all)")
    return areas / total


def uniform_in_triangles(a: NDArray, b: NDArray, c: NDArray, count: int,
                         rng: np.random.Generator) -> tuple[NDArray, NDArray]:
    """``count`` points uniformly distributed over triangles ``(a, b, c)`` (each ``(t, 3)``),
    and the triangle each came from."""
    with np.errstate(over="ignore", invalid="ignore"):  # refused below if not finite
        area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    pick = rng.choice(len(a), size=count, p=_weights(area, "triangles"))
    r1, r2 = rng.random(count), rng.random(count)
    flip = r1 + r2 > 1
    r1[flip], r2[flip] = 1 - r1[flip], 1 - r2[flip]
    points = a[pick] + r1[:, None] * (b - a)[pick] + r2[:, None] * (c - a)[pick]
    return points, pick


def _corners(ring: NDArray, tol: float) -> NDArray[np.float64]:
    """A convex ring without repeated or straight-through vertices."""
    keep = np.ones(len(ring), dtype=bool)
    changed = True
    while changed and keep.sum() > 3:
        changed = False
        idx = np.flatnonzero(keep)
        r = ring[idx]
        prev, nxt = np.roll(r, 1, axis=0), np.roll(r, -1, axis=0)
        a, b = r - prev, nxt - r
        cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
        flat = np.abs(cross) <= tol * (np.linalg.norm(a, axis=1) + np.linalg.norm(b, axis=1))
        if flat.any():
            keep[idx[int(np.argmax(flat))]] = False
            changed = True
    return ring[keep]


def convex_pieces(face: PlanarFace, rounding: float = 0.0) -> list[NDArray[np.float64]]:
    """The face as convex polygons (plane coordinates, counter-clockwise) that cover it.

    A convex face is one piece. A non-convex face, or one with holes, is cut
    into its mesh triangles, and neighbouring pieces are merged while their
    union stays convex (Hertel and Mehlhorn's greedy merge): the paper's
    "local convex regions" of a face (§5.2). ``rounding`` (a length) is how far the
    doubles where the object stands may have moved its corners: a corner made reflex by
    no more than that (a straight corner of a copy moved by 1e8) is not a cut.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> block = bundled("holed-block")
    >>> top = max(block.faces, key=lambda f: f.normal[2])
    >>> side = max(block.faces, key=lambda f: f.normal[0])
    >>> len(convex_pieces(top)) > 1, len(convex_pieces(side))
    (True, 1)
    """
    if face.triangle_outline is not None:  # one triangle: itself (as the polygon has it)
        return [face.triangle_outline]
    shape = face.polygon.to_shapely()
    length = CONVEX_RTOL * max(face.polygon.size, 1e-300)
    tol = (length + 4 * rounding) * face.polygon.size  # an area
    if shape.convex_hull.area - shape.area <= tol:
        return [_ccw(np.asarray(shape.exterior.coords)[:-1])]
    V, T = face._vertices, face._mesh
    pieces = [shapely.Polygon(face.to_plane(V[T[t]])) for t in face.triangles]
    merged = True
    while merged:
        merged = False
        for i in range(len(pieces)):
            for j in range(i + 1, len(pieces)):
                a, b = pieces[i], pieces[j]
                if a.intersection(b).length <= length:  # not sharing an edge
                    continue
                union = a.union(b)
                if union.geom_type == "Polygon" and union.convex_hull.area - union.area <= tol:
                    pieces[i] = shapely.Polygon(union.convex_hull.exterior)
                    del pieces[j]
                    merged = True
                    break
            if merged:
                break
    return [_ccw(np.asarray(shapely.simplify(p, 0).exterior.coords)[:-1]) for p in pieces]


def _ccw(ring: NDArray) -> NDArray[np.float64]:
    return np.ascontiguousarray(ring if signed_area(ring) > 0 else ring[::-1], dtype=float)


@dataclass(frozen=True, eq=False)
class SpatialRegions(RegionSet):
    """One region per finger on a polyhedron, such that every choice of one point per
    region is force-closure. Subclasses give :meth:`certify`, the proof.

    Attributes
    ----------
    polyhedron : Polyhedron
    model : str
        Contact model of every finger: ``"frictionless"``, ``"hard"`` or ``"soft"``.
    mu : float
        Friction coefficient (0 for frictionless fingers).
    regions : tuple of tuple of FacePatch
        Each finger's region: one or more convex patches.
    construction : str
    """

    polyhedron: Polyhedron
    model: str
    mu: float
    regions: tuple[tuple[FacePatch, ...], ...]
    construction: str

    @property
    def faces(self) -> tuple[tuple[int, ...], ...]:
        """The faces each finger's region touches."""
        return tuple(tuple(p.face for p in region) for region in self.regions)

    @cached_property
    def areas(self) -> tuple[float, ...]:
        """Area of each finger's region."""
        return tuple(sum(p.area for p in region) for region in self.regions)

    @property
    def object(self) -> Polyhedron:
        return self.polyhedron

    @property
    def sizes(self) -> tuple[float, ...]:
        """Area of each finger's region (:attr:`areas`)."""
        return self.areas

    @property
    def kinds(self) -> tuple[str, ...]:
        return ("patch",) * len(self.regions)

    @property
    def min_area(self) -> float:
        """The smallest region: the placement error the grasp tolerates."""
        return min(self.areas)

    def describe(self) -> list[str]:
        """``finger 1 on face 3``, ``on faces 3, 4`` or, for a region grown over many
        triangles, ``on 112 faces (3 to 2810)`` (the full list is in :meth:`to_dict`)."""
        return [f"finger {k + 1} on {_faces_text(f)}" for k, f in enumerate(self.faces)]

    def sample(self, count: int, seed: int = 0) -> tuple[NDArray[np.float64],
                                                          NDArray[np.float64]]:
        """``(count, fingers, 3)`` point tuples, each finger's point uniform over its region,
        and the outward normal of the face each point lies on."""
        rng = np.random.default_rng(seed)
        points = np.empty((count, len(self.regions), 3))
        normals = np.empty_like(points)
        for k, region in enumerate(self.regions):
            areas = np.array([p.area for p in region])
            which = rng.choice(len(region), size=count, p=_weights(areas, f"region {k + 1}"))
            for i, patch in enumerate(region):
                rows = np.flatnonzero(which == i)
                points[rows, k] = patch.sample(len(rows), rng)
                normals[rows, k] = self.polyhedron.faces[patch.face].normal
        return points, normals

    def to_dict(self) -> dict[str, builtins.object]:
        """The JSON record: each finger's faces and patches, areas, construction, certificate."""
        size = self.polyhedron.size
        return {"faces": [sorted(set(f)) for f in self.faces],
                "regions": [[p.to_dict() for p in region] for region in self.regions],
                "areas": list(self.areas), "min_area": self.min_area,
                "relative_min_area": self.min_area / size**2,
                "construction": self.construction, **self._common()}


def _faces_text(faces: tuple[int, ...]) -> str:
    ids = sorted(set(faces))
    if len(ids) == 1:
        return f"face {ids[0]}"
    if len(ids) <= 6:
        return f"faces {', '.join(map(str, ids))}"
    return f"{len(ids)} faces ({ids[0]} to {ids[-1]})"


def sampling_check(regions: SpatialRegions, samples: int = 2000, seed: int = 0,
                   corners: bool = True) -> Certificate:
    """Check a region set independently: random point tuples through the general analysis.

    Every finger's point is drawn uniformly from its region; with ``corners``
    the tuples of patch vertices (each finger at one of its region's
    vertices, all combinations up to ``samples``) are added, since the
    conditions are tightest there. Each tuple is analysed with exact
    circular friction cones (Theorem 1, :func:`forceclosure.analysis.batch.analyze_batch`).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis import soft_pair_regions
    >>> r = soft_pair_regions(bundled("cube"), 0, 1, mu=0.5)   # two opposite faces
    >>> sampling_check(r, samples=500).holds
    True
    """
    from ...analysis.batch import analyze_batch

    points, normals = regions.sample(samples, seed)
    if corners:
        rng = np.random.default_rng(seed + 1)
        faces = regions.polyhedron.faces
        verts = [np.vstack([p.points for p in region]) for region in regions.regions]
        vert_normals = [np.vstack([np.tile(faces[p.face].normal, (len(p.points), 1))
                                   for p in region]) for region in regions.regions]
        picks = [rng.integers(len(v), size=samples) for v in verts]
        points = np.concatenate([points, np.stack(
            [v[pick] for v, pick in zip(verts, picks, strict=True)], axis=1)])
        normals = np.concatenate([normals, np.stack(
            [n[pick] for n, pick in zip(vert_normals, picks, strict=True)], axis=1)])
    result = analyze_batch(points, normals, mu=regions.mu, model=regions.model, cone="exact")
    bad = np.flatnonzero(result.code != VerdictCode.CLOSURE)
    detail = (f"{len(points)} point tuples, each force-closure with exact cones"
              if not len(bad) else
              f"{len(bad)} of {len(points)} point tuples are not force-closure, e.g. "
              f"{np.round(points[bad[0]], 6).tolist()} ({result.verdict[bad[0]]})")
    return Certificate(not len(bad), "sampling", detail)

"""Polygons: the planar objects whose edges fingers touch (Nguyen 1988, §5.1, §5.4).

A :class:`Polygon` is validated and normalised on construction. The outer
boundary runs counter-clockwise and holes clockwise, so the material is
always on the left of an edge and its outward normal on the right.
Consecutive edges that are *exactly* collinear (decided in rational
arithmetic) are merged into one physical edge, which keeps the indices of
the input edges it came from. Nearly collinear vertices (a straight line
sampled in floating point, a finely tessellated arc) stay corners: every
edge's normal is then the normal of the geometry as given, and no region
is ever certified on a normal the object does not have. Each :class:`Edge` maps a
parameter ``t`` in ``[0, length]`` to a point and back.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from fractions import Fraction
from functools import cached_property
from typing import NamedTuple

import numpy as np
import shapely
from numpy.typing import ArrayLike, NDArray

from ..errors import InputError
from ..geometry.rings import signed_area

__all__ = ["RTOL", "Edge", "EdgeArrays", "Polygon", "axis_label", "in_units"]

#: Relative tolerance (of the polygon's size) for repeated vertices and zero area.
RTOL = 1e-9


@dataclass(frozen=True, eq=False)
class Edge:
    """One physical edge of a polygon.

    Attributes
    ----------
    index : int
        Position among the polygon's edges (outer ring first, then holes).
    ring : int
        0 for the outer boundary, ``h + 1`` for hole ``h``.
    start, end : (2,) arrays
        Endpoints, in the ring's direction (material on the left).
    normal : (2,) array
        Outward unit normal (pointing out of the material).
    length : float
    source : tuple of int
        Indices of the input edges merged into this one (input edges are
        numbered ring by ring, edge ``i`` from input vertex ``i`` to ``i+1``).
    """

    index: int
    ring: int
    start: NDArray[np.float64]
    end: NDArray[np.float64]
    normal: NDArray[np.float64]
    length: float
    source: tuple[int, ...]

    @property
    def direction(self) -> NDArray[np.float64]:
        """Unit vector from ``start`` to ``end``."""
        return (self.end - self.start) / self.length

    def point(self, t: ArrayLike) -> NDArray[np.float64]:
        """The point at distance ``t`` from ``start`` along the edge.

        Examples
        --------
        >>> e = Polygon.from_points([[0, 0], [1, 0], [1, 1], [0, 1]]).edges[0]
        >>> e.point(e.length / 2).tolist()
        [0.5, 0.0]
        """
        t = np.asarray(t, dtype=float)
        return self.start + t[..., None] * self.direction

    def parameter(self, p: ArrayLike) -> NDArray[np.float64]:
        """The parameter ``t`` of the projection of ``p`` onto the edge's line."""
        return (np.asarray(p, dtype=float) - self.start) @ self.direction


def _ring_array(points: ArrayLike, what: str) -> NDArray[np.float64]:
    try:
        ring = np.asarray(points, dtype=float)
    except (TypeError, ValueError, OverflowError):
        raise InputError(f"{what}: vertices must be numbers") from None
    if ring.size == 0:
        raise InputError(f"{what}: no vertices")
    if ring.ndim != 2 or ring.shape[1] != 2:
        raise InputError(f"{what}: vertices must be (x, y) pairs, got shape {ring.shape}")
    bad = np.flatnonzero(~np.all(np.isfinite(ring), axis=1))
    if len(bad):
        raise InputError(f"{what}: vertex {bad[0] + 1} is not finite: {ring[bad[0]].tolist()}")
    huge = np.flatnonzero(np.any(np.abs(ring) > 1e100, axis=1))
    if len(huge):  # beyond it, squared lengths overflow and no tolerance means anything
        raise InputError(f"{what}: vertex {huge[0] + 1} is beyond 1e100 in magnitude: "
                         f"{ring[huge[0]].tolist()} (rescale the object)")
    if len(ring) > 1 and np.array_equal(ring[0], ring[-1]):
        ring = ring[:-1]  # an explicitly closed ring (GeoJSON, SVG 'Z' after a return)
    return ring


def _check_ring(ring: NDArray[np.float64], what: str, tol: float) -> None:
    if len(ring) < 3 or len(np.unique(ring, axis=0)) < 3:
        raise InputError(f"{what}: fewer than 3 distinct vertices")
    step = np.linalg.norm(np.roll(ring, -1, axis=0) - ring, axis=1)
    short = np.flatnonzero(step <= tol)
    if len(short):
        i = short[0]
        j = (i + 1) % len(ring)
        raise InputError(f"{what}: vertex {j + 1} repeats vertex {i + 1} at "
                         f"{ring[i].round(9).tolist()} (a zero-length edge)")


def _straight(ring: NDArray[np.float64]) -> NDArray[np.bool_]:
    """Which vertices lie exactly on the segment between their neighbours.

    A floating-point screen keeps only the vertices whose turn is tiny, and
    those are decided with ``Fraction``: the cross product of the two edges
    must be exactly zero and their directions the same.
    """
    d = np.roll(ring, -1, axis=0) - ring
    prev = np.roll(d, 1, axis=0)
    cross = prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0]
    scale = np.linalg.norm(prev, axis=1) * np.linalg.norm(d, axis=1)
    straight = np.zeros(len(ring), dtype=bool)
    for k in np.flatnonzero((np.abs(cross) <= 1e-6 * scale) & (np.sum(prev * d, axis=1) > 0)):
        (ax, ay), (bx, by), (cx, cy) = ([Fraction(float(c)) for c in ring[i % len(ring)]]
                                        for i in (k - 1, k, k + 1))
        straight[k] = (bx - ax) * (cy - by) == (by - ay) * (cx - bx)
    return straight


def _validity(outer: NDArray, holes: Sequence[NDArray], name: str) -> None:
    spread = np.linalg.svd(outer - outer.mean(axis=0), compute_uv=False)
    if spread[1] <= RTOL * spread[0]:
        raise InputError(f"{name}: the polygon has zero area (its vertices are collinear)")
    poly = shapely.Polygon(outer, holes)
    if not poly.is_valid:
        reason = shapely.is_valid_reason(poly)  # e.g. "Self-intersection[1 1]"
        kind, _, where = reason.partition("[")
        coords = where.rstrip("]").split()
        at = f" at ({', '.join(f'{float(c):.6g}' for c in coords)})" if coords else ""
        raise InputError(f"{name}: invalid polygon: {kind.strip().lower()}{at}")
    if poly.area <= 0:
        raise InputError(f"{name}: the polygon has zero area")


class EdgeArrays(NamedTuple):
    """A polygon's edges as arrays (:attr:`Polygon.edge_arrays`)."""

    start: NDArray[np.float64]
    direction: NDArray[np.float64]
    normal: NDArray[np.float64]
    length: NDArray[np.float64]


def in_units(units: str | None, power: int = 1) -> str:
    """The words after a length (``power`` 1) or an area (2) in ``units`` (a
    :attr:`Polygon.units`), for people; nothing when the file states no units.

    Examples
    --------
    >>> f"size 12{in_units('mm')}", f"size 12{in_units('0.5 mm')}", f"size 12{in_units(None)}"
    ('size 12 mm', 'size 12 (units of 0.5 mm)', 'size 12')
    >>> f"area 3{in_units('mm', 2)}", f"area 3{in_units('0.5 mm', 2)}"
    ('area 3 mm²', 'area 3 (squares of 0.5 mm)')
    """
    if not units:
        return ""
    if " " in units:
        return f" ({'units' if power == 1 else 'squares'} of {units})"
    return f" {units}" + ("²" if power == 2 else "")


def axis_label(axis: str, units: str | None) -> str:
    """A picture's axis title: ``"x (mm)"``, ``"x (units of 0.5 mm)"``, or ``"x"``.

    Examples
    --------
    >>> axis_label("x", "mm"), axis_label("y", "0.5 mm"), axis_label("x", None)
    ('x (mm)', 'y (units of 0.5 mm)', 'x')
    """
    if not units:
        return axis
    return f"{axis} ({units})" if " " not in units else f"{axis} (units of {units})"


@dataclass(frozen=True, eq=False)
class Polygon:
    """A simple polygon, possibly with holes, ready for grasping.

    Build one with :meth:`from_points`, :meth:`from_shapely`,
    :meth:`regular`, or the loaders in :mod:`forceclosure.objects.io`.

    Attributes
    ----------
    outer : (n, 2) array
        Outer boundary, counter-clockwise, collinear vertices removed.
    holes : tuple of (k, 2) arrays
        Holes, clockwise.
    edges : tuple of Edge
        The physical edges: the outer ring's, then each hole's.
    name : str
    warnings : tuple of str
        What a loader did to read the file as drawn (e.g. curves tessellated), for people.
    spread : float
        Radians by which the normal of the object the polygon stands for may
        differ from its edges' normals: 0 for a polygon given by its vertices,
        the largest turn of a curve against its chord when a loader cut curves
        into chords. Certificates narrow every friction cone by it (and
        frictionless fingers hold for every normal within it), so nothing is
        proved on a normal the real outline does not have.
    units : str or None
        What one coordinate measures, when the file says (an SVG's ``"mm"``, or
        ``"0.5 mm"`` for half a millimetre a unit); ``None`` for files that do not
        (GeoJSON, CSV, JSON): the file's own units.
    """

    outer: NDArray[np.float64]
    holes: tuple[NDArray[np.float64], ...]
    edges: tuple[Edge, ...]
    name: str = "polygon"
    warnings: tuple[str, ...] = ()
    spread: float = 0.0
    units: str | None = None

    @classmethod
    def from_points(cls, outer: ArrayLike, holes: Sequence[ArrayLike] = (),
                    name: str = "polygon", warnings: Sequence[str] = (),
                    spread: float = 0.0) -> Polygon:
        """Validate and normalise a polygon given by its vertices.

        Refuses, in one line naming the vertex or the place: non-finite
        coordinates, fewer than three distinct vertices, repeated vertices
        (zero-length edges), self-intersections (bow-ties), self-touching
        rings, holes outside the boundary, and zero area.

        Examples
        --------
        >>> p = Polygon.from_points([[0, 0], [0, 1], [1, 1], [2, 1], [2, 0]])  # clockwise
        >>> len(p.edges), p.edges[1].source  # (1, 1)-(2, 1) merged into the top edge
        (4, (1, 2))
        >>> Polygon.from_points([[0, 0], [1, 1], [1, 0], [0, 1]])
        Traceback (most recent call last):
        ...
        forceclosure.errors.InputError: polygon: invalid polygon: self-intersection at (0.5, 0.5)
        """
        rings = [_ring_array(outer, f"{name}: outer boundary")]
        rings += [_ring_array(h, f"{name}: hole {i + 1}") for i, h in enumerate(holes)]
        size = max(float(np.ptp(np.vstack(rings), axis=0).max()), 1e-300)
        tol = RTOL * size
        for i, ring in enumerate(rings):
            _check_ring(ring, f"{name}: " + ("outer boundary" if i == 0 else f"hole {i}"), tol)
        _validity(rings[0], rings[1:], name)
        oriented = []
        for i, ring in enumerate(rings):
            ccw = signed_area(ring) > 0
            oriented.append(ring if ccw == (i == 0) else ring[::-1].copy())
        # input edge numbering follows the input order of each ring
        offsets = np.cumsum([0] + [len(r) for r in rings])
        edges: list[Edge] = []
        kept: list[NDArray[np.float64]] = []
        for i, (ring, original) in enumerate(zip(oriented, rings, strict=True)):
            flipped = ring is not original
            n = len(ring)
            ids = [(n - 2 - k) % n if flipped else k for k in range(n)]  # edge k -> input id
            corners = np.flatnonzero(~_straight(ring))
            kept.append(ring[corners])
            for a, b in zip(corners, np.roll(corners, -1), strict=True):
                span = [(a + k) % n for k in range((b - a) % n or n)]
                start, end = ring[a], ring[b]
                vec = end - start
                length = float(np.linalg.norm(vec))
                normal = np.array([vec[1], -vec[0]]) / length
                source = tuple(sorted(int(offsets[i] + ids[k]) for k in span))
                edges.append(Edge(len(edges), i, start, end, normal, length, source))
        for e in edges:
            for arr in (e.start, e.end, e.normal):
                arr.setflags(write=False)
        return cls(kept[0], tuple(kept[1:]), tuple(edges), name, tuple(warnings),
                   float(spread))

    @classmethod
    def from_shapely(cls, geometry: shapely.Polygon | shapely.MultiPolygon,
                     name: str = "polygon", warnings: Sequence[str] = ()) -> Polygon:
        """A polygon from a shapely ``Polygon`` (or a one-part ``MultiPolygon``).

        Examples
        --------
        >>> import shapely
        >>> disk = shapely.Point(0, 0).buffer(1, quad_segs=2)
        >>> ring = disk.difference(shapely.box(-0.2, -0.2, 0.2, 0.2))
        >>> p = Polygon.from_shapely(ring)
        >>> len(p.holes), len(p.edges)
        (1, 12)
        """
        if isinstance(geometry, shapely.MultiPolygon):
            parts = list(geometry.geoms)
            if len(parts) != 1:
                raise InputError(f"{name}: a MultiPolygon of {len(parts)} parts; give one polygon")
            geometry = parts[0]
        if not isinstance(geometry, shapely.Polygon):
            raise InputError(f"{name}: expected a shapely Polygon, got {geometry.geom_type}")
        if geometry.is_empty:
            raise InputError(f"{name}: the polygon is empty")
        return cls.from_points(np.asarray(geometry.exterior.coords)[:, :2],
                               [np.asarray(h.coords)[:, :2] for h in geometry.interiors], name,
                               warnings)

    @classmethod
    def regular(cls, n: int, radius: float = 1.0, name: str | None = None) -> Polygon:
        """The regular ``n``-gon inscribed in a circle of ``radius`` about the origin."""
        theta = 2 * np.pi * np.arange(n) / n + np.pi / n
        pts = radius * np.stack([np.cos(theta), np.sin(theta)], axis=1)
        return cls.from_points(pts, name=name or f"regular {n}-gon")

    @property
    def dim(self) -> int:
        """2: polygons are planar objects."""
        return 2

    @property
    def rings(self) -> tuple[NDArray[np.float64], ...]:
        """The outer boundary and the holes."""
        return (self.outer, *self.holes)

    @property
    def area(self) -> float:
        """Area of the material (holes excluded)."""
        return signed_area(self.outer) + sum(signed_area(h) for h in self.holes)

    @property
    def perimeter(self) -> float:
        """Total length of all edges."""
        return float(sum(e.length for e in self.edges))

    @property
    def bounds(self) -> NDArray[np.float64]:
        """``[[xmin, ymin], [xmax, ymax]]``."""
        return np.array([self.outer.min(axis=0), self.outer.max(axis=0)])

    @cached_property
    def size(self) -> float:
        """Length of the bounding box's diagonal: the object's length scale (cached)."""
        return float(np.linalg.norm(np.ptp(self.outer, axis=0)))

    @property
    def centroid(self) -> NDArray[np.float64]:
        """Centre of area."""
        return np.asarray(self.to_shapely().centroid.coords[0])

    @cached_property
    def edge_arrays(self) -> EdgeArrays:
        """The edges' ``start``, ``direction``, ``normal`` (``(n, 2)``) and ``length``
        (``(n,)``) as arrays, made once per polygon (the vectorised constructions read them).

        Examples
        --------
        >>> a = Polygon.regular(4).edge_arrays
        >>> a.normal.shape, float(a.length.sum()) == Polygon.regular(4).perimeter
        ((4, 2), True)
        """
        return EdgeArrays(*(np.array([getattr(e, k) for e in self.edges], dtype=float)
                            for k in ("start", "direction", "normal", "length")))

    @cached_property
    def convex_corners(self) -> tuple[tuple[int, int, int], ...]:
        """The convex corners as ``(index, incoming edge, outgoing edge)``, indexed in edge
        order (corner ``k`` is where edge ``incoming`` ends and ``outgoing`` starts).

        Examples
        --------
        >>> Polygon.regular(3).convex_corners
        ((0, 0, 1), (1, 1, 2), (2, 2, 0))
        """
        out: list[tuple[int, int, int]] = []
        edges = self.edges
        first: dict[int, int] = {}  # each ring's first edge: rings are stored in order
        for e in edges:
            first.setdefault(e.ring, e.index)
        for e in edges:
            k = e.index + 1
            nxt = edges[k] if k < len(edges) and edges[k].ring == e.ring else \
                edges[first[e.ring]]
            turn = e.direction[0] * nxt.direction[1] - e.direction[1] * nxt.direction[0]
            if turn > 0:  # material on the left: a left turn is a convex corner
                out.append((len(out), e.index, nxt.index))
        return tuple(out)

    @property
    def convex(self) -> bool:
        """Whether the polygon is convex (and has no holes)."""
        if self.holes:
            return False
        d = np.roll(self.outer, -1, axis=0) - self.outer
        prev = np.roll(d, 1, axis=0)
        return bool(np.all(prev[:, 0] * d[:, 1] - prev[:, 1] * d[:, 0] > 0))

    def to_shapely(self) -> shapely.Polygon:
        """The polygon as a shapely ``Polygon``."""
        return shapely.Polygon(self.outer, self.holes)

    def locate(self, p: ArrayLike) -> tuple[int, float, float]:
        """The edge nearest to point ``p``: ``(edge index, t, distance)``.

        Examples
        --------
        >>> Polygon.from_points([[0, 0], [2, 0], [2, 1], [0, 1]]).locate([1, -0.1])
        (0, 1.0, 0.1)
        """
        p = np.asarray(p, dtype=float)
        best = (0, 0.0, np.inf)
        for e in self.edges:
            t = float(np.clip(e.parameter(p), 0.0, e.length))
            dist = float(np.linalg.norm(e.point(t) - p))
            if dist < best[2]:
                best = (e.index, round(t, 12), round(dist, 12))
        return best

    def summary(self) -> dict[str, object]:
        """Counts and sizes, for people and JSON."""
        return {"name": self.name, "kind": "polygon", "vertices": int(sum(len(r) for r in
                                                                          self.rings)),
                "edges": len(self.edges), "holes": len(self.holes), "convex": self.convex,
                "area": self.area, "perimeter": self.perimeter, "size": self.size,
                "bounds": self.bounds.tolist(), "spread": self.spread,
                "warnings": list(self.warnings), "units": self.units}

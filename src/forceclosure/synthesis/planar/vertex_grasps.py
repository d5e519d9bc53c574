"""Soft fingers on the convex vertices of a polygon (Nguyen 1988, §2.1, §4.1).

A soft finger pressed on a convex vertex touches a small patch across both
edges, and its wrench convex is the convex sum of their friction cones: a
cone wider than either (§2.1, Fig. 3). The paper notes that this is why
people grasp objects at edges and corners (§4.1). Here a finger may sit on
a convex vertex, paired with a finger on an edge, or with one on another
vertex:

* the vertex cone is the conic hull of the four generators ``-n ± mu t`` of
  its two edges, bounded by its two extreme generators ``g_lo, g_hi``. A
  direction ``w`` is strictly inside iff ``cross(g_lo, w) > 0`` and
  ``cross(w, g_hi) > 0``, two linear conditions with no trigonometry;
* with the vertex fixed, Corollary 3 is linear in the other finger's edge
  parameter. So the grasps on the edge form one interval, and the largest
  region, shrunk by the margin, is that whole interval;
* the certificate checks the interval's two ends exactly, in rationals.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from ...geometry.cones import friction_forces
from ...objects.polygon import Polygon
from ..construction import Construction, Hand
from ..regions import (
    Certificate,
    RegionSet,
    exact_inward,
    exact_point,
    narrowed,
    proved_once,
    rounded,
)

__all__ = ["VertexGrasp", "convex_vertices"]


def convex_vertices(polygon: Polygon) -> list[tuple[int, int, int]]:
    """The convex corners as ``(index, incoming edge, outgoing edge)``, indexed in
    edge order (:attr:`Polygon.convex_corners`, kept on the polygon)."""
    return list(polygon.convex_corners)


def pushing_generators(normals, mu) -> list:
    """The pushing generators ``-n ± mu t`` of a contact, for each of its normals
    (:func:`forceclosure.geometry.cones.friction_forces`), as lists."""
    return friction_forces(np.asarray(normals, dtype=float), float(mu)).reshape(-1, 2).tolist()


def extreme_generators(gens) -> tuple[list, list] | None:
    """The two generators bounding their conic hull (``g_lo`` clockwise-most), or None when
    the hull is a half-plane or more (then the finger alone pushes every way it needs)."""
    def cross(a, b):
        return a[0] * b[1] - a[1] * b[0]

    for lo in gens:
        if all(cross(lo, g) >= 0 for g in gens):
            # the choice only needs an ordering; a near-tie picked wrong narrows the cone,
            # which keeps every check sound
            hi = max((g for g in gens if g is not lo),
                     key=lambda g: math.atan2(float(cross(lo, g)),
                                              float(lo[0] * g[0] + lo[1] * g[1])))
            if cross(lo, hi) > 0:
                return lo, hi
    return None


def _inside(cone, w, strict_margin=0) -> bool:
    lo, hi = cone
    return (lo[0] * w[1] - lo[1] * w[0] > strict_margin
            and w[0] * hi[1] - w[1] * hi[0] > strict_margin)


@dataclass(frozen=True, eq=False)
class VertexGrasp(RegionSet):
    """A soft finger on a convex vertex and a finger on an edge (a segment) or a vertex.

    Its :attr:`sizes` are 0 for a vertex and the segment's length for an edge;
    :attr:`min_size` is the segment's (0 for two vertices): a finger finds a
    vertex by itself, the placement error that counts is along the edge.

    Attributes
    ----------
    polygon : Polygon
    vertex : int
        Index into :func:`convex_vertices`.
    other : (str, int)
        ``("edge", k)`` or ``("vertex", k)``.
    segment : (u, v) or None
        For an edge: the independent region on it (edge parameters).
    mu : float
    corners : tuple of (incoming, outgoing) edge pairs
        The edges meeting at the vertex, and at the other vertex if there is one.
    """

    polygon: Polygon
    vertex: int
    other: tuple[str, int]
    segment: tuple[float, float] | None
    mu: float
    corners: tuple[tuple[int, int], ...]

    @property
    def point(self) -> NDArray[np.float64]:
        """The vertex, in object coordinates."""
        return self.polygon.edges[self.corners[0][0]].end

    def to_dict(self) -> dict[str, object]:
        """The JSON record: the vertex, the other site, its region, the certificate."""
        kind, k = self.other
        other = "edge" if kind == "edge" else "other_vertex"  # not "vertex": that is the own
        record: dict[str, object] = {"vertex": self.vertex, "vertex_point": self.point.tolist(),
                                     other: k, "mu": self.mu}
        if self.segment is not None:
            e = self.polygon.edges[k]
            record.update(segment=list(self.segment),
                          points=[e.point(t).tolist() for t in self.segment],
                          length=self.min_length)
        else:
            record["other_point"] = self.polygon.edges[self.corners[1][0]].end.tolist()
        return {**record, **self._common()}

    @property
    def object(self) -> Polygon:
        return self.polygon

    @property
    def min_length(self) -> float:
        """The length of the region on the edge (0 for two vertices)."""
        return 0.0 if self.segment is None else self.segment[1] - self.segment[0]

    @property
    def sizes(self) -> tuple[float, float]:
        """0 for the vertex, and the segment's length on the edge (0 for a vertex)."""
        return (0.0, self.min_length)

    @property
    def min_size(self) -> float:
        return self.min_length

    @property
    def kinds(self) -> tuple[str, str]:
        return ("vertex", "segment" if self.other[0] == "edge" else "vertex")

    def describe(self) -> list[str]:
        """``vertex 2 at [x, y]``, then ``edge 0 from [..] to [..] (0.897 long)`` or
        ``vertex 3``."""
        size = self.polygon.size
        kind, k = self.other
        if kind == "edge":
            e = self.polygon.edges[k]
            assert self.segment is not None  # the region on an edge is a segment
            ends = [rounded(e.point(t), size) for t in self.segment]
            where = f"edge {k} from {ends[0]} to {ends[1]} ({self.min_length:.4g} long)"
        else:
            where = f"vertex {k}"
        return [f"vertex {self.vertex} at {rounded(self.point, size)}", where]

    @proved_once
    def certify(self) -> Certificate:
        """Corollary 3, exactly in rationals, at the region's ends (linear in between)."""
        F = Fraction
        edges = self.polygon.edges

        def cone(indices):
            normals = [[-x for x in exact_inward(edges[i])] for i in indices]
            return extreme_generators(pushing_generators(normals,
                                                         F(narrowed(self.mu, self.polygon.spread))))

        kind, k = self.other
        cone_p = cone(self.corners[0])
        if kind == "edge":
            cone_q = cone([k])
            e = edges[k]
            assert self.segment is not None  # the region on an edge is a segment
            ends = [exact_point(e, t) for t in self.segment]
        else:
            cone_q = cone(self.corners[1])
            ends = [[F(x) for x in edges[self.corners[1][0]].end]]
        P = [F(x) for x in self.point]
        for q in ends:
            w = [q[0] - P[0], q[1] - P[1]]
            ok_p = cone_p is None or _inside(cone_p, w)
            ok_q = cone_q is None or _inside(cone_q, [-w[0], -w[1]])
            if not (ok_p and ok_q and any(w)):
                return Certificate(False, "end check (exact rationals)",
                                   "a grasp at an end of the region is not strictly inside "
                                   "both cones")
        return Certificate(True, "end check (exact rationals)",
                           "Corollary 3 holds strictly at the ends of the region, hence "
                           "(linear conditions) along all of it")


def vertex_sites(polygon: Polygon, hand: Hand):
    """Step 1: each convex vertex with every edge not adjacent to it, then with every later
    convex vertex: rows ``(corner, kind, k)`` (``kind`` ``"edge"`` or ``"vertex"``)."""
    corners = convex_vertices(polygon)
    sites = []
    for c, (_, a, b) in enumerate(corners):
        sites += [(c, "edge", e.index) for e in polygon.edges if e.index not in (a, b)]
        sites += [(c, "vertex", d) for d in range(c + 1, len(corners))]
    yield sites


def _build_vertex(polygon: Polygon, site, hand: Hand) -> VertexGrasp | None:
    shrunk = narrowed(hand.mu, hand.margin)
    if shrunk <= 0:
        return None
    edges, corners = polygon.edges, convex_vertices(polygon)
    c, kind, k = site
    v, a, b = corners[c]
    p = edges[a].end
    cone_p = extreme_generators(pushing_generators([edges[a].normal, edges[b].normal], shrunk))
    if kind == "edge":
        segment = _interval(p, edges[k], cone_p,
                            extreme_generators(pushing_generators([edges[k].normal], shrunk)))
        return None if segment is None else VertexGrasp(polygon, v, ("edge", k), segment,
                                                        hand.mu, ((a, b),))
    w, a2, b2 = corners[k]
    cone_q = extreme_generators(pushing_generators([edges[a2].normal, edges[b2].normal], shrunk))
    d = edges[a2].end - p
    if (cone_p is None or _inside(cone_p, d)) and (cone_q is None or _inside(cone_q, -d)):
        return VertexGrasp(polygon, v, ("vertex", w), None, hand.mu, ((a, b), (a2, b2)))
    return None


VERTICES = Construction(
    dim=2, fingers=2, contact="hard", name="vertices", paper="Corollary 3 at a vertex",
    method="edges", sites=vertex_sites, build=_build_vertex,
    searched="a soft finger on every convex vertex, with every edge not adjacent to it and "
             "every other convex vertex")


def _interval(p: NDArray, edge, cone_p, cone_q) -> tuple[float, float] | None:
    """The parameters ``t`` on ``edge`` with ``q(t) - p`` inside both cones (linear in t)."""
    lo, hi = 0.0, edge.length
    conditions = []
    for cone, sign in ((cone_p, 1.0), (cone_q, -1.0)):
        if cone is None:
            continue
        g_lo, g_hi = (np.asarray(g, float) for g in cone)
        for ell in (np.array([-g_lo[1], g_lo[0]]), np.array([g_hi[1], -g_hi[0]])):
            # sign * ell . (start - p + t d) > 0
            conditions.append((sign * ell @ (edge.start - p), sign * ell @ edge.direction))
    for c0, c1 in conditions:
        if abs(c1) < 1e-15:
            if c0 <= 0:
                return None
            continue
        root = -c0 / c1
        lo, hi = (max(lo, root), hi) if c1 > 0 else (lo, min(hi, root))
    if hi - lo <= 1e-9 * edge.length:
        return None
    return float(lo) + 0.0, float(hi)

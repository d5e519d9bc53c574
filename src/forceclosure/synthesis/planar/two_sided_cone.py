"""Nguyen's Algorithm 1: a two-sided cone between two edges (Nguyen 1988, §5.1).

The paper's own construction of independent regions for two fingers with
friction, kept beside the maximal regions of :mod:`.planar` for comparison
(docs/synthesis.md): wherever its trade-off region exists it finds the
maximal regions, and where that region is empty it finds nothing.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import NDArray

from ...objects.polygon import Edge, Polygon
from ..construction import Construction, Hand
from ..spatial.patches import clip
from .edge_pair import ANGLE_MARGIN, IndependentRegions, Sector, senses, shrunk_pair
from .two_fingers import counter_overlap_prune, edge_pair_sites, largest_segments_bound

__all__ = ["NGUYEN", "nguyen_regions"]


def _ray_hits(edge: Edge, direction: NDArray) -> tuple[NDArray, float]:
    """The parameter ``t`` where the ray ``apex + s direction`` meets the edge's line, as an
    affine function of the apex: ``t = g . apex + h``."""
    denom = edge.direction[0] * direction[1] - edge.direction[1] * direction[0]
    g = np.array([direction[1], -direction[0]]) / denom
    return g, float(-(g @ edge.start))


def nguyen_regions(polygon: Polygon, i: int, j: int, mu: float, mu_q: float | None = None,
                   margin: float = ANGLE_MARGIN, *, spreading: bool | None = None,
                   ) -> IndependentRegions | None:
    """Independent regions by Nguyen's Algorithm 1: a two-sided cone between two edges (§5.1).

    A two-sided cone with vertex ``I`` and the counter-overlapping sector
    ``S`` cuts ``s1 = e1 ∩ (I - S)`` and ``s2 = e2 ∩ (I + S)``. Any ``p`` in
    ``s1`` and ``q`` in ``s2`` have ``q - p`` in ``S``. The paper's steps:
    (1) the sector; (2, 3) the triangles ``Δ1``, ``Δ2`` of vertices whose
    cone cuts inside ``e1``, resp. ``e2``, and their intersection, the
    trade-off region; (4) the locus where the two cuts have equal length (the
    paper's "bisector"), where the best vertex lies, or the point of the
    trade-off region nearest to it; (5) the segments cut at that vertex.
    Inside the trade-off region both cut lengths are affine in ``I``, so the
    best vertex is a vertex of the region or a point where the equal-length
    line crosses its boundary: all are tried.

    Fingers pushing apart from inside a slot or a hole (Corollary 3's ``QP``
    case) are the same construction with the sector negated (``q - p`` in
    ``-S``): ``spreading`` True builds that, False the squeezing one, None
    (the default) whichever gives the longer shorter segment (squeezing on a
    tie).

    Returns None when the trade-off region is empty: the edges are far apart
    for their lengths, so no vertex cuts both within them and the paper's
    construction yields nothing. :func:`maximal_regions` then often takes
    the full edges.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> from forceclosure.synthesis.planar.two_fingers import maximal_regions
    >>> square = bundled("square")
    >>> r = nguyen_regions(square, 0, 2, mu=0.3)   # never longer than the maximal segments
    >>> round(r.min_length, 3), r.min_length <= maximal_regions(square, 0, 2, 0.3).min_length
    (0.598, True)
    >>> r = nguyen_regions(bundled("frame"), 4, 6, mu=0.3)   # inside the hole: apart
    >>> r.spreading, r.certify().holds
    (True, True)
    """
    e1, e2, _, sector = shrunk_pair(polygon, i, j, mu, mu_q, margin)
    if sector is None:
        return None
    mu_q = mu if mu_q is None else mu_q
    found = [r for way in senses(spreading)
             if (r := _two_sided_cone(polygon, i, j, e1, e2, sector, mu, mu_q, way)) is not None]
    return max(found, key=lambda r: r.min_length, default=None)


def _two_sided_cone(polygon: Polygon, i: int, j: int, e1: Edge, e2: Edge, sector: Sector,
                    mu: float, mu_q: float, spreading: bool) -> IndependentRegions | None:
    """Algorithm 1 on one orientation: ``q - p`` in ``sector`` (squeezing) or in its
    negation (spreading)."""
    if spreading:
        sector = Sector(sector.low + math.pi, sector.high + math.pi)
    rays = [np.array([math.cos(a), math.sin(a)]) for a in (sector.low, sector.high)]
    # Each cut endpoint, as an affine function of I: backward rays to e1, forward rays to e2.
    ends = []
    for edge, sign in ((e1, -1.0), (e2, 1.0)):
        if any(abs(edge.direction[0] * r[1] - edge.direction[1] * r[0]) < 1e-12 for r in rays):
            return None  # a sector boundary runs along the edge: no proper cut
        ends.append([_ray_hits(edge, sign * r) for r in rays])
    # The trade-off region Δ1 ∩ Δ2: the cuts lie within the edges, and the edges lie on the
    # proper side of I (the rays move away from I towards them).
    span = 4 * (polygon.size + float(np.abs(polygon.outer).max()))
    region = np.array([[-span, -span], [span, -span], [span, span], [-span, span]])
    constraints = []
    for edge, (hit_lo, hit_hi), sign in ((e1, ends[0], -1.0), (e2, ends[1], 1.0)):
        for g, h in (hit_lo, hit_hi):
            constraints += [(g, h), (-g, edge.length - h)]  # 0 <= t <= length
        towards = sign * sector.bisector  # I + s * towards reaches the edge for s > 0
        across = np.array([-edge.direction[1], edge.direction[0]])
        side = float(np.sign(across @ towards))
        constraints.append((-side * across, side * float(across @ edge.start)))
    region = clip(region, np.array([g for g, _ in constraints], dtype=float),
                  -np.array([h for _, h in constraints], dtype=float))
    if len(region) == 0:
        return None

    def lengths(apex: NDArray) -> tuple[float, float]:
        return tuple(abs((hi[0] @ apex + hi[1]) - (lo[0] @ apex + lo[1])) for lo, hi in ends)

    candidates = list(region)
    diff = np.array([lengths(v)[0] - lengths(v)[1] for v in region])
    for k in range(len(region)):  # where the equal-length locus crosses the boundary
        a, b = diff[k], diff[(k + 1) % len(region)]
        if (a > 0) != (b > 0) and a != b:
            candidates.append(region[k] + (region[(k + 1) % len(region)] - region[k])
                              * (a / (a - b)))
    # the best apexes form a convex set (the shorter cut is concave in the apex): of those
    # within rounding of the best, the middle of the extremes in x (each the middle of its
    # extent in y), not whichever the clip listed first, so a moved copy gets the same cuts
    value = np.array([min(lengths(v)) for v in candidates])
    near = np.asarray(candidates)[value >= value.max() - 1e-9 * polygon.size]
    ends_x = []
    for at in (near[:, 0].min(), near[:, 0].max()):
        column = near[np.abs(near[:, 0] - at) <= 1e-9 * polygon.size]
        ends_x.append([at, 0.5 * (column[:, 1].min() + column[:, 1].max())])
    best = 0.5 * (np.array(ends_x[0]) + np.array(ends_x[1]))
    if min(lengths(best)) <= 1e-9 * polygon.size:
        return None
    segments = []
    for (lo, hi), e in zip(ends, (e1, e2), strict=True):  # within the edge, whatever rounding
        t = sorted(float(g @ best + h) for g, h in (lo, hi))
        segments.append((max(t[0], 0.0) + 0.0, min(t[1], e.length)))
    regions = IndependentRegions(polygon, (i, j), tuple(segments),
                                 "Nguyen's two-sided cone (Algorithm 1)",
                                 (float(mu), float(mu_q)),
                                 (float(best[0]) + 0.0, float(best[1]) + 0.0), spreading)
    return regions if regions.certify().holds else None


def _build_nguyen(polygon: Polygon, site: NDArray, hand: Hand) -> IndependentRegions | None:
    i, j, way = (int(x) for x in site)
    return nguyen_regions(polygon, i, j, hand.mu, margin=hand.margin, spreading=bool(way))


NGUYEN = Construction(
    dim=2, fingers=2, contact="hard", name="nguyen", paper="§5.1, Algorithm 1",
    method="edges", sites=edge_pair_sites, prune=counter_overlap_prune,
    bound=largest_segments_bound, build=_build_nguyen,
    searched="every pair of edges, the fingers squeezing or pushing apart, with a two-sided "
             "cone where the edges admit one (pairs too far apart for their lengths have "
             "none: construction='maximal' covers them)")

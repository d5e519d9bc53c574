"""Two fingers with friction on two edges of a polygon (§4.1 Lemma 1, §5.1).

By Corollary 3, hard fingers at ``p`` on edge ``e1`` and ``q`` on edge ``e2``
are force-closure iff ``w = q - p`` lies strictly inside the friction cone
at ``p`` and strictly inside minus the cone at ``q``. The intersection is the
**counter-overlapping sector**. "Strictly inside the cone about the pushing
direction ``m`` with friction ``mu``" needs no trigonometry: it is the two
linear inequalities ``mu (w . m) - cross(m, w) > 0`` and
``mu (w . m) + cross(m, w) > 0``. Since ``w`` is affine in the edge
parameters ``(t1, t2)``, so are the four conditions. Therefore:

* **Lemma 1**: the complete set of force-closure grasps on the pair is the
  parameter box ``[0, L1] x [0, L2]`` cut by four open half-planes, a convex
  polygon in ``(t1, t2)`` (:func:`pair_grasps`), for fingers squeezing the
  object; Corollary 3's other case, ``QP`` (fingers pushing apart from inside
  a slot or a hole), is the same four conditions on ``-w``, every sign
  flipped: a second convex polygon (empty on a convex polygon);
* **independent regions**: segments ``s1 x s2`` on which *every* pair is
  force-closure. A linear condition holds on a box iff it holds at the box's
  four corners, so the largest such pair of segments (largest minimum
  length) is a small linear program (:func:`maximal_regions`), in either
  orientation;
* **certificates**: the corner check is redone in exact rational arithmetic
  on the floating-point data (:meth:`IndependentRegions.certify`): a proof,
  not a numerical judgement.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ...errors import InputError
from ...geometry.clip import clip
from ...geometry.cones import counter_overlap
from ...geometry.rings import signed_area
from ...objects.polygon import Edge, Polygon
from ..construction import Construction, Hand, Undecided
from ..regions import TRIMS, first_proved, narrowed
from .edge_pair import (
    ANGLE_MARGIN,
    IndependentRegions,
    Sector,
    check_mu,
    counter_overlapping_sector,
    edge_pair,
    senses,
    shrunk_pair,
)

__all__ = ["ANGLE_MARGIN", "CHUNK", "MAX_EDGE_PAIRS", "IndependentRegions", "PairGrasps", "Sector",
           "counter_overlapping_sector", "max_min_segments", "maximal_regions",
           "pair_grasps"]

#: Edge pairs solved at once by :func:`max_min_segments` (bounds the memory used).
CHUNK = 2_048

#: Most edge pairs the two-finger search takes (a polygon of about 6,300 edges).
MAX_EDGE_PAIRS = 20_000_000


def _functionals(m_p, mu_p, m_q, mu_q) -> NDArray[np.float64]:
    """The four linear functionals ``l_k`` with Corollary 3 <=> ``l_k . w > 0`` for all k.

    ``m_p = -n_p`` and ``m_q = -n_q`` are the pushing directions (``(..., 2)``
    arrays), ``w = q - p``; the result is ``(..., 4, 2)``.
    """
    m_p, m_q = np.asarray(m_p, float), np.asarray(m_q, float)
    mu_p = np.asarray(mu_p, float)[..., None]
    mu_q = np.asarray(mu_q, float)[..., None]
    perp_p = np.stack([-m_p[..., 1], m_p[..., 0]], axis=-1)
    perp_q = np.stack([-m_q[..., 1], m_q[..., 0]], axis=-1)
    return np.stack([mu_p * m_p - perp_p, mu_p * m_p + perp_p,
                     -mu_q * m_q + perp_q, -mu_q * m_q - perp_q], axis=-2)


def _affine_arrays(start1, dir1, normal1, start2, dir2, normal2, mu_p, mu_q):
    """``(A, b)`` with Corollary 3 <=> ``A @ (t1, t2) + b > 0``, for ``(..., 2)`` edge data."""
    ell = _functionals(-normal1, mu_p, -normal2, mu_q)  # (..., 4, 2)
    # w = (start2 - start1) + t2 d2 - t1 d1
    A = np.stack([-np.einsum("...kj,...j->...k", ell, dir1),
                  np.einsum("...kj,...j->...k", ell, dir2)], axis=-1)
    b = np.einsum("...kj,...j->...k", ell, start2 - start1)
    return A, b


def _affine(e1: Edge, e2: Edge, mu_p: float, mu_q: float) -> tuple[NDArray, NDArray]:
    """``(A, b)`` with the conditions ``A @ (t1, t2) + b > 0`` (one row per functional)."""
    return _affine_arrays(e1.start, e1.direction, e1.normal, e2.start, e2.direction,
                          e2.normal, mu_p, mu_q)


@dataclass(frozen=True, eq=False)
class PairGrasps:
    """Lemma 1: every force-closure grasp with one finger on each of two edges.

    Attributes
    ----------
    edges : (int, int)
    sector : Sector or None
        The counter-overlapping sector; None when the cones do not counter-overlap.
        (For the spreading piece: the sector negated, the directions ``q - p``
        take when the fingers push apart.)
    region : (k, 2) array
        Convex polygon in ``(t1, t2)``, edge parameters (distances from each
        edge's start). Its interior is the set of force-closure grasps of this
        piece's orientation; empty when there are none.
    A, b : arrays
        Corollary 3's conditions on ``w = q - p``: ``A @ (t1, t2) + b > 0``
        squeezing, ``< 0`` (every row) spreading.
    reason : str
        Why the set is empty, or a description of it (of both pieces, on what
        :func:`pair_grasps` returns).
    spreading : bool
        This piece's orientation: False, the fingers squeeze (``PQ``); True,
        they push apart (``QP``).
    other : PairGrasps or None
        On what :func:`pair_grasps` returns (the squeezing piece): the
        spreading piece. :attr:`pieces` gives both, :attr:`empty` and
        :meth:`contains` are about their union.
    """

    edges: tuple[int, int]
    sector: Sector | None
    region: NDArray[np.float64]
    A: NDArray[np.float64]
    b: NDArray[np.float64]
    reason: str
    spreading: bool = False
    other: PairGrasps | None = None

    @property
    def pieces(self) -> tuple[PairGrasps, ...]:
        """The convex pieces: squeezing, then (on what :func:`pair_grasps` returns)
        spreading."""
        return (self,) if self.other is None else (self, *self.other.pieces)

    @property
    def empty(self) -> bool:
        """True when no grasp on the pair is force-closure (in any piece)."""
        return all(len(g.region) < 3 for g in self.pieces)

    def contains(self, t1, t2) -> NDArray[np.bool_]:
        """Whether the grasps at ``(t1, t2)`` are force-closure, in any piece (vectorised)."""
        t = np.stack(np.broadcast_arrays(np.asarray(t1, float), np.asarray(t2, float)), -1)
        inside = np.zeros(t.shape[:-1], bool)
        for g in self.pieces:
            sign = -1.0 if g.spreading else 1.0
            inside |= np.all(sign * (t @ g.A.T + g.b) > 0, axis=-1)
        return inside


def pair_grasps(polygon: Polygon, i: int, j: int, mu: float, mu_q: float | None = None,
                ) -> PairGrasps:
    """All force-closure grasps with hard fingers on edges ``i`` and ``j`` (Lemma 1).

    Two convex pieces: the fingers squeezing (``w = q - p`` in the
    counter-overlapping sector, ``A t + b > 0``), which is returned, and the
    fingers pushing apart from inside a slot or a hole (Corollary 3's ``QP``
    case, ``-w`` in it, ``A t + b < 0``), its :attr:`~PairGrasps.other`. On a
    convex polygon the second is always empty; :attr:`~PairGrasps.empty` and
    :meth:`~PairGrasps.contains` are about both.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> g = pair_grasps(bundled("square"), 0, 2, mu=0.3)   # opposite sides, 2 apart
    >>> g.contains(1.0, 1.0).item(), g.contains(0.2, 0.2).item()   # head on; 1.6 apart sideways
    (True, False)
    >>> h = pair_grasps(bundled("frame"), 4, 6, mu=0.3)   # the hole's sides, 2 apart
    >>> h.contains(1.0, 1.0).item(), [len(g.region) > 0 for g in h.pieces]   # pushing apart
    (True, [False, True])
    """
    mu_q = mu if mu_q is None else mu_q
    check_mu(mu, mu_q)
    e1, e2 = edge_pair(polygon, i, j)
    sector = counter_overlapping_sector(e1.normal, mu, e2.normal, mu_q)
    A, b = _affine(e1, e2, mu, mu_q)
    if sector is None:
        why = ("the friction cones do not counter-overlap (the normals are too far from "
               "opposite for this friction)")
        none = np.zeros((0, 2))
        return PairGrasps((i, j), None, none, A, b, why, False,
                          PairGrasps((i, j), None, none, A, b, why, True))
    squeeze, spread = (_piece(e1, e2, (i, j), sector, A, b, s) for s in (False, True))
    said = [g.reason for g in (squeeze, spread) if len(g.region)]
    reason = "; ".join(said) if said else squeeze.reason
    return PairGrasps((i, j), sector, squeeze.region, A, b, reason, False, spread)


def _piece(e1: Edge, e2: Edge, edges: tuple[int, int], sector: Sector, A: NDArray,
           b: NDArray, spreading: bool) -> PairGrasps:
    """One orientation's convex piece of Lemma 1's set: the box cut by four half-planes."""
    box = np.array([[0, 0], [e1.length, 0], [e1.length, e2.length], [0, e2.length]], float)
    sign = -1.0 if spreading else 1.0
    if spreading:
        sector = Sector(sector.low + math.pi, sector.high + math.pi)
    region = clip(box, sign * A, -sign * b)
    if len(region) < 3 or abs(signed_area(region)) <= 1e-12 * e1.length * e2.length:
        return PairGrasps(edges, sector, np.zeros((0, 2)), A, b,
                          "the edges are placed so that no segment between them lies in the "
                          "counter-overlapping sector", spreading)
    share = abs(signed_area(region)) / (e1.length * e2.length)
    how = "the fingers pushing apart" if spreading else "the fingers squeezing"
    return PairGrasps(edges, sector, region, A, b,
                      f"{share:.1%} of the pairs of points on the two edges are force-closure, "
                      f"{how}", spreading)


def _constraint_triples() -> NDArray[np.int64]:
    """Triples of the 9 constraints; those with ``z >= 0`` tight give no regions anyway."""
    from itertools import combinations

    return np.array([t for t in combinations(range(9), 3) if 8 not in t])


_TRIPLES = _constraint_triples()


def max_min_segments(A: NDArray, b: NDArray, L1: NDArray, L2: NDArray,
                     ) -> tuple[NDArray, NDArray, NDArray]:
    """Solve the maximal-regions LP for many edge pairs at once, exactly.

    For each pair: maximise ``z`` over segments ``[u1, u1 + z]`` of
    ``[0, L1]`` and ``[u2, u2 + z]`` of ``[0, L2]`` such that
    ``A @ (t1, t2) + b >= 0`` at all four corners. (Both segments may have
    length exactly ``z``: shrinking a segment never breaks the conditions.)
    The minimum of ``a1 t1 + a2 t2`` over the corners takes ``u`` or
    ``u + z`` by the coefficients' signs, so each condition is linear in
    ``x = (u1, u2, z)``. That leaves a three-variable LP with 9 constraints,
    whose optimum is a vertex: one of the triples of tight constraints (56,
    leaving out ``z >= 0``, which only an empty answer would need), all
    solved at once by Cramer's rule and filtered for feasibility.

    Parameters
    ----------
    A : (P, 4, 2), b : (P, 4), L1, L2 : (P,)

    Returns
    -------
    z, u1, u2 : (P,) arrays
        ``z`` is ``-inf`` where no segments satisfy the conditions.
    """
    P = len(b)
    c = np.minimum(A[..., 0], 0) + np.minimum(A[..., 1], 0)
    G = np.zeros((P, 9, 3))
    h = np.zeros((P, 9))
    G[:, :4, 0], G[:, :4, 1], G[:, :4, 2], h[:, :4] = -A[..., 0], -A[..., 1], -c, b
    G[:, 4, 0] = G[:, 5, 1] = G[:, 8, 2] = -1.0  # u1 >= 0, u2 >= 0, z >= 0
    G[:, 6, 0] = G[:, 6, 2] = G[:, 7, 1] = G[:, 7, 2] = 1.0  # u + z <= L
    h[:, 6], h[:, 7] = L1, L2
    scale = np.maximum(np.abs(G).max(axis=2), 1e-300)
    G, h = G / scale[..., None], h / scale
    r1, r2, r3 = (G[:, _TRIPLES[:, k]] for k in range(3))  # (P, 84, 3)
    h1, h2, h3 = (h[:, _TRIPLES[:, k]] for k in range(3))
    c23, c31, c12 = np.cross(r2, r3), np.cross(r3, r1), np.cross(r1, r2)
    det = np.einsum("pti,pti->pt", r1, c23)
    ok = np.abs(det) > 1e-12
    x = (h1[..., None] * c23 + h2[..., None] * c31 + h3[..., None] * c12) / np.where(
        ok, det, 1.0)[..., None]
    slack = h[:, None, :] - np.einsum("pkj,ptj->ptk", G, x)
    tol = 1e-9 * np.maximum(1.0, np.maximum(L1, L2))[:, None]
    feasible = ok & np.all(slack >= -tol[..., None], axis=2)
    z = np.where(feasible, x[..., 2], -np.inf)
    return _face_centre(x, z, tol)


def _face_centre(x: NDArray, z: NDArray, tol: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    """One optimum per pair that does not depend on rounding: the middle of the optimal face.

    The segments of the largest length can often slide (the optimal face of the LP is an
    edge or a polygon, not a vertex), and which of its vertices the feasibility test keeps
    last is a matter of rounding, so a moved copy got them elsewhere. Of the vertices within
    ``tol`` of the best ``z``, the face's extremes in ``u1`` (each the middle of its extent in
    ``u2``) are averaged: a point of the (convex) face, its centre on an edge of it.
    """
    with np.errstate(invalid="ignore"):  # pairs with no optimum: inf - inf, set aside below
        return _centre_of(x, z, tol)


def _centre_of(x: NDArray, z: NDArray, tol: NDArray) -> tuple[NDArray, NDArray, NDArray]:
    zmax = z.max(axis=1)
    opt = np.isfinite(z) & (z >= zmax[:, None] - tol)
    u1, u2 = x[..., 0], x[..., 1]
    lo = np.where(opt, u1, np.inf).min(axis=1)
    hi = np.where(opt, u1, -np.inf).max(axis=1)

    def middle_u2(at):
        return 0.5 * (np.where(at, u2, np.inf).min(axis=1) + np.where(at, u2, -np.inf).max(axis=1))

    a2 = middle_u2(opt & (u1 <= lo[:, None] + tol))
    b2 = middle_u2(opt & (u1 >= hi[:, None] - tol))
    zc = np.where(opt, z, np.inf).min(axis=1)
    found = np.isfinite(zmax)
    return (np.where(found, zc, -np.inf), np.where(found, 0.5 * (lo + hi), 0.0),
            np.where(found, 0.5 * (a2 + b2), 0.0))


def maximal_regions(polygon: Polygon, i: int, j: int, mu: float, mu_q: float | None = None,
                    margin: float = ANGLE_MARGIN, *, spreading: bool | None = None,
                    ) -> IndependentRegions | Undecided | None:
    """The largest independent regions of contact on edges ``i`` and ``j`` (exact LP).

    Maximises the shorter segment's length, subject to every pair of points
    being force-closure with at least ``margin`` radians to spare in both
    cones. The conditions are linear in the segment endpoints (checked at
    the corners), so this is a small linear program, solved exactly by
    :func:`max_min_segments`. ``spreading``: the fingers squeeze (False), push
    apart from inside a slot or a hole (True), or whichever gives the larger
    regions (None; squeezing on a tie).

    Returns None when the pair has no such regions, and
    :class:`~forceclosure.synthesis.construction.Undecided` when the LP found
    some that no cut of them could prove (the object's numbers do not resolve
    them).

    Examples
    --------
    Opposite sides of a square of side 2, friction 0.3: aligned segments of
    length ``z`` need ``z / 2 < tan(atan(0.3) - margin)`` over the gap of 2,
    so ``z`` is just under ``2 * 0.3 = 0.6``:

    >>> from forceclosure.objects import bundled
    >>> r = maximal_regions(bundled("square"), 0, 2, mu=0.3)
    >>> round(r.min_length, 3), r.certify().holds
    (0.598, True)

    Inside the square hole of the frame, 2 across, the fingers push apart:

    >>> r = maximal_regions(bundled("frame"), 4, 6, mu=0.3)
    >>> round(r.min_length, 3), r.spreading, r.certify().holds
    (0.598, True, True)
    """
    e1, e2, shrink, sector = shrunk_pair(polygon, i, j, mu, mu_q, margin)
    if sector is None:
        return None
    mu_q = mu if mu_q is None else mu_q
    A, b = _affine(e1, e2, *shrink)
    found, undecided = [], None
    for way in senses(spreading):
        sign = -1.0 if way else 1.0
        z, u1, u2 = max_min_segments(sign * A[None], sign * b[None], np.array([e1.length]),
                                     np.array([e2.length]))
        r = _certified(polygon, i, j, float(z[0]), float(u1[0]), float(u2[0]), (mu, mu_q),
                       way)
        if isinstance(r, IndependentRegions):
            found.append(r)
        elif r is not None:
            undecided = r
    return max(found, key=lambda r: r.min_length, default=undecided)


def _certified(polygon: Polygon, i: int, j: int, z: float, u1: float, u2: float,
               mu: tuple[float, float], spreading: bool = False,
               ) -> IndependentRegions | Undecided | None:
    """Segments of length ``z`` from ``u1``, ``u2``, returned only with a holding certificate;
    :class:`~forceclosure.synthesis.construction.Undecided` when no cut of them
    (:data:`~forceclosure.synthesis.regions.TRIMS`) can be proved."""
    e1, e2 = polygon.edges[i], polygon.edges[j]
    z = float(z)
    if not z > 1e-9 * max(e1.length, e2.length):
        return None
    u1, u2 = max(float(u1), 0.0) + 0.0, max(float(u2), 0.0) + 0.0  # + 0.0: no -0.0
    segments = ((u1, min(u1 + z, e1.length)), (u2, min(u2 + z, e2.length)))
    mu = (float(mu[0]), float(mu[1]))
    regions = first_proved(lambda trim: IndependentRegions(  # rounding may cut a corner
        polygon, (i, j), tuple((u + trim * (v - u), v - trim * (v - u)) for u, v in segments),
        "maximal (linear program)", mu, spreading=bool(spreading)))
    if regions is not None:
        return regions
    return Undecided(f"segments {z:.6g} long on edges {i} and {j} by the linear program, "
                     "none of them proved force-closure in the coordinates given (even cut by "
                     f"{TRIMS[-1]:.1%})", size=z / polygon.size)


def edge_pair_sites(polygon: Polygon, hand: Hand):
    """Step 1: every edge pair ``i < j`` in both of Corollary 3's orientations, rows
    ``(i, j, spreading)`` in blocks of rows ``i`` (memory follows the pairs kept, not all
    ``n (n - 1)``); only squeezing pairs on a convex polygon (no grasp on it spreads).
    More than :data:`MAX_EDGE_PAIRS` pairs are refused."""
    n = len(polygon.edges)
    total = n * (n - 1) // 2
    if total > MAX_EDGE_PAIRS:
        raise InputError(f"the polygon has {n} edges, {total} edge pairs to search: more than "
                         f"{MAX_EDGE_PAIRS}; simplify it (fewer vertices)")
    ways = (0,) if _convex(polygon) else (0, 1)
    rows = max(1, CHUNK * CHUNK // max(n, 1))
    for lo in range(0, n, rows):
        i, j = np.nonzero(np.triu(np.ones((min(rows, n - lo), n), dtype=bool), lo + 1))
        k = len(ways)  # in order of (i, j, spreading), the order that breaks ties
        yield np.stack([np.repeat(i + lo, k), np.repeat(j, k), np.tile(ways, len(i))],
                       axis=1).astype(np.int64)


def counter_overlap_prune(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray[np.bool_]:
    """Step 2: the pair's cones, narrowed by the margin, can counter-overlap (``-n_i`` and
    ``n_j`` less than ``2 atan(mu)`` apart); spreading, each edge also reaches outside the
    other's line. Both are necessary."""
    shrunk = narrowed(hand.mu, hand.margin)
    if shrunk <= 0:
        return np.zeros(len(sites), dtype=bool)
    normal = polygon.edge_arrays.normal
    i, j, way = sites.T
    keep = counter_overlap(normal[i], normal[j], shrunk)
    spread = way == 1
    if spread.any():
        start, direction, _, length = polygon.edge_arrays
        end = start + direction * length[:, None]
        tol = 1e-12 * polygon.size

        def outside(a, b):
            return np.maximum(np.einsum("pk,pk->p", start[b] - start[a], normal[a]),
                              np.einsum("pk,pk->p", end[b] - start[a], normal[a])) > -tol

        keep[spread] &= outside(i[spread], j[spread]) & outside(j[spread], i[spread])
    return keep


def solve_sites(polygon: Polygon, sites: NDArray, mu: float) -> tuple[NDArray, NDArray, NDArray]:
    """:func:`max_min_segments` on every site, in blocks of :data:`CHUNK`."""
    start, direction, normal, length = polygon.edge_arrays
    n = len(sites)
    z, u1, u2 = np.full(n, -np.inf), np.zeros(n), np.zeros(n)
    for lo in range(0, n, CHUNK):
        sl = slice(lo, lo + CHUNK)
        i, j, way = sites[sl].T
        A, b = _affine_arrays(start[i], direction[i], normal[i], start[j], direction[j],
                              normal[j], mu, mu)
        sign = np.where(way == 1, -1.0, 1.0)
        z[sl], u1[sl], u2[sl] = max_min_segments(sign[:, None, None] * A, sign[:, None] * b,
                                                 length[i], length[j])
    return z, u1, u2


def largest_segments_bound(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray:
    """Step 3: the largest shorter segment of each pair over the object's size, solved for
    all pairs at once (exact: the regions built are these, trimmed at most by 2e-9)."""
    return solve_sites(polygon, sites, narrowed(hand.mu, hand.margin))[0] / polygon.size


@dataclass
class _Solves:
    """The linear program of the pairs a search builds, solved block by block in the order
    of their bound (:func:`shorter_edge_bound`), kept in the search's
    :attr:`~forceclosure.synthesis.construction.Hand.memo`: a solve of one pair alone costs
    as much as of a few hundred, and the pairs built come in that order."""

    polygon: Polygon
    mu: float
    sites: NDArray
    keys: NDArray  # each site's (i n + j) 2 + spreading, sorted
    rows: NDArray  # the sites' rows in that sorted order
    order: NDArray  # the sites' rows by decreasing bound
    place: NDArray  # each row's place in ``order``
    z: NDArray
    u1: NDArray
    u2: NDArray

    @classmethod
    def of(cls, polygon: Polygon, sites: NDArray, mu: float, bound: NDArray) -> _Solves:
        n = len(polygon.edges)
        keys = (sites[:, 0] * n + sites[:, 1]) * 2 + sites[:, 2]
        rows = np.argsort(keys, kind="stable")
        order = np.argsort(-bound, kind="stable")
        place = np.empty(len(sites), dtype=np.int64)
        place[order] = np.arange(len(sites))
        nan = np.full(len(sites), np.nan)
        return cls(polygon, mu, sites, keys[rows], rows, order, place, nan, nan.copy(),
                   nan.copy())

    def segments(self, site: NDArray) -> tuple[float, float, float] | None:
        """``(z, u1, u2)`` of ``site``, solving it with the next :data:`BLOCK` sites in
        the bound's order when it is not yet solved; None for a site not searched."""
        n = len(self.polygon.edges)
        key = (int(site[0]) * n + int(site[1])) * 2 + int(site[2])
        at = int(np.searchsorted(self.keys, key))
        if at == len(self.keys) or self.keys[at] != key:
            return None
        row = int(self.rows[at])
        if np.isnan(self.z[row]):
            block = self.order[self.place[row]:self.place[row] + BLOCK]
            block = block[np.isnan(self.z[block])]
            self.z[block], self.u1[block], self.u2[block] = solve_sites(
                self.polygon, self.sites[block], self.mu)
        return float(self.z[row]), float(self.u1[row]), float(self.u2[row])


#: Pairs solved at once when a search builds one whose linear program is not yet solved.
BLOCK = 512
#: The key of a search's :class:`_Solves` in its memo.
_SOLVES = "two_fingers.solves"


def shorter_edge_bound(polygon: Polygon, sites: NDArray, hand: Hand) -> NDArray:
    """Step 3 of the maximal construction: a pair's regions are no longer than its shorter
    edge (over the object's size). Cheap, so the search solves the linear program
    (:func:`max_min_segments`) only of the pairs it builds, in this order, block by block
    (:class:`_Solves`), rather than of every pair the prune keeps."""
    length = polygon.edge_arrays.length
    bound = np.minimum(length[sites[:, 0]], length[sites[:, 1]]) / polygon.size
    hand.memo[_SOLVES] = _Solves.of(polygon, np.asarray(sites), narrowed(hand.mu, hand.margin),
                                    bound)
    return bound


def _build_maximal(polygon: Polygon, site: NDArray, hand: Hand,
                   ) -> IndependentRegions | Undecided | None:
    mu = narrowed(hand.mu, hand.margin)
    solves = hand.memo.get(_SOLVES)
    found = (solves.segments(site) if solves is not None and solves.polygon is polygon
             and solves.mu == mu else None)
    if found is None:
        z, u1, u2 = (float(a[0]) for a in solve_sites(polygon, np.asarray(site)[None], mu))
    else:
        z, u1, u2 = found
    i, j, way = (int(x) for x in site)
    return _certified(polygon, i, j, z, u1, u2, (hand.mu, hand.mu), bool(way))


MAXIMAL = Construction(
    dim=2, fingers=2, contact="hard", name="maximal", paper="§5.1, Corollary 3",
    method="edges", sites=edge_pair_sites, prune=counter_overlap_prune,
    bound=shorter_edge_bound, build=_build_maximal,
    searched="every pair of edges, the fingers squeezing or pushing apart", complete=True,
    completeness="Lemma 1 gives every two-finger grasp")


def _convex(polygon: Polygon) -> bool:
    """A polygon without holes whose outline never turns both ways: no grasp on it spreads
    (``p - q`` never points into the object from ``p``)."""
    if polygon.holes:
        return False
    d = np.array([e.direction for e in polygon.edges])
    turns = d[:, 0] * np.roll(d[:, 1], -1) - d[:, 1] * np.roll(d[:, 0], -1)
    return bool(np.all(turns >= 0) or np.all(turns <= 0))

"""Two fingers on two edges of a polygon: the shared pieces of §4.1 and §5.1.

The counter-overlapping sector ``C_p ∩ -C_q`` of two edges (Lemma 1), the
friction they are checked and narrowed with, and the region pair type
(:class:`IndependentRegions`) that both constructions on a pair of edges
return: the maximal segments (:mod:`.planar`) and Nguyen's two-sided cone
(:mod:`.nguyen`). Both import from here, and neither from the other's
module but :mod:`.planar`'s search, which runs either.

Examples
--------
>>> from forceclosure.objects import bundled
>>> e1, e2, shrink, sector = shrunk_pair(bundled("square"), 0, 2, 0.3, None, ANGLE_MARGIN)
>>> sector is not None and round(math.degrees(sector.width), 1) < 2 * math.degrees(0.3)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray

from ...errors import InputError
from ...objects.polygon import Edge, Polygon
from ..regions import (
    MARGIN,
    Certificate,
    Regions,
    check_edges,
    check_margin,
    exact_inward,
    exact_point,
    narrowed,
    proved_once,
    surely_positive,
)

__all__ = ["ANGLE_MARGIN", "IndependentRegions", "Sector", "check_mu", "counter_overlapping_sector",
           "edge_pair", "senses", "shrunk_pair"]

#: Default angular margin (radians) kept between region grasps and the cone boundary.
ANGLE_MARGIN = MARGIN  # the one margin (regions.check_margin)


@dataclass(frozen=True)
class Sector:
    """The counter-overlapping sector ``C_p ∩ -C_q`` (Lemma 1): directions of ``q - p``.

    ``low`` and ``high`` are its bounding angles (radians, ``low < high``);
    ``width = high - low``.
    """

    low: float
    high: float

    @property
    def width(self) -> float:
        """Opening angle of the sector."""
        return self.high - self.low

    @property
    def bisector(self) -> NDArray[np.float64]:
        """Unit direction halfway between the bounds."""
        mid = 0.5 * (self.low + self.high)
        return np.array([math.cos(mid), math.sin(mid)])


def counter_overlapping_sector(n_p, mu_p: float, n_q, mu_q: float) -> Sector | None:
    """``C_p ∩ -C_q`` for outward normals ``n_p``, ``n_q`` (Lemma 1), or None if empty.

    The exact sector, with its bounding angles; whether it is empty is the
    test of :func:`forceclosure.geometry.cones.counter_overlap` (the one used
    to screen pairs), computed here from the same angles so that the sector's
    bounds and its emptiness never disagree.

    Examples
    --------
    >>> s = counter_overlapping_sector([-1, 0], 0.5, [1, 0], 0.5)
    >>> round(math.degrees(s.width), 4)   # two cones of 26.57 degrees, head on
    53.1301
    """
    m_p = -np.asarray(n_p, float) / np.linalg.norm(n_p)
    theta_p = math.atan2(m_p[1], m_p[0])
    n_q = np.asarray(n_q, float) / np.linalg.norm(n_q)
    delta = math.remainder(math.atan2(n_q[1], n_q[0]) - theta_p, 2 * math.pi)
    a_p, a_q = math.atan(mu_p), math.atan(mu_q)
    low, high = max(-a_p, delta - a_q), min(a_p, delta + a_q)
    if low >= high:
        return None
    return Sector(theta_p + low, theta_p + high)


def edge_pair(polygon: Polygon, i: int, j: int) -> tuple[Edge, Edge]:
    """Edges ``i`` and ``j`` of ``polygon`` (checked: two different edges of it)."""
    i, j = check_edges(polygon, (i, j), 2)
    return polygon.edges[i], polygon.edges[j]


def check_mu(mu_p: float, mu_q: float, margin: float = ANGLE_MARGIN) -> None:
    """Refuse a friction coefficient that is not a finite number >= 0, or a bad margin."""
    for mu in (mu_p, mu_q):
        if not (isinstance(mu, int | float) and math.isfinite(mu) and mu >= 0):
            raise InputError(f"friction coefficient must be a finite number >= 0, got {mu!r}")
    check_margin(margin)


def senses(spreading: bool | None) -> tuple[bool, ...]:
    """The senses of Corollary 3 asked for: ``spreading`` itself, or both (squeezing,
    ``False``, then spreading, ``True``) when it is None.

    Examples
    --------
    >>> senses(None), senses(True)
    ((False, True), (True,))
    """
    return (False, True) if spreading is None else (bool(spreading),)


def shrunk_pair(polygon: Polygon, i: int, j: int, mu: float, mu_q: float | None,
                 margin: float) -> tuple[Edge, Edge, list[float], Sector | None]:
    """The two edges, the friction shrunk by ``margin`` radians, and the sector it leaves."""
    mu_q = mu if mu_q is None else mu_q
    check_mu(mu, mu_q, margin)
    e1, e2 = edge_pair(polygon, i, j)
    shrink = [narrowed(m, margin) for m in (mu, mu_q)]
    sector = (counter_overlapping_sector(e1.normal, shrink[0], e2.normal, shrink[1])
              if min(shrink) > 0 else None)
    return e1, e2, shrink, sector


@dataclass(frozen=True, eq=False)
class IndependentRegions(Regions):
    """Two segments, one per edge, such that *every* pair of points is force-closure.

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    mu : (float, float)
        The friction at each finger.
    apex : (float, float) or None
        The vertex of Nguyen's two-sided cone, if it made them.
    spreading : bool
        The fingers push apart from inside a slot or a hole (Corollary 3's ``QP``
        case: ``p - q`` in the cone at ``p``) rather than squeeze (``PQ``).
    """

    mu: tuple[float, float] = (0.0, 0.0)
    apex: tuple[float, float] | None = None  # Nguyen's two-sided cone vertex, if it made them
    spreading: bool = False

    def friction(self) -> tuple[float, ...]:
        """The friction coefficient at each finger."""
        return tuple(self.mu)

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``mu``, ``spreading`` (and
        ``apex``)."""
        record = {**super().to_dict(), "mu": list(self.mu), "spreading": self.spreading}
        if self.apex is not None:
            record["apex"] = list(self.apex)
        return record

    @proved_once
    def certify(self) -> Certificate:
        """Prove, in exact rational arithmetic, that every pair of points is force-closure.

        The four Corollary 3 conditions are linear in ``w = q - p``, and ``w``
        is affine in the two edge parameters. So they hold on the whole box
        ``s1 x s2`` iff they hold at its four corners. The corners are
        checked exactly at the very floating-point points that are printed and
        returned, with each edge's normal taken exactly from its two vertices:
        in doubles where a proved error bound settles the sign
        (:func:`~forceclosure.synthesis.regions.surely_positive`), otherwise
        with ``fractions.Fraction``; no rounding enters. Squeezing regions are
        checked with ``w = q - p``, spreading ones with ``w = p - q``
        (Corollary 3's two cases).
        """
        e1, e2 = (self.polygon.edges[k] for k in self.edges)
        F = Fraction
        # narrowed by the outline's spread: then the cone holds for every normal the real
        # outline has along the edge
        nu_p, nu_q = (float(narrowed(m, self.polygon.spread)) for m in self.mu)

        def inside(m: list[Fraction], mu: Fraction, w: list[Fraction]) -> bool:
            dot = m[0] * w[0] + m[1] * w[1]
            cross = m[0] * w[1] - m[1] * w[0]
            return mu * dot - cross > 0 and mu * dot + cross > 0

        def surely_inside(m: tuple[float, float], mu: float, w: tuple[float, float]) -> bool:
            """``inside`` decided in doubles where their error bound allows: ``m`` and ``w``
            are each rounded once from exact values, then a product, a sum, ``mu`` times
            it and one more sum (six roundings on a path)."""
            dot = m[0] * w[0] + m[1] * w[1]
            cross = m[0] * w[1] - m[1] * w[0]
            size = abs(mu) * (abs(m[0] * w[0]) + abs(m[1] * w[1])) + abs(m[0] * w[1]) \
                + abs(m[1] * w[0])
            return (surely_positive(mu * dot - cross, size, 6)
                    and surely_positive(mu * dot + cross, size, 6))

        def inward(e: Edge) -> tuple[float, float]:
            return (-(float(e.end[1]) - float(e.start[1])), float(e.end[0]) - float(e.start[0]))

        for e, (u, v) in zip((e1, e2), self.segments, strict=True):
            if not 0 <= u <= v <= e.length:
                return Certificate(False, "corner check (exact rationals)",
                                   f"the segment ({u:.17g}, {v:.17g}) is not within edge "
                                   f"{e.index} (length {e.length:.17g})")
        f_p, f_q = inward(e1), inward(e2)
        exact: list[list[Fraction]] = []  # the inward normals in rationals, if needed
        for t1 in self.segments[0]:
            for t2 in self.segments[1]:
                pf, qf = e1.point(t1), e2.point(t2)  # the points printed and returned
                wf = (float(qf[0]) - float(pf[0]), float(qf[1]) - float(pf[1]))
                if self.spreading:
                    wf = (-wf[0], -wf[1])
                if surely_inside(f_p, nu_p, wf) and surely_inside(f_q, nu_q,
                                                                  (-wf[0], -wf[1])):
                    continue
                if not exact:
                    exact += [exact_inward(e1), exact_inward(e2)]
                m_p, m_q = exact
                p, q = exact_point(e1, t1), exact_point(e2, t2)
                w = [q[0] - p[0], q[1] - p[1]]
                if self.spreading:
                    w = [-w[0], -w[1]]
                if not (inside(m_p, F(nu_p), w) and inside(m_q, F(nu_q), [-w[0], -w[1]])):
                    return Certificate(False, "corner check (exact rationals)",
                                       f"the grasp at t = ({t1:.6g}, {t2:.6g}) is not "
                                       "strictly inside both friction cones")
        how = ", the fingers pushing apart (QP)" if self.spreading else ""
        return Certificate(True, "corner check (exact rationals)",
                           f"Corollary 3 holds strictly at the four corners of s1 x s2{how}, "
                           "hence (linear conditions) at every pair of points")

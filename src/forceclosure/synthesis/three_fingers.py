"""Three fingers with friction on three edges: a sufficient linear condition (beyond §5).

Corollary 4 turns a nonmarginal equilibrium into a proof of force closure.
Three forces are in equilibrium when their lines meet at one point ``X``
and positive multiples of them sum to zero. So the grasp at ``p1, p2, p3``
is force-closure if, for some point ``X``:

(a) every ``X - p_i`` lies strictly inside the friction cone at ``p_i``
    (the finger can push along the line from ``p_i`` to ``X``), and
(b) any three directions, one from each cone, positively span the plane.
    Then the three ``X - p_i`` do, and positive multiples of them balance.

(a) is linear in ``X`` and the contact points together. For segments, it
holds for every point of ``s_i`` iff it holds at both ends. So the largest
regions sharing one ``X`` are a linear program in ``(X, u1, u2, u3, z)``.
(b) involves only the edges' normals. ``cross(f_i, f_j)`` is bilinear over
the two cones, so it keeps one sign on them iff it does on their extreme
generators: eight combinations, checked exactly. The condition is
sufficient, not necessary: it finds grasps such as three fingers around a
triangle, which no two fingers on edges can hold.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from scipy.optimize import linprog

from ..errors import InputError
from ..objects.polygon import Polygon
from .regions import (
    MARGIN,
    Certificate,
    Regions,
    check_edges,
    check_margin,
    exact_inward,
    exact_point,
    narrowed,
)
from .vertices import _extremes, _generators

__all__ = ["DEPTH", "ThreeFingerRegions", "best_three_finger_regions", "three_finger_regions"]

#: ``X`` is kept this fraction of the object's size inside the material beyond each contact.
DEPTH = 1e-3


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _spans_whatever_the_choice(cones) -> bool:
    """(b): one direction from each cone, any choice, positively spans the plane."""
    signs = set()
    for a, b, c in itertools.product(*cones):
        crosses = (_cross(a, b), _cross(b, c), _cross(c, a))
        if any(x == 0 for x in crosses):
            return False
        signs.update(x > 0 for x in crosses)
        if len(signs) > 1:
            return False
    return True


@dataclass(frozen=True, eq=False)
class ThreeFingerRegions(Regions):
    """Three segments such that every choice of three points is force-closure (Corollary 4).

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    centre : (float, float)
        The point ``X`` where the three lines of force meet.
    mu : float
    """

    centre: tuple[float, float] = (0.0, 0.0)
    mu: float = 0.0

    def certify(self) -> Certificate:
        """Exactly, in rationals: (a) at both ends of every segment, and (b) on the
        cones' extreme generators."""
        F = Fraction
        X = [F(x) for x in self.centre]
        cones = []
        for e, seg in zip((self.polygon.edges[k] for k in self.edges), self.segments,
                          strict=True):
            cone = _extremes(_generators([[-x for x in exact_inward(e)]],
                                         F(narrowed(self.mu, self.polygon.spread))))
            cones.append(cone)
            for t in seg:
                p = exact_point(e, t)
                w = [X[0] - p[0], X[1] - p[1]]
                if not (_cross(cone[0], w) > 0 and _cross(w, cone[1]) > 0):
                    return Certificate(False, "Corollary 4 (exact rationals)",
                                       f"from edge {e.index} at t = {t:.6g} the line to X "
                                       "leaves the friction cone")
        if not _spans_whatever_the_choice(cones):
            return Certificate(False, "Corollary 4 (exact rationals)",
                               "some choice of directions from the cones does not positively "
                               "span the plane")
        return Certificate(True, "Corollary 4 (exact rationals)",
                           "from every point of every segment the line to X lies strictly "
                           "inside the friction cone, and any directions from the three cones "
                           "balance: a nonmarginal equilibrium for every choice")

    def friction(self) -> tuple[float, ...]:
        """The friction coefficient at each finger."""
        return (self.mu,) * 3

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``centre`` and ``mu``."""
        return {**super().to_dict(), "centre": list(self.centre), "mu": self.mu}


def three_finger_regions(polygon: Polygon, edges: tuple[int, int, int], mu: float,
                         margin: float = MARGIN) -> ThreeFingerRegions | None:
    """The largest regions on three edges certified by the condition of the module.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> r = three_finger_regions(bundled("triangle"), (0, 1, 2), mu=0.3)
    >>> round(r.min_length, 3), r.certify().holds
    (0.299, True)
    """
    edges = check_edges(polygon, edges, 3)
    if not (isinstance(mu, int | float) and np.isfinite(mu) and mu > 0):
        raise InputError(f"friction coefficient must be a positive number, got {mu!r}")
    shrunk = narrowed(mu, check_margin(margin))
    if shrunk <= 0:
        return None
    es = [polygon.edges[k] for k in edges]
    cones = [_extremes(_generators([e.normal], shrunk)) for e in es]
    if not _spans_whatever_the_choice(cones):
        return None
    depth = DEPTH * polygon.size
    rows, rhs = [], []  # variables (X, Y, u1, u2, u3, z); rows @ x <= rhs
    for i, (e, (g_lo, g_hi)) in enumerate(zip(es, cones, strict=True)):
        push = -e.normal
        # cross(g_lo, X - p) > 0, cross(X - p, g_hi) > 0, push . (X - p) >= depth
        for ell, need in (((-g_lo[1], g_lo[0]), 0.0), ((g_hi[1], -g_hi[0]), 0.0),
                          (tuple(push), depth)):
            ell = np.asarray(ell, float)
            for at_end in (0.0, 1.0):  # p = start + (u + at_end * z) d
                row = np.zeros(6)
                row[:2] = -ell
                row[2 + i] = ell @ e.direction
                row[5] = at_end * (ell @ e.direction)
                rows.append(row)
                rhs.append(-(ell @ e.start) - need)
        box = np.zeros(6)
        box[2 + i], box[5] = 1.0, 1.0  # u + z <= length
        rows.append(box)
        rhs.append(e.length)
    bounds = [(None, None)] * 2 + [(0, None)] * 4
    res = linprog([0, 0, 0, 0, 0, -1], A_ub=np.array(rows), b_ub=np.array(rhs),
                  bounds=bounds, method="highs")
    if res.status != 0 or not res.x[5] > 1e-9 * polygon.size:
        return None
    X, Y, *u, z = (float(v) for v in res.x)
    for trim in (0.0, 1e-9):  # should rounding have cut a corner, trim and check again
        segments = tuple((max(ui, 0.0) + trim * z + 0.0, min(ui + z, e.length) - trim * z)
                         for ui, e in zip(u, es, strict=True))
        regions = ThreeFingerRegions(polygon, edges, segments,
                                     "common centre (Corollary 4, linear program)",
                                     (X + 0.0, Y + 0.0), float(mu))
        if regions.certify().holds:
            return regions
    return None


def best_three_finger_regions(polygon: Polygon, mu: float, top: int = 5,
                              margin: float = MARGIN) -> list[ThreeFingerRegions]:
    """Three-finger regions on every triple of edges, best (longest shortest segment) first.

    Triples whose cones fail condition (b) are pruned before any linear program.
    """
    if not isinstance(top, int) or isinstance(top, bool) or top < 1:
        raise InputError(f"'top' must be a positive integer, got {top!r}")
    found = []
    for triple in itertools.combinations(range(len(polygon.edges)), 3):
        regions = three_finger_regions(polygon, triple, mu, margin)
        if regions is not None:
            found.append(regions)
    found.sort(key=lambda r: (-round(r.min_length / polygon.size, 12), r.edges))
    return found[:top]

"""Three fingers with friction on three edges (beyond §5): three certified families.

By Theorem 1 a grasp is force-closure iff some strictly positive combination
of its generating wrenches vanishes, and by Corollary 4 such a nonmarginal
equilibrium, with at least two distinct contacts, proves force closure. Three
nonzero forces in equilibrium lie on lines that meet at one point ``X`` (or
are parallel). Three families of independent regions are built and proved:

**Common centre** (the original construction; preferred on a tie).
The grasp at ``p1, p2, p3`` is force-closure if, for some point ``X`` and
signs ``s_i`` (``+1``: ``X`` ahead of the finger, ``-1``: behind it):

(a) every ``s_i (X - p_i)`` lies strictly inside a sector ``D_i`` of
    directions contained in the friction cone at ``p_i``, and
(b) any three directions, one from each ``D_i``, positively span the plane.
    Then the three forces along ``s_i (X - p_i)`` balance with positive
    weights, and their lines meet at ``X``: a nonmarginal equilibrium.

(a) is linear in ``X`` and the contact points together; for segments it
holds for every point of ``s_i`` iff it holds at both ends. So the largest
regions sharing one ``X`` are a linear program in ``(X, u1, u2, u3, z)``.
(b) involves only the sectors: ``cross(f_i, f_j)`` is bilinear over two
sectors, so it keeps one sign on them iff it does on their extreme
directions (eight combinations, checked exactly). With ``D_i`` the whole
cone and every ``s_i = +1`` this is the original construction; it finds
grasps such as three fingers around a triangle, which no two fingers hold.
But when the cones are wide, (b) fails on whole cones.

**Around a prototype.** So every triple is also sampled: fingers on a grid
of :data:`GRID` points per edge are tested by Theorem 1 (the compiled batch
analysis, cones narrowed by the margin). For the best force-closure
prototype of the triple (the next best, up to :data:`TRIES`, should it give
no regions), the forces of its largest-margin equilibrium give
directions ``phi_i``, the point ``X`` where their lines meet, and signs
``s_i``; should ``X`` fall on or near a finger, other equilibria of the
prototype (steps in the null space of its wrench matrix) are tried as well.
``D_i`` is the widest sector about ``phi_i`` inside the cone that keeps (b),
and the same linear program gives the regions, proved by the same exact
check. Around a force-closure grasp whose lines of force meet away from
the fingers such regions exist (the conditions are strict), so a triple is
missed when no grid point of it is force-closure with the narrowed cones,
or (on none of the bundled polygons) when its prototypes give no sectors.

**A force-closure pair plus a free finger.** If two of the three edges
admit two-finger independent regions (Corollary 3,
:func:`~forceclosure.synthesis.planar.two_fingers.maximal_regions`, squeezing or
pushing apart), the third finger may touch anywhere on its edge: adding a
finger only adds wrenches, and a set of wrenches that positively spans the
wrench space still does with more. Its proof is the pair's exact corner
check (:meth:`~forceclosure.synthesis.planar.two_fingers.IndependentRegions.certify`).

What a search that returns nothing has and has not ruled out is
:data:`SEARCHED`.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
import scipy.linalg
from numpy.typing import NDArray
from scipy.optimize import linprog

from ...errors import InputError
from ...objects.polygon import Polygon
from ..construction import Construction, Hand
from ..regions import (
    MARGIN,
    Certificate,
    Regions,
    check_edges,
    check_margin,
    exact_inward,
    exact_point,
    face_middle,
    first_proved,
    narrowed,
    proved_once,
    tie_rounded,
)
from .edge_sites import by_shortest_edge, edge_tuples, force_direction_prune, shortest_edge
from .two_fingers import IndependentRegions, maximal_regions
from .vertex_grasps import extreme_generators, pushing_generators

__all__ = ["DEPTH", "GRID", "SEARCHED", "ThreeFingerRegions",
           "three_finger_regions"]

#: ``X`` is kept this fraction of the object's size away from each contact, along its force.
DEPTH = 1e-3
#: Prototype fingers per edge: at ``(k + OFFSET) / GRID`` of its length, ``k = 0 .. GRID - 1``.
GRID = 6
#: Where in its cell of the grid each prototype finger sits (the middle).
OFFSET = 0.5
#: Prototypes tried per triple, best Theorem 1 margin first, until one gives regions.
TRIES = 8
#: Lines of force meeting closer than this fraction of the object's size to a finger are moved.
CLEAR = 0.02
#: Grasps analysed by one call of the batch analysis (bounds the memory used).
BATCH = 65_536

#: What the three-finger search covers, said when it finds nothing (for the CLI).
SEARCHED = (
    "every triple of edges whose friction cones, narrowed by the margin, can balance "
    "(force-direction closure), by three certified constructions: (1) lines of force meeting at "
    "a common centre, with the whole cones (a linear program); (2) the same around the "
    f"force-closure prototypes with the largest Theorem 1 margins (up to {TRIES} per triple) "
    f"among {GRID} x {GRID} x {GRID} fingers at evenly spaced points of the three edges; (3) a "
    "pair of edges with two-finger independent regions (Corollary 3, squeezing or pushing "
    "apart, an exact linear program) plus a third finger anywhere on a third edge. Finding "
    "nothing does not prove that no three-finger grasp exists: grasps between the grid's "
    "points, or closer than the margin to losing closure, are not ruled out")


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _spans_whatever_the_choice(cones) -> bool:
    """(b): one direction from each cone, any choice, positively spans the plane."""
    signs: set[bool] = set()
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
    """Three segments such that every choice of three points is force-closure.

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    centre : (float, float) or None
        The point ``X`` where the three lines of force meet (common-centre
        regions); None for a pair plus a free finger.
    mu : float
    sectors : tuple of three ((float, float), (float, float)), or None
        For regions around a prototype: each finger's sector ``D_i`` of force
        directions, as its clockwise and counter-clockwise bounding
        directions; None: the whole friction cones.
    signs : (int, int, int)
        ``+1`` where ``X`` lies ahead of the finger (its force points at
        ``X``), ``-1`` where behind it.
    pair : (int, int) or None
        For a pair plus a free finger: the two edges whose segments are
        force-closure alone (Corollary 3); the third segment is its whole edge.
    spreading : bool
        That pair's fingers push apart from inside a slot or a hole.
    """

    centre: tuple[float, float] | None = (0.0, 0.0)
    mu: float = 0.0
    sectors: tuple[tuple[tuple[float, float], tuple[float, float]], ...] | None = None
    signs: tuple[int, int, int] = (1, 1, 1)
    pair: tuple[int, int] | None = None
    spreading: bool = False

    @proved_once
    def certify(self) -> Certificate:
        """Exactly, in rationals. Common centre: (a) at both ends of every segment and
        (b) on the sectors' extreme directions. A pair plus a free finger: the pair's
        corner check (Corollary 3) and the third segment inside its edge."""
        if self.pair is not None:
            return self._certify_pair(self.pair)
        return self._certify_centre()

    def _certify_pair(self, pair: tuple[int, int]) -> Certificate:
        method = "Corollary 3 on a pair (exact rationals), plus a finger"
        a, b = (self.edges.index(k) for k in pair)
        (c,) = {0, 1, 2} - {a, b}
        u, v = self.segments[c]
        free = self.polygon.edges[self.edges[c]]
        if not 0 <= u <= v <= free.length:
            return Certificate(False, method, f"the segment on edge {free.index} leaves it")
        two = IndependentRegions(self.polygon, pair, (self.segments[a], self.segments[b]),
                                 self.construction, (self.mu, self.mu),
                                 spreading=self.spreading).certify()
        if not two.holds:
            return Certificate(False, method, f"edges {pair}: {two.detail}")
        return Certificate(True, method,
                           f"edges {pair[0]} and {pair[1]}: {two.detail}; the finger "
                           f"on edge {free.index} only adds wrenches, and wrenches that "
                           "positively span the wrench space still do with more (Theorem 1)")

    def _certify_centre(self) -> Certificate:
        method = "Corollary 4 (exact rationals)"
        F = Fraction
        if self.centre is None:
            return Certificate(False, method, "no centre")
        if not all(s in (1, -1) for s in self.signs):
            return Certificate(False, method, f"signs must be +1 or -1, got {self.signs}")
        X = [F(x) for x in self.centre]
        sectors = []
        for k, (e, seg, s) in enumerate(zip((self.polygon.edges[k] for k in self.edges),
                                            self.segments, self.signs, strict=True)):
            cone = extreme_generators(pushing_generators([[-x for x in exact_inward(e)]],
                                                         F(narrowed(self.mu, self.polygon.spread))))
            assert cone is not None  # one normal's friction cone is narrower than a half-plane
            sector = list(cone)
            if self.sectors is not None:
                sector = [[F(x) for x in d] for d in self.sectors[k]]
                if not (_cross(sector[0], sector[1]) > 0
                        and all(_cross(cone[0], d) >= 0 and _cross(d, cone[1]) >= 0
                                for d in sector)):
                    return Certificate(False, method, f"the sector of force directions on "
                                       f"edge {e.index} is not inside its friction cone")
            sectors.append(sector)
            for t in seg:
                p = exact_point(e, t)
                w = [s * (X[0] - p[0]), s * (X[1] - p[1])]
                if not (_cross(sector[0], w) > 0 and _cross(w, sector[1]) > 0):
                    return Certificate(False, method,
                                       f"from edge {e.index} at t = {t:.6g} the line to X "
                                       "leaves the friction cone")
        if not _spans_whatever_the_choice(sectors):
            return Certificate(False, method,
                               "some choice of directions from the cones does not positively "
                               "span the plane")
        where = ("" if all(s > 0 for s in self.signs) else
                 " (pushing away from X on the fingers X lies behind)")
        return Certificate(True, method,
                           "from every point of every segment the line to X lies strictly "
                           f"inside the friction cone{where}, and any directions from the three "
                           "cones balance: a nonmarginal equilibrium for every choice")

    def friction(self) -> tuple[float, ...]:
        """The friction coefficient at each finger."""
        return (self.mu,) * 3

    def notes(self) -> list[str]:
        """Which kind of grasp it is: a force-closure pair with an idle third finger (which
        adds nothing the pair needs), or three lines of force through a common centre."""
        if self.pair is not None:
            (a, b), free = self.pair, next(e for e in self.edges if e not in self.pair)
            return [f"edges {a} + {b} hold the object alone: the finger on edge {free} is "
                    "idle (a two-finger grasp plus a finger anywhere)"]
        return ["the three lines of force meet at a common centre (all three fingers bear "
                "load)"]

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``centre`` (null for a pair
        plus a free finger) and ``mu``; ``pair`` and ``spreading`` for a pair plus a free
        finger, ``signs`` and ``sectors`` for regions around a prototype."""
        record: dict[str, object] = {
            **super().to_dict(), "mu": self.mu,
            "centre": None if self.centre is None else list(self.centre)}
        if self.pair is not None:
            record.update(pair=list(self.pair), spreading=self.spreading)
        if self.sectors is not None:
            record.update(signs=list(self.signs),
                          sectors=[[list(d) for d in s] for s in self.sectors])
        return record


def _check(polygon: Polygon, mu: float, margin: float) -> float:
    if not (isinstance(mu, int | float) and np.isfinite(mu) and mu > 0):
        raise InputError(f"friction coefficient must be a positive number, got {mu!r}")
    return narrowed(mu, check_margin(margin))


def _centre(polygon: Polygon, edges: tuple[int, ...], mu: float, sectors, signs,
            construction: str, keep: bool, need: float) -> ThreeFingerRegions | None:
    """The largest regions whose lines of force ``s_i (X - p_i)`` stay inside ``sectors``
    (float bounding directions), for one common ``X``: a linear program; certified."""
    es = [polygon.edges[k] for k in edges]
    depth = DEPTH * polygon.size
    rows, rhs = [], []  # variables (X, Y, u1, u2, u3, z); rows @ x <= rhs
    for i, (e, (g_lo, g_hi), s) in enumerate(zip(es, sectors, signs, strict=True)):
        push = -e.normal
        # s cross(g_lo, X - p) > 0, s cross(X - p, g_hi) > 0, s push . (X - p) >= depth
        for ell, want in (((-g_lo[1], g_lo[0]), need), ((g_hi[1], -g_hi[0]), need),
                          (tuple(push), depth)):
            ell = s * np.asarray(ell, float)
            for at_end in (0.0, 1.0):  # p = start + (u + at_end * z) d
                row = np.zeros(6)
                row[:2] = -ell
                row[2 + i] = ell @ e.direction
                row[5] = at_end * (ell @ e.direction)
                rows.append(row)
                rhs.append(-(ell @ e.start) - want)
        box = np.zeros(6)
        box[2 + i], box[5] = 1.0, 1.0  # u + z <= length
        rows.append(box)
        rhs.append(e.length)
    bounds = [(None, None)] * 2 + [(0, None)] * 4
    res = linprog([0, 0, 0, 0, 0, -1], A_ub=np.array(rows), b_ub=np.array(rhs),
                  bounds=bounds, method="highs")
    if res.status != 0 or not res.x[5] > 1e-9 * polygon.size:
        return None
    x = face_middle(np.array(rows), np.array(rhs), bounds, res.x, 5)
    X, Y, *u, z = (float(v) for v in x)
    kept = (tuple(((float(lo[0]), float(lo[1])), (float(hi[0]), float(hi[1])))
                  for lo, hi in sectors) if keep else None)
    return first_proved(lambda trim: ThreeFingerRegions(  # rounding may cut a corner
        polygon, edges, tuple((max(ui, 0.0) + trim * z + 0.0, min(ui + z, e.length) - trim * z)
                              for ui, e in zip(u, es, strict=True)),
        construction, (X + 0.0, Y + 0.0), float(mu), kept,
        (int(signs[0]), int(signs[1]), int(signs[2]))))


def _whole_cones(polygon: Polygon, edges: tuple[int, ...], mu: float,
                 shrunk: float) -> ThreeFingerRegions | None:
    """The original construction: whole (narrowed) cones, ``X`` ahead of every finger."""
    cones = [extreme_generators(pushing_generators([polygon.edges[k].normal], shrunk))
             for k in edges]
    if not _spans_whatever_the_choice(cones):
        return None
    return _centre(polygon, edges, mu, cones, (1, 1, 1),
                   "common centre (Corollary 4, linear program)", False, 0.0)


def _prototypes(polygon: Polygon, triples: NDArray[np.int64],
                shrunk: float) -> dict[tuple[int, ...], NDArray[np.float64]]:
    """For each triple of edges, the ``(m, 3, 2)`` contact points of its (up to
    :data:`TRIES`) force-closure grasps with the largest Theorem 1 margins among :data:`GRID`
    evenly spaced points per edge (compiled batch analysis, cones narrowed), best first;
    triples with none are left out."""
    from ...analysis.batch import analyze_batch

    start, direction, normal, length = polygon.edge_arrays
    t = (np.arange(GRID) + OFFSET) / GRID
    combos = t[np.array(list(itertools.product(range(GRID), repeat=3)))]  # (K, 3)
    per = max(1, BATCH // len(combos))
    best = {}
    for lo in range(0, len(triples), per):
        tr = triples[lo:lo + per]
        along = combos[None] * length[tr][:, None, :]  # (B, K, 3)
        P = start[tr][:, None] + along[..., None] * direction[tr][:, None]  # (B, K, 3, 2)
        N = np.broadcast_to(normal[tr][:, None], P.shape)
        res = analyze_batch(P.reshape(-1, 3, 2), N.reshape(-1, 3, 2), mu=shrunk)
        margin = np.where(res.force_closure, res.margin, -np.inf).reshape(len(tr), -1)
        ranked = np.argsort(-margin, axis=1, kind="stable")[:, :TRIES]
        for b in range(len(tr)):
            keep = ranked[b][np.isfinite(margin[b, ranked[b]])]
            if len(keep):
                best[tuple(int(x) for x in tr[b])] = P[b, keep]
    return best


def _meeting_point(weights: NDArray[np.float64], G: NDArray[np.float64],
                   points: NDArray[np.float64]):
    """The three forces of an equilibrium (weights of the generators ``G``), the point where
    their lines meet, and its least distance from a finger; None for parallel forces."""
    force = (weights[:, None] * G).reshape(3, 2, 2).sum(axis=1)
    unit = force / np.linalg.norm(force, axis=1, keepdims=True)
    i, j = max(itertools.combinations(range(3), 2), key=lambda ij: abs(_cross(*unit[list(ij)])))
    if abs(_cross(unit[i], unit[j])) < 1e-6:  # parallel forces: no finite centre
        return None
    a, _ = np.linalg.solve(np.column_stack([force[i], -force[j]]), points[j] - points[i])
    X = points[i] + a * force[i]
    return force, X, float(np.linalg.norm(X - points, axis=1).min())


def _around(polygon: Polygon, edges: tuple[int, ...], mu: float, shrunk: float,
            points: NDArray[np.float64]) -> ThreeFingerRegions | None:
    """Common-centre regions around a force-closure prototype at ``points``: its largest-margin
    equilibrium gives the directions, the centre's side of each finger and the sectors."""
    es = [polygon.edges[k] for k in edges]
    gens = []
    for e in es:
        n = np.asarray(e.normal, float)
        tangent = np.array([-n[1], n[0]])
        gens += [(-n + s * shrunk * tangent) / math.hypot(1, shrunk) for s in (1, -1)]
    G = np.array(gens)
    arm = np.repeat(points - points.mean(axis=0), 2, axis=0) / polygon.size
    W = np.vstack([G.T, arm[:, 0] * G[:, 1] - arm[:, 1] * G[:, 0]])  # (3, 6)
    # Theorem 1's margin: maximise s with W (s 1 + u) = 0, 6 s + sum(u) = 1, u >= 0
    A_eq = np.vstack([np.hstack([W, W.sum(axis=1, keepdims=True)]), [1.0] * 6 + [6.0]])
    res = linprog([0.0] * 6 + [-1.0], A_eq=A_eq, b_eq=[0, 0, 0, 1],
                  bounds=[(0, None)] * 6 + [(None, None)], method="highs")
    if res.status != 0 or not res.x[6] > 0:
        return None
    weights = res.x[:6] + res.x[6]
    first = _meeting_point(weights, G, points)
    meetings = [first]
    if first is None or first[2] < CLEAR * polygon.size:
        # the lines meet on or near a finger (grid points aligned with a corner, say): other
        # equilibria, a step along each direction of W's null space that keeps every weight
        # above half the least, may meet clear of the fingers; the farthest is tried too
        step = 0.5 * weights.min()
        tries = [_meeting_point(weights + sign * step * v / np.abs(v).max(), G, points)
                 for v in scipy.linalg.null_space(W).T for sign in (1, -1)]
        meetings.append(max((f for f in tries if f is not None), key=lambda f: f[2],
                            default=None))
    built = [_regions_for(polygon, edges, mu, shrunk, points, *f[:2]) for f in meetings
             if f is not None and f[2] > 1e-9 * polygon.size]
    return max((r for r in built if r is not None), key=lambda r: r.min_length, default=None)


def _regions_for(polygon: Polygon, edges: tuple[int, ...], mu: float, shrunk: float,
                 points: NDArray[np.float64], force: NDArray[np.float64],
                 X: NDArray[np.float64]) -> ThreeFingerRegions | None:
    """The linear program's regions for sectors about an equilibrium's forces meeting at
    ``X``, each the widest inside its cone that keeps (b)."""
    es = [polygon.edges[k] for k in edges]
    ahead = np.einsum("ij,ij->i", X - points, force)
    signs = tuple(1 if x > 0 else -1 for x in ahead)
    phi = np.arctan2(force[:, 1], force[:, 0])
    slack = [math.atan(shrunk) - abs(math.remainder(float(p) - math.atan2(-e.normal[1],
                                                                          -e.normal[0]),
                                                    2 * math.pi))
             for p, e in zip(phi, es, strict=True)]
    order = np.argsort(phi % (2 * np.pi))
    delta = np.array(slack)
    for k in range(3):  # consecutive directions: keep their order and their gap below pi
        a_, b_ = order[k], order[(k + 1) % 3]
        gap = (phi[b_] - phi[a_]) % (2 * np.pi)
        room = min(np.pi - gap, gap) / 2
        delta[a_], delta[b_] = min(delta[a_], room), min(delta[b_], room)
    delta *= 1 - 1e-6
    if not np.all(delta > 0):
        return None
    sectors = [((math.cos(p - d), math.sin(p - d)), (math.cos(p + d), math.sin(p + d)))
               for p, d in zip(phi, delta, strict=True)]
    return _centre(polygon, edges, mu, sectors, signs,
                   "common centre around a prototype (Corollary 4, linear program)", True,
                   1e-9 * polygon.size)


def _with_free_finger(polygon: Polygon, edges: tuple[int, ...], mu: float,
                      pair: IndependentRegions) -> ThreeFingerRegions | None:
    """The pair's two segments and the third edge whole; certified."""
    (free,) = set(edges) - set(pair.edges)
    segments = tuple(pair.segments[pair.edges.index(k)] if k in pair.edges
                     else (0.0, polygon.edges[k].length) for k in edges)
    how = ", pushing apart" if pair.spreading else ""
    regions = ThreeFingerRegions(polygon, edges, segments,
                                 f"force-closure pair (Corollary 3{how}) on edges "
                                 f"{pair.edges[0]} and {pair.edges[1]}, plus a finger anywhere "
                                 f"on edge {free}", None, float(mu), None, (1, 1, 1),
                                 (pair.edges[0], pair.edges[1]), pair.spreading)
    return regions if regions.certify().holds else None


def _best_of(polygon: Polygon, edges: tuple[int, ...], mu: float, shrunk: float,
             pairs: dict, prototypes: NDArray[np.float64] | None) -> ThreeFingerRegions | None:
    """The largest (longest shortest segment) of the three families on one triple; on a tie
    the common centre with whole cones, then around a prototype, then a pair."""
    found = [_whole_cones(polygon, edges, mu, shrunk)]
    for points in () if prototypes is None else prototypes:  # the first that gives regions
        around = _around(polygon, edges, mu, shrunk, points)
        if around is not None:
            found.append(around)
            break
    for a, b in itertools.combinations(sorted(edges), 2):
        if (a, b) in pairs:
            found.append(_with_free_finger(polygon, edges, mu, pairs[a, b]))
    made = [r for r in found if r is not None]
    return max(made, key=lambda r: tie_rounded(r.min_length), default=None)


def three_finger_regions(polygon: Polygon, edges: tuple[int, int, int], mu: float,
                         margin: float = MARGIN) -> ThreeFingerRegions | None:
    """The largest certified regions on three edges, by the families of the module.

    Returns None when none of them gives regions (:data:`SEARCHED` says what
    that rules out: not every grasp between the prototype grid's points).

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> r = three_finger_regions(bundled("triangle"), (0, 1, 2), mu=0.3)
    >>> round(r.min_length, 3), r.certify().holds
    (0.299, True)
    >>> r = three_finger_regions(bundled("square"), (0, 1, 2), mu=0.8)
    >>> r.pair, r.segments[1], r.certify().holds   # edges 0 and 2 face each other
    ((0, 2), (0.0, 2.0), True)
    """
    edges = check_edges(polygon, edges, 3)
    shrunk = _check(polygon, mu, margin)
    if shrunk <= 0:
        return None
    pairs = {}
    for a, b in itertools.combinations(sorted(edges), 2):
        r = maximal_regions(polygon, a, b, mu, margin=margin)
        if isinstance(r, IndependentRegions):  # an undecided pair: not searched with (this
            pairs[a, b] = r                    # construction does not claim completeness)
    triple = np.array([edges])
    prototypes = (_prototypes(polygon, triple, shrunk).get(edges)
                  if force_direction_prune(polygon, triple, Hand(3, "hard", mu, margin))[0]
                  else None)
    return _best_of(polygon, edges, mu, shrunk, pairs, prototypes)


def _build(polygon: Polygon, site: NDArray, hand: Hand) -> ThreeFingerRegions | None:
    i, j, k = (int(e) for e in site)
    return three_finger_regions(polygon, (i, j, k), hand.mu, hand.margin)


THREE_FINGERS = Construction(
    dim=2, fingers=3, contact="hard", name="maximal", paper="§5.4 (three fingers)",
    method="edges", sites=edge_tuples(3), prune=force_direction_prune, bound=shortest_edge,
    levels=by_shortest_edge(3), build=_build, searched=SEARCHED)

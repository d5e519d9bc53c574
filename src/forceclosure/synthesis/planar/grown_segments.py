"""Any number of fingers of any contact model on a polygon: segments grown around sampled
prototype grasps (beyond Nguyen 1988, §5; the planar case of the mesh method's search
zones, Roa and Suárez 2009), each proved by an exact corner check.

The table's fallback on polygons: it serves the hands no paper construction does (five
frictionless fingers, three frictionless is refused — the plane needs four —, five or more
hard fingers…).

**Prototypes.** ``samples`` random grasps (each finger uniform over the boundary, by
length) are analysed in one batch (Theorem 1,
:func:`~forceclosure.analysis.batch_analysis.analyze_batch`, cones narrowed by the margin);
the force-closure ones with the largest Theorem 1 margins become prototypes, one per tuple
of edges.

**Growth (search zones).** The prototype's generating wrenches ``w = (f, p x f)`` span a
hull ``H`` in ``R^3`` with the origin inside. For each vertex ``v`` of ``H`` the zone
``Z_v = {w : a_k . w > 0}`` over the facets ``k`` at ``v``; any grasp with a wrench in every
zone is force-closure (every direction ``a`` is a non-negative combination of the facet
normals at some vertex, so some wrench has ``a . w > 0``: Theorem 1). On an edge a
finger's wrench is affine in its position ``t`` (fixed force, torque ``p(t) x f``), so
the ``t`` whose wrench stays in the finger's zones is an interval: its segment.

**Proof (exact, and necessary as well as sufficient).** The segments are proved by
Theorem 1 at their corners, in rational arithmetic. That a force-closure check at the
corners of a box decides the whole box is *not* true in general (in space, or for any
condition that is not monotone or multi-affine per finger); here it is, because the
condition splits finger by finger. The grasp fails iff some ``a != 0`` has ``a . w <= 0``
for every wrench the fingers can apply, so every choice in the box is force-closure iff
for every ``a`` *some finger* ``i`` has ``h_i(a, t_i) > 0`` for *all* ``t_i`` in its
segment (the quantifiers swap because each ``t_i`` is free on its own: if every finger had
a bad ``t_i``, together they make a bad grasp). Then:

* a hard (or, in the plane, soft) finger applies the cone of its two generators ``f+-``:
  ``h_i = max over f+- of a . (f, p(t) x f)``, and both are affine in ``t`` with the same
  slope ``a_3 cross(d, f)`` (``cross(d, f+-) = cross(d, -n)``: the tangent parts are
  parallel to the edge ``d``), so ``h_i`` is affine and positive on the segment iff at its
  two ends;
* a frictionless finger pushes along any direction of the fan within the margin of its
  normal, every one of which must work; the fan's directions are those of
  ``f(s) = (1 - s) f- + s f+`` for ``s`` in ``[0, 1]`` (its two ends, a force's size does
  not matter), so ``a . (f(s), p(t) x f(s))`` is bilinear in ``(t, s)`` and its least
  value over the box is at one of its four corners.

So the regions are force-closure everywhere iff they are at every combination of segment
ends (and fan ends): ``2^n`` (``4^n`` frictionless with a margin) grasps. They are not
listed one by one (``4^8`` is 65,536): the same swap says they all hold iff every
direction ``a`` is held by some finger in each of its options (ends), and it is enough to
look at the directions ``+-(w_p x w_q)`` over every two of the corner wrenches (a failing
grasp of rank 3 leaves a pointed cone of unresisted directions whose extreme rays are such
cross products; one of rank 2 fails along its plane's normal, another; rank 1 is looked for
apart), ``a . w_l = det(w_p, w_q, w_l)``: :func:`corner_closure`.
Determinants larger than a bound on their rounding keep the sign floating point gives;
the rest are computed with ``fractions.Fraction``. The search is not complete: it covers
the prototypes sampled (``complete: false``).

References
----------
V.-D. Nguyen, "Constructing Force-Closure Grasps", IJRR 7(3), 1988, Theorem 1.
M. A. Roa and R. Suárez, "Computation of independent contact regions for grasping 3-D
objects", IEEE Trans. Robotics 25(4), 2009 (search zones).

Examples
--------
>>> from forceclosure.objects import bundled
>>> from forceclosure.synthesis.construction import Hand
>>> from forceclosure.synthesis.ranked_search import search
>>> found = search(GROWN, bundled("square"), Hand(5, "frictionless", 0.0, samples=2000, top=1))
>>> len(found), len(found[0].edges), found[0].certify().holds
(1, 5, True)
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray
from scipy.spatial import ConvexHull, QhullError

from ...objects.polygon import Polygon
from ..construction import Construction, Hand
from ..regions import Certificate, Regions, exact_inward, exact_point, narrowed, proved_once

__all__ = ["GROWN", "GrownRegions", "corner_closure", "grown_regions", "prototypes"]

#: Prototypes grown per region set asked for (the best by Theorem 1's margin, one per tuple
#: of edges).
PER_TOP = 3
#: Every zone condition holds with at least this margin, ``a_k . w >= ZONE_MARGIN`` (the
#: wrenches are about 1 in the search's object-centred coordinates).
ZONE_MARGIN = 1e-6
#: Rounds of widening the zones' segments, and bisection steps per end and round.
ROUNDS, STEPS = 1, 6
#: The widening keeps every determinant it relies on this fraction of its terms' sizes from
#: zero (far more than their rounding), so that the exact proof holds where it stops.
WIDEN = 1e-7
#: A determinant larger than this fraction of the sum of its terms' sizes has the sign
#: floating point shows (thousands of times the worst rounding of its few products).
SURE = 1e-12


def _perp(m):
    return [-m[1], m[0]]


def _forces(inward: list, mu: float, turn: float) -> list[list[list]]:
    """A finger's options at one point: for a hard finger one option, its two cone
    generators (``mu``'s cone narrowed by ``turn``); for a frictionless one, each end of the
    fan of directions within ``turn`` of the inward normal, as one option each. Exact when
    ``inward`` is rational (the cosine, sine and friction are the rationals of their
    floats)."""
    q = _perp(inward)
    if mu > 0:
        c = Fraction(narrowed(mu, turn))
        return [[[m + s * c * p for m, p in zip(inward, q, strict=True)] for s in (1, -1)]]
    if turn <= 0:
        return [[list(inward)]]
    # rounded outward, so the rational fan is at least as wide as ``turn``
    cos = Fraction(math.nextafter(math.cos(turn), 0.0))
    sin = Fraction(math.nextafter(math.sin(turn), math.inf))
    return [[[cos * m + s * sin * p for m, p in zip(inward, q, strict=True)]] for s in (1, -1)]


def _wrench(point: list, force: list) -> list:
    return [force[0], force[1], point[0] * force[1] - point[1] * force[0]]


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _verdicts(pos: NDArray[np.bool_], nonpos: NDArray[np.bool_], option: NDArray[np.int64],
              finger: NDArray[np.int64], n_options: int, n_fingers: int
              ) -> tuple[NDArray[np.bool_], NDArray[np.bool_]]:
    """For directions (rows) with each wrench's support surely positive (``pos``) or surely
    not (``nonpos``): whether surely some finger supports the direction in every option
    (``held``), and whether surely none does (``lost``)."""
    rows = pos.shape[0]
    opt_pos = np.zeros((rows, n_options), bool)
    opt_non = np.ones((rows, n_options), bool)
    np.logical_or.at(opt_pos.T, option, pos.T)
    np.logical_and.at(opt_non.T, option, nonpos.T)
    owner = np.zeros(n_options, np.int64)
    owner[option] = finger
    fin_pos = np.ones((rows, n_fingers), bool)
    fin_non = np.zeros((rows, n_fingers), bool)
    np.logical_and.at(fin_pos.T, owner, opt_pos.T)
    np.logical_or.at(fin_non.T, owner, opt_non.T)
    return np.any(fin_pos, axis=1), np.all(fin_non, axis=1)


def corner_closure(options: list[list[list[list[Fraction]]]]) -> tuple[bool, int]:
    """Whether every grasp made of one option per finger positively spans ``R^3`` (each
    option a list of exact wrenches: a hard finger's cone generators at one segment end, a
    frictionless finger's wrench at one end and one fan end), and how many directions were
    decided in rationals.

    Decided without listing the grasps: they all positively span iff every direction
    ``a != 0`` is *held*, some finger having in every option a wrench with ``a . w > 0``
    (if every finger had an option without, those options make a grasp that does not
    resist ``a``). It is enough to look at the directions ``+-(w_p x w_q)`` for every two
    wrenches: a grasp of rank 3 that fails leaves a pointed cone of unresisted
    directions, whose extreme rays are such cross products, and one of rank 2 fails along
    the normal of its plane, another; grasps of rank 1 (every wrench on one line) are
    looked for apart.

    Examples
    --------
    >>> e1, e2, e3 = [[Fraction(int(i == j)) for j in range(3)] for i in range(3)]
    >>> last = [[[Fraction(-1), Fraction(-1), Fraction(-1)]], [[Fraction(-1), Fraction(-2),
    ...                                                         Fraction(-1)]]]
    >>> corner_closure([[[e1]], [[e2]], [[e3]], last])
    (True, 0)
    >>> last[1] = [[Fraction(-1), Fraction(-1), Fraction(0)]]  # no wrench with a negative torque
    >>> corner_closure([[[e1]], [[e2]], [[e3]], last])[0]
    False
    """
    exact_w, finger, option = [], [], []
    n_options = 0
    for i, opts in enumerate(options):
        for opt in opts:
            for w in opt:
                exact_w.append(w)
                finger.append(i)
                option.append(n_options)
            n_options += 1
    finger_a, option_a = np.array(finger), np.array(option)
    if _collinear_grasp(options):
        return False, 0
    W = np.array([[float(v) for v in w] for w in exact_w])
    m = len(W)
    J, K = np.triu_indices(m, 1)
    a, b = W[J], W[K]
    u, v = [1, 2, 0], [2, 0, 1]
    X = np.cross(a, b)
    Xb = np.abs(a[:, u] * b[:, v]) + np.abs(a[:, v] * b[:, u])
    D = X @ W.T  # (pairs, wrenches): det(w_p, w_q, w_l)
    bound = Xb @ np.abs(W).T
    own = (np.arange(m)[None] == J[:, None]) | (np.arange(m)[None] == K[:, None])
    D[own] = 0.0  # a pair's own two are exactly zero (floats give them a sign of rounding)
    sure = (np.abs(D) > SURE * bound) | own
    nonzero = (np.abs(X) > SURE * Xb).any(axis=1)
    undecided = np.zeros(len(J), bool)
    for sign in (1.0, -1.0):
        held, lost = _verdicts(sure & (sign * D > 0), sure & ~(sign * D > 0), option_a,
                               finger_a, n_options, len(options))
        if (lost & nonzero).any():
            return False, 0
        undecided |= ~held
    exact = 0
    for k in np.flatnonzero(undecided):  # in rationals
        exact += 1
        x = _cross(exact_w[J[k]], exact_w[K[k]])
        if not any(x):
            continue
        d = np.array([x[0] * w[0] + x[1] * w[1] + x[2] * w[2] for w in exact_w], dtype=object)
        for sign in (1, -1):
            held, _ = _verdicts(np.array([[sign * v > 0 for v in d]]),
                                np.array([[not sign * v > 0 for v in d]]), option_a, finger_a,
                                n_options, len(options))
            if not held[0]:
                return False, exact
    return True, exact


def _collinear_grasp(options) -> bool:
    """Whether one option per finger puts every wrench on one line (rank 1), exactly."""
    for opt in options[0]:
        line = opt[0]
        if all(any(all(not any(_cross(line, w)) for w in o) for o in opts) for opts in options):
            return True
    return False


@dataclass(frozen=True, eq=False)
class GrownRegions(Regions):
    """One segment per finger (two fingers may share an edge), grown around a sampled
    prototype grasp, such that every choice of one point per segment is force-closure
    (for every force direction within ``margin`` of a frictionless finger's normal).

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    mu : float
        0 for frictionless fingers.
    margin : float
    """

    mu: float = 0.0
    margin: float = 0.0

    def friction(self) -> tuple[float, ...]:
        return (self.mu,) * len(self.edges)

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``mu`` and ``margin``."""
        return {**super().to_dict(), "mu": self.mu, "margin": self.margin}

    @proved_once
    def certify(self) -> Certificate:
        """Theorem 1 at every combination of segment ends (and fan ends for frictionless
        fingers), in exact rationals: necessary and sufficient for every grasp in the
        segments (the module's docstring)."""
        method = "corner check (exact rationals)"
        polygon = self.polygon
        turn = max(self.margin, polygon.spread)  # the outline's normals turn too
        lo, hi = polygon.bounds
        centre = [Fraction(float(0.5 * a + 0.5 * b)) for a, b in zip(lo, hi, strict=True)]
        options = []
        for e_index, seg in zip(self.edges, self.segments, strict=True):
            e = polygon.edges[e_index]
            if not 0 <= seg[0] <= seg[1] <= e.length:
                return Certificate(False, method, f"the segment ({seg[0]:.17g}, {seg[1]:.17g}) "
                                   f"is not within edge {e.index} (length {e.length:.17g})")
            fan = _forces(exact_inward(e), self.mu, turn)
            ends = [[p - c for p, c in zip(exact_point(e, t), centre, strict=True)]
                    for t in seg]
            options.append([[_wrench(p, f) for f in opt] for p in ends for opt in fan])
        holds, exact = corner_closure(options)
        count = math.prod(len(o) for o in options)  # the grasps the check stands for
        if not holds:
            return Certificate(False, method, "a grasp at the segments' ends is not "
                               "force-closure")
        return Certificate(True, method, f"Theorem 1 holds at all {count} combinations of "
                           f"segment ends{' and fan ends' if self.mu == 0 and turn > 0 else ''}"
                           f" ({exact} directions decided in rationals), hence everywhere: each "
                           "finger's least support is at its segment's ends")


def prototypes(polygon: Polygon, hand: Hand) -> list[tuple[tuple[int, ...], tuple[float, ...]]]:
    """Step 1: force-closure grasps among ``hand.samples`` random ones, the largest Theorem 1
    margin first, one per tuple of edges, ``PER_TOP * hand.top`` of them; each as its edges
    and edge parameters, fingers in the order of their edges and positions."""
    from ...analysis.batch import analyze_batch

    start, direction, normal, length = polygon.edge_arrays
    rng = np.random.default_rng(hand.seed)
    along = rng.uniform(0.0, float(length.sum()), (hand.samples, hand.fingers))
    ends = np.cumsum(length)
    edge = np.minimum(np.searchsorted(ends, along, side="right"), len(length) - 1)
    t = np.clip(along - (ends[edge] - length[edge]), 0.0, length[edge])
    P = start[edge] + t[..., None] * direction[edge]
    turn = max(hand.margin, polygon.spread)
    frictionless = hand.contact == "frictionless"
    res = analyze_batch(P, normal[edge], mu=0.0 if frictionless else narrowed(hand.mu, turn),
                        model="frictionless" if frictionless else "hard")
    margin = np.where(res.force_closure, res.margin, -np.inf)
    out: list[tuple[tuple[int, ...], tuple[float, ...]]] = []
    seen: set[tuple[int, ...]] = set()
    for g in np.argsort(-margin, kind="stable"):
        if not np.isfinite(margin[g]) or len(out) == PER_TOP * hand.top:
            break
        fingers = sorted(zip(edge[g].tolist(), t[g].tolist(), strict=True))
        key = tuple(e for e, _ in fingers)
        if key not in seen:
            seen.add(key)
            out.append((key, tuple(x for _, x in fingers)))
    return out


def _sites(polygon: Polygon, hand: Hand):
    yield prototypes(polygon, hand)


def grown_regions(polygon: Polygon, edges: tuple[int, ...], ts: tuple[float, ...],
                  hand: Hand) -> GrownRegions | None:
    """Step 4: the segments around the prototype grasp at ``ts`` on ``edges`` whose every
    grasp keeps a wrench in each of the prototype's search zones (the module's docstring);
    None when the prototype is not force-closure or sits on a zone's boundary. Proved by
    the search (:meth:`GrownRegions.certify`)."""
    turn = max(hand.margin, polygon.spread)
    mu = 0.0 if hand.contact == "frictionless" else float(hand.mu)
    lo_b, hi_b = polygon.bounds
    ref, scale = 0.5 * lo_b + 0.5 * hi_b, polygon.size
    rows = []  # (finger, w0 (3,), slope (3,)) per generator: w(t) = w0 + t slope
    for i, (e_index, t) in enumerate(zip(edges, ts, strict=True)):
        e = polygon.edges[e_index]
        inward = [-float(e.normal[0]), -float(e.normal[1])]
        for opt in _forces(inward, mu, turn):
            for exact_force in opt:
                f = np.array([float(v) for v in exact_force])
                s, d = e.start - ref, e.direction
                rows.append((i, np.array([f[0], f[1], (s[0] * f[1] - s[1] * f[0]) / scale]),
                             np.array([0.0, 0.0, (d[0] * f[1] - d[1] * f[0]) / scale]), t))
    finger = np.array([r[0] for r in rows])
    W = np.array([w0 + t * slope for _, w0, slope, t in rows])
    try:
        hull = ConvexHull(W)
    except QhullError:
        return None
    a, b = hull.equations[:, :3], -hull.equations[:, 3]
    if b.min() <= 1e-9:
        return None
    at = [np.flatnonzero((hull.simplices == v).any(axis=1)) for v in range(len(W))]
    segments = []
    for i, (e_index, t) in enumerate(zip(edges, ts, strict=True)):
        lo, hi = 0.0, float(polygon.edges[e_index].length)
        mine = np.flatnonzero(finger == i)
        for v in mine:
            if not len(at[v]):
                continue
            # hard: the vertex's own generator stays in its zone; frictionless: every end
            # of the fan (the force may be any of them)
            for g in (mine if mu == 0 else [v]):
                value = a[at[v]] @ rows[g][1] - ZONE_MARGIN
                slope = a[at[v]] @ rows[g][2]
                with np.errstate(divide="ignore", invalid="ignore"):
                    bound = -value / slope
                if np.any((slope == 0) & (value < 0)):
                    return None
                lo = max(lo, float(bound[slope > 0].max(initial=-np.inf)))
                hi = min(hi, float(bound[slope < 0].min(initial=np.inf)))
        if not lo < t < hi:
            return None
        segments.append([lo, hi])
    for i, j in itertools.pairwise(range(len(edges))):  # fingers on one edge: apart
        if edges[i] == edges[j] and segments[i][1] > segments[j][0]:
            middle = 0.5 * (ts[i] + ts[j])
            segments[i][1], segments[j][0] = min(segments[i][1], middle), max(segments[j][0],
                                                                                middle)
    if any(not v - u > 1e-9 * scale for u, v in segments):
        return None
    segments = _widened(polygon, edges, segments, mu, turn)
    return GrownRegions(polygon, tuple(edges), tuple((u + 0.0, v + 0.0) for u, v in segments),
                        "grown around a sampled prototype (search zones, widened)", mu,
                        hand.margin)


def _widened(polygon: Polygon, edges, segments: list[list[float]], mu: float, turn: float
             ) -> list[list[float]]:
    """The zones' segments widened, end by end (shortest segment first, :data:`ROUNDS`
    rounds, bisection), as far as the corner condition holds in floating point with a
    safety margin (:data:`WIDEN`); the proof decides the result exactly. Fingers on one
    edge stay apart."""
    lo_b, hi_b = polygon.bounds
    ref, scale = 0.5 * lo_b + 0.5 * hi_b, polygon.size
    forces = []
    for e_index in edges:
        e = polygon.edges[e_index]
        fan = _forces([-float(e.normal[0]), -float(e.normal[1])], mu, turn)
        forces.append([np.array([[float(v) for v in f] for f in opt]) for opt in fan])
    finger_ids, option_ids = [], []  # as holds() stacks the wrenches
    n_options = 0
    for i, fs in enumerate(forces):
        for _ in (0, 1):  # the two ends
            for F in fs:
                finger_ids += [i] * len(F)
                option_ids += [n_options] * len(F)
                n_options += 1
    finger, option = np.array(finger_ids), np.array(option_ids)

    def holds(segs) -> bool:
        rows = []
        for e_index, (u, v), fs in zip(edges, segs, forces, strict=True):
            e = polygon.edges[e_index]
            for t in (u, v):
                arm = (e.start + t * e.direction - ref) / scale
                for F in fs:
                    rows.append(np.column_stack([F, arm[0] * F[:, 1] - arm[1] * F[:, 0]]))
        W = np.vstack(rows)
        J, K = np.triu_indices(len(W), 1)
        a, b = W[J], W[K]
        u_, v_ = [1, 2, 0], [2, 0, 1]
        X = np.cross(a, b)
        Xb = np.abs(a[:, u_] * b[:, v_]) + np.abs(a[:, v_] * b[:, u_])
        D, bound = X @ W.T, Xb @ np.abs(W).T
        keep = (np.abs(X) > WIDEN * Xb).any(axis=1)
        for sign in (1.0, -1.0):
            held, _ = _verdicts(sign * D[keep] > WIDEN * bound[keep],
                                np.zeros(D[keep].shape, bool), option, finger, n_options,
                                len(edges))
            if not held.all():
                return False
        return True

    segs = [list(x) for x in segments]
    if not holds(segs):
        return segments
    for _ in range(ROUNDS):
        for i in sorted(range(len(edges)), key=lambda k: segs[k][1] - segs[k][0]):
            length = float(polygon.edges[edges[i]].length)
            same = [j for j in range(len(edges)) if j != i and edges[j] == edges[i]]
            room_lo = max([segs[j][1] for j in same if segs[j][1] <= segs[i][0]], default=0.0)
            room_hi = min([segs[j][0] for j in same if segs[j][0] >= segs[i][1]],
                          default=length)
            for end, limit in ((0, room_lo), (1, room_hi)):
                good, bad = segs[i][end], limit
                trial = [list(x) for x in segs]
                trial[i][end] = bad
                if holds(trial):
                    segs = trial
                    continue
                for _ in range(STEPS):
                    middle = 0.5 * (good + bad)
                    trial[i][end] = middle
                    if holds(trial):
                        good = middle
                    else:
                        bad = middle
                segs[i][end] = good
    return segs


def _build(polygon: Polygon, site, hand: Hand) -> GrownRegions | None:
    edges, ts = site
    return grown_regions(polygon, edges, ts, hand)


GROWN = Construction(
    dim=2, fingers=None, contact="any", name="grown",
    paper="beyond §5: search zones around sampled prototypes, Theorem 1 at the corners",
    method="edges", sites=_sites, build=_build,
    searched="around the best sampled grasps by Theorem 1's margin, one per tuple of edges")

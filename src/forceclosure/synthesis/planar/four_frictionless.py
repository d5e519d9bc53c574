"""Four frictionless fingers on four edges of a polygon (Nguyen 1988, §5.4).

Frictionless contacts push along ``f_i = -n_i`` through ``p_i``, giving the
wrenches ``w_i = (f_i, cross(p_i, f_i))``. Four wrenches in ``R^3`` of rank 3
have a one-dimensional null space, spanned by the signed minors: ``sum_i C_i
w_i = 0`` with ``C_i = (-1)^i det(W without column i)``. The grasp is
force-closure (Theorem 1) iff the four ``C_i`` are nonzero with one common
sign; a nonzero ``C_i`` also gives rank 3.

Expanding a minor along its torque row, ``det = tau_j cross(f_k, f_l) -
tau_k cross(f_j, f_l) + tau_l cross(f_j, f_k)``, which is linear in the
torques. Each ``tau_i = cross(s_i + t_i d_i, f_i)`` is affine in its own edge
parameter, so every ``C_i`` is **affine in (t1, ..., t4)**. This is the
paper's observation that the condition of Corollary 2 is linear in the
contacts, without the parallelograms. The independent regions are then a
box in ``(t1, ..., t4)`` on whose 16 corners the conditions hold, the
maximal such box is a small linear program, and its certificate is the
corner check in exact rational arithmetic.

The margin (:func:`~forceclosure.synthesis.regions.check_margin`) asks
more: every force direction within ``margin`` radians of each normal must
work. Each ``C_i`` is linear in each force (a minor is linear in each of
its columns, and a wrench in its force), so over the fan of directions
``(1 - s) f_i^- + s f_i^+`` between the two turned normals it is affine in
``s_i`` too. The conditions then hold everywhere iff they hold for the 16
combinations of turned normals, at the 16 corners: 64 rows in the linear
program, 256 exact checks in the certificate.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray
from scipy.optimize import linprog

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
    proved_once,
)
from .edge_sites import by_shortest_edge, edge_tuples, force_direction_prune, shortest_edge
from .vertex_grasps import extreme_generators

__all__ = ["STRICT", "FrictionlessRegions", "cofactors",
           "maximal_frictionless_regions", "nguyen_frictionless_regions"]

#: The cofactors are kept this fraction of the polygon's size away from zero.
STRICT = 1e-6


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def cofactors(points, forces) -> list:
    """The signed minors ``C_i`` of four planar wrenches ``(f_i, cross(p_i, f_i))``.

    Works on floats and on ``Fraction`` alike (exact when given fractions).
    """
    tau = [_cross(p, f) for p, f in zip(points, forces, strict=True)]
    out = []
    for i in range(4):
        j, k, m = (x for x in range(4) if x != i)
        minor = (tau[j] * _cross(forces[k], forces[m]) - tau[k] * _cross(forces[j], forces[m])
                 + tau[m] * _cross(forces[j], forces[k]))
        out.append(minor if i % 2 == 0 else -minor)
    return out


def _turned(m, turns, cos, sin) -> list:
    """``m`` turned by ``turns`` times the angle whose cosine and sine are given."""
    return [cos * m[0] - turns * sin * m[1], turns * sin * m[0] + cos * m[1]]


def _cofactors_with_bounds(P: NDArray, F: NDArray) -> tuple[NDArray, NDArray]:
    """:func:`cofactors` of many grasps at once (points and forces ``(..., 4, 2)``), and for
    each the sum of the sizes of its terms, which bounds its rounding error."""
    def cross(a, b):
        return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]

    def size(a, b):
        return np.abs(a[..., 0] * b[..., 1]) + np.abs(a[..., 1] * b[..., 0])

    P, F = np.broadcast_arrays(P, F)
    tau, tau_size = cross(P, F), size(P, F)
    C, bound = np.empty(tau.shape), np.empty(tau.shape)
    for i in range(4):
        j, k, m = (x for x in range(4) if x != i)
        fj, fk, fm = F[..., j, :], F[..., k, :], F[..., m, :]
        minor = (tau[..., j] * cross(fk, fm) - tau[..., k] * cross(fj, fm)
                 + tau[..., m] * cross(fj, fk))
        C[..., i] = minor if i % 2 == 0 else -minor
        bound[..., i] = (tau_size[..., j] * size(fk, fm) + tau_size[..., k] * size(fj, fm)
                         + tau_size[..., m] * size(fj, fk))
    return C, bound


def _affine(polygon: Polygon, edges: tuple[int, ...], turns=(0, 0, 0, 0),
            margin: float = 0.0) -> tuple[NDArray, NDArray]:
    """``C(t) = A @ t + b`` for the four cofactors (rows) and edge parameters (columns),
    with each pushing direction turned by ``turns[i] * margin``."""
    es = [polygon.edges[k] for k in edges]
    c, s = np.cos(margin), np.sin(margin)
    forces = [np.array(_turned(-e.normal, k, c, s)) for e, k in zip(es, turns, strict=True)]
    base = cofactors([e.start for e in es], forces)
    A = np.zeros((4, 4))
    for j in range(4):  # C is affine: the slope in t_j is C(start + d_j) - C(start)
        moved = [e.start + (e.direction if k == j else 0) for k, e in enumerate(es)]
        A[:, j] = np.array(cofactors(moved, forces)) - np.array(base)
    return A, np.array(base)


@dataclass(frozen=True, eq=False)
class FrictionlessRegions(Regions):
    """Four segments, one per edge, such that every choice of four points is force-closure,
    with every normal turned by up to ``margin`` radians.

    Attributes (beyond :class:`Regions`)
    ------------------------------------
    margin : float
    """

    margin: float = 0.0

    def to_dict(self) -> dict[str, object]:
        """The JSON record (see :meth:`Regions.to_dict`), with ``margin``."""
        return {**super().to_dict(), "margin": self.margin}

    @proved_once
    def certify(self) -> Certificate:
        """Prove, exactly, that every choice of one point per segment is force-closure,
        for every pushing direction within ``margin`` of each normal.

        The cofactors are affine in the four edge parameters and in each
        finger's position in its fan of directions, so they keep one strict
        sign on the whole box iff they do at its 16 corners for the 16
        combinations of extreme directions (the rational cosine and sine of
        the margin, from their floating-point values). The corners are the
        very points that are printed, the normals exact (unnormalised):
        scaling a wrench by a positive number scales its cofactor's partner
        and keeps every sign. A cofactor far from zero against a bound on its
        rounding has the sign floating point shows; the rest are evaluated
        with ``fractions.Fraction``.
        """
        es = [self.polygon.edges[k] for k in self.edges]
        inward = [exact_inward(e) for e in es]
        turn = max(self.margin, self.polygon.spread)  # the outline's normals turn too
        cos, sin = Fraction(math.cos(turn)), Fraction(math.sin(turn))
        fans = (-1, 1) if turn > 0 else (0,)
        corners = list(itertools.product(*self.segments))
        turns = list(itertools.product(fans, repeat=4))
        # a static filter: floating-point cofactors whose size exceeds a bound on their
        # rounding (1e-12 of the sum of their terms' sizes, thousands of times the worst
        # case) have the sign they show; only the others are computed in rationals
        P = np.array([[e.point(t) for e, t in zip(es, c, strict=True)] for c in corners])
        m = np.array([[float(x) for x in n] for n in inward])
        k = np.array(turns, dtype=float)[..., None]
        perp = np.stack([-m[:, 1], m[:, 0]], axis=1)
        F = math.cos(turn) * m + k * math.sin(turn) * perp  # (turns, 4, 2)
        C, bound = _cofactors_with_bounds(P[:, None], F[None])  # (corners, turns, 4)
        sure = np.abs(C) > 1e-12 * bound
        signs = set(np.sign(C[sure]).tolist())
        if len(signs) > 1:
            return Certificate(False, "corner check (exact rationals)",
                               "the cofactors change sign between corners or directions")
        for a, b in zip(*np.nonzero(~sure.all(axis=2)), strict=True):
            pts = [exact_point(e, t) for e, t in zip(es, corners[a], strict=True)]
            forces = [_turned(n, q, cos, sin) for n, q in zip(inward, turns[b], strict=True)]
            c = cofactors(pts, forces)
            if any(x == 0 for x in c) or len({x > 0 for x in c}) != 1:
                return Certificate(False, "corner check (exact rationals)",
                                   f"the grasp at t = {tuple(round(x, 6) for x in corners[a])}"
                                   " is not force-closure")
            signs.add(1.0 if c[0] > 0 else -1.0)
        if len(signs) != 1:
            return Certificate(False, "corner check (exact rationals)",
                               "the cofactors change sign between corners")
        return Certificate(True, "corner check (exact rationals)",
                           "the four cofactors (the null vector of the wrenches) are nonzero "
                           "with one sign at all 16 corners (for every extreme direction "
                           "within the margin), hence (affine) everywhere")



def _check(polygon: Polygon, edges: tuple[int, int, int, int],
           margin: float) -> tuple[int, int, int, int]:
    check_margin(margin)
    return check_edges(polygon, edges, 4)


def maximal_frictionless_regions(polygon: Polygon, edges: tuple[int, int, int, int],
                                 margin: float = MARGIN,
                                 ) -> FrictionlessRegions | None:
    """The largest independent regions for four frictionless fingers on four edges.

    Maximises the shortest segment such that all four cofactors keep one
    sign, at least ``STRICT * size`` from zero, on the whole box of segments
    and for every combination of normals turned by ``± margin``. Both signs
    are tried; each is a linear program in ``(u1, ..., u4, z)`` with the
    segments ``[u_i, u_i + z]``.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> r = maximal_frictionless_regions(bundled("square"), (0, 1, 2, 3))
    >>> round(r.min_length, 3), r.certify().holds
    (0.999, True)
    """
    edges = _check(polygon, edges, margin)
    affine = [_affine(polygon, edges, turns, margin)
              for turns in itertools.product((-1, 1), repeat=4)]
    # in units of the polygon's size (C / size = A t' + b / size with t = size t'), so that
    # the solver's absolute tolerances mean the same on a part of any size
    size = polygon.size
    A, b = np.vstack([a for a, _ in affine]), np.concatenate([c for _, c in affine]) / size
    lengths = [polygon.edges[e].length / size for e in edges]
    delta = STRICT
    best = None
    for sign in (1.0, -1.0):
        sA, sb = sign * A, sign * b
        # min over the box of sA_k . t = sA_k . u + sum_j min(sA_kj, 0) z  >=  delta - sb_k
        rows = np.hstack([-sA, -np.minimum(sA, 0).sum(axis=1, keepdims=True)])
        rhs = sb - delta
        box = np.hstack([np.eye(4), np.ones((4, 1))])  # u_j + z <= L_j
        A_ub, b_ub = np.vstack([rows, box]), np.r_[rhs, lengths]
        res = linprog(np.r_[np.zeros(4), -1.0], A_ub=A_ub, b_ub=b_ub,
                      bounds=[(0, None)] * 5, method="highs")
        if res.status == 0 and res.x[4] > 1e-9 and (best is None or res.x[4] > best[4]):
            best = face_middle(A_ub, b_ub, [(0, None)] * 5, res.x, 4)
    if best is None:
        return None
    best = best * size
    z = float(best[4])
    lengths = [polygon.edges[e].length for e in edges]
    return first_proved(lambda trim: FrictionlessRegions(  # rounding may cut a corner
        polygon, edges, tuple((float(u) + trim * z + 0.0, min(float(u) + z, L) - trim * z)
                              for u, L in zip(best[:4], lengths, strict=True)),
        "maximal (linear program)", margin))


def _builder(build):
    def on(polygon: Polygon, site: NDArray, hand: Hand) -> FrictionlessRegions | None:
        return build(polygon, tuple(int(e) for e in site), hand.margin)
    return on


def _meeting_point(e1, e2):
    """``P12(t1, t2)``, where the normal lines at the two contacts meet, as an affine map:
    ``P12 = c + M @ (t1, t2)``; None when the normals are parallel (no meeting point)."""
    denom = e1.normal[0] * e2.normal[1] - e1.normal[1] * e2.normal[0]  # cross(n1, n2)
    if abs(denom) < 1e-9:
        return None

    def at(t1, t2):
        p1, p2 = e1.point(t1), e2.point(t2)
        s = ((p2 - p1)[0] * e2.normal[1] - (p2 - p1)[1] * e2.normal[0]) / denom
        return p1 + s * e1.normal

    c = at(0.0, 0.0)
    return c, np.stack([at(1.0, 0.0) - c, at(0.0, 1.0) - c], axis=1)


def nguyen_frictionless_regions(polygon: Polygon, edges: tuple[int, int, int, int],
                                margin: float = MARGIN) -> FrictionlessRegions | None:
    """Nguyen's construction for four frictionless fingers (§5.4, Fig. 10).

    Fingers 1 and 2 act like one contact at ``P12``, where their normal
    lines meet, able to push along the cone ``C12 = cone(-n1, -n2)``; so do
    fingers 3 and 4 at ``P34``. By Corollary 2 the grasp is force-closure
    when ``P34 - P12`` lies in the sector ``S = C12 ∩ -C34``. As the fingers
    slide, ``P12`` sweeps a parallelogram ``Π12`` (affine in ``t1, t2``), and
    likewise ``Π34``. A two-sided cone with vertex ``I`` and sector ``S`` cuts
    them into ``Π'12 ⊂ I - S`` and ``Π'34 ⊂ I + S``, and boxes of edge
    parameters inside those give the independent regions. The paper searches
    for the best vertex geometrically. Here the conditions are linear in
    ``I`` and the segment ends together, so the best vertex and segments come
    from one linear program, for each of the three pairings of the fingers.
    The result is certified by the exact cofactor check.

    Examples
    --------
    >>> from forceclosure.objects import bundled
    >>> r = nguyen_frictionless_regions(bundled("hexagon"), (0, 1, 3, 4))
    >>> round(r.min_length, 3), r.certify().holds
    (0.497, True)
    """
    edges = _check(polygon, edges, margin)
    best = None
    for a, b, c, d in ((0, 1, 2, 3), (0, 2, 1, 3), (0, 3, 1, 2)):
        order = [edges[k] for k in (a, b, c, d)]
        es = [polygon.edges[k] for k in order]
        maps = [_meeting_point(es[0], es[1]), _meeting_point(es[2], es[3])]
        if maps[0] is None or maps[1] is None:
            continue
        c12 = extreme_generators(_generators_of([-es[0].normal, -es[1].normal]))
        c34 = extreme_generators(_generators_of([es[2].normal, es[3].normal]))  # -C34
        if c12 is None or c34 is None:
            continue
        funcs = [np.array([-g[0][1], g[0][0]]) for g in (c12, c34)] + \
            [np.array([g[1][1], -g[1][0]]) for g in (c12, c34)]
        # the turned normals are not in this program: keep room for them (an angle of margin
        # moves a meeting point by about margin times the object's size); the certificate
        # decides
        delta = max(STRICT, margin) * polygon.size
        rows, rhs = [], []  # x = (Ix, Iy, u1, u2, u3, u4, z), in the pairing's order
        for pair, sign in ((0, -1.0), (1, 1.0)):  # I - P12 in S; P34 - I in S
            off, M = maps[pair]
            for ta, tb in itertools.product((0.0, 1.0), repeat=2):
                for ell in funcs:
                    # sign * ell . (P - I) >= delta, P = off + M @ (u + t z)
                    g = sign * (ell @ M)
                    row = np.zeros(7)
                    row[:2] = sign * ell
                    row[2 + 2 * pair], row[3 + 2 * pair] = -g[0], -g[1]
                    row[6] = -(g[0] * ta + g[1] * tb)
                    rows.append(row)
                    rhs.append(sign * (ell @ off) - delta)
        for k, e in enumerate(es):
            row = np.zeros(7)
            row[2 + k], row[6] = 1.0, 1.0
            rows.append(row)
            rhs.append(e.length)
        bounds = [(None, None)] * 2 + [(0, None)] * 5
        res = linprog(np.r_[np.zeros(6), -1.0], A_ub=np.array(rows), b_ub=np.array(rhs),
                      bounds=bounds, method="highs")
        if res.status != 0 or not res.x[6] > 1e-9 * polygon.size:
            continue
        res.x = face_middle(np.array(rows), np.array(rhs), bounds, res.x, 6)
        z = float(res.x[6])
        segments = dict(zip(order, ((float(u) + 0.0, min(float(u) + z, e.length))
                                    for u, e in zip(res.x[2:6], es, strict=True)),
                            strict=True))
        regions = FrictionlessRegions(polygon, edges, tuple(segments[k] for k in edges),
                                      "Nguyen's two-sided cone between parallelograms (§5.4)",
                                      margin)
        # a later pairing only when larger beyond rounding (1e-6): ties go by pairing order
        if regions.certify().holds and (best is None or regions.min_length
                                        > best.min_length * (1 + 1e-6)):
            best = regions
    return best


def _generators_of(directions):
    return [list(map(float, v)) for v in directions]


def _four(name: str, build, paper: str) -> Construction:
    return Construction(
        dim=2, fingers=4, contact="frictionless", name=name, paper=paper, method="edges",
        sites=edge_tuples(4), prune=force_direction_prune, bound=shortest_edge,
        levels=by_shortest_edge(4), build=_builder(build),
        searched="every four edges whose normals positively span the plane")


MAXIMAL = _four("maximal", maximal_frictionless_regions, "§5.4")
NGUYEN = _four("nguyen", nguyen_frictionless_regions, "§5.4, Algorithm 2")

"""Theorem 1 compiled: the force-closure verdict for many point-contact grasps at once.

Each grasp goes through the same steps as
:func:`forceclosure.analysis.closure.vector_closure`, with the same tolerance, the same
generating wrenches and the same margin LP, so verdicts and margins agree with the reference path:

1. generating wrenches in the grasp's frame (the contacts' centroid and
   their largest distance from it), unit-normalised columns;
2. the rank half of Theorem 1 from the eigenvalues of ``U U^T``;
3. the counting fact (``m = d`` vectors never positively span ``R^d``);
4. the margin LP (:mod:`.simplex`): ``closure`` needs margin and singular
   value ratio above ``tol`` *and* weights that stay strictly positive once
   corrected onto the exact null space of ``U`` — a certificate checked
   here, independently of the LP;
5. otherwise a twist that repels every wrench: first from the margin LP's
   duals, else from the separation LP ``min |U lam|_1, lam in simplex``
   (its value is the reference's ``max_t min_i U_i . t``, ``|t|_inf <= 1``).

Soft fingers with the paper's two-sided torques are decided modulo the span
of those torques, as the reference does. Spatial friction with
``exact`` cones brackets the circular cone between inscribed and
circumscribed pyramids of 8 … 256 edges, as
:func:`forceclosure.analysis.closure.decide` does, and settles at once an
inscribed pyramid's ``marginal`` that a turn about two contacts proves for
every pyramid (``geometry.cones.one_sided``).

A grasp the kernel cannot settle with a clear margin is flagged ``DEFER``
and decided by the reference path: a singular value ratio below ``GUARD``
(where the reference's numerical rank rule, not geometry, decides), a
quantity within ``BAND`` of a threshold (unless it is 0 to ``ROUNDOFF``), a
certificate that fails, or a stalled simplex. On random grasps that is a handful in a million.
"""

from __future__ import annotations

import math
from collections import namedtuple

import numba as nb
import numpy as np

from ..contacts import MODELS
from ..geometry import cones
from ..verdicts import VerdictCode
from .simplex import INFEASIBLE, OPTIMAL, solve_tableau, tableau

__all__ = ["BAND", "BLOCK", "BRACKET", "CLOSURE", "DEFER", "EXACT_EDGES", "FRICTIONLESS", "GUARD",
           "HARD", "MARGINAL", "NONE", "ROUNDOFF", "SOFT", "Work", "closure_kernel",
           "closure_serial", "columns_per_grasp", "grasp", "least_friction_kernel", "wrenches"]

NONE, MARGINAL, CLOSURE = (int(c) for c in VerdictCode)  # their codes everywhere
#: A grasp the kernel leaves to the reference path.
DEFER = 3
#: The friction the least-friction bisection tries first as its upper end.
BRACKET = 10.0
FRICTIONLESS, HARD, SOFT = (MODELS.index(m) for m in ("frictionless", "hard", "soft"))

#: Singular value ratio below which the rank is left to the reference's SVD.
GUARD = 1e-5
#: Margins and repelling work this close to the tolerance go to the reference.
BAND = 1e-8
#: Margins and repelling work this close to 0 are 0 up to round-off: clearly below a
#: tolerance of at least 100 times as much (structurally marginal grasps, e.g. on boxes).
ROUNDOFF = 1e-12
#: Pyramid sizes of the exact-cone bracket (as ``closure.EXACT_CONE_EDGES``).
EXACT_EDGES = np.array([8, 16, 32, 64, 128, 256], dtype=np.int64)

#: Grasps per parallel task (one workspace each).
BLOCK = 256

#: Scratch arrays of one thread, allocated once per block of grasps.
Work = namedtuple("Work", "W two U W2 norms G V lam c x y tab basis weights r sigma_min tw rim")


def columns_per_grasp(k: int, dim: int, edges: int) -> int:
    """Most generating wrenches ``k`` contacts can have with ``edges``-edge pyramids."""
    return k * (4 if dim == 2 else max(2 * edges, edges + 2))


#: The friction pyramid's edge angles and radius, compiled from the one source the
#: reference (``contacts.primitive_wrenches``) runs uncompiled: both build the same bits.
_fill_rim = nb.njit(cache=True, nogil=True)(cones.fill_rim)
_divisor = nb.njit(cache=True, nogil=True)(cones.pyramid_divisor)
_one_sided = nb.njit(cache=True, nogil=True)(cones.one_sided)


@nb.njit(cache=True, nogil=True)
def work_arrays(maxm, max_edges):  # pragma: no cover - compiled
    """The scratch arrays (:data:`Work`) of one thread, for grasps of at most ``maxm``
    generating wrenches and pyramids of at most ``max_edges`` edges."""
    n = maxm + 12
    return Work(np.empty((6, maxm)), np.empty(maxm, dtype=np.bool_), np.empty((6, maxm)),
                np.empty((6, maxm)), np.empty(maxm), np.empty((6, 6)), np.empty((6, 6)),
                np.empty(6), np.empty(n), np.empty(n), np.empty(7), np.empty(8 * (n + 8)),
                np.empty(7, dtype=np.int64),
                np.empty(maxm), np.empty(6), np.empty(1), np.empty(6),
                np.zeros((2, max_edges + 1)))


@nb.njit(cache=True, nogil=True, inline="always")
def _gram(U, mm, d, G):  # pragma: no cover - compiled
    """``G = U U^T`` over the first ``d`` rows and ``mm`` columns of ``U``."""
    for i in range(d):
        for j in range(i, d):
            s = 0.0
            for col in range(mm):
                s += U[i, col] * U[j, col]
            G[i, j] = s
            G[j, i] = s


@nb.njit(cache=True, nogil=True, inline="always")  # inlined: as fast as the loops written out
def _rotate(A, p, q, c, s, d):  # pragma: no cover - compiled
    """Columns ``p`` and ``q`` of ``A`` (rows ``0 .. d - 1``) turned by the plane rotation
    ``(c, s)``, in place (a step of :func:`_eigh`)."""
    for k in range(d):
        akp = A[k, p]
        akq = A[k, q]
        A[k, p] = c * akp - s * akq
        A[k, q] = s * akp + c * akq


@nb.njit(cache=True, nogil=True)
def _eigh(G, V, lam):  # pragma: no cover - compiled
    """Eigen-decomposition of a small symmetric ``G`` (cyclic Jacobi, destroys ``G``)."""
    d = G.shape[0]
    for i in range(d):
        for j in range(d):
            V[i, j] = 1.0 if i == j else 0.0
    for _ in range(60):
        off = 0.0
        diag = 0.0
        for i in range(d):
            diag += G[i, i] * G[i, i]
            for j in range(i + 1, d):
                off += G[i, j] * G[i, j]
        if off <= 1e-32 * diag:
            break
        for p in range(d - 1):
            for q in range(p + 1, d):
                if G[p, q] == 0.0:
                    continue
                theta = (G[q, q] - G[p, p]) / (2.0 * G[p, q])
                t = (1.0 if theta >= 0 else -1.0) / (abs(theta) + math.sqrt(theta * theta + 1))
                c = 1.0 / math.sqrt(t * t + 1.0)
                s = t * c
                _rotate(G, p, q, c, s, d)  # G J
                _rotate(G.T, p, q, c, s, d)  # J^T (G J)
                _rotate(V, p, q, c, s, d)
    for i in range(d):
        lam[i] = G[i, i]


@nb.njit(cache=True, nogil=True)
def contact_frame(P, ref):  # pragma: no cover - compiled
    """Centroid of the contact points and their largest distance from it (``contacts.frame``)."""
    k, d = P.shape
    for j in range(d):
        s = 0.0
        for i in range(k):
            s += P[i, j]
        ref[j] = s / k
    scale = 0.0
    big = 0.0
    for i in range(k):
        r = 0.0
        for j in range(d):
            r += (P[i, j] - ref[j]) ** 2
            big = max(big, abs(P[i, j]))
        scale = max(scale, math.sqrt(r))
    if scale <= 1e-12 * max(1.0, big):
        scale = 1.0
    return scale


@nb.njit(cache=True, nogil=True)
def _column(W, col, f, arm, scale, d, spin):  # pragma: no cover - compiled
    """Write the wrench ``(f, arm x f / scale + spin)`` as column ``col``."""
    if d == 2:
        W[0, col] = f[0]
        W[1, col] = f[1]
        W[2, col] = (arm[0] * f[1] - arm[1] * f[0]) / scale
    else:
        for j in range(3):
            W[j, col] = f[j]
        W[3, col] = (arm[1] * f[2] - arm[2] * f[1]) / scale + spin[0]
        W[4, col] = (arm[2] * f[0] - arm[0] * f[2]) / scale + spin[1]
        W[5, col] = (arm[0] * f[1] - arm[1] * f[0]) / scale + spin[2]


@nb.njit(cache=True, nogil=True)
def wrenches(P, N, mu, tors, model, edges, radius_divisor, ref, scale, W, two, rim,
             frames=None):
    # pragma: no cover - compiled
    """Generating wrenches of one grasp (as ``contacts.primitive_wrenches``); returns ``m``.

    The pyramid's edges are at ``mu / radius_divisor`` (``geometry.cones.
    pyramid_divisor``). ``rim`` caches the cosines and sines of the pyramid's
    edge angles (``geometry.cones.fill_rim``); its last column says for how
    many edges. ``frames`` (``(k, 2, 3)``, ``geometry.cones.fill_frame``)
    orients each contact's pyramid; None: from the coordinate axes. The
    columns equal the reference's bit for bit (tests/kernels/test_wrench_builders.py).
    """
    if rim[0, -1] != edges:
        _fill_rim(rim, edges)
        rim[0, -1] = edges
    k, d = P.shape
    col = 0
    f = np.empty(d)
    arm = np.empty(d)
    shifted = np.empty(d)
    spin = np.zeros(3)
    t = np.empty((2, 3))
    for i in range(k):
        n = N[i]
        for j in range(d):
            arm[j] = P[i, j] - ref[j]
        spin[:] = 0.0
        if model[i] == FRICTIONLESS:
            for j in range(d):
                f[j] = -n[j]
            _column(W, col, f, arm, scale, d, spin)
            two[col] = False
            col += 1
            continue
        coupled = model[i] == SOFT and not math.isnan(tors[i])
        if d == 2:
            tx, ty = -n[1], n[0]
            for sh in range(2 if coupled else 1):
                off = 0.0 if not coupled else (tors[i] if sh == 0 else -tors[i])
                shifted[0] = arm[0] + off * tx
                shifted[1] = arm[1] + off * ty
                for side in range(2):
                    sgn = 1.0 - 2.0 * side
                    f[0] = -n[0] + sgn * mu[i] * tx
                    f[1] = -n[1] + sgn * mu[i] * ty
                    _column(W, col, f, shifted, scale, 2, spin)
                    two[col] = False
                    col += 1
            continue
        if frames is not None:  # the grasp's own (geometry.cones.fill_frame)
            for j in range(3):
                t[0, j] = frames[i, 0, j]
                t[1, j] = frames[i, 1, j]
        else:  # as contacts.tangent_basis: t1 = e x n from the axis least aligned with n
            ax = 0
            for j in range(1, 3):
                if abs(n[j]) < abs(n[ax]):
                    ax = j
            a1, a2 = (ax + 1) % 3, (ax + 2) % 3
            t[0, ax] = 0.0
            t[0, a1] = -n[a2]
            t[0, a2] = n[a1]
            norm = math.sqrt(t[0, 0] ** 2 + t[0, 1] ** 2 + t[0, 2] ** 2)
            for j in range(3):
                t[0, j] /= norm
            t[1, 0] = n[1] * t[0, 2] - n[2] * t[0, 1]
            t[1, 1] = n[2] * t[0, 0] - n[0] * t[0, 2]
            t[1, 2] = n[0] * t[0, 1] - n[1] * t[0, 0]
        radius = mu[i] / radius_divisor
        for side in range(2 if coupled else 1):
            sgn = 1.0 - 2.0 * side
            for j in range(3):
                spin[j] = sgn * tors[i] * n[j] / scale if coupled else 0.0
            for r in range(edges):
                c, s = rim[0, r], rim[1, r]
                for j in range(3):
                    f[j] = -n[j] + radius * (c * t[0, j] + s * t[1, j])
                _column(W, col, f, arm, scale, 3, spin)
                two[col] = False
                col += 1
        if model[i] == SOFT and not coupled:
            for side in range(2):
                sgn = 1.0 - 2.0 * side
                for j in range(3):
                    W[j, col] = 0.0
                    W[3 + j, col] = sgn * n[j]
                two[col] = True
                col += 1
    return col


@nb.njit(cache=True, nogil=True)
def _closure(W, m, d, tol, work, twist, rank_only=False, closed_only=False):
    # pragma: no cover - compiled
    """Theorem 1 for the first ``m`` columns of ``W`` (``d`` rows); returns (code, rank, margin).

    ``twist`` (length ``d``) receives a repelling or least-resisted twist for
    ``none`` and ``marginal``. With ``rank_only`` it stops after the rank and
    counting checks, returning code -1 when they pass. With ``closed_only`` a grasp
    the margin LP (solved, its value clear of ``tol``) shows not closed is ``marginal``
    at once, with no twist: for callers that ask only whether it closes, who then
    skip the separation LP (which still runs where the margin LP is not solved or the
    singular value ratio is within the band of ``tol``).
    """
    U = work.U
    norms = work.norms
    big = 0.0
    for col in range(m):
        s = 0.0
        for j in range(d):
            s += W[j, col] * W[j, col]
        norms[col] = math.sqrt(s)
        big = max(big, norms[col])
    cutoff = 1e-12 * max(1.0, big)
    mm = 0
    for col in range(m):
        if norms[col] > cutoff:
            for j in range(d):
                U[j, mm] = W[j, col] / norms[col]
            mm += 1
    for j in range(d):
        twist[j] = 0.0
    if mm == 0:
        twist[0] = 1.0
        return NONE, 0, np.nan
    G = work.G[:d, :d]
    _gram(U, mm, d, G)
    V = work.V[:d, :d]
    lam = work.lam[:d]
    low = -1
    ratio = _ratio_bound(G, V, d, work) if mm > d else 0.0
    if ratio <= max(GUARD, tol + BAND):  # not clear from the bound: the eigenvalues
        _eigh(G, V, lam)
        top = 0
        low = 0
        for i in range(d):
            if lam[i] > lam[top]:
                top = i
            if lam[i] < lam[low]:
                low = i
        ratio = math.sqrt(max(lam[low], 0.0) / lam[top])
        work.sigma_min[0] = math.sqrt(max(lam[low], 0.0))
    if mm < d:
        # rank <= mm < d. The mm-th largest eigenvalue tells whether rank = mm exactly.
        order = np.sort(lam)[::-1]
        if math.sqrt(max(order[mm - 1], 0.0) / order[0]) < GUARD:
            return DEFER, 0, np.nan
        _null_twist(V[:, low], twist)
        return NONE, mm, np.nan
    if ratio < GUARD:
        return DEFER, 0, np.nan
    if mm == d:  # the counting fact; twist from the separation LP below
        z = _separate(U, mm, d, work, twist)
        return (NONE, d, np.nan) if z >= 0.0 else (DEFER, d, np.nan)  # z = -1: unsolved
    if rank_only:
        return -1, d, np.nan
    # the margin LP: max s, U lam = 0, sum lam = 1, lam >= s  (lam = u + 1/m - v)
    T = tableau(work.tab, d + 1, mm + 1)
    c = work.c[: mm + 1]
    c[:] = 0.0
    c[mm] = -1.0
    rhs = mm + 1 + d + 1
    for j in range(d):
        row = 0.0
        for col in range(mm):
            T[j, col] = U[j, col]
            row += U[j, col]
        T[j, mm] = -row
        T[j, rhs] = -row / mm
    for col in range(mm):
        T[d, col] = 1.0
    T[d, mm] = -float(mm)
    x = work.x[: mm + 1]
    y = work.y[: d + 1]
    status = solve_tableau(T, d + 1, mm + 1, c, work.basis[: d + 1], x, y)
    margin = np.nan
    if status == OPTIMAL:
        margin = 1.0 - mm * x[mm]
        if _unclear(margin, tol):
            return DEFER, d, margin
        if margin > tol and ratio > tol:
            if _certified(U, mm, d, x, work):
                return CLOSURE, d, margin
            return DEFER, d, margin
        if closed_only and abs(ratio - tol) >= BAND:
            return MARGINAL, d, margin
        if margin < 0.0:
            # duals: U_i . t >= -margin / m > 0 for every column
            big_t = 0.0
            for j in range(d):
                big_t = max(big_t, abs(y[j]))
            if big_t > 0.0 and (-margin / mm) / big_t > tol + BAND:
                for j in range(d):
                    twist[j] = y[j] / big_t
                return NONE, d, margin
    elif status != INFEASIBLE:  # stalled or unbounded: not ours to decide
        return DEFER, d, margin
    z = _separate(U, mm, d, work, twist)
    if z < -ROUNDOFF or _unclear(z, tol) or abs(ratio - tol) < BAND:  # z = -1: unsolved
        return DEFER, d, margin
    if z > tol:
        return NONE, d, margin
    if ratio <= tol:
        _null_twist(V[:, low], twist)
    return MARGINAL, d, margin


@nb.njit(cache=True, nogil=True)
def _unclear(value, tol):  # pragma: no cover - compiled
    """Whether ``value`` is too close to ``tol`` to be compared with it here."""
    if abs(value) <= ROUNDOFF and tol >= 100.0 * ROUNDOFF:
        return False
    return abs(value - tol) < BAND


@nb.njit(cache=True, nogil=True)
def _cholesky(G, L, d, floor):  # pragma: no cover - compiled
    """``G = L L^T`` into the lower triangle of ``L`` (``L`` may be ``G``): ``det G``.

    Returns -1 when a pivot is at most ``floor`` (not numerically positive definite).
    """
    det = 1.0
    for j in range(d):
        s = G[j, j]
        for k in range(j):
            s -= L[j, k] * L[j, k]
        if s <= floor:
            return -1.0
        det *= s
        L[j, j] = math.sqrt(s)
        for i in range(j + 1, d):
            s = G[i, j]
            for k in range(j):
                s -= L[i, k] * L[j, k]
            L[i, j] = s / L[j, j]
    return det


@nb.njit(cache=True, nogil=True)
def _ratio_bound(G, L, d, work):  # pragma: no cover - compiled
    """A lower bound on the singular value ratio, ``sqrt(det G / trace(G)^d)``, by Cholesky.

    ``lambda_min >= det G / lambda_max^(d-1)`` and ``lambda_max <= trace G``;
    ``work.sigma_min`` receives the matching bound on the smallest singular
    value. Returns 0 when ``G`` is not numerically positive definite.
    """
    trace = 0.0
    for i in range(d):
        trace += G[i, i]
    det = _cholesky(G, L, d, 1e-300)
    if det < 0.0:
        return 0.0
    work.sigma_min[0] = math.sqrt(det / trace ** (d - 1))
    return math.sqrt(det / trace**d)


@nb.njit(cache=True, nogil=True)
def _null_twist(v, out):  # pragma: no cover - compiled
    """``v`` scaled so that its largest component is +1 (``closure._null_twist``)."""
    big = 0
    for j in range(v.shape[0]):
        if abs(v[j]) > abs(v[big]):
            big = j
    for j in range(v.shape[0]):
        out[j] = v[j] / v[big]


@nb.njit(cache=True, nogil=True)
def _separate(U, mm, d, work, twist):  # pragma: no cover - compiled
    """``max_t min_i U_i . t`` (``|t|_inf <= 1``) as ``min |U lam|_1`` over the simplex.

    Returns -1 when the LP is not solved.
    """
    n = mm + 2 * d
    T = tableau(work.tab, d + 1, n)
    c = work.c[:n]
    c[:] = 0.0
    for j in range(d):
        for col in range(mm):
            T[j, col] = U[j, col]
        T[j, mm + j] = -1.0
        T[j, mm + d + j] = 1.0
        c[mm + j] = -1.0
        c[mm + d + j] = -1.0
    for col in range(mm):
        T[d, col] = 1.0
    T[d, n + d + 1] = 1.0
    x = work.x[:n]
    y = work.y[: d + 1]
    status = solve_tableau(T, d + 1, n, c, work.basis[: d + 1], x, y)
    if status != OPTIMAL:
        return -1.0
    z = 0.0
    for j in range(d):
        z += x[mm + j] + x[mm + d + j]
    z = max(z, 0.0)  # a sum of non-negative variables, up to rounding
    big = 0.0
    for j in range(d):
        big = max(big, abs(y[j]))
    if big > 0.0:
        for j in range(d):
            twist[j] = y[j] / big
    return z


@nb.njit(cache=True, nogil=True)
def _null_correct(U, mm, d, lam, work):  # pragma: no cover - compiled
    """``lam -= U^T (U U^T)^-1 (U lam)`` by Cholesky of the Gram matrix; False if singular."""
    G = work.G[:d, :d]
    r = work.r[:d]
    for i in range(d):
        s = 0.0
        for col in range(mm):
            s += U[i, col] * lam[col]
        r[i] = s
    _gram(U, mm, d, G)
    if _cholesky(G, G, d, 0.0) < 0.0:
        return False
    for i in range(d):  # forward
        s = r[i]
        for k in range(i):
            s -= G[i, k] * r[k]
        r[i] = s / G[i, i]
    for i in range(d - 1, -1, -1):  # backward with L^T
        s = r[i]
        for k in range(i + 1, d):
            s -= G[k, i] * r[k]
        r[i] = s / G[i, i]
    for col in range(mm):
        s = 0.0
        for j in range(d):
            s += U[j, col] * r[j]
        lam[col] -= s
    return True


@nb.njit(cache=True, nogil=True)
def _certified(U, mm, d, x, work):  # pragma: no cover - compiled
    """``closure._certify``: LP weights corrected onto the null space of ``U`` stay positive."""
    lam = work.weights[:mm]
    shift = 1.0 / mm - x[mm]
    low = np.inf
    for col in range(mm):
        lam[col] = x[col] + shift
        low = min(low, lam[col])
    if not _null_correct(U, mm, d, lam, work):
        return False
    corrected_low = np.inf
    for col in range(mm):
        corrected_low = min(corrected_low, lam[col])
    return corrected_low > max(0.5 * low, 2.0 * _leftover(U, mm, d, lam, work))


@nb.njit(cache=True, nogil=True)
def _leftover(U, mm, d, lam, work):  # pragma: no cover - compiled
    """``|U lam| / sigma_min``: how far rounding leaves ``lam`` from the null space."""
    total = 0.0
    for j in range(d):
        s = 0.0
        for col in range(mm):
            s += U[j, col] * lam[col]
        total += s * s
    return math.sqrt(total) / work.sigma_min[0]


@nb.njit(cache=True, nogil=True)
def _modulo_two_sided(W, two, m, tol, work, twist, closed_only=False):
    # pragma: no cover - compiled
    """Theorem 1 modulo the span ``L`` of the two-sided torques (``closure._modulo_lineality``).

    The cone of the wrenches is the whole space iff the one-sided columns,
    projected onto ``L``'s orthogonal complement, positively span it. The LP
    is invariant under the choice of orthonormal basis of that complement,
    so the margin is the reference's.
    """
    # orthonormal basis of L (torque space) by Gram-Schmidt over the pure torques
    basis = np.zeros((3, 3))
    dim_l = 0
    for col in range(m):
        if not two[col] or dim_l == 3:
            continue
        v = np.empty(3)
        for j in range(3):
            v[j] = W[3 + j, col]
        for b in range(dim_l):
            dot = v[0] * basis[b, 0] + v[1] * basis[b, 1] + v[2] * basis[b, 2]
            for j in range(3):
                v[j] -= dot * basis[b, j]
        left = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        if left > 1e-9:
            for j in range(3):
                basis[dim_l, j] = v[j] / left
            dim_l += 1
        elif left > 1e-13:  # nearly dependent: the reference's SVD rank decides
            return DEFER, 6, np.nan
    # the complement: the force axes, and torque axes made orthogonal to L
    Q = np.zeros((6, 6))
    for j in range(3):
        Q[j, j] = 1.0
    dq = 3
    for axis in range(3):
        if dq == 6 - dim_l:
            break
        v = np.zeros(3)
        v[axis] = 1.0
        for b in range(dim_l):
            dot = basis[b, axis]
            for j in range(3):
                v[j] -= dot * basis[b, j]
        for b in range(3, dq):
            dot = v[0] * Q[3, b] + v[1] * Q[4, b] + v[2] * Q[5, b]
            for j in range(3):
                v[j] -= dot * Q[3 + j, b]
        left = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
        if left > 0.5:
            for j in range(3):
                Q[3 + j, dq] = v[j] / left
            dq += 1
    if dq != 6 - dim_l:
        return DEFER, 6, np.nan
    R = work.W2
    mr = 0
    for col in range(m):
        if two[col]:
            continue
        for a in range(dq):
            s = 0.0
            for j in range(6):
                s += Q[j, a] * W[j, col]
            R[a, mr] = s
        mr += 1
    sub = work.tw
    code, _, margin = _closure(R, mr, dq, tol, work, sub, False, closed_only)
    big = 0.0
    for j in range(6):
        s = 0.0
        for a in range(dq):
            s += Q[j, a] * sub[a]
        twist[j] = s
        big = max(big, abs(s))
    if big > 0.0:
        for j in range(6):
            twist[j] /= big
    return code, 6, margin


@nb.njit(cache=True, nogil=True)
def decide_pyramid(P, N, mu, tors, model, edges, divisor, ref, scale, tol, work, twist,
                   frames=None, closed_only=False):
    # pragma: no cover - compiled
    """Theorem 1 for one grasp with one pyramid: (code, rank, margin); ``frames`` as in
    :func:`wrenches`, ``closed_only`` as in :func:`_closure`."""
    d = P.shape[1]
    D = 3 if d == 2 else 6
    m = wrenches(P, N, mu, tors, model, edges, divisor, ref, scale, work.W, work.two, work.rim,
                 frames)
    has_two = False
    for col in range(m):
        has_two = has_two or work.two[col]
    if not has_two:
        return _closure(work.W, m, D, tol, work, twist, False, closed_only)
    # the full set's rank first, as the reference does, then the quotient
    code, rank, margin = _closure(work.W, m, D, tol, work, twist, True)
    if code != -1:
        return code, rank, margin
    return _modulo_two_sided(work.W, work.two, m, tol, work, twist, closed_only)


@nb.njit(cache=True, nogil=True)
def _physical(y, ref, scale, d, out):  # pragma: no cover - compiled
    """``motion.shift_twist``, normalised as ``motion_of`` does: ``(omega, v)`` about the origin."""
    if d == 2:
        omega = y[2] / scale
        vx = y[0] + omega * ref[1]
        vy = y[1] - omega * ref[0]
        out[0], out[1], out[2] = omega, vx, vy
        w_norm = abs(omega)
        v_norm = math.sqrt(vx * vx + vy * vy)
        k = 1
    else:
        for j in range(3):
            out[j] = y[3 + j] / scale
        out[3] = y[0] - (out[1] * ref[2] - out[2] * ref[1])
        out[4] = y[1] - (out[2] * ref[0] - out[0] * ref[2])
        out[5] = y[2] - (out[0] * ref[1] - out[1] * ref[0])
        w_norm = math.sqrt(out[0] ** 2 + out[1] ** 2 + out[2] ** 2)
        v_norm = math.sqrt(out[3] ** 2 + out[4] ** 2 + out[5] ** 2)
        k = 3
    unit = v_norm if (w_norm * scale <= 1e-9 * v_norm or w_norm == 0.0) else w_norm
    if unit > 0.0:
        for j in range(k + d):
            out[j] /= unit


@nb.njit(cache=True, nogil=True)
def _marginal_at_once(P, N, mu, model, ref, scale, tol):  # pragma: no cover - compiled
    """Whether a turn about two contacts settles the exact cones' ``marginal``
    (``geometry.cones.one_sided``, as ``closure._one_sided``): hard and frictionless
    contacts."""
    k = P.shape[0]
    friction = np.empty(k)
    for i in range(k):
        if model[i] == SOFT:
            return False
        friction[i] = 0.0 if model[i] == FRICTIONLESS else mu[i]
    return _one_sided(P, N, friction, ref, scale, k * EXACT_EDGES[-1], tol)


@nb.njit(cache=True, nogil=True)
def grasp(P, N, mu, tors, model, edges, fit, exact, tol, work, ref, y):
    # pragma: no cover - compiled
    """One grasp, as :func:`forceclosure.analysis.closure.decide`: (code, rank, margin, scale).

    ``ref`` receives the torque reference point and ``y`` the twist in the
    scaled wrench frame.
    """
    k, d = P.shape
    scale = contact_frame(P, ref)
    friction = False
    if d == 3:
        for i in range(k):
            friction = friction or (model[i] != FRICTIONLESS and mu[i] > 0.0)
    y[:] = 0.0
    if not (exact and friction):
        use = 8 if exact else edges  # closure.decide: Cone() when there is nothing to bracket
        divisor = _divisor(use, fit == 1 and not exact)
        c, r, mg = decide_pyramid(P, N, mu, tors, model, use, divisor, ref, scale, tol, work, y)
        return c, r, mg, scale
    kept = np.empty_like(y)
    c, r, mg = DEFER, 0, np.nan
    for e in EXACT_EDGES:  # inscribed proves closure, circumscribed refutes it
        c, r, mg = decide_pyramid(P, N, mu, tors, model, e, 1.0, ref, scale, tol, work, y)
        if c in (CLOSURE, DEFER):
            return c, r, mg, scale
        if c == MARGINAL and _marginal_at_once(P, N, mu, model, ref, scale, tol):
            return c, r, mg, scale
        inner_r, inner_mg = r, mg
        kept[:] = y
        c, r, mg = decide_pyramid(P, N, mu, tors, model, e, _divisor(e, True), ref, scale, tol,
                                  work, y)
        if c in (NONE, DEFER):
            return c, r, mg, scale
        y[:] = kept
        c, r, mg = MARGINAL, inner_r, inner_mg
    return c, r, mg, scale


@nb.njit(cache=True, nogil=True)
def _closure_range(points, normals, mu, tors, model, edges, fit, exact, tol, maxm,
                   code, rank, margin, twist, lo, hi):  # pragma: no cover - compiled
    """:func:`closure_kernel`'s work on grasps ``lo`` to ``hi``, with one work area."""
    d = points.shape[2]
    work = work_arrays(maxm, max(edges, EXACT_EDGES[-1]))
    ref = np.empty(d)
    y = np.empty(3 if d == 2 else 6)
    for g in range(lo, hi):
        c, r, mg, scale = grasp(points[g], normals[g], mu[g], tors[g], model, edges, fit,
                                exact, tol, work, ref, y)
        code[g] = c
        rank[g] = r
        margin[g] = mg
        if c in (NONE, MARGINAL):
            _physical(y, ref, scale, d, twist[g])
        else:
            twist[g, :] = np.nan


@nb.njit(parallel=True, cache=True, nogil=True)
def closure_kernel(points, normals, mu, tors, model, edges, fit, exact, tol, maxm,
                   code, rank, margin, twist):  # pragma: no cover - compiled
    """Theorem 1 for ``(N, k, d)`` grasps; fills ``code``, ``rank``, ``margin``, ``twist``.

    ``fit`` is 0 (inscribed) or 1 (circumscribed): the fixed pyramid used
    when ``exact`` is False. Blocks of :data:`BLOCK` grasps run in parallel.
    """
    n_blocks = (points.shape[0] + BLOCK - 1) // BLOCK
    for blk in nb.prange(n_blocks):
        _closure_range(points, normals, mu, tors, model, edges, fit, exact, tol, maxm, code,
                       rank, margin, twist, blk * BLOCK,
                       min(points.shape[0], (blk + 1) * BLOCK))


@nb.njit(cache=True, nogil=True)
def closure_serial(points, normals, mu, tors, model, edges, fit, exact, tol, maxm,
                   code, rank, margin, twist):  # pragma: no cover - compiled
    """:func:`closure_kernel` on the calling thread: for batches of one block or less, which
    gain nothing from the thread pool and, on a busy machine, lose milliseconds waking it."""
    _closure_range(points, normals, mu, tors, model, edges, fit, exact, tol, maxm, code,
                   rank, margin, twist, 0, points.shape[0])


@nb.njit(cache=True, nogil=True)
def _bisection_step(P, N, mu, tors, model, edges, fit, exact, tol, work, ref, y, known):
    # pragma: no cover - compiled
    """:func:`grasp`'s verdict code at the common friction ``mu[0]``, for the least-friction
    bisection: with exact spatial cones, a pyramid whose verdict here follows from an
    earlier step's is skipped.

    Cones grow with friction (each pyramid's axis ``-n`` is the mean of its edges), so
    an inscribed pyramid with no strictly positive combination at zero (margin <= 0) at
    a larger friction has none here, and a circumscribed one not refuted at a smaller
    friction is not refuted here (the twists repelling a cone repel the smaller ones).
    A margin in ``(0, tol]`` proves nothing for smaller frictions: the singular value
    ratio the verdict also needs falls as friction grows. ``known[0, l]`` and
    ``known[1, l]`` keep, for the ladder's level ``l``, the largest friction so far with
    the inscribed pyramid's margin <= 0 and the smallest at which the circumscribed one
    was not refuted (-1 and inf before the first step).
    Near ``mu*`` that leaves one pyramid a step where the ladder built twelve, and of
    an inscribed pyramid only whether it closes is asked.
    """
    if not exact or P.shape[1] == 2:
        return grasp(P, N, mu, tors, model, edges, fit, exact, tol, work, ref, y)[0]
    f = mu[0]
    scale = contact_frame(P, ref)
    for level in range(EXACT_EDGES.shape[0]):
        e = EXACT_EDGES[level]
        if f > known[0, level]:  # whether it closes, no more (no separation LP)
            c, _, mg = decide_pyramid(P, N, mu, tors, model, e, 1.0, ref, scale, tol, work, y,
                                      None, True)
            if c in (CLOSURE, DEFER):
                return c
            if mg <= 0.0:  # no positive combination: none at a smaller friction either
                known[0, level] = f
        if f < known[1, level]:
            c = decide_pyramid(P, N, mu, tors, model, e, _divisor(e, True), ref, scale, tol,
                               work, y)[0]
            if c in (NONE, DEFER):
                return c
            known[1, level] = f
    return MARGINAL


@nb.njit(parallel=True, cache=True, nogil=True)
def least_friction_kernel(points, normals, tors, model, edges, fit, exact, tol, maxm,
                          mu_max, rtol, out, deferred):  # pragma: no cover - compiled
    """Least common friction closing each grasp (``quality.least_friction``), compiled.

    One pass over the grasps; per grasp a bisection on the cone half-angle
    to relative precision ``rtol``, each step a Theorem 1 verdict. Frictionless
    contacts count as hard fingers. ``deferred[g]`` is set where the end
    points (no friction, ``mu_max``) could not be decided here.
    """
    n_grasps, k, d = points.shape
    model_f = model.copy()
    model_0 = model.copy()  # without friction a hard finger is a frictionless one (one column)
    columns_0 = 0  # primitive wrenches without friction: a force, and a soft finger's torques
    for i in range(k):
        if model_f[i] == FRICTIONLESS:
            model_f[i] = HARD
        if model_0[i] == HARD:
            model_0[i] = FRICTIONLESS
        columns_0 += 3 if (model[i] == SOFT and d == 3) else 1
    # fewer vectors than the dimension plus one never span it positively: not closed
    # without friction, whatever the geometry (no need to decide it)
    frictionless_can_close = columns_0 >= (3 if d == 2 else 6) + 1
    n_blocks = (n_grasps + BLOCK - 1) // BLOCK
    for blk in nb.prange(n_blocks):
        work = work_arrays(maxm, max(edges, EXACT_EDGES[-1]))
        ref = np.empty(d)
        y = np.empty(3 if d == 2 else 6)
        mu = np.empty(k)
        known = np.empty((2, EXACT_EDGES.shape[0]))
        for g in range(blk * BLOCK, min(n_grasps, (blk + 1) * BLOCK)):
            deferred[g] = False
            known[0, :] = -1.0
            known[1, :] = np.inf
            mu[:] = 0.0
            c = NONE
            if frictionless_can_close:
                c = grasp(points[g], normals[g], mu, tors[g], model_0, edges, fit, exact, tol,
                          work, ref, y)[0]
            if c in (CLOSURE, DEFER):
                out[g] = 0.0
                deferred[g] = c == DEFER
                continue
            # most grasps close at a moderate friction: bracket there first, where cones are
            # far from half-spaces (near mu_max a step may have to be deferred)
            mu[:] = BRACKET
            c = _bisection_step(points[g], normals[g], mu, tors[g], model_f, edges, fit,
                                exact, tol, work, ref, y, known)
            lo, hi = 0.0, math.atan(BRACKET)
            if c != CLOSURE:
                mu[:] = mu_max
                c = _bisection_step(points[g], normals[g], mu, tors[g], model_f, edges,
                                    fit, exact, tol, work, ref, y, known)
                if c != CLOSURE:
                    out[g] = np.inf
                    deferred[g] = c == DEFER
                    continue
                hi = math.atan(mu_max)  # lo stays 0: the reference's bisection, step by step
            while hi - lo > rtol * hi:
                mid = 0.5 * (lo + hi)
                mu[:] = math.tan(mid)
                c = _bisection_step(points[g], normals[g], mu, tors[g], model_f, edges,
                                    fit, exact, tol, work, ref, y, known)
                # a step too near the boundary to settle here counts as not closed: the
                # answer stays a friction the kernel has shown to close, and the bracket
                # closes on that step (the boundary is within the kernel's band of it)
                if c == CLOSURE:
                    hi = mid
                else:
                    lo = mid
            out[g] = math.tan(hi)


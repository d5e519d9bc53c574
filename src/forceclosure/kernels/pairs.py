"""Corollary 3 compiled: two fingers with friction, any number of pairs, no trigonometry.

The condition ``angle(Q - P, -n_P) < atan(mu_P) - tol`` is decided from
``c = (Q - P) . (-n_P)`` and ``s = |(Q - P) x n_P|`` (both scaled by
``|n_P|``, which cancels): with ``T = tan(tol)``,

    angle < atan(mu) - tol   <=>   c > 0  and  s (1 + mu T) < c (mu - T),
    angle > atan(mu) + tol   <=>   c <= 0 or s (1 - mu T) > c (mu + T)   (mu T < 1),

and the least friction is ``tan(angle) = s / c`` (``inf`` once ``c <= 0``).
That is the same three-way verdict as :func:`forceclosure.two_finger.
two_finger_closure` computes from angles, at a few multiplications a pair.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

#: Pair codes, as in :mod:`forceclosure.two_finger`.
NONE, MARGINAL, CLOSURE = 0, 1, 2
#: A pair whose code is not final: spatial soft fingers, non-antiparallel
#: normals, Corollary 3's condition failing (decided by Theorem 1 instead).
UNDECIDED = 3
#: A pair with a zero normal, or a non-finite coordinate (the caller reports it).
ZERO_NORMAL, NON_FINITE = 4, 5


@nb.njit(inline="always")
def _inside(c: float, s: float, mu: float, T: float) -> bool:
    """angle(c, s) < atan(mu) - tol."""
    return c > 0.0 and mu > T and s * (1.0 + mu * T) < c * (mu - T)


@nb.njit(inline="always")
def _outside(c: float, s: float, mu: float, T: float) -> bool:
    """angle(c, s) > atan(mu) + tol."""
    muT = mu * T
    if muT < 1.0:
        return c <= 0.0 or s * (1.0 - muT) > c * (mu + T)
    return c < 0.0 and s * (muT - 1.0) < -c * (mu + T)


@nb.njit(parallel=True, cache=True, nogil=True)
def pair_kernel(p, n_p, q, n_q, mu_p, mu_q, tol, code, least):  # pragma: no cover - compiled
    """Fill ``code`` (int8) and ``least`` (float64) for ``(N, d)`` pairs, ``d`` = 2 or 3."""
    T = math.tan(tol)
    d = p.shape[1]
    for i in nb.prange(p.shape[0]):
        scale = 1.0
        pq2 = 0.0
        cp = 0.0
        cq = 0.0
        np2 = 0.0
        nq2 = 0.0
        for j in range(d):
            scale = max(scale, abs(p[i, j]), abs(q[i, j]))
            v = q[i, j] - p[i, j]
            pq2 += v * v
            cp -= v * n_p[i, j]
            cq += v * n_q[i, j]
            np2 += n_p[i, j] * n_p[i, j]
            nq2 += n_q[i, j] * n_q[i, j]
        if not (math.isfinite(pq2) and math.isfinite(np2) and math.isfinite(nq2)
                and math.isfinite(cp) and math.isfinite(cq)):
            code[i] = NON_FINITE
            least[i] = np.nan
            continue
        if np2 <= 1e-24 or nq2 <= 1e-24:
            code[i] = ZERO_NORMAL
            least[i] = np.inf
            continue
        if d == 2:
            vx = q[i, 0] - p[i, 0]
            vy = q[i, 1] - p[i, 1]
            sp = abs(vx * n_p[i, 1] - vy * n_p[i, 0])
            sq = abs(vx * n_q[i, 1] - vy * n_q[i, 0])
        else:
            vx = q[i, 0] - p[i, 0]
            vy = q[i, 1] - p[i, 1]
            vz = q[i, 2] - p[i, 2]
            a = vy * n_p[i, 2] - vz * n_p[i, 1]
            b = vz * n_p[i, 0] - vx * n_p[i, 2]
            c = vx * n_p[i, 1] - vy * n_p[i, 0]
            sp = math.sqrt(a * a + b * b + c * c)
            a = vy * n_q[i, 2] - vz * n_q[i, 1]
            b = vz * n_q[i, 0] - vx * n_q[i, 2]
            c = vx * n_q[i, 1] - vy * n_q[i, 0]
            sq = math.sqrt(a * a + b * b + c * c)
        if math.sqrt(pq2) <= 1e-12 * scale:  # coincident points: nothing closes them
            code[i] = NONE
            least[i] = np.inf
            continue
        mp = mu_p[i]
        mq = mu_q[i]
        if _inside(cp, sp, mp, T) and _inside(cq, sq, mq, T):
            code[i] = CLOSURE
        elif _outside(cp, sp, mp, T) or _outside(cq, sq, mq, T):
            code[i] = NONE
        else:
            code[i] = MARGINAL
        if d == 3 and code[i] != CLOSURE:
            # Corollary 3 is only sufficient in space unless the normals are antiparallel.
            inv_p = 1.0 / math.sqrt(np2)
            inv_q = 1.0 / math.sqrt(nq2)
            gap = 0.0
            for j in range(3):
                g = n_p[i, j] * inv_p + n_q[i, j] * inv_q
                gap += g * g
            if math.sqrt(gap) > 1e-9:
                code[i] = UNDECIDED
        if cp > 0.0 and cq > 0.0:
            least[i] = max(sp / cp, sq / cq)
        else:
            least[i] = np.inf

"""Corollary 3 compiled: two fingers with friction, any number of pairs, no trigonometry.

The condition ``angle(Q - P, -n_P) < atan(mu_P) - tol`` is decided from
``c = (Q - P) . (-n_P)`` and ``s = |(Q - P) x n_P|`` (both scaled by
``|n_P|``, which cancels): with ``T = tan(tol)``,

    angle < atan(mu) - tol   <=>   c > 0  and  s (1 + mu T) < c (mu - T),
    angle > atan(mu) + tol   <=>   c <= 0 or s (1 - mu T) > c (mu + T)   (mu T < 1),

and the least friction is ``tan(angle) = s / c`` (``inf`` once ``c <= 0``).
The corollary holds for the segment ``PQ`` *or* ``QP``: fingers squeezing
the object, or spreading apart inside it (``c`` negated at both ends). That
is the same three-way verdict as :func:`forceclosure.analysis.two_finger.
two_finger_closure` computes from angles, at a few multiplications a pair.

Spatial soft pairs have their least friction in closed form too
(:func:`_least_soft`; docs/analysis.md derives it).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__ = ["CLOSURE", "MARGINAL", "NONE", "NON_FINITE", "TOO_LARGE", "UNDECIDED", "ZERO_NORMAL",
           "pair_kernel", "pair_labels_parallel", "pair_labels_serial"]

#: Pair codes, as in :mod:`forceclosure.analysis.two_finger`.
NONE, MARGINAL, CLOSURE = 0, 1, 2
#: A pair whose code is not final: spatial soft fingers whose closed form is
#: ill-conditioned (decided by Theorem 1 instead).
UNDECIDED = 3
#: A pair with a zero normal, or a non-finite coordinate (the caller reports it).
ZERO_NORMAL, NON_FINITE = 4, 5
#: A pair with a point coordinate too large to compute with (the caller reports it).
TOO_LARGE = 6


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


@nb.njit(inline="always")
def _directed(cp: float, sp: float, cq: float, sq: float, mp: float, mq: float, T: float) -> int:
    if _inside(cp, sp, mp, T) and _inside(cq, sq, mq, T):
        return CLOSURE
    if _outside(cp, sp, mp, T) or _outside(cq, sq, mq, T):
        return NONE
    return MARGINAL


@nb.njit(inline="always")
def _verdict(cp: float, sp: float, cq: float, sq: float, mp: float, mq: float, T: float) -> int:
    """The better of ``PQ`` squeezing and ``QP`` spreading (Corollary 3's "PQ, or QP")."""
    return max(_directed(cp, sp, cq, sq, mp, mq, T), _directed(-cp, sp, -cq, sq, mp, mq, T))


@nb.njit(inline="always")
def _directed_least(cp: float, sp: float, cq: float, sq: float) -> float:
    """max(tan angle_P, tan angle_Q) = max(sp / cp, sq / cq), with one division."""
    if cp > 0.0 and cq > 0.0:
        return sp / cp if sp * cq >= sq * cp else sq / cq
    return np.inf


@nb.njit(inline="always")
def _least(cp: float, sp: float, cq: float, sq: float) -> float:
    """The least friction of Corollary 3, squeezing or spreading."""
    return min(_directed_least(cp, sp, cq, sq), _directed_least(-cp, sp, -cq, sq))


@nb.njit(inline="always")
def _least_soft(vx, vy, vz, ax, ay, az, bx, by, bz) -> float:
    """The least friction of two spatial soft fingers (uncoupled torques), exactly.

    ``v = Q - P``; ``a``, ``b`` unit outward normals, not parallel. With
    ``beta`` the angle between ``b`` and ``-a``, ``c = b - a`` their bisector
    and ``psi`` the angle between the lines of ``c`` and of ``v`` projected on
    the plane of ``a`` and ``b``, the pair is force-closure iff the cones'
    half-angle exceeds ``beta / 2 + psi`` (docs/analysis.md).
    """
    mx, my, mz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    sin_b = math.sqrt(mx * mx + my * my + mz * mz)
    beta = math.atan2(sin_b, -(ax * bx + ay * by + az * bz))
    mx, my, mz = mx / sin_b, my / sin_b, mz / sin_b
    along = vx * mx + vy * my + vz * mz
    wx, wy, wz = vx - along * mx, vy - along * my, vz - along * mz
    if wx * wx + wy * wy + wz * wz <= 1e-24 * (vx * vx + vy * vy + vz * vz):
        return np.inf  # PQ along a x b: the rotation about PQ is free
    cx, cy, cz = bx - ax, by - ay, bz - az
    cross = math.sqrt((wy * cz - wz * cy) ** 2 + (wz * cx - wx * cz) ** 2
                      + (wx * cy - wy * cx) ** 2)
    angle = 0.5 * beta + math.atan2(cross, abs(wx * cx + wy * cy + wz * cz))
    return math.tan(angle) if angle < 0.5 * math.pi else np.inf


@nb.njit(inline="always")
def _flag(code, least, i, pq2, np2, nq2, cp, cq) -> bool:
    """Mark pair ``i`` if it cannot be decided (non-finite, zero normal); whether it was."""
    if not math.isfinite(pq2 + np2 + nq2 + cp + cq):  # any NaN or inf (or overflow)
        code[i] = NON_FINITE
        least[i] = np.nan
        return True
    if np2 <= 1e-24 or nq2 <= 1e-24:
        code[i] = ZERO_NORMAL
        least[i] = np.inf
        return True
    return False


@nb.njit(inline="always")
def _soft_verdict(vx, vy, vz, ax, ay, az, bx, by, bz, mp, mq, tol) -> int:
    """Two spatial soft fingers (uncoupled torques), decided in closed form.

    ``a``, ``b`` unit normals. In the plane ``Π`` of ``-a`` and ``b`` (angle
    ``beta`` apart), the hull of the polar cones' wedges, ``[-g_P, g_P]`` and
    ``[beta - g_Q, beta + g_Q]`` (``g = pi/2 - atan(mu)``), must miss the
    line of ``(a x b) x (Q - P)``; the grasp's margin is the angle by which
    it misses it (docs/analysis.md).
    ``UNDECIDED`` where that is ill-conditioned: nearly parallel normals, or
    ``PQ`` nearly along ``a x b``.
    """
    mx, my, mz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    sin_b = math.sqrt(mx * mx + my * my + mz * mz)
    if sin_b <= 1e-6:
        return UNDECIDED
    mx, my, mz = mx / sin_b, my / sin_b, mz / sin_b
    along = vx * mx + vy * my + vz * mz
    wx, wy, wz = vx - along * mx, vy - along * my, vz - along * mz
    if wx * wx + wy * wy + wz * wz <= 1e-12 * (vx * vx + vy * vy + vz * vz):
        return UNDECIDED
    # the plane's axes: u1 = -a, u2 the unit vector in it with b . u2 > 0
    ux, uy, uz = my * az - mz * ay, mz * ax - mx * az, mx * ay - my * ax  # m x a
    if ux * bx + uy * by + uz * bz < 0.0:
        ux, uy, uz = -ux, -uy, -uz
    beta = math.atan2(ux * bx + uy * by + uz * bz, -(ax * bx + ay * by + az * bz))
    ex, ey, ez = my * wz - mz * wy, mz * wx - mx * wz, mx * wy - my * wx  # m x w
    phi = math.atan2(ux * ex + uy * ey + uz * ez, -(ax * ex + ay * ey + az * ez))
    g_p = 0.5 * math.pi - math.atan(mp)
    g_q = 0.5 * math.pi - math.atan(mq)
    low, high = min(-g_p, beta - g_q), max(g_p, beta + g_q)  # the wedges' hull
    free = math.pi - (high - low)  # the arc of lines it leaves
    if free <= 0.0:
        margin = free
    else:
        t = (phi - high) % math.pi
        margin = min(t, free - t) if t < free else -min(t - free, math.pi - t)
    if margin > tol:
        return CLOSURE
    if margin < -tol:
        return NONE
    return MARGINAL


@nb.njit(inline="always")
def _planar_pair(px, py, qx, qy, ax, ay, bx, by, mp, mq, T):
    """Code and least friction of one planar pair whose inputs passed :func:`_flag`."""
    vx = qx - px
    vy = qy - py
    pq2 = vx * vx + vy * vy
    scale = max(1.0, abs(px), abs(py), abs(qx), abs(qy))
    if pq2 <= 1e-24 * scale * scale:  # coincident points: nothing closes them
        return NONE, np.inf
    cp = -(vx * ax + vy * ay)
    cq = vx * bx + vy * by
    sp = abs(vx * ay - vy * ax)
    sq = abs(vx * by - vy * bx)
    return _verdict(cp, sp, cq, sq, mp, mq, T), _least(cp, sp, cq, sq)


@nb.njit(inline="always")
def _spatial_pair(px, py, pz, qx, qy, qz, ax, ay, az, bx, by, bz, mp, mq, T, tol):
    """Code (``UNDECIDED`` where the closed form is ill-conditioned) and least friction of
    one spatial soft pair whose inputs passed :func:`_flag`."""
    vx = qx - px
    vy = qy - py
    vz = qz - pz
    pq2 = vx * vx + vy * vy + vz * vz
    np2 = ax * ax + ay * ay + az * az
    nq2 = bx * bx + by * by + bz * bz
    cp = -(vx * ax + vy * ay + vz * az)
    cq = vx * bx + vy * by + vz * bz
    scale = max(1.0, abs(px), abs(py), abs(pz), abs(qx), abs(qy), abs(qz))
    if pq2 <= 1e-24 * scale * scale:
        return NONE, np.inf
    sp = math.sqrt((vy * az - vz * ay) ** 2 + (vz * ax - vx * az) ** 2
                   + (vx * ay - vy * ax) ** 2)
    sq = math.sqrt((vy * bz - vz * by) ** 2 + (vz * bx - vx * bz) ** 2
                   + (vx * by - vy * bx) ** 2)
    c = _verdict(cp, sp, cq, sq, mp, mq, T)
    # Corollary 3 is only sufficient in space unless the normals are antiparallel
    inv_p = 1.0 / math.sqrt(np2)
    inv_q = 1.0 / math.sqrt(nq2)
    ax, ay, az, bx, by, bz = ax * inv_p, ay * inv_p, az * inv_p, bx * inv_q, by * inv_q, \
        bz * inv_q
    antiparallel = (ax + bx) ** 2 + (ay + by) ** 2 + (az + bz) ** 2 <= 1e-18
    if c != CLOSURE and not antiparallel:
        c = _soft_verdict(vx, vy, vz, ax, ay, az, bx, by, bz, mp, mq, tol)
    if antiparallel:
        least = _least(cp, sp, cq, sq)
    elif (ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2 <= 1e-18:
        least = np.inf  # parallel normals: both fingers push the same way
    else:
        least = _least_soft(vx, vy, vz, ax, ay, az, bx, by, bz)
    return c, least


@nb.njit(parallel=True, cache=True, nogil=True)
def pair_kernel(p, n_p, q, n_q, mu_p, mu_q, tol, code, least):  # pragma: no cover - compiled
    """Fill ``code`` (int8) and ``least`` (float64) for ``(N, d)`` pairs, ``d`` = 2 or 3.

    ``mu_p`` and ``mu_q`` have a value per pair, or one value for all.
    Returns how many pairs have a code other than the three verdicts.
    """
    T = math.tan(tol)
    flagged = 0
    step_p = 1 if mu_p.shape[0] > 1 else 0
    step_q = 1 if mu_q.shape[0] > 1 else 0
    if p.shape[1] == 2:
        for i in nb.prange(p.shape[0]):
            vx = q[i, 0] - p[i, 0]
            vy = q[i, 1] - p[i, 1]
            ax, ay, bx, by = n_p[i, 0], n_p[i, 1], n_q[i, 0], n_q[i, 1]
            if _flag(code, least, i, vx * vx + vy * vy, ax * ax + ay * ay, bx * bx + by * by,
                     -(vx * ax + vy * ay), vx * bx + vy * by):
                flagged += 1
                continue
            c, m = _planar_pair(p[i, 0], p[i, 1], q[i, 0], q[i, 1], ax, ay, bx, by,
                                mu_p[i * step_p], mu_q[i * step_q], T)
            code[i] = c
            least[i] = m
        return flagged
    for i in nb.prange(p.shape[0]):
        vx = q[i, 0] - p[i, 0]
        vy = q[i, 1] - p[i, 1]
        vz = q[i, 2] - p[i, 2]
        ax, ay, az = n_p[i, 0], n_p[i, 1], n_p[i, 2]
        bx, by, bz = n_q[i, 0], n_q[i, 1], n_q[i, 2]
        if _flag(code, least, i, vx * vx + vy * vy + vz * vz, ax * ax + ay * ay + az * az,
                 bx * bx + by * by + bz * bz, -(vx * ax + vy * ay + vz * az),
                 vx * bx + vy * by + vz * bz):
            flagged += 1
            continue
        c, m = _spatial_pair(p[i, 0], p[i, 1], p[i, 2], q[i, 0], q[i, 1], q[i, 2],
                             ax, ay, az, bx, by, bz, mu_p[i * step_p], mu_q[i * step_q], T, tol)
        if c == UNDECIDED:
            flagged += 1
        code[i] = c
        least[i] = m
    return flagged


# --- labels of (N, 2, d) pairs as a user calls them: conditioning inside, one pass ----------

@nb.njit(inline="always")
def _unit(x, y, z):
    """``(x, y, z)`` divided by its length and the length, without overflow (as
    :func:`forceclosure.contacts.unit_rows`); length 0 for a zero vector."""
    big = max(abs(x), abs(y), abs(z))
    if big == 0.0:
        return x, y, z, 0.0
    x, y, z = x / big, y / big, z / big
    small = math.sqrt(x * x + y * y + z * z)
    return x / small, y / small, z / small, big * small


@nb.njit(inline="always")
def _label_row(points, normals, i, mu, T, tol, hard, mu_max, max_coordinate, code, least):
    """Condition, check and label pair ``i`` of ``(N, 2, d)`` arrays; whether it is flagged
    (a code other than the three verdicts: bad input, or ``UNDECIDED``)."""
    d = points.shape[2]
    big = 0.0
    finite = True
    for k in range(2):
        for j in range(d):
            x = points[i, k, j]
            y = normals[i, k, j]
            finite = finite and math.isfinite(x) and math.isfinite(y)
            big = max(big, abs(x))
    if not finite:
        code[i] = NON_FINITE
        least[i] = np.nan
        return True
    if big > max_coordinate:
        code[i] = TOO_LARGE
        least[i] = np.nan
        return True
    s = 1.0
    if big > 2.0**64:  # units of a power of two: exact, and the verdict does not change
        s = 1.0 / math.ldexp(1.0, min(math.frexp(big)[1], 1023))
    if d == 2:
        ax, ay, _, la = _unit(normals[i, 0, 0], normals[i, 0, 1], 0.0)
        bx, by, _, lb = _unit(normals[i, 1, 0], normals[i, 1, 1], 0.0)
        if la <= 1e-12 or lb <= 1e-12:
            code[i] = ZERO_NORMAL
            least[i] = np.inf
            return True
        c, m = _planar_pair(points[i, 0, 0] * s, points[i, 0, 1] * s, points[i, 1, 0] * s,
                            points[i, 1, 1] * s, ax, ay, bx, by, mu, mu, T)
    else:
        ax, ay, az, la = _unit(normals[i, 0, 0], normals[i, 0, 1], normals[i, 0, 2])
        bx, by, bz, lb = _unit(normals[i, 1, 0], normals[i, 1, 1], normals[i, 1, 2])
        if la <= 1e-12 or lb <= 1e-12:
            code[i] = ZERO_NORMAL
            least[i] = np.inf
            return True
        if hard:  # two hard fingers in space: rank 5, never force-closure
            code[i] = NONE
            least[i] = np.inf
            return False
        c, m = _spatial_pair(points[i, 0, 0] * s, points[i, 0, 1] * s, points[i, 0, 2] * s,
                             points[i, 1, 0] * s, points[i, 1, 1] * s, points[i, 1, 2] * s,
                             ax, ay, az, bx, by, bz, mu, mu, T, tol)
    code[i] = c
    least[i] = np.inf if m > mu_max else m
    return c == UNDECIDED


@nb.njit(cache=True, nogil=True)
def pair_labels_serial(points, normals, mu, tol, hard, mu_max, max_coordinate, code,
                       least):  # pragma: no cover - compiled
    """:func:`pair_labels_parallel` on the calling thread (no pool to wake)."""
    T = math.tan(tol)
    flagged = 0
    for i in range(points.shape[0]):
        if _label_row(points, normals, i, mu, T, tol, hard, mu_max, max_coordinate, code,
                      least):
            flagged += 1
    return flagged


@nb.njit(parallel=True, cache=True, nogil=True)
def pair_labels_parallel(points, normals, mu, tol, hard, mu_max, max_coordinate, code,
                         least):  # pragma: no cover - compiled
    """Fill ``code`` (int8) and ``least`` (float64, ``inf`` beyond ``mu_max``) for the
    ``(N, 2, d)`` contact pairs ``points``, ``normals`` (any lengths) at one friction ``mu``,
    in one pass: each row's normals made unit, coordinates beyond ``2**64`` divided by a
    power of two, bad rows flagged (``NON_FINITE``, ``TOO_LARGE`` beyond
    ``max_coordinate``, ``ZERO_NORMAL``). ``hard`` spatial pairs are never closed.
    Returns how many pairs have a code other than the three verdicts."""
    T = math.tan(tol)
    flagged = 0
    for i in nb.prange(points.shape[0]):
        if _label_row(points, normals, i, mu, T, tol, hard, mu_max, max_coordinate, code,
                      least):
            flagged += 1
    return flagged

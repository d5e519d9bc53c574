"""Corollary 3 compiled: two fingers with friction, any number of pairs, no trigonometry.

The condition ``angle(Q - P, -n_P) < atan(mu_P) - tol`` is decided from
``c = (Q - P) . (-n_P)`` and ``s = |(Q - P) x n_P|`` (both scaled by
``|n_P|``, which cancels): with ``T = tan(tol)``,

    angle < atan(mu) - tol   <=>   c > 0  and  s (1 + mu T) < c (mu - T),
    angle > atan(mu) + tol   <=>   c <= 0 or s (1 - mu T) > c (mu + T)   (mu T < 1),

and the least friction is ``tan(angle) = s / c`` (``inf`` once ``c <= 0``).
The corollary holds for the segment ``PQ`` *or* ``QP``: fingers squeezing
the object, or spreading apart inside it (``c`` negated at both ends). That
is the same three-way verdict as
:func:`forceclosure.analysis.two_finger.two_finger_closure` computes from angles, at a
few multiplications a pair.

Spatial soft pairs have their least friction in closed form too
(:func:`_least_soft`; docs/analysis.md derives it).
"""

from __future__ import annotations

import itertools
import math

import numba as nb
import numpy as np

from ..verdicts import VerdictCode

__all__ = ["CLOSURE", "MARGINAL", "NONE", "NON_FINITE", "TOO_LARGE", "UNDECIDED", "ZERO_NORMAL",
           "pair_labels", "pair_labels_kernel", "pair_verdict_kernel",
           "pair_verdicts"]

#: Pair codes: the verdicts' (:class:`forceclosure.verdicts.VerdictCode`), then the ones below.
NONE, MARGINAL, CLOSURE = (int(c) for c in VerdictCode)
#: A pair whose code is not final: spatial soft fingers whose closed form is
#: ill-conditioned (decided by Theorem 1 instead).
UNDECIDED = 3
#: A pair with a zero normal, or a non-finite coordinate (the caller reports it).
ZERO_NORMAL, NON_FINITE = 4, 5
#: A pair with a point coordinate too large to compute with (the caller reports it).
TOO_LARGE = 6


# The tests below are written without branches (bitwise & and |, selects), so that loops
# over pairs vectorise (:func:`_common_planar`, :func:`_common_rows`); they compute the same
# values, bit for bit, as the branching forms would.

@nb.njit(inline="always")
def _inside(c: float, s: float, mu: float, T: float) -> bool:
    """angle(c, s) < atan(mu) - tol."""
    return (c > 0.0) & (mu > T) & (s * (1.0 + mu * T) < c * (mu - T))


@nb.njit(inline="always")
def _outside_below(c: float, s: float, mu: float, T: float) -> bool:
    """:func:`_outside` where ``mu T < 1``."""
    return (c <= 0.0) | (s * (1.0 - mu * T) > c * (mu + T))


@nb.njit(inline="always")
def _outside(c: float, s: float, mu: float, T: float) -> bool:
    """angle(c, s) > atan(mu) + tol."""
    muT = mu * T
    above = (c < 0.0) & (s * (muT - 1.0) < -c * (mu + T))  # muT >= 1
    return (muT < 1.0) & _outside_below(c, s, mu, T) | (muT >= 1.0) & above


@nb.njit(inline="always")
def _directed(cp: float, sp: float, cq: float, sq: float, mp: float, mq: float, T: float,
              below: bool = False) -> int:
    """The verdict of squeezing (``PQ``); ``below``: ``mu T < 1`` at both fingers."""
    closed = _inside(cp, sp, mp, T) & _inside(cq, sq, mq, T)
    if below:
        opened = _outside_below(cp, sp, mp, T) | _outside_below(cq, sq, mq, T)
    else:
        opened = _outside(cp, sp, mp, T) | _outside(cq, sq, mq, T)
    return CLOSURE if closed else (NONE if opened else MARGINAL)


@nb.njit(inline="always")
def _verdict(cp: float, sp: float, cq: float, sq: float, mp: float, mq: float, T: float) -> int:
    """The better of ``PQ`` squeezing and ``QP`` spreading (Corollary 3's "PQ, or QP")."""
    return max(_directed(cp, sp, cq, sq, mp, mq, T), _directed(-cp, sp, -cq, sq, mp, mq, T))


@nb.njit(inline="always")
def _directed_least(cp: float, sp: float, cq: float, sq: float) -> float:
    """max(tan angle_P, tan angle_Q) = max(sp / cp, sq / cq), with one division."""
    positive = (cp > 0.0) & (cq > 0.0)
    first = sp * cq >= sq * cp
    # divided by 1 where not positive (the ratio is not used): no division by zero, which
    # raises in kernels compiled with Python's error model
    ratio = (sp if first else sq) / ((cp if first else cq) if positive else 1.0)
    return ratio if positive else np.inf


@nb.njit(inline="always")
def _least(cp: float, sp: float, cq: float, sq: float) -> float:
    """The least friction of Corollary 3, squeezing or spreading."""
    return min(_directed_least(cp, sp, cq, sq), _directed_least(-cp, sp, -cq, sq))


@nb.njit(inline="always")
def _least_soft(vx, vy, vz, ax, ay, az, bx, by, bz):
    """The least friction of two spatial soft fingers (uncoupled torques), exactly.

    ``v = Q - P``; ``a``, ``b`` unit outward normals, not parallel. With
    ``beta`` the angle between ``b`` and ``-a``, ``c = b - a`` their bisector
    and ``psi`` the angle between the lines of ``c`` and of ``v`` projected on
    the plane of ``a`` and ``b``, the pair is force-closure iff the cones'
    half-angle exceeds ``beta / 2 + psi`` (docs/analysis.md). Returns that least friction,
    ``tan(beta / 2)``, and whether :func:`_soft_verdict` would find the pair
    well-conditioned (not ``UNDECIDED``).
    """
    mx, my, mz = ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx
    sin_b = math.sqrt(mx * mx + my * my + mz * mz)
    one_plus_cos = 1.0 - (ax * bx + ay * by + az * bz)  # cos beta = -a . b
    if one_plus_cos <= 0.0:
        return np.inf, np.inf, False  # parallel to round-off: both fingers push the same way
    tan_half_beta = sin_b / one_plus_cos
    mx, my, mz = mx / sin_b, my / sin_b, mz / sin_b
    along = vx * mx + vy * my + vz * mz
    wx, wy, wz = vx - along * mx, vy - along * my, vz - along * mz
    w2, v2 = wx * wx + wy * wy + wz * wz, vx * vx + vy * vy + vz * vz
    well = sin_b > 1e-6 and w2 > 1e-12 * v2
    if w2 <= 1e-24 * v2:
        return np.inf, tan_half_beta, well  # PQ along a x b: the rotation about PQ is free
    cx, cy, cz = bx - ax, by - ay, bz - az
    cross = math.sqrt((wy * cz - wz * cy) ** 2 + (wz * cx - wx * cz) ** 2
                      + (wx * cy - wy * cx) ** 2)
    dot = abs(wx * cx + wy * cy + wz * cz)
    # tan(beta / 2 + psi), tan psi = cross / dot, by the addition formula (no inverse
    # trigonometry); beta / 2 + psi >= 90 degrees where the denominator is not positive
    denominator = dot - tan_half_beta * cross
    if denominator <= 0.0:
        return np.inf, tan_half_beta, well
    return (tan_half_beta * dot + cross) / denominator, tan_half_beta, well


@nb.njit(inline="always")
def _screen(least, tan_half_beta, mu, tol) -> int:
    """The verdict of :func:`_soft_verdict` for equal friction ``mu`` at both fingers, read
    from the pair's least friction where it is far from the boundary (no inverse
    trigonometry); ``UNDECIDED`` near it.

    With ``alpha = atan(mu)``, the margin of :func:`_soft_verdict` is
    ``alpha - beta / 2 - psi`` while the wedges leave lines free (``tan(beta / 2) < mu``),
    else ``2 alpha - beta``; ``least = tan(beta / 2 + psi)``. Since ``atan`` has slope at
    least ``1 / (1 + x**2)`` up to ``x``, ``(mu - least) / (1 + mu**2)`` bounds the first
    margin from below, ``(least - mu) / (1 + least**2)`` its opposite, and
    ``(tan(beta / 2) - mu) / (1 + tan(beta / 2)**2)`` half the opposite of the second:
    past ``2 tol + 1e-4`` the code is certain."""
    band = 2.0 * tol + 1e-4
    if least < mu:
        return CLOSURE if (mu - least) / (1.0 + mu * mu) > band else UNDECIDED
    if tan_half_beta < mu:  # lines left free: the margin is alpha - beta / 2 - psi
        if math.isinf(least):  # beta / 2 + psi >= 90 degrees: the margin <= -atan(1 / mu)
            return NONE if mu / (1.0 + mu * mu) > band else UNDECIDED
        return NONE if (least - mu) / (1.0 + least * least) > band else UNDECIDED
    if math.isinf(tan_half_beta):
        return UNDECIDED
    return NONE if (tan_half_beta - mu) / (1.0 + tan_half_beta * tan_half_beta) > band \
        else UNDECIDED


@nb.njit(cache=True)
def _soft_verdict(vx, vy, vz, ax, ay, az, bx, by, bz, mp, mq, tol, atan_p=-1.0,
                  atan_q=-1.0) -> int:
    """Two spatial soft fingers (uncoupled torques), decided in closed form.

    ``a``, ``b`` unit normals. In the plane ``Π`` of ``-a`` and ``b`` (angle
    ``beta`` apart), the hull of the polar cones' wedges, ``[-g_P, g_P]`` and
    ``[beta - g_Q, beta + g_Q]`` (``g = pi/2 - atan(mu)``), must miss the
    line of ``(a x b) x (Q - P)``; the grasp's margin is the angle by which
    it misses it (docs/analysis.md).
    ``UNDECIDED`` where that is ill-conditioned: nearly parallel normals, or
    ``PQ`` nearly along ``a x b``. ``atan_p``, ``atan_q``: ``atan(mp)``, ``atan(mq)`` when
    the caller has them (negative: computed here).
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
    g_p = 0.5 * math.pi - (math.atan(mp) if atan_p < 0.0 else atan_p)
    g_q = 0.5 * math.pi - (math.atan(mq) if atan_q < 0.0 else atan_q)
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


@nb.njit(cache=True)
def _same_side(ax, ay, az, bx, by, bz, atan_p, atan_q) -> bool:
    """Whether every force of both cones (unit normals ``a``, ``b`` at most 90 degrees
    apart) has a positive component along ``-(a + b)``, by more than 0.1 radian: then no
    positive combination of the wrenches has zero force (the pure torques have none), and
    the pair is not force-closure, far from the marginal band. It settles nearly parallel
    normals at friction below about 9, where the closed form of :func:`_soft_verdict` is
    ill-conditioned (Theorem 1 decides the rest)."""
    dot = ax * bx + ay * by + az * bz
    if dot <= 0.0:
        return False
    cross = math.sqrt((ay * bz - az * by) ** 2 + (az * bx - ax * bz) ** 2
                      + (ax * by - ay * bx) ** 2)
    half = 0.5 * math.atan2(cross, dot)  # each normal's angle from the bisector
    return half + max(atan_p, atan_q) < 0.5 * math.pi - 0.1


@nb.njit(inline="always")
def _planar_pair(px, py, qx, qy, ax, ay, bx, by, mp, mq, T):
    """Code and least friction of one planar pair whose inputs :func:`_conditioned_pair`
    checked."""
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
def _sides(vx, vy, vz, ax, ay, az, bx, by, bz, np2, nq2):
    """Corollary 3's ``c`` and ``s`` at both contacts of a spatial pair (``v = Q - P``,
    normals ``a``, ``b`` of squared lengths ``np2``, ``nq2``) and the unit normals."""
    cp = -(vx * ax + vy * ay + vz * az)
    cq = vx * bx + vy * by + vz * bz
    sp = math.sqrt((vy * az - vz * ay) ** 2 + (vz * ax - vx * az) ** 2
                   + (vx * ay - vy * ax) ** 2)
    sq = math.sqrt((vy * bz - vz * by) ** 2 + (vz * bx - vx * bz) ** 2
                   + (vx * by - vy * bx) ** 2)
    inv_p = 1.0 / math.sqrt(np2)
    inv_q = 1.0 / math.sqrt(nq2)
    return (cp, sp, cq, sq, ax * inv_p, ay * inv_p, az * inv_p, bx * inv_q, by * inv_q,
            bz * inv_q)


@nb.njit(cache=True)
def _spatial_pair(px, py, pz, qx, qy, qz, ax, ay, az, bx, by, bz, mp, mq, T, tol,
                  atan_p=-1.0, atan_q=-1.0):
    """Code (``UNDECIDED`` where the closed form is ill-conditioned) and least friction of
    one spatial soft pair whose inputs :func:`_conditioned_pair` checked; ``atan_p``,
    ``atan_q`` as in :func:`_soft_verdict`."""
    vx = qx - px
    vy = qy - py
    vz = qz - pz
    pq2 = vx * vx + vy * vy + vz * vz
    scale = max(1.0, abs(px), abs(py), abs(pz), abs(qx), abs(qy), abs(qz))
    if pq2 <= 1e-24 * scale * scale:
        return NONE, np.inf
    cp, sp, cq, sq, ax, ay, az, bx, by, bz = _sides(vx, vy, vz, ax, ay, az, bx, by, bz,
                                                    ax * ax + ay * ay + az * az,
                                                    bx * bx + by * by + bz * bz)
    c = _verdict(cp, sp, cq, sq, mp, mq, T)
    # Corollary 3 is only sufficient in space unless the normals are antiparallel
    antiparallel = (ax + bx) ** 2 + (ay + by) ** 2 + (az + bz) ** 2 <= 1e-18
    screened = UNDECIDED
    if antiparallel:
        least = _least(cp, sp, cq, sq)
    elif (ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2 <= 1e-18:
        least = np.inf  # parallel normals: both fingers push the same way
    else:
        least, tan_half_beta, well = _least_soft(vx, vy, vz, ax, ay, az, bx, by, bz)
        if c != CLOSURE and well and mp == mq:
            screened = _screen(least, tan_half_beta, mp, tol)
    if c != CLOSURE and not antiparallel:
        if screened != UNDECIDED:
            c = screened
        else:
            c = _soft_verdict(vx, vy, vz, ax, ay, az, bx, by, bz, mp, mq, tol, atan_p, atan_q)
            if c == UNDECIDED and _same_side(ax, ay, az, bx, by, bz,
                                             math.atan(mp) if atan_p < 0.0 else atan_p,
                                             math.atan(mq) if atan_q < 0.0 else atan_q):
                c = NONE
    return c, least


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
def _conditioned_pair(d, px, py, pz, qx, qy, qz, ax, ay, az, bx, by, bz, mp, mq, atan_p,
                      atan_q, T, tol, hard, max_coordinate):
    """Condition, check and decide one pair given by its raw coordinates (``z`` = 0 in the
    plane): the code (a verdict, ``UNDECIDED``, or the flag of bad input) and the least
    friction. Points beyond ``2**64`` divided by a power of two (exact; the verdict does not
    depend on units); normals outside lengths 1e-10 to 1e100 made unit first (as
    :func:`forceclosure.contacts.unit_rows`: no overflow), others used as given (their
    length cancels in every test); bad rows flagged (``NON_FINITE``, ``TOO_LARGE`` beyond
    ``max_coordinate``, ``ZERO_NORMAL`` at length 1e-12 or less); ``hard`` spatial pairs
    are never closed (rank 5)."""
    na = ax * ax + ay * ay + az * az
    nb_ = bx * bx + by * by + bz * bz
    # one sum is finite iff every term is, barring overflow (which only sends rows to the
    # exact checks below)
    if not math.isfinite(px + py + pz + qx + qy + qz + na + nb_) and not (
            math.isfinite(px) and math.isfinite(py) and math.isfinite(pz)
            and math.isfinite(qx) and math.isfinite(qy) and math.isfinite(qz)
            and math.isfinite(ax) and math.isfinite(ay) and math.isfinite(az)
            and math.isfinite(bx) and math.isfinite(by) and math.isfinite(bz)):
        return NON_FINITE, np.nan
    big = max(abs(px), abs(py), abs(pz), abs(qx), abs(qy), abs(qz))
    if big > max_coordinate:
        return TOO_LARGE, np.nan
    s = 1.0
    if big > 2.0**64:  # units of a power of two: exact, and the verdict does not change
        s = 1.0 / math.ldexp(1.0, min(math.frexp(big)[1], 1023))
    # normals of lengths 1e-10 to 1e100 are used as they are (the verdict and the least
    # friction are ratios in which their length cancels; nothing overflows); others are
    # made unit, scaled first as unit_rows does, and refused at length 1e-12 or less
    if not (1e-20 < na < 1e200 and 1e-20 < nb_ < 1e200):
        ax, ay, az, la = _unit(ax, ay, az)
        bx, by, bz, lb = _unit(bx, by, bz)
        if la <= 1e-12 or lb <= 1e-12:
            return ZERO_NORMAL, np.inf
    if d == 2:
        return _planar_pair(px * s, py * s, qx * s, qy * s, ax, ay, bx, by, mp, mq, T)
    if hard:  # two hard fingers in space: rank 5, never force-closure
        return NONE, np.inf
    return _spatial_pair(px * s, py * s, pz * s, qx * s, qy * s, qz * s, ax, ay, az, bx, by,
                         bz, mp, mq, T, tol, atan_p, atan_q)


@nb.njit(cache=True, nogil=True)
def pair_verdict_kernel(p, n_p, q, n_q, mu_p, mu_q, tol, hard, max_coordinate, code,
                        least):  # pragma: no cover - compiled
    """Fill ``code`` (int8) and ``least`` (float64) for ``(N, d)`` pairs as a user gives
    them, ``d`` = 2 or 3, in one pass on the calling thread (it releases the GIL:
    :func:`pair_verdicts` runs it on slices in threads): each row conditioned (points
    beyond ``2**64`` in units of a power of two, extreme normals made unit) and checked,
    bad rows flagged (``NON_FINITE``, ``TOO_LARGE`` beyond ``max_coordinate``,
    ``ZERO_NORMAL``), then decided by :func:`_planar_pair` or :func:`_spatial_pair`
    (``hard`` spatial pairs never closed). ``mu_p`` and ``mu_q`` have a value per pair,
    or one value for all. Returns how many pairs have a code other than the three
    verdicts."""
    T = math.tan(tol)
    flagged = 0
    step_p = 1 if mu_p.shape[0] > 1 else 0
    step_q = 1 if mu_q.shape[0] > 1 else 0
    if p.shape[1] == 2:  # the dimension outside the loops, scalars only inside: measured
        # most rows branch-free (vectorised), then the scalar path for the rows left
        _common_planar(p, n_p, q, n_q, mu_p, mu_q, step_p, step_q, T, max_coordinate, code,
                       least)
        for i in range(p.shape[0]):  # 1.4x faster than a row function's loop
            if code[i] != _REDO:
                continue
            c, m = _conditioned_pair(2, p[i, 0], p[i, 1], 0.0, q[i, 0], q[i, 1], 0.0,
                                     n_p[i, 0], n_p[i, 1], 0.0, n_q[i, 0], n_q[i, 1], 0.0,
                                     mu_p[i * step_p], mu_q[i * step_q], -1.0, -1.0, T, tol,
                                     False, max_coordinate)
            code[i] = c
            least[i] = m
            if c > CLOSURE:
                flagged += 1
        return flagged
    for i in range(p.shape[0]):
        c, m = _conditioned_pair(3, p[i, 0], p[i, 1], p[i, 2], q[i, 0], q[i, 1], q[i, 2],
                                 n_p[i, 0], n_p[i, 1], n_p[i, 2], n_q[i, 0], n_q[i, 1],
                                 n_q[i, 2], mu_p[i * step_p], mu_q[i * step_q], -1.0, -1.0, T,
                                 tol, hard, max_coordinate)
        code[i] = c
        least[i] = m
        if c > CLOSURE:
            flagged += 1
    return flagged


#: The code :func:`_common_rows` and :func:`_common_planar` give a row they leave to the
#: scalar path (never returned).
_REDO = 7


@nb.njit(inline="always")
def _as_given(total, big, na, nb_, max_coordinate):
    """Whether a pair needs none of :func:`_conditioned_pair`'s conditioning: ``total`` (the
    sum of its coordinates and squared normal lengths ``na``, ``nb_``) finite, its largest
    coordinate ``big`` within ``2**64`` and ``max_coordinate``, normals of lengths 1e-10 to
    1e100. Bitwise ``&`` (not ``and``): no branches."""
    return ((abs(total) < np.inf) & (big <= 2.0**64) & (big <= max_coordinate) & (na > 1e-20)
            & (na < 1e200) & (nb_ > 1e-20) & (nb_ < 1e200))


@nb.njit(inline="always")
def _common_planar_row(px, py, qx, qy, ax, ay, bx, by, mp, mq, T, max_coordinate):
    """:func:`_common_planar`'s code (``_REDO`` outside its case) and μ* of one pair."""
    na = ax * ax + ay * ay
    nb_ = bx * bx + by * by
    big = max(abs(px), abs(py), abs(qx), abs(qy))
    vx, vy = qx - px, qy - py
    scale = max(1.0, big)
    common = (_as_given(px + py + qx + qy + na + nb_, big, na, nb_, max_coordinate)
              & (vx * vx + vy * vy > 1e-24 * scale * scale) & (mp * T < 1.0) & (mq * T < 1.0))
    cp = -(vx * ax + vy * ay)
    cq = vx * bx + vy * by
    sp = abs(vx * ay - vy * ax)
    sq = abs(vx * by - vy * bx)
    # of squeezing (PQ) and spreading (QP), only the one with c_P > 0 can close or have a
    # finite μ*; the other is NONE (its c_P <= 0, and mu T < 1) with μ* = inf, so it
    # changes neither max(verdicts) nor min(μ*): decided once, not twice
    sign = 1.0 if cp > 0.0 else -1.0
    cp, cq = sign * cp, sign * cq
    code = _directed(cp, sp, cq, sq, mp, mq, T, True)
    return (code if common else _REDO), _directed_least(cp, sp, cq, sq)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _common_planar(p, n_p, q, n_q, mu_p, mu_q, step_p, step_q, T, max_coordinate, code,
                   least):  # pragma: no cover - compiled
    """The common case of :func:`pair_verdict_kernel` in the plane without branches on the
    row, so that the compiler vectorises it: pairs whose inputs need no conditioning
    (finite, points within ``2**64`` and ``max_coordinate``, normals of lengths 1e-10 to
    1e100), whose points are apart, and with ``mu T < 1``. The codes and μ* are the scalar
    path's (:func:`_conditioned_pair`, :func:`_planar_pair`) bit for bit; every other row
    gets ``_REDO``. Measured: about 1.4x faster than the scalar path on random pairs, one
    friction for all (``bench_targets.py``'s pairs row)."""
    if step_p == 0 and step_q == 0:  # one friction for all: a loop the compiler vectorises
        mp, mq = mu_p[0], mu_q[0]
        for i in range(p.shape[0]):
            code[i], least[i] = _common_planar_row(p[i, 0], p[i, 1], q[i, 0], q[i, 1],
                                                   n_p[i, 0], n_p[i, 1], n_q[i, 0],
                                                   n_q[i, 1], mp, mq, T, max_coordinate)
        return
    for i in range(p.shape[0]):
        code[i], least[i] = _common_planar_row(p[i, 0], p[i, 1], q[i, 0], q[i, 1], n_p[i, 0],
                                               n_p[i, 1], n_q[i, 0], n_q[i, 1],
                                               mu_p[i * step_p], mu_q[i * step_q], T,
                                               max_coordinate)


@nb.njit(cache=True, nogil=True, error_model="numpy")
def _common_rows(points, normals, mu, T, tol, mu_max, max_coordinate, code,
                 least):  # pragma: no cover - compiled
    """The common case of :func:`pair_labels_kernel` without branches, so that the compiler
    vectorises it: spatial soft pairs whose inputs need no conditioning (finite, points
    within ``2**64``, normals of lengths 1e-10 to 1e100), whose points are apart and
    normals neither parallel nor antiparallel, and which Corollary 3 or :func:`_screen`
    decides. Every step is the scalar path's (:func:`_conditioned_pair`,
    :func:`_spatial_pair`), the same operations in the same order (no fast-math), so the
    codes and μ* are the same bit for bit; every other row gets ``_REDO``. Measured:
    about 4x faster than the scalar path on sampled jaw poses."""
    for i in range(points.shape[0]):
        px, py, pz = points[i, 0, 0], points[i, 0, 1], points[i, 0, 2]
        qx, qy, qz = points[i, 1, 0], points[i, 1, 1], points[i, 1, 2]
        ax, ay, az = normals[i, 0, 0], normals[i, 0, 1], normals[i, 0, 2]
        bx, by, bz = normals[i, 1, 0], normals[i, 1, 1], normals[i, 1, 2]
        na = ax * ax + ay * ay + az * az
        nb_ = bx * bx + by * by + bz * bz
        big = max(abs(px), abs(py), abs(pz), abs(qx), abs(qy), abs(qz))
        common = _as_given(px + py + pz + qx + qy + qz + na + nb_, big, na, nb_,
                           max_coordinate)
        vx, vy, vz = qx - px, qy - py, qz - pz
        scale = max(1.0, big)
        common &= vx * vx + vy * vy + vz * vz > 1e-24 * scale * scale
        cp, sp, cq, sq, ax, ay, az, bx, by, bz = _sides(vx, vy, vz, ax, ay, az, bx, by, bz,
                                                        na, nb_)
        c = _verdict(cp, sp, cq, sq, mu, mu, T)
        common &= ((ax + bx) ** 2 + (ay + by) ** 2 + (az + bz) ** 2 > 1e-18) & (
            (ax - bx) ** 2 + (ay - by) ** 2 + (az - bz) ** 2 > 1e-18)
        least_, tan_half_beta, well = _least_soft(vx, vy, vz, ax, ay, az, bx, by, bz)
        if c != CLOSURE:
            c = _screen(least_, tan_half_beta, mu, tol)
            common &= well & (c != UNDECIDED)
        code[i] = c if common else _REDO
        least[i] = np.inf if least_ > mu_max else least_


@nb.njit(cache=True, nogil=True)
def pair_labels_kernel(points, normals, mu, tol, hard, mu_max, max_coordinate, code,
                       least):  # pragma: no cover - compiled
    """Fill ``code`` (int8) and ``least`` (float64, ``inf`` beyond ``mu_max``) for the
    ``(N, 2, d)`` contact pairs ``points``, ``normals`` (any lengths) at one friction ``mu``,
    on the calling thread (it releases the GIL: :func:`pair_labels` runs it on slices in
    threads): spatial soft pairs first by :func:`_common_rows` (vectorised); the rows it
    leaves, and all others, one at a time, each conditioned as :func:`_conditioned_pair`
    does (extreme normals made unit, coordinates beyond ``2**64`` divided by a power of
    two), bad rows flagged (``NON_FINITE``, ``TOO_LARGE`` beyond ``max_coordinate``,
    ``ZERO_NORMAL``). ``hard`` spatial pairs are never closed.
    Returns how many pairs have a code other than the three verdicts."""
    T = math.tan(tol)
    atan_mu = math.atan(mu)
    flagged = 0
    planar = points.shape[2] == 2
    common = not planar and not hard
    if common:  # most rows, vectorised; the scalar loop below does the rest
        _common_rows(points, normals, mu, T, tol, mu_max, max_coordinate, code, least)
    for i in range(points.shape[0]):  # scalars only in the loop (no row function taking
        if common and code[i] != _REDO:  # the arrays: measured 1.4x slower)
            continue
        if planar:
            c, m = _conditioned_pair(2, points[i, 0, 0], points[i, 0, 1], 0.0,
                                     points[i, 1, 0], points[i, 1, 1], 0.0, normals[i, 0, 0],
                                     normals[i, 0, 1], 0.0, normals[i, 1, 0], normals[i, 1, 1],
                                     0.0, mu, mu, atan_mu, atan_mu, T, tol, hard,
                                     max_coordinate)
        else:
            c, m = _conditioned_pair(3, points[i, 0, 0], points[i, 0, 1], points[i, 0, 2],
                                     points[i, 1, 0], points[i, 1, 1], points[i, 1, 2],
                                     normals[i, 0, 0], normals[i, 0, 1], normals[i, 0, 2],
                                     normals[i, 1, 0], normals[i, 1, 1], normals[i, 1, 2], mu,
                                     mu, atan_mu, atan_mu, T, tol, hard, max_coordinate)
        code[i] = c
        least[i] = np.inf if m > mu_max else m
        if c > CLOSURE:
            flagged += 1
    return flagged


_POOL: list = []


def _in_slices(kernel, n, serial_below, *args):
    """``kernel(*args)`` on the calling thread for fewer than ``serial_below`` rows; else on
    one contiguous slice of every array of ``n`` rows per thread (numba's thread count): the
    first on the calling thread, the others in a pool of Python threads that sleep between
    calls (one wake-up per extra thread, no spinning). Returns the sum of the slices'
    answers."""
    if n < serial_below:
        return kernel(*args)
    threads = max(1, int(nb.config.NUMBA_NUM_THREADS))
    if threads == 1:
        return kernel(*args)
    if not _POOL:
        from concurrent.futures import ThreadPoolExecutor

        _POOL.append(ThreadPoolExecutor(threads - 1, thread_name_prefix="forceclosure-pairs"))
    bounds = np.linspace(0, n, threads + 1).astype(np.int64)
    slices = [[a[lo:hi] if isinstance(a, np.ndarray) and a.ndim and a.shape[0] == n else a
               for a in args] for lo, hi in itertools.pairwise(bounds)]
    jobs = [_POOL[0].submit(kernel, *part) for part in slices[1:]]
    return kernel(*slices[0]) + sum(job.result() for job in jobs)


def pair_labels(points, normals, mu, tol, hard, mu_max, max_coordinate, code, least,
                serial_below):
    """:func:`pair_labels_kernel` on the calling thread for fewer than ``serial_below``
    pairs; else on one contiguous slice per thread (:func:`_in_slices`)."""
    return _in_slices(pair_labels_kernel, points.shape[0], serial_below, points, normals, mu,
                      tol, hard, mu_max, max_coordinate, code, least)


def pair_verdicts(p, n_p, q, n_q, mu_p, mu_q, tol, hard, max_coordinate, code, least,
                  serial_below):
    """:func:`pair_verdict_kernel` on the calling thread for fewer than ``serial_below``
    pairs; else on one contiguous slice per thread (:func:`_in_slices`; ``mu_p``, ``mu_q``
    sliced when they have a value per pair)."""
    return _in_slices(pair_verdict_kernel, p.shape[0], serial_below, p, n_p, q, n_q, mu_p,
                      mu_q, tol, hard, max_coordinate, code, least)

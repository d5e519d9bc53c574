"""Friction cones: their angles, whether two counter-overlap, and the friction pyramid.

A contact with outward unit normal ``n`` and friction ``mu`` pushes along the
friction cone ``C`` of axis ``-n`` and half-angle ``alpha = atan(mu)``. Two
cones *counter-overlap* when ``C_i ∩ -C_j`` has an interior (Lemma 1, §5.2,
§5.3): the angle between ``-n_i`` and ``n_j`` is below ``alpha_i + alpha_j``.
This module holds the one test of that, :func:`counter_overlap`, and the one
builder of a cone's generating forces, :func:`friction_forces` (exact in the
plane, a ``k``-edge pyramid in space), whose edge angles :func:`fill_rim` and
radius :func:`pyramid_divisor` are plain arithmetic that the compiled kernels
(:mod:`forceclosure.kernels.theorem1`) compile from this same source, so that
both paths build bit-for-bit the same wrenches (tests/kernels/test_wrench_builders.py).

A spatial pyramid has an orientation: where its first edge lies about the
cone's axis. :func:`tangent_basis` takes it from the coordinate axes (the
verdicts, which bracket the circular cone, do not depend on it);
:func:`fill_frame` takes it from the grasp itself, so that a quality measured
on the pyramids (Ferrari–Canny epsilon) is the same when the grasp is turned,
moved, scaled or its contacts reordered (see its docstring for the rule, its
fallbacks and the one case left to a coordinate axis).

numba keys a cached kernel by its own file only: after editing :func:`fill_rim`,
:func:`pyramid_divisor` or :func:`fill_frame`, touch ``kernels/theorem1.py`` and
``kernels/quality.py`` (or clear numba's cache) and run ``forceclosure warmup``,
or the kernels keep the old code (and the bit-for-bit tests fail, as they should).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["FRAME_TOL", "angle_between", "counter_overlap", "counter_overlap_angle",
           "fill_frame", "fill_rim", "friction_forces", "grasp_tangents", "one_sided",
           "pyramid_divisor", "pyramid_radius", "pyramid_rim", "tangent_basis"]

#: Relative size below which a candidate for a pyramid's first tangent counts as absent
#: (:func:`fill_frame`): far above round-off, so that a turned copy of a grasp takes the
#: same branch, and a direction taken is accurate to about ``1e-16 / FRAME_TOL`` radians
#: (times the grasp's distance from the origin over its size).
FRAME_TOL = 1e-6


def angle_between(u: ArrayLike, v: ArrayLike) -> NDArray[np.float64]:
    """Angle between vectors along the last axis (2-D or 3-D), stable near 0 and pi.

    ``atan2(|u x v|, u . v)``: neither vector needs to be a unit vector.

    Examples
    --------
    >>> round(float(angle_between([1.0, 0.0], [1.0, 1.0])), 12) == round(math.pi / 4, 12)
    True
    >>> angle_between([[0, 0, 2.0], [1.0, 0, 0]], [[0, 0, -1.0], [1.0, 0, 0]]).tolist()
    [3.141592653589793, 0.0]
    """
    u = np.asarray(u, dtype=float)
    v = np.asarray(v, dtype=float)
    dot = np.sum(u * v, axis=-1)
    if u.shape[-1] == 2:
        cross = np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
    else:
        cross = np.linalg.norm(np.cross(u, v), axis=-1)
    return np.arctan2(cross, dot)


def counter_overlap_angle(n_i: ArrayLike, n_j: ArrayLike) -> NDArray[np.float64]:
    """Angle between the axes of ``C_i`` and ``-C_j``: between ``-n_i`` and ``n_j``.

    0 for contacts on opposite sides facing each other (normals antiparallel),
    pi for two contacts on one face.

    Examples
    --------
    >>> float(counter_overlap_angle([0, 0, 1.0], [0, 0, -1.0]))
    0.0
    """
    return angle_between(-np.asarray(n_i, dtype=float), n_j)


def counter_overlap(n_i: ArrayLike, n_j: ArrayLike, mu_i: ArrayLike,
                    mu_j: ArrayLike | None = None) -> NDArray[np.bool_]:
    """Whether the friction cones at two contacts counter-overlap: ``C_i ∩ -C_j`` has an
    interior, that is ``angle(-n_i, n_j) < atan(mu_i) + atan(mu_j)`` with both frictions
    positive (a frictionless cone is a ray: it has no interior to share).

    Vectorised over leading axes (normals ``(..., d)``, ``d`` 2 or 3; friction
    broadcast against ``(...)``); ``mu_j`` defaults to ``mu_i``. Normals need
    not be unit vectors. The test on the normals alone: in the plane it is
    Lemma 1's ``S = C_p ∩ -C_q`` being non-empty, in space the paper's
    force-direction closure of two soft fingers (Theorem 2, §5.2) and a
    counter-overlapping pair of §5.3.

    Examples
    --------
    >>> bool(counter_overlap([0, 0, 1], [0, 0, -1], 0.1))   # opposite faces
    True
    >>> bool(counter_overlap([0, 0, 1], [1, 0, 0], 0.9))    # at right angles: needs mu > 1
    False
    >>> counter_overlap([[-1, 0], [-1, 0]], [[0, 1], [1, 0]], 1.01).tolist()
    [True, True]
    >>> bool(counter_overlap([0, 1], [0, -1], 0.0, 5.0))   # a ray inside a cone: no interior
    False
    """
    mu_i = np.asarray(mu_i, dtype=float)
    mu_j = mu_i if mu_j is None else np.asarray(mu_j, dtype=float)
    limit = np.arctan(mu_i) + np.arctan(mu_j)
    return (counter_overlap_angle(n_i, n_j) < limit) & (mu_i > 0) & (mu_j > 0)


def tangent_basis(normals: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Two unit tangents ``t1, t2`` with ``(t1, t2, n)`` right-handed, for ``(..., 3)`` normals.

    ``t1`` is built from the coordinate axis least aligned with ``n``, so an
    axis-aligned normal gets axis-aligned tangents (exact in floating point).

    Examples
    --------
    >>> t1, t2 = tangent_basis(np.array([0.0, 0.0, 1.0]))
    >>> (t1 + 0.0).tolist(), (t2 + 0.0).tolist()
    ([0.0, -1.0, 0.0], [1.0, 0.0, 0.0])
    """
    n = np.asarray(normals, dtype=float)
    axis = np.argmin(np.abs(n), axis=-1)
    e = np.zeros_like(n)
    np.put_along_axis(e, np.asarray(axis)[..., None], 1.0, axis=-1)
    t1 = np.cross(e, n)
    t1 /= np.linalg.norm(t1, axis=-1, keepdims=True)
    t2 = np.cross(n, t1)
    return t1, t2


def fill_frame(points: NDArray[np.float64], normals: NDArray[np.float64],
               frames: NDArray[np.float64]) -> None:
    """Each contact's pyramid frame from the grasp itself: ``frames[i] = (t1, t2)``.

    For ``M`` spatial contacts (rows of ``points`` and unit outward ``normals``,
    ``(M, 3)``) write unit tangents with ``(t1, t2, n)`` right-handed into
    ``frames`` (``(M, 2, 3)``). ``t1`` is the first of these found, each taken
    only when larger than :data:`FRAME_TOL` of its scale (``c`` the contacts'
    centroid, ``s`` their largest distance from it, ``P`` the projection on
    the contact's tangent plane):

    A. ``P (c - p)``: towards the centroid — every contact whose normal line
       misses the centroid;
    B. the principal axis of ``sum_q P(q - p) P(q - p)^T`` over the other
       contacts (the centroid is on the normal line, e.g. three fingers around
       a cylinder pointing at its axis); its sign from the third moment, else
       from the other normals, else left to the basis;
    C. ``sum_q P n_q``, the other contacts' normals, else their principal axis
       and sign as in B (every contact on the normal line: a pinch whose other
       pad is tilted);
    D. the coordinate axis least along all the normals together, ``e``, one
       for every contact: ``t1 ∝ e x n``.

    A, B and C are functions of the grasp alone (they turn with it and do not
    depend on the contacts' order, units or position), so a pyramid built on
    them, and a quality measured on it, is the same for a turned, moved,
    scaled or reordered grasp, to round-off (about ``1e-16 / FRAME_TOL``
    where a candidate is barely above the threshold). A sign left to the
    basis does not matter for an even number of edges (the pyramid turned by
    pi is itself); for an odd number it may (three fingers 120 degrees apart).
    D is reached, in exact arithmetic, in two cases only:

    1. every contact lies on one line and every normal is along it, ``±a`` (a
       head-on pinch): the grasp and its torque frame are unchanged by any
       rotation about the line, and ``e x n`` is ``±(e x a)`` for every
       contact, so another ``e`` (another turn of the grasp) turns all the
       pyramids together about the line — a symmetry: the value is the same
       (for a head-on pair of soft pads it does not even depend on the
       pyramids' turns, tests/analysis/test_epsilon_frame.py);
    2. about some contact's normal line, which holds the centroid, the other
       contacts' offsets and normals both balance to second order (their first
       and second moments about it vanish). That takes at least four (point,
       normal) pairs — never two or three point contacts — e.g. four fingers
       at a regular tetrahedron's vertices pointing at its centre. There the
       value may change with the turn (by about 2 % there), within the bracket of any
       inscribed pyramid: between the circular cones' value at friction
       ``mu cos(pi / k)`` and at ``mu``.

    Plain scalar arithmetic, so that the compiled kernels compile this very
    function and both paths build the same bits.

    Examples
    --------
    Two fingers 2 apart along x, pressing up a little (normals tilted to -z): both
    first tangents lie in the plane of the pinch, towards the centroid.

    >>> P = np.array([[-1.0, 0, 0], [1.0, 0, 0]])
    >>> N = np.array([[-0.8, 0, -0.6], [0.8, 0, -0.6]])
    >>> frames = np.empty((2, 2, 3))
    >>> fill_frame(P, N, frames)
    >>> (np.round(frames[:, 0], 12) + 0.0).tolist()
    [[0.6, 0.0, -0.8], [-0.6, 0.0, -0.8]]
    """
    m = points.shape[0]
    cen = np.zeros(3)
    for q in range(m):
        for j in range(3):
            cen[j] += points[q, j]
    for j in range(3):
        cen[j] /= m
    size = 0.0
    big = 0.0
    along = np.zeros(3)  # how much the normals lie along each coordinate axis, together
    for q in range(m):
        r = 0.0
        for j in range(3):
            r += (points[q, j] - cen[j]) ** 2
            along[j] += normals[q, j] ** 2
            big = max(big, abs(points[q, j]))
        size = max(size, math.sqrt(r))
    common = 0
    for j in range(1, 3):
        if along[j] < along[common]:
            common = j
    # points that coincide (to round-off in their centroid) give no direction: A and B skipped
    near = FRAME_TOL * size if size > 1e-12 * big else math.inf
    e = np.empty(3)
    f = np.empty(3)
    d = np.empty(3)
    for i in range(m):
        n = normals[i]
        # any orthonormal (e, f) of the tangent plane: the tangent found does not depend on it
        ax = 0
        for j in range(1, 3):
            if abs(n[j]) < abs(n[ax]):
                ax = j
        a1, a2 = (ax + 1) % 3, (ax + 2) % 3
        e[ax] = 0.0
        e[a1] = -n[a2]
        e[a2] = n[a1]
        length = math.sqrt(e[0] ** 2 + e[1] ** 2 + e[2] ** 2)
        for j in range(3):
            e[j] /= length
        f[0] = n[1] * e[2] - n[2] * e[1]
        f[1] = n[2] * e[0] - n[0] * e[2]
        f[2] = n[0] * e[1] - n[1] * e[0]
        found = False
        cx, cy = 0.0, 0.0
        # A: towards the centroid
        x = 0.0
        y = 0.0
        for j in range(3):
            x += (cen[j] - points[i, j]) * e[j]
            y += (cen[j] - points[i, j]) * f[j]
        r = math.sqrt(x * x + y * y)
        if r > near:
            cx, cy, found = x / r, y / r, True
        for source in range(2):  # B: the other contacts; C: their normals
            if found:
                break
            hx, hy, a, b, m2 = 0.0, 0.0, 0.0, 0.0, 0.0
            for q in range(m):
                for j in range(3):
                    d[j] = points[q, j] - points[i, j] if source == 0 else normals[q, j]
                x = d[0] * e[0] + d[1] * e[1] + d[2] * e[2]
                y = d[0] * f[0] + d[1] * f[1] + d[2] * f[2]
                hx += x
                hy += y
                a += x * x - y * y
                b += 2.0 * x * y
                m2 += x * x + y * y
            unit = near if source == 0 else FRAME_TOL * m
            r = math.sqrt(hx * hx + hy * hy)
            if source == 1 and r > unit:  # C's first moment (B's is A)
                cx, cy, found = hx / r, hy / r, True
                break
            if m2 <= unit * unit or math.sqrt(a * a + b * b) <= FRAME_TOL * m2:
                continue
            phi = 0.5 * math.atan2(b, a)
            cx, cy, found = math.cos(phi), math.sin(phi), True
            # the axis's sign: its third moment, else the normals' first
            third, scale3, first = 0.0, 0.0, 0.0
            for q in range(m):
                for j in range(3):
                    d[j] = points[q, j] - points[i, j] if source == 0 else normals[q, j]
                x = d[0] * e[0] + d[1] * e[1] + d[2] * e[2]
                y = d[0] * f[0] + d[1] * f[1] + d[2] * f[2]
                t = x * cx + y * cy
                third += t * t * t
                scale3 += math.sqrt(x * x + y * y) ** 3
                for j in range(3):
                    first += normals[q, j] * (cx * e[j] + cy * f[j])
            if abs(third) > FRAME_TOL * scale3:
                if third < 0.0:
                    cx, cy = -cx, -cy
            elif abs(first) > FRAME_TOL * m and first < 0.0:
                cx, cy = -cx, -cy
        t1 = frames[i, 0]
        if found:
            for j in range(3):
                t1[j] = cx * e[j] + cy * f[j]
        else:  # D: one coordinate axis for every contact (a symmetry makes it immaterial)
            use = common if abs(n[common]) < 0.8 else ax
            u1, u2 = (use + 1) % 3, (use + 2) % 3
            t1[use] = 0.0
            t1[u1] = -n[u2]
            t1[u2] = n[u1]
        length = math.sqrt(t1[0] ** 2 + t1[1] ** 2 + t1[2] ** 2)
        for j in range(3):
            t1[j] /= length
        t2 = frames[i, 1]
        t2[0] = n[1] * t1[2] - n[2] * t1[1]
        t2[1] = n[2] * t1[0] - n[0] * t1[2]
        t2[2] = n[0] * t1[1] - n[1] * t1[0]


def grasp_tangents(points: ArrayLike, normals: ArrayLike
                   ) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """:func:`fill_frame` as arrays: ``(t1, t2)``, each ``(M, 3)``, for ``M`` spatial contacts.

    Examples
    --------
    A pinch turned by a quarter turn about z: its frames turn with it.

    >>> P = np.array([[-1.0, 0.2, 0], [1.0, 0, 0.1]])
    >>> N = np.array([[-1.0, 0, 0], [1.0, 0, 0]])
    >>> R = np.array([[0.0, -1, 0], [1, 0, 0], [0, 0, 1]])
    >>> t1, t2 = grasp_tangents(P, N)
    >>> u1, u2 = grasp_tangents(P @ R.T + 5.0, N @ R.T)
    >>> bool(np.allclose(u1, t1 @ R.T) and np.allclose(u2, t2 @ R.T))
    True
    """
    points = np.ascontiguousarray(points, dtype=float)
    normals = np.ascontiguousarray(normals, dtype=float)
    frames = np.empty((len(points), 2, 3))
    fill_frame(points, normals, frames)
    return frames[:, 0], frames[:, 1]


def one_sided(points: NDArray[np.float64], normals: NDArray[np.float64],
              mu: NDArray[np.float64], ref: NDArray[np.float64], scale: float,
              columns: int, tol: float) -> bool:
    """Whether a turn about the line through two contacts proves that no pyramid
    inscribed in the spatial friction cones closes the grasp with a margin above ``tol``:
    every exact cone lies on one side of it.

    Forces at those two contacts do no work on such a turn, whatever their direction
    (when two fingers pinch within their cones, the turn about them is what no
    inscribed pyramid can resist one way).
    The turn ``t = (t_f, t_tau)`` is taken in the scaled wrench frame (wrenches
    ``(f, a x f / scale)``, ``a`` the point less ``ref``); a force ``f`` at contact ``i``
    does work ``f . g_i`` on it, ``g_i = t_f + t_tau x a_i / scale``. On the cone of axis
    ``-n_i`` and friction ``mu_i`` (0: a frictionless contact, the ray ``-n_i``) the least
    work per unit normal force is, in closed form,
    ``h_i = -n_i . g_i - mu_i |g_i - (g_i . n_i) n_i|``. If every ``h_i >= -delta`` and
    one contact has ``h_k > 0``, any balanced combination of ``columns`` unit generating
    wrenches puts weight at most ``delta / (c_k h_k)`` on each of contact ``k``'s
    (``c_k`` the least normal force of a unit wrench there), so Theorem 1's margin
    ``m min lam`` is at most ``columns delta / (c_k h_k)``. True when that bound is below
    a quarter of ``tol`` for some pair of contacts and sense of turning (``delta`` taking
    round-off; ``tol >= 1e-10``): room for the LPs' own error, which a ``closure`` of the
    reference's must also get past its certificate (weights corrected onto the exact
    null space keep more than half the LP's least weight).

    Where an inscribed pyramid is ``marginal`` (its LP finds no twist repelled by more
    than ``tol``), this settles the exact cones' ``marginal`` at once: no finer inscribed
    pyramid closes, and no circumscribed one is refuted (a twist repelling the larger
    cone would repel the smaller one). Two fingers pinching within their cones, the
    third's cone on one side of the turn about them, are such a grasp. The margin and
    twist reported are then the level's that fired, not the 256-edge pyramid's. It looks
    at the geometry alone, not at an LP's twist, so the reference and the kernels settle
    the same grasps. Plain scalar arithmetic, compiled from this source by the kernels.

    Examples
    --------
    Two opposed fingers on the x axis and a third on top pushing along -y: turning
    about the x axis one way, only the third one's force does work, never negative:

    >>> P = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 0, 1]])
    >>> N = np.array([[-1.0, 0, 0], [1.0, 0, 0], [0.0, 1, 0]])
    >>> one_sided(P, N, np.full(3, 0.5), P.mean(axis=0), 1.0, 768, 1e-6)
    True
    >>> N[2] = [0.0, 0.3, 0.91 ** 0.5]   # the third cone across the turn: no proof
    >>> one_sided(P, N, np.full(3, 0.5), P.mean(axis=0), 1.0, 768, 1e-6)
    False
    """
    if not tol >= 1e-10:
        return False
    k = points.shape[0]
    for i in range(k):
        for j in range(i + 1, k):  # in units of scale: no overflow for huge coordinates
            w0 = (points[j, 0] - points[i, 0]) / scale
            w1 = (points[j, 1] - points[i, 1]) / scale
            w2 = (points[j, 2] - points[i, 2]) / scale
            length = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
            if not length > 1e-9:
                continue
            w0, w1, w2 = w0 / length, w1 / length, w2 / length
            b0 = (points[i, 0] - ref[0]) / scale
            b1 = (points[i, 1] - ref[1]) / scale
            b2 = (points[i, 2] - ref[2]) / scale
            # the turn omega = w about the line through contact i: t_f = -w x b, t_tau = w
            t0, t1, t2 = w2 * b1 - w1 * b2, w0 * b2 - w2 * b0, w1 * b0 - w0 * b1
            size = max(1.0, abs(t0), abs(t1), abs(t2))
            for sense in (1.0, -1.0):
                worst = 0.0
                best = 0.0
                for c in range(k):
                    a0 = (points[c, 0] - ref[0]) / scale
                    a1 = (points[c, 1] - ref[1]) / scale
                    a2 = (points[c, 2] - ref[2]) / scale
                    g0 = sense * (t0 + w1 * a2 - w2 * a1)
                    g1 = sense * (t1 + w2 * a0 - w0 * a2)
                    g2 = sense * (t2 + w0 * a1 - w1 * a0)
                    n0, n1, n2 = normals[c, 0], normals[c, 1], normals[c, 2]
                    gn = g0 * n0 + g1 * n1 + g2 * n2
                    p0, p1, p2 = g0 - gn * n0, g1 - gn * n1, g2 - gn * n2
                    h = -gn - mu[c] * math.sqrt(p0 * p0 + p1 * p1 + p2 * p2)
                    if h < 0.0:
                        worst = max(worst, -h)
                    else:  # a unit wrench there has normal force >= this
                        arm = a0 * a0 + a1 * a1 + a2 * a2
                        best = max(best, h / math.sqrt((1.0 + arm) * (1.0 + mu[c] * mu[c])))
                delta = worst + 1e-13 * size  # round-off in g, h and the pyramids' edges
                if best > 0.0 and columns * delta <= 0.25 * tol * best:
                    return True
    return False


def fill_rim(rim: NDArray[np.float64], edges: int) -> None:
    """Write the cosines and sines of a ``edges``-edge pyramid's edge angles
    ``2 pi r / edges`` into ``rim[0, :edges]`` and ``rim[1, :edges]``.

    Plain scalar arithmetic, so the compiled kernels compile this very
    function (``math.cos`` is the C library's in both).

    Examples
    --------
    >>> rim = np.zeros((2, 4))
    >>> fill_rim(rim, 4)
    >>> np.round(rim, 12).tolist()
    [[1.0, 0.0, -1.0, -0.0], [0.0, 1.0, 0.0, -1.0]]
    """
    for r in range(edges):
        theta = 2.0 * np.pi * r / edges
        rim[0, r] = math.cos(theta)
        rim[1, r] = math.sin(theta)


@lru_cache(maxsize=64)
def pyramid_rim(edges: int) -> NDArray[np.float64]:
    """``(2, edges)``: cosines and sines of the pyramid's edge angles (:func:`fill_rim`).

    Examples
    --------
    >>> pyramid_rim(3).shape
    (2, 3)
    """
    rim = np.empty((2, edges))
    fill_rim(rim, edges)
    rim.setflags(write=False)
    return rim


def pyramid_divisor(edges: int, circumscribed: bool) -> float:
    """What ``mu`` is divided by for the pyramid's edge radius: 1 for the inscribed
    pyramid (edges on the circular cone), ``cos(pi / edges)`` for the circumscribed one
    (faces tangent to it).

    Examples
    --------
    >>> pyramid_divisor(8, False), round(pyramid_divisor(4, True) ** 2, 12)
    (1.0, 0.5)
    """
    return math.cos(math.pi / edges) if circumscribed else 1.0


def pyramid_radius(mu: float, edges: int, circumscribed: bool) -> float:
    """Distance of the pyramid's edges from the cone axis at unit normal force.

    Examples
    --------
    >>> round(pyramid_radius(0.5, 8, True), 6)   # mu / cos(pi/8)
    0.541196
    """
    return mu / pyramid_divisor(edges, circumscribed)


def friction_forces(normals: ArrayLike, radius: ArrayLike | None, edges: int = 8,
                    tangents: tuple[NDArray[np.float64], NDArray[np.float64]] | None = None,
                    ) -> NDArray[np.float64]:
    """The generating forces of friction cones, ``(N, g, d)``, with unit normal component.

    For outward normals ``(N, d)``: ``radius`` None gives the frictionless
    force ``-n`` (``g = 1``); in the plane ``-n + r t`` and ``-n - r t`` with
    ``t = (-n_y, n_x)`` (``g = 2``, exact); in space the ``edges`` edges
    ``-n + r (cos θ t1 + sin θ t2)`` of a pyramid (:func:`tangent_basis`,
    :func:`pyramid_rim`). ``radius`` (``(N,)`` or a number) is ``mu`` for the
    exact planar cone and the inscribed pyramid, :func:`pyramid_radius` for the
    circumscribed one. ``tangents`` (``(t1, t2)``, each ``(N, 3)``) orients
    spatial pyramids (e.g. :func:`grasp_tangents`); by default
    :func:`tangent_basis`.

    Examples
    --------
    >>> friction_forces(np.array([[0.0, 1.0]]), 0.5).tolist()
    [[[-0.5, -1.0], [0.5, -1.0]]]
    >>> f = friction_forces(np.array([[0.0, 0.0, 1.0]]), 0.5, edges=4)
    >>> (np.round(f[0], 12) + 0.0).tolist()   # t1 = -y, t2 = +x
    [[0.0, -0.5, -1.0], [0.5, 0.0, -1.0], [0.0, 0.5, -1.0], [-0.5, 0.0, -1.0]]
    """
    normals = np.asarray(normals, dtype=float)
    inward = -normals
    if radius is None:
        return inward[:, None, :]
    r = np.broadcast_to(np.asarray(radius, dtype=float), normals.shape[:1])[:, None, None]
    if normals.shape[-1] == 2:
        tangent = np.stack([-normals[:, 1], normals[:, 0]], axis=-1)
        return inward[:, None, :] + r * np.stack([tangent, -tangent], axis=1)
    t1, t2 = tangent_basis(normals) if tangents is None else tangents
    cos, sin = pyramid_rim(edges)
    rim = cos[None, :, None] * t1[:, None, :] + sin[None, :, None] * t2[:, None, :]
    return inward[:, None, :] + r * rim

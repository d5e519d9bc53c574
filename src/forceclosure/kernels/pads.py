"""Where flat pads touch a mesh, compiled: :func:`pad_extremes` (the first touch) and
:func:`pad_pressure` (the pressure of a pressed pad) and :func:`pad_nearest` (the
pressed point nearest a given point).

For each (pose, triangle) pair, with the triangle's corners in the pose's
jaw frame, the lowest and the highest ``y`` of the triangle clipped to the
pad's rectangle ``x ∈ [x0, x1]``, ``|z| ≤ h/2`` (:mod:`forceclosure.gripper.pads`
gives the geometry and the contact normal of each kind of
extreme). ``y`` is affine on the triangle, so both extremes lie at the
clipped polygon's corners: the triangle's vertices inside the rectangle
(kind 0), the rectangle's corners inside the triangle (kind 1), and the
crossings of the triangle's edges with the rectangle's sides (kind 2). All
are enumerated, none clipped; a pair whose triangle misses the rectangle
keeps ``inf``.
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["line_pairs", "minimum_at", "pad_extremes", "pad_lever", "pad_nearest",
           "pad_pressure", "pad_touch"]


@nb.njit(cache=True, nogil=True)
def minimum_at(out, index, values):  # pragma: no cover - compiled
    """``numpy.minimum.at(out, index, values)`` for 1-D or 2-D ``values``, compiled."""
    if values.ndim == 1:
        for i in range(len(index)):
            if values[i] < out[index[i]]:
                out[index[i]] = values[i]
    else:
        for i in range(len(index)):
            for j in range(values.shape[1]):
                if values[i, j] < out[index[i], j]:
                    out[index[i], j] = values[i, j]


@nb.njit(cache=True, nogil=True)
def _near(centroid, spread, origin, direction, radius, i, t):  # pragma: no cover
    """Whether triangle ``t``'s bounding sphere (``centroid``, ``spread``) comes within
    ``radius[i]`` of line ``i``."""
    d0 = centroid[t, 0] - origin[i, 0]
    d1 = centroid[t, 1] - origin[i, 1]
    d2 = centroid[t, 2] - origin[i, 2]
    along = d0 * direction[i, 0] + d1 * direction[i, 1] + d2 * direction[i, 2]
    reach = spread[t] + radius[i]
    return (d0 * d0 + d1 * d1 + d2 * d2) - along * along <= reach * reach


@nb.njit(cache=True, nogil=True)
def line_pairs(centroid, spread, origin, direction, radius):  # pragma: no cover - compiled
    """``(line, triangle)`` pairs, by line then triangle, of the triangles whose bounding
    spheres (``centroid``, ``spread``) come within ``radius[line]`` of each line (through
    ``origin[line]`` along the unit ``direction[line]``): counted, then filled, with no
    ``(lines, triangles)`` array in between."""
    n, T = len(origin), len(centroid)
    count = 0
    for i in range(n):
        for t in range(T):
            if _near(centroid, spread, origin, direction, radius, i, t):
                count += 1
    line = np.empty(count, np.int64)
    tri = np.empty(count, np.int64)
    k = 0
    for i in range(n):
        for t in range(T):
            if _near(centroid, spread, origin, direction, radius, i, t):
                line[k], tri[k] = i, t
                k += 1
    return line, tri


@nb.njit(cache=True, nogil=True)
def _in_pose(V, F, p, t, origin, R, out):  # pragma: no cover - compiled
    """Triangle ``t`` of the mesh ``(V, F)`` in pose ``p``'s frame (rotation ``R[p]`` about
    ``origin[p]``), written into the first three rows of ``out``."""
    for v in range(3):
        for k in range(3):
            acc = 0.0
            for j in range(3):
                acc += R[p, k, j] * (V[F[t, v], j] - origin[p, j])
            out[v, k] = acc


@nb.njit(cache=True, nogil=True)
def _extreme(V, F, p, t, origin, R, depth, length, h, P, cand):  # pragma: no cover
    """Pair ``(p, t)``'s lowest ``y`` and minus its highest under the pad (``inf``: the
    triangle misses the pad); ``P`` (3, 3: the triangle in the pose's frame, left there)
    and ``cand`` (19, 3) are scratch."""
    _in_pose(V, F, p, t, origin, R, P)
    return _extreme_of(P, depth[p], length, h, cand)


@nb.njit(cache=True, nogil=True)
def _extreme_of(P, x1, length, h, cand):  # pragma: no cover - compiled
    """:func:`_extreme` of the triangle ``P`` in the pose's frame, its tips at ``x1``."""
    a1 = x1
    a0 = x1 - length
    z0, z1 = -0.5 * h, 0.5 * h
    lo, hi = np.inf, np.inf
    if ((P[0, 0] < a0 and P[1, 0] < a0 and P[2, 0] < a0)
            or (P[0, 0] > a1 and P[1, 0] > a1 and P[2, 0] > a1)
            or (P[0, 2] < z0 and P[1, 2] < z0 and P[2, 2] < z0)
            or (P[0, 2] > z1 and P[1, 2] > z1 and P[2, 2] > z1)):
        return lo, hi  # the triangle misses the rectangle
    scale = 0.0
    for v in range(3):
        for k in range(3):
            scale = max(scale, abs(P[v, k]))
    eps = 1e-12 * (scale + 1.0)
    m = 0
    for v in range(3):  # vertices inside the rectangle
        x, z = P[v, 0], P[v, 2]
        if a0 - eps <= x <= a1 + eps and z0 - eps <= z <= z1 + eps:
            cand[m, 0], cand[m, 1], cand[m, 2] = x, P[v, 1], z
            m += 1
    ex1, ey1, ez1 = P[1, 0] - P[0, 0], P[1, 1] - P[0, 1], P[1, 2] - P[0, 2]
    ex2, ey2, ez2 = P[2, 0] - P[0, 0], P[2, 1] - P[0, 1], P[2, 2] - P[0, 2]
    det = ex1 * ez2 - ez1 * ex2
    big = max(abs(ex1), abs(ez1)) * max(abs(ex2), abs(ez2))
    if abs(det) > 1e-12 * big and big > 0:  # rectangle corners inside the triangle
        for c in range(4):
            cx = a0 if c < 2 else a1
            cz = z0 if c % 2 == 0 else z1
            dx, dz = cx - P[0, 0], cz - P[0, 2]
            u = (dx * ez2 - dz * ex2) / det
            w = (ex1 * dz - ez1 * dx) / det
            if u >= -1e-12 and w >= -1e-12 and u + w <= 1 + 1e-12:
                cand[m, 0], cand[m, 1], cand[m, 2] = cx, P[0, 1] + u * ey1 + w * ey2, cz
                m += 1
    for e in range(3):  # edges crossing the rectangle's sides
        j = (e + 1) % 3
        px, py, pz = P[e, 0], P[e, 1], P[e, 2]
        dx, dy, dz = P[j, 0] - px, P[j, 1] - py, P[j, 2] - pz
        for s in range(4):
            if s < 2:
                den, lev, start = dx, (a0 if s == 0 else a1), px
            else:
                den, lev, start = dz, (z0 if s == 2 else z1), pz
            if abs(den) <= 1e-300:
                continue
            u = (lev - start) / den
            if u < 0.0 or u > 1.0:
                continue
            qx, qy, qz = px + u * dx, py + u * dy, pz + u * dz
            within = (z0 - eps <= qz <= z1 + eps) if s < 2 else (a0 - eps <= qx <= a1 + eps)
            if within:
                cand[m, 0], cand[m, 1], cand[m, 2] = qx, qy, qz
                m += 1
    for c in range(m):
        lo = min(lo, cand[c, 1])
        hi = min(hi, -cand[c, 1])
    return lo, hi


@nb.njit(cache=True, nogil=True)
def pad_extremes(V, F, pose_of, tri_of, origin, R, depth, length, h
                 ):  # pragma: no cover - compiled
    """Per (pose, triangle) pair (``pose_of``, ``tri_of``; the mesh ``V``, ``F``; each
    pose's ``origin``, frame rows ``R`` and fingertip ``depth``; the pad's ``length``
    and height ``h``) and per jaw (0: the lowest ``y``, 1: the highest, stored as
    ``-y``) of the triangle under the pad (``inf``: it misses the pad)."""
    n = len(pose_of)
    value = np.full((n, 2), np.inf)
    P = np.empty((3, 3))
    cand = np.empty((19, 3))
    for i in range(n):
        value[i, 0], value[i, 1] = _extreme(V, F, pose_of[i], tri_of[i], origin, R, depth,
                                            length, h, P, cand)
    return value


#: Rows of the scratch polygons: a triangle clipped by the pad's four sides and the pressed
#: layer has at most 3 + 5 corners.
CORNERS = 8


@nb.njit(cache=True, nogil=True)
def _clip(poly, count, axis, level, keep_below, out):  # pragma: no cover - compiled
    """The convex polygon ``poly[:count]`` (3-D points) clipped to ``p[axis] <= level``
    (``keep_below``) or ``>= level``, written to ``out`` (at least ``count + 1`` rows):
    the new corners' count."""
    m = 0
    for k in range(count):
        j = (k + 1) % count
        dp = (level - poly[k, axis]) if keep_below else (poly[k, axis] - level)
        dq = (level - poly[j, axis]) if keep_below else (poly[j, axis] - level)
        if dp >= 0:
            for c in range(3):
                out[m, c] = poly[k, c]
            m += 1
        if (dp >= 0) != (dq >= 0):
            t = dp / (dp - dq)
            for c in range(3):
                out[m, c] = poly[k, c] + t * (poly[j, c] - poly[k, c])
            m += 1
    return m


@nb.njit(cache=True, nogil=True)
def _pressed(V, F, p, t, origin, R, depth, length, h, level, jaw, one, two
             ):  # pragma: no cover - compiled
    """Triangle ``t`` in pose ``p``'s frame, clipped to the pad's rectangle and the pressed
    layer, in the scratch polygons ``one`` and ``two`` (:data:`CORNERS` rows each): the
    polygon holding the corners and their count (0: none)."""
    _in_pose(V, F, p, t, origin, R, one)
    return _clipped(one, two, depth[p], length, h, level[p], jaw)


@nb.njit(cache=True, nogil=True)
def _clipped(one, two, x1, length, h, lev, jaw):  # pragma: no cover - compiled
    """The triangle ``one[:3]`` (in the pose's frame) clipped to the pad's rectangle (its
    tips at ``x1``) and the pressed layer at ``lev``, in ``one`` and ``two``: the polygon
    holding the corners and their count (0: none)."""
    if (jaw == 0 and one[0, 1] > lev and one[1, 1] > lev and one[2, 1] > lev) or (
            jaw == 1 and one[0, 1] < lev and one[1, 1] < lev and one[2, 1] < lev):
        return one, 0  # wholly beyond the pressed layer
    x0 = x1 - length
    m = _clip(one, 3, 0, x1, True, two)
    if m == 0:
        return two, 0
    m = _clip(two, m, 0, x0, False, one)
    if m == 0:
        return one, 0
    m = _clip(one, m, 2, 0.5 * h, True, two)
    if m == 0:
        return two, 0
    m = _clip(two, m, 2, -0.5 * h, False, one)
    if m == 0:
        return one, 0
    m = _clip(one, m, 1, lev, jaw == 0, two)
    return two, m


@nb.njit(cache=True, nogil=True)
def _pressure_of(cur, m, lev, jaw):  # pragma: no cover - compiled
    """The pressure's integral and x and z moments over the pressed polygon ``cur[:m]``
    (:func:`pad_pressure`)."""
    w0 = w1 = w2 = 0.0
    for k in range(1, m - 1):  # fan triangles; the penetration is affine on each
        a, b, c = cur[0], cur[k], cur[k + 1]
        area = 0.5 * abs((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]))
        if jaw == 0:
            da, db, dc = lev - a[1], lev - b[1], lev - c[1]
        else:
            da, db, dc = a[1] - lev, b[1] - lev, c[1] - lev
        sd = da + db + dc
        w0 += area * sd / 3.0
        w1 += area / 12.0 * (a[0] * da + b[0] * db + c[0] * dc + (a[0] + b[0] + c[0]) * sd)
        w2 += area / 12.0 * (a[2] * da + b[2] * db + c[2] * dc + (a[2] + b[2] + c[2]) * sd)
    return w0, w1, w2


@nb.njit(cache=True, nogil=True)
def pad_pressure(V, F, pose_of, tri_of, origin, R, depth, length, h, level, jaw
                 ):  # pragma: no cover - compiled
    """Per (pose, triangle) pair, the pad's pressure on the pressed part of the triangle
    as a uniform elastic layer (pressure proportional to the penetration past
    ``level[pose]``, over the pad's x-z area): its integral and its x and z moments."""
    n = len(pose_of)
    out = np.zeros((n, 3))
    one, two = np.empty((CORNERS, 3)), np.empty((CORNERS, 3))
    for i in range(n):
        cur, m = _pressed(V, F, pose_of[i], tri_of[i], origin, R, depth, length, h, level,
                          jaw, one, two)
        if m < 3:
            continue
        out[i, 0], out[i, 1], out[i, 2] = _pressure_of(cur, m, level[pose_of[i]], jaw)
    return out


@nb.njit(cache=True, nogil=True)
def _nearest_of(cur, m, cx, cz):  # pragma: no cover - compiled
    """The point of the pressed polygon ``cur[:m]`` (``m`` > 0) nearest ``(cx, cz)`` in the
    x-z plane: that squared distance (inf: none) and the point (:func:`pad_nearest`)."""
    dist, px, py, pz = np.inf, 0.0, 0.0, 0.0
    # the centre inside the polygon's x-z projection: the polygon's point above it
    inside = m >= 3
    sgn = 0.0
    for k in range(m):
        a, b = cur[k], cur[(k + 1) % m]
        cr = (b[0] - a[0]) * (cz - a[2]) - (b[2] - a[2]) * (cx - a[0])
        if abs(cr) <= 1e-15 * (abs(b[0] - a[0]) + abs(b[2] - a[2]) + 1e-300):
            continue
        if sgn == 0.0:
            sgn = 1.0 if cr > 0 else -1.0
        elif (cr > 0) != (sgn > 0):
            inside = False
            break
    if inside and sgn != 0.0:
        a, b, c = cur[0], cur[1], cur[2]
        best_area = 0.0
        for k in range(1, m - 1):  # the widest fan triangle: a well-conditioned plane
            e1x, e1z = cur[k][0] - a[0], cur[k][2] - a[2]
            e2x, e2z = cur[k + 1][0] - a[0], cur[k + 1][2] - a[2]
            area = abs(e1x * e2z - e1z * e2x)
            if area > best_area:
                best_area, b, c = area, cur[k], cur[k + 1]
        e1x, e1y, e1z = b[0] - a[0], b[1] - a[1], b[2] - a[2]
        e2x, e2y, e2z = c[0] - a[0], c[1] - a[1], c[2] - a[2]
        det = e1x * e2z - e1z * e2x
        if det != 0.0:
            dx, dz = cx - a[0], cz - a[2]
            u = (dx * e2z - dz * e2x) / det
            w = (e1x * dz - e1z * dx) / det
            return 0.0, cx, a[1] + u * e1y + w * e2y, cz
    for k in range(m):  # else the nearest point of the polygon's edges
        a, b = cur[k], cur[(k + 1) % m]
        ex, ez = b[0] - a[0], b[2] - a[2]
        ll = ex * ex + ez * ez
        s = 0.0 if ll == 0.0 else min(1.0, max(0.0, ((cx - a[0]) * ex + (cz - a[2]) * ez)
                                               / ll))
        qx, qz = a[0] + s * ex, a[2] + s * ez
        d = (qx - cx) ** 2 + (qz - cz) ** 2
        if d < dist:
            dist, px, py, pz = d, qx, a[1] + s * (b[1] - a[1]), qz
    return dist, px, py, pz


@nb.njit(cache=True, nogil=True)
def pad_nearest(V, F, pose_of, tri_of, origin, R, depth, length, h, level, jaw, centre
                ):  # pragma: no cover - compiled
    """Per (pose, triangle) pair, the point of the triangle under the pad and within the
    pressed layer (``y <= level[pose]`` for jaw 0, ``y >= level[pose]`` for jaw 1) nearest
    ``centre[pose]`` (x, z) in the x-z plane: that squared distance (inf: none) and the
    point, in the pose's frame."""
    n = len(pose_of)
    dist = np.full(n, np.inf)
    point = np.zeros((n, 3))
    one, two = np.empty((CORNERS, 3)), np.empty((CORNERS, 3))
    for i in range(n):
        p = pose_of[i]
        cur, m = _pressed(V, F, p, tri_of[i], origin, R, depth, length, h, level, jaw, one,
                          two)
        if m == 0:
            continue
        dist[i], point[i, 0], point[i, 1], point[i, 2] = _nearest_of(cur, m, centre[p, 0],
                                                                      centre[p, 1])
    return dist, point


@nb.njit(cache=True, nogil=True)
def _lever_part(a, b, c, da, db, dc, cx, cy, cz, nx, ny, nz):  # pragma: no cover
    """Pressure (``da, db, dc`` at the corners, affine) times the distance of its centre
    from the axis through ``(cx, cy, cz)`` along the unit ``n``, over the x-z area of the
    triangle ``abc``: a lower bound of the pressure-weighted distance (Jensen)."""
    area = 0.5 * abs((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]))
    sd = da + db + dc
    w = area * sd / 3.0
    if w <= 0.0:
        return 0.0
    k = area / 12.0 / w
    vx = k * (a[0] * da + b[0] * db + c[0] * dc + (a[0] + b[0] + c[0]) * sd) - cx
    vy = k * (a[1] * da + b[1] * db + c[1] * dc + (a[1] + b[1] + c[1]) * sd) - cy
    vz = k * (a[2] * da + b[2] * db + c[2] * dc + (a[2] + b[2] + c[2]) * sd) - cz
    along = vx * nx + vy * ny + vz * nz
    vx, vy, vz = vx - along * nx, vy - along * ny, vz - along * nz
    return w * np.sqrt(vx * vx + vy * vy + vz * vz)


#: The four pieces of a triangle split at its edges' midpoints (corners a, b, c as 0, 1, 2;
#: midpoints ab, bc, ca as 3, 4, 5): (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca).
SPLIT = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])


@nb.njit(cache=True, nogil=True)
def _lever_of(cur, m, lev, jaw, cx, cy, cz, nx, ny, nz, splits, tri, dep, nxt, ndep, six,
              sixd):  # pragma: no cover - compiled
    """The pressure-weighted distance of the pressed polygon ``cur[:m]`` (``m`` >= 3) from
    the axis along ``n`` through ``c`` (:func:`pad_lever`); the rest are scratch arrays
    (``4 ** splits`` pieces; six corners)."""
    out = 0.0
    for f in range(1, m - 1):
        for c in range(3):
            tri[0, 0, c], tri[0, 1, c], tri[0, 2, c] = cur[0, c], cur[f, c], cur[f + 1, c]
        for v in range(3):
            dep[0, v] = (lev - tri[0, v, 1]) if jaw == 0 else (tri[0, v, 1] - lev)
        count = 1
        for _ in range(splits):
            made = 0
            for t in range(count):
                for c in range(3):
                    six[0, c], six[1, c], six[2, c] = tri[t, 0, c], tri[t, 1, c], tri[t, 2, c]
                    six[3, c] = 0.5 * (tri[t, 0, c] + tri[t, 1, c])
                    six[4, c] = 0.5 * (tri[t, 1, c] + tri[t, 2, c])
                    six[5, c] = 0.5 * (tri[t, 2, c] + tri[t, 0, c])
                sixd[0], sixd[1], sixd[2] = dep[t, 0], dep[t, 1], dep[t, 2]
                sixd[3] = 0.5 * (dep[t, 0] + dep[t, 1])
                sixd[4] = 0.5 * (dep[t, 1] + dep[t, 2])
                sixd[5] = 0.5 * (dep[t, 2] + dep[t, 0])
                for q in range(4):
                    for v in range(3):
                        for c in range(3):
                            nxt[made, v, c] = six[SPLIT[q, v], c]
                        ndep[made, v] = sixd[SPLIT[q, v]]
                    made += 1
            for t in range(made):
                for v in range(3):
                    for c in range(3):
                        tri[t, v, c] = nxt[t, v, c]
                    dep[t, v] = ndep[t, v]
            count = made
        for t in range(count):
            out += _lever_part(tri[t, 0], tri[t, 1], tri[t, 2], dep[t, 0], dep[t, 1],
                               dep[t, 2], cx, cy, cz, nx, ny, nz)
    return out


@nb.njit(cache=True, nogil=True)
def pad_lever(V, F, pose_of, tri_of, origin, R, depth, length, h, level, jaw, contact, axis,
              splits):  # pragma: no cover - compiled
    """Per (pose, triangle) pair, the pressure-weighted distance of the pressed part of the
    triangle from the axis of ``axis[pose]`` through ``contact[pose]`` (both in the pose's
    frame), from below: each fan triangle of the pressed polygon split ``splits`` times
    into four, each piece's pressure centre standing for its points (the distance is
    convex: Jensen). Divided by the pressure's integral it is the pad's torsional lever."""
    n = len(pose_of)
    out = np.zeros(n)
    pieces = 4**splits
    tri, dep = np.empty((pieces, 3, 3)), np.empty((pieces, 3))
    nxt, ndep = np.empty((pieces, 3, 3)), np.empty((pieces, 3))
    one, two = np.empty((CORNERS, 3)), np.empty((CORNERS, 3))
    six, sixd = np.empty((6, 3)), np.empty(6)
    for i in range(n):
        p = pose_of[i]
        cur, m = _pressed(V, F, p, tri_of[i], origin, R, depth, length, h, level, jaw, one,
                          two)
        if m < 3:
            continue
        out[i] = _lever_of(cur, m, level[p], jaw, contact[p, 0], contact[p, 1], contact[p, 2],
                           axis[p, 0], axis[p, 1], axis[p, 2], splits, tri, dep, nxt, ndep,
                           six, sixd)
    return out


@nb.njit(cache=True, nogil=True)
def pad_touch(V, F, FN, starts, tri_of, origin, R, closing, depth, length, h, press, levers,
              splits, block):  # pragma: no cover - compiled
    """:func:`forceclosure.gripper.pads.pad_contacts` in one compiled pass over the poses:
    pose ``p``'s candidate triangles are ``tri_of[starts[p]:starts[p + 1]]``. Per pose,
    the first touch (:func:`pad_extremes`), then per jaw the pressed polygons (clipped
    once), the pressure's centre (:func:`pad_pressure`), its nearest pressed point
    (:func:`pad_nearest`) and, with ``levers``, the torsional lever (:func:`pad_lever`).
    Sums and ties are taken as the batched kernels take them over pairs in blocks of
    ``block`` (sums restart at each block; the last least distance of the first block
    holding one wins), so the results are theirs to the bit.

    Returns the contacts' ``points``, ``normals`` and ``triangles``, ``touched``, the
    first touches (``first``) and the ``lever``s, as
    :class:`~forceclosure.gripper.pads.PadContacts` holds them.
    """
    m = len(starts) - 1
    points = np.zeros((m, 2, 3))
    normals = np.zeros((m, 2, 3))
    triangles = np.full((m, 2), -1, np.int64)
    lever = np.zeros((m, 2))
    first = np.full((m, 2), np.inf)
    cand = np.empty((19, 3))
    most = 0
    for p in range(m):
        most = max(most, starts[p + 1] - starts[p])
    local = np.empty((most, 3, 3))  # the pose's triangles in its frame
    touched = np.empty(m, np.bool_)
    one, two = np.empty((CORNERS, 3)), np.empty((CORNERS, 3))
    poly = np.empty((most, CORNERS, 3))
    count = np.empty(most, np.int64)
    tri = np.empty(most, np.int64)
    at = np.empty(most, np.int64)
    dist = np.empty(most)
    near = np.empty((most, 3))
    pieces = 4**splits
    ltri, ldep = np.empty((pieces, 3, 3)), np.empty((pieces, 3))
    lnxt, lndep = np.empty((pieces, 3, 3)), np.empty((pieces, 3))
    six, sixd = np.empty((6, 3)), np.empty(6)
    place = np.zeros(2, np.int64)  # per pad, the pairs facing it so far (the batches' blocks)
    lc, la = np.empty(3), np.empty(3)  # the contact and its normal in the pose's frame
    for p in range(m):
        for k in range(starts[p], starts[p + 1]):
            lo, hi = _extreme(V, F, p, tri_of[k], origin, R, depth, length, h,
                              local[k - starts[p]], cand)
            if lo < first[p, 0]:
                first[p, 0] = lo
            if hi < first[p, 1]:
                first[p, 1] = hi
        touched[p] = np.isfinite(first[p, 0]) and np.isfinite(first[p, 1])
        for jaw in range(2):
            lev = ((first[p, jaw] + press) if touched[p] else 0.0) * (1.0 if jaw == 0 else -1.0)
            j = place[jaw]
            q = 0
            for k in range(starts[p], starts[p + 1]):
                t = tri_of[k]
                facing = FN[t, 0] * closing[p, 0] + FN[t, 1] * closing[p, 1] \
                    + FN[t, 2] * closing[p, 2]
                if (jaw == 0 and not facing < 0) or (jaw == 1 and not facing > 0):
                    continue
                for r in range(3):
                    for u in range(3):
                        one[r, u] = local[k - starts[p], r, u]
                cur, c = _clipped(one, two, depth[p], length, h, lev, jaw)
                for r in range(c):
                    for u in range(3):
                        poly[q, r, u] = cur[r, u]
                count[q], tri[q], at[q] = c, t, j
                q += 1
                j += 1
            place[jaw] = j
            # the pressure's integral and moments, summed block by block
            w0 = w1 = w2 = 0.0
            s0 = s1 = s2 = 0.0
            now = -1
            for i in range(q):
                b = at[i] // block
                if b != now:
                    if now >= 0:
                        w0, w1, w2 = w0 + s0, w1 + s1, w2 + s2
                    s0 = s1 = s2 = 0.0
                    now = b
                if count[i] >= 3:
                    a0, a1, a2 = _pressure_of(poly[i], count[i], lev, jaw)
                    s0, s1, s2 = s0 + a0, s1 + a1, s2 + a2
            if now >= 0:
                w0, w1, w2 = w0 + s0, w1 + s1, w2 + s2
            loaded = w0 > 0
            if loaded:
                cx, cz = w1 / w0, w2 / w0
            else:
                cx, cz = depth[p] - 0.5 * length, 0.0
            # the pressed point nearest that centre: the last least of the first block
            best = np.inf
            for i in range(q):
                dist[i] = np.inf
                if count[i] > 0:
                    dist[i], near[i, 0], near[i, 1], near[i, 2] = _nearest_of(
                        poly[i], count[i], cx, cz)
                if dist[i] < best:
                    best = dist[i]
            win, where = -1, -1
            for i in range(q):
                if np.isfinite(dist[i]) and dist[i] <= best:
                    b = at[i] // block
                    if where < 0 or b == where:
                        win, where = i, b
            if win >= 0:
                for s in range(3):
                    points[p, jaw, s] = origin[p, s] + (R[p, 0, s] * near[win, 0]
                                                        + R[p, 1, s] * near[win, 1]
                                                        + R[p, 2, s] * near[win, 2])
                    normals[p, jaw, s] = FN[tri[win], s]
                triangles[p, jaw] = tri[win]
            if not levers:
                continue
            for s in range(3):  # in NumPy's einsum's order (0 + 2) + 1, to the bit
                lc[s] = (R[p, s, 0] * (points[p, jaw, 0] - origin[p, 0])
                         + R[p, s, 2] * (points[p, jaw, 2] - origin[p, 2])) \
                    + R[p, s, 1] * (points[p, jaw, 1] - origin[p, 1])
                la[s] = (R[p, s, 0] * normals[p, jaw, 0] + R[p, s, 2] * normals[p, jaw, 2]) \
                    + R[p, s, 1] * normals[p, jaw, 1]
            total = part = 0.0
            now = -1
            for i in range(q):
                b = at[i] // block
                if b != now:
                    if now >= 0:
                        total += part
                    part = 0.0
                    now = b
                if count[i] >= 3:
                    part += _lever_of(poly[i], count[i], lev, jaw, lc[0], lc[1], lc[2],
                                      la[0], la[1], la[2], splits, ltri, ldep, lnxt, lndep,
                                      six, sixd)
            if now >= 0:
                total += part
            lever[p, jaw] = total / w0 if loaded else 0.0
    for p in range(m):
        touched[p] = touched[p] and triangles[p, 0] >= 0 and triangles[p, 1] >= 0
        if touched[p]:
            first[p, 1] = -first[p, 1]
        else:
            first[p, 0] = first[p, 1] = 0.0
    return points, normals, triangles, touched, first, lever

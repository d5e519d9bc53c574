"""Where flat pads touch a mesh, compiled: :func:`pad_extremes` (the first touch) and
:func:`pad_pressure` (the pressure of a pressed pad) and :func:`pad_nearest` (the
pressed point nearest a given point).

For each (pose, triangle) pair, with the triangle's corners in the pose's
jaw frame, the lowest and the highest ``y`` of the triangle clipped to the
pad's rectangle ``x ∈ [x0, x1]``, ``|z| ≤ h/2`` (:mod:`forceclosure.
gripper.pads` gives the geometry and the contact normal of each kind of
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
           "pad_pressure"]


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
def pad_extremes(V, F, pose_of, tri_of, origin, R, depth, length, h
                 ):  # pragma: no cover - compiled
    """Per (pose, triangle) pair (``pose_of``, ``tri_of``; the mesh ``V``, ``F``; each
    pose's ``origin``, frame rows ``R`` and fingertip ``depth``; the pad's ``length``
    and height ``h``) and per jaw (0: the lowest ``y``, 1: the highest, stored as
    ``-y``) of the triangle under the pad (``inf``: it misses the pad)."""
    n = len(pose_of)
    P = np.empty((n, 3, 3))
    x0 = np.empty(n)
    x1 = np.empty(n)
    for i in range(n):
        p, t = pose_of[i], tri_of[i]
        x1[i] = depth[p]
        x0[i] = depth[p] - length
        for v in range(3):
            for k in range(3):
                acc = 0.0
                for j in range(3):
                    acc += R[p, k, j] * (V[F[t, v], j] - origin[p, j])
                P[i, v, k] = acc
    value = np.full((n, 2), np.inf)
    z0, z1 = -0.5 * h, 0.5 * h
    cand = np.empty((19, 3))
    for i in range(n):
        a0, a1 = x0[i], x1[i]
        if ((P[i, 0, 0] < a0 and P[i, 1, 0] < a0 and P[i, 2, 0] < a0)
                or (P[i, 0, 0] > a1 and P[i, 1, 0] > a1 and P[i, 2, 0] > a1)
                or (P[i, 0, 2] < z0 and P[i, 1, 2] < z0 and P[i, 2, 2] < z0)
                or (P[i, 0, 2] > z1 and P[i, 1, 2] > z1 and P[i, 2, 2] > z1)):
            continue  # the triangle misses the rectangle
        scale = 0.0
        for v in range(3):
            for k in range(3):
                scale = max(scale, abs(P[i, v, k]))
        eps = 1e-12 * (scale + 1.0)
        m = 0
        for v in range(3):  # vertices inside the rectangle
            x, z = P[i, v, 0], P[i, v, 2]
            if a0 - eps <= x <= a1 + eps and z0 - eps <= z <= z1 + eps:
                cand[m, 0], cand[m, 1], cand[m, 2] = x, P[i, v, 1], z
                m += 1
        ex1, ey1, ez1 = P[i, 1, 0] - P[i, 0, 0], P[i, 1, 1] - P[i, 0, 1], P[i, 1, 2] - P[i, 0, 2]
        ex2, ey2, ez2 = P[i, 2, 0] - P[i, 0, 0], P[i, 2, 1] - P[i, 0, 1], P[i, 2, 2] - P[i, 0, 2]
        det = ex1 * ez2 - ez1 * ex2
        big = max(abs(ex1), abs(ez1)) * max(abs(ex2), abs(ez2))
        if abs(det) > 1e-12 * big and big > 0:  # rectangle corners inside the triangle
            for c in range(4):
                cx = a0 if c < 2 else a1
                cz = z0 if c % 2 == 0 else z1
                dx, dz = cx - P[i, 0, 0], cz - P[i, 0, 2]
                u = (dx * ez2 - dz * ex2) / det
                w = (ex1 * dz - ez1 * dx) / det
                if u >= -1e-12 and w >= -1e-12 and u + w <= 1 + 1e-12:
                    cand[m, 0], cand[m, 1], cand[m, 2] = cx, P[i, 0, 1] + u * ey1 + w * ey2, cz
                    m += 1
        for e in range(3):  # edges crossing the rectangle's sides
            j = (e + 1) % 3
            px, py, pz = P[i, e, 0], P[i, e, 1], P[i, e, 2]
            dx, dy, dz = P[i, j, 0] - px, P[i, j, 1] - py, P[i, j, 2] - pz
            for s in range(4):
                if s < 2:
                    den, lev, start = dx, (a0 if s == 0 else a1), px
                else:
                    den, lev, start = dz, (z0 if s == 2 else z1), pz
                if abs(den) <= 1e-300:
                    continue
                t = (lev - start) / den
                if t < 0.0 or t > 1.0:
                    continue
                qx, qy, qz = px + t * dx, py + t * dy, pz + t * dz
                within = (z0 - eps <= qz <= z1 + eps) if s < 2 else (a0 - eps <= qx <= a1 + eps)
                if within:
                    cand[m, 0], cand[m, 1], cand[m, 2] = qx, qy, qz
                    m += 1
        for c in range(m):
            value[i, 0] = min(value[i, 0], cand[c, 1])
            value[i, 1] = min(value[i, 1], -cand[c, 1])
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
    for v in range(3):
        for k in range(3):
            acc = 0.0
            for j in range(3):
                acc += R[p, k, j] * (V[F[t, v], j] - origin[p, j])
            one[v, k] = acc
    lev = level[p]
    if (jaw == 0 and one[0, 1] > lev and one[1, 1] > lev and one[2, 1] > lev) or (
            jaw == 1 and one[0, 1] < lev and one[1, 1] < lev and one[2, 1] < lev):
        return one, 0  # wholly beyond the pressed layer
    x1 = depth[p]
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
        lev = level[pose_of[i]]
        for k in range(1, m - 1):  # fan triangles; the penetration is affine on each
            a, b, c = cur[0], cur[k], cur[k + 1]
            area = 0.5 * abs((b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]))
            if jaw == 0:
                da, db, dc = lev - a[1], lev - b[1], lev - c[1]
            else:
                da, db, dc = a[1] - lev, b[1] - lev, c[1] - lev
            sd = da + db + dc
            out[i, 0] += area * sd / 3.0
            out[i, 1] += area / 12.0 * (a[0] * da + b[0] * db + c[0] * dc
                                         + (a[0] + b[0] + c[0]) * sd)
            out[i, 2] += area / 12.0 * (a[2] * da + b[2] * db + c[2] * dc
                                         + (a[2] + b[2] + c[2]) * sd)
    return out


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
        cx, cz = centre[p, 0], centre[p, 1]
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
                dist[i] = 0.0
                point[i, 0], point[i, 1], point[i, 2] = cx, a[1] + u * e1y + w * e2y, cz
                continue
        for k in range(m):  # else the nearest point of the polygon's edges
            a, b = cur[k], cur[(k + 1) % m]
            ex, ez = b[0] - a[0], b[2] - a[2]
            ll = ex * ex + ez * ez
            s = 0.0 if ll == 0.0 else min(1.0, max(0.0, ((cx - a[0]) * ex + (cz - a[2]) * ez)
                                                   / ll))
            qx, qz = a[0] + s * ex, a[2] + s * ez
            d = (qx - cx) ** 2 + (qz - cz) ** 2
            if d < dist[i]:
                dist[i] = d
                point[i, 0] = qx
                point[i, 1] = a[1] + s * (b[1] - a[1])
                point[i, 2] = qz
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
    tri = np.empty((pieces, 3, 3))
    dep = np.empty((pieces, 3))
    nxt = np.empty((pieces, 3, 3))
    ndep = np.empty((pieces, 3))
    one, two = np.empty((CORNERS, 3)), np.empty((CORNERS, 3))
    # the four pieces of a triangle (corners a, b, c; midpoints ab, bc, ca as 3, 4, 5):
    # (a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)
    split = np.array([[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]])
    six = np.empty((6, 3))
    sixd = np.empty(6)
    for i in range(n):
        p = pose_of[i]
        cur, m = _pressed(V, F, p, tri_of[i], origin, R, depth, length, h, level, jaw, one,
                          two)
        if m < 3:
            continue
        lev = level[p]
        cx, cy, cz = contact[p, 0], contact[p, 1], contact[p, 2]
        nx, ny, nz = axis[p, 0], axis[p, 1], axis[p, 2]
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
                                nxt[made, v, c] = six[split[q, v], c]
                            ndep[made, v] = sixd[split[q, v]]
                        made += 1
                for t in range(made):
                    for v in range(3):
                        for c in range(3):
                            tri[t, v, c] = nxt[t, v, c]
                        dep[t, v] = ndep[t, v]
                count = made
            for t in range(count):
                out[i] += _lever_part(tri[t, 0], tri[t, 1], tri[t, 2], dep[t, 0], dep[t, 1],
                                      dep[t, 2], cx, cy, cz, nx, ny, nz)
    return out

"""The wrench hull compiled: how far its boundary is from the origin.

Ferrari–Canny's epsilon is the distance from the origin to the nearest facet
of the convex hull of a grasp's wrenches. Qhull cannot be called from
compiled code, so :func:`hull_radius` builds the hull itself, by the
beneath–beyond method: a first simplex, then one point at a time, each
replacing the facets it sees by the cone from the point over their horizon.
Facets are ``d``-vertex simplices that know their neighbour across each ridge.
A new facet's neighbour across its horizon ridge is the facet that stays;
across the others, the new facet found by turning about that sub-ridge
through the facets being removed, so no search is needed. A new facet's
hyperplane comes from the pencil of the two it replaces along the ridge.

Points within ``COPLANAR`` of a facet's hyperplane count as inside. The hull
is accepted only after a check independent of how it was built: every
facet's neighbour links are mutual (a closed surface) and no point lies
outside any facet's hyperplane by more than ``CHECK``. Each facet then lies
on the boundary of the true hull, and a closed surface of them covers it, so
the nearest facet is the true one to ``CHECK``. A hull that fails the check
(degenerate, nearly flat, or a broken surface from round-off) gives NaN and
the caller falls back to Qhull.
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np

__all__ = ["CHECK", "COPLANAR", "FLAT", "hull_radius"]

#: A point this close to a facet's hyperplane does not see the facet.
COPLANAR = 1e-11
#: Largest distance of a point outside an accepted hull's facet (relative to the points' size).
CHECK = 1e-9
#: A first simplex flatter than this (relative) means the points span less than ``R^d``.
FLAT = 1e-9


@nb.njit(cache=True, nogil=True)
def _reject(v, basis, k):  # pragma: no cover - compiled
    """``v`` less its projection on the first ``k`` rows of ``basis`` (orthonormal); ``|v|^2``.

    Modified Gram–Schmidt, done twice ("twice is enough" for orthogonality).
    """
    d = v.shape[0]
    for _ in range(2):
        for r in range(k):
            dot = 0.0
            for j in range(d):
                dot += v[j] * basis[r, j]
            for j in range(d):
                v[j] -= dot * basis[r, j]
    length = 0.0
    for j in range(d):
        length += v[j] ** 2
    return length


@nb.njit(cache=True, nogil=True)
def _plane(X, verts, f, inner, normal):  # pragma: no cover - compiled
    """Unit normal (pointing away from ``inner``) and offset of the hyperplane through facet ``f``.

    Writes ``normal[f]`` from the points ``X[verts[f]]``: the edge vectors
    from the first vertex made orthonormal (:func:`_reject`), then the
    coordinate axis with the largest remainder; returns the offset, or NaN
    if the vertices are affinely dependent.
    """
    d = X.shape[1]
    Q = np.empty((d - 1, d))
    x0 = X[verts[f, 0]]
    for i in range(d - 1):
        scale = 0.0
        for j in range(d):
            Q[i, j] = X[verts[f, i + 1], j] - x0[j]
            scale += Q[i, j] ** 2
        length = math.sqrt(_reject(Q[i], Q, i))
        if length <= FLAT * math.sqrt(scale) or length == 0.0:
            return np.nan
        for j in range(d):
            Q[i, j] /= length
    best = -1.0
    for axis in range(d):  # the axis least in the facet's span gives the best-conditioned normal
        rest = 1.0
        for r in range(d - 1):
            rest -= Q[r, axis] ** 2
        if rest > best:
            best = rest
            for j in range(d):
                normal[f, j] = 1.0 if j == axis else 0.0
    length = math.sqrt(_reject(normal[f], Q, d - 1))
    side = 0.0
    offset = 0.0
    for j in range(d):
        normal[f, j] /= length
        side += normal[f, j] * (inner[j] - x0[j])
    if side > 0.0:
        for j in range(d):
            normal[f, j] = -normal[f, j]
    for i in range(d):
        for j in range(d):
            offset += normal[f, j] * X[verts[f, i], j]
    return offset / d


@nb.njit(cache=True, nogil=True)
def _through(X, verts, h, f, g, p, size, inner, normal, offset):  # pragma: no cover - compiled
    """Hyperplane of the new facet ``h``: the ridge of ``f`` and ``g``, and the point ``p``.

    It belongs to the pencil of the two facets' hyperplanes through their
    ridge: ``dist_f(p) H_g - dist_g(p) H_f``, a combination with
    non-negative weights, so it faces outward — ``d`` operations instead of
    :func:`_plane`'s ``d**3``. Taken only if it meets the facet's own
    vertices to ``COPLANAR`` and keeps ``inner`` inside; else :func:`_plane`.
    """
    d = X.shape[1]
    a = -offset[f]
    b = offset[g]
    for j in range(d):
        a += normal[f, j] * X[p, j]
        b -= normal[g, j] * X[p, j]
    length = 0.0
    for j in range(d):
        normal[h, j] = a * normal[g, j] + b * normal[f, j]
        length += normal[h, j] ** 2
    length = math.sqrt(length)
    if length > 0.1 * (a + b):
        mean = 0.0
        for j in range(d):
            normal[h, j] /= length
        low, high = np.inf, -np.inf
        for i in range(d):
            v = 0.0
            for j in range(d):
                v += normal[h, j] * X[verts[h, i], j]
            low, high = min(low, v), max(high, v)
            mean += v
        mean /= d
        side = -mean
        for j in range(d):
            side += normal[h, j] * inner[j]
        if high - low <= COPLANAR * size and side < 0.0:
            return mean
    return _plane(X, verts, h, inner, normal)


@nb.njit(cache=True, nogil=True)
def _first_simplex(X, m, chosen):  # pragma: no cover - compiled
    """``d + 1`` points spanning the most room, greedily; False if the points are flat."""
    d = X.shape[1]
    basis = np.empty((d, d))
    size = 0.0
    far = 0
    for i in range(m):
        r = 0.0
        for j in range(d):
            r += X[i, j] ** 2
        if r > size:
            size = r
            far = i
    chosen[0] = far
    size = math.sqrt(size)
    rest = np.empty(d)
    for k in range(1, d + 1):
        best = -1.0
        for i in range(m):  # the point farthest from the flat of those chosen
            for j in range(d):
                rest[j] = X[i, j] - X[far, j]
            length = _reject(rest, basis, k - 1)
            if length > best:
                best = length
                chosen[k] = i
                basis[k - 1] = rest
        best = math.sqrt(best)
        if best <= FLAT * max(size, 1e-300):
            return False
        for j in range(d):
            basis[k - 1, j] /= best
    return True


@nb.njit(cache=True, nogil=True)
def _slot(table, f, value):  # pragma: no cover - compiled
    """Where ``value`` sits in row ``f`` of ``table`` (-1 if absent)."""
    for i in range(table.shape[1]):
        if table[f, i] == value:
            return i
    return -1


@nb.njit(cache=True, nogil=True)
def hull_radius(X, m):  # pragma: no cover - compiled
    """Distance from the origin to the nearest facet of the hull of ``X[:m]`` (rows are points).

    Returns the (signed) distance: positive when the origin is inside the
    hull; NaN when the hull could not be built and checked here.

    Examples
    --------
    The cube ``[-1, 1]^3`` (each square face two coplanar triangles) and the
    same cube moved so that the origin is 3 outside a face:

    >>> import itertools, numpy as np
    >>> cube = np.array(list(itertools.product([-1.0, 1.0], repeat=3)))
    >>> round(hull_radius(cube, 8), 12), round(hull_radius(cube + [4.0, 0, 0], 8), 12)
    (1.0, -3.0)
    """
    d = X.shape[1]
    if m < d + 1:
        return np.nan
    size = 0.0
    for i in range(m):
        for j in range(d):
            size = max(size, abs(X[i, j]))
    chosen = np.empty(d + 1, dtype=np.int64)
    if size == 0.0 or not _first_simplex(X, m, chosen):
        return np.nan
    inner = np.zeros(d)
    for i in range(d + 1):
        for j in range(d):
            inner[j] += X[chosen[i], j] / (d + 1)

    cap = 64
    verts = np.empty((cap, d), dtype=np.int64)
    nbr = np.empty((cap, d), dtype=np.int64)
    normal = np.empty((cap, d))
    offset = np.empty(cap)
    alive = np.zeros(cap, dtype=np.bool_)
    seen = np.full(cap, -1, dtype=np.int64)  # the point that last saw the facet
    newf = np.empty((cap, d), dtype=np.int64)  # new facet over the ridge, for seen facets
    free = np.empty(cap, dtype=np.int64)
    n_free = 0

    for f in range(d + 1):  # facet f of the first simplex leaves out chosen[f]
        k = 0
        for i in range(d + 1):
            if i != f:
                verts[f, k] = chosen[i]
                nbr[f, k] = i  # the facet across leaves out chosen[i] too
                k += 1
        offset[f] = _plane(X, verts, f, inner, normal)
        if math.isnan(offset[f]):
            return np.nan
        alive[f] = True
    top = d + 1

    in_simplex = np.zeros(m, dtype=np.bool_)
    for i in range(d + 1):
        in_simplex[chosen[i]] = True
    # farthest points first: they are the likeliest vertices, and inner points then see nothing
    reach = np.empty(m)
    for i in range(m):
        r = 0.0
        for j in range(d):
            r += (X[i, j] - inner[j]) ** 2
        reach[i] = -r
    order = np.argsort(reach)
    visible = np.empty(cap, dtype=np.int64)
    made = np.empty((cap, 2), dtype=np.int64)  # new facet -> (seen facet, slot)

    for p in order:
        if in_simplex[p]:
            continue
        n_vis = 0
        for f in range(top):
            if alive[f]:
                dist = -offset[f]
                for j in range(d):
                    dist += normal[f, j] * X[p, j]
                if dist > COPLANAR * size:
                    if n_vis == visible.shape[0]:
                        visible = np.concatenate((visible, np.empty(n_vis, dtype=np.int64)))
                    visible[n_vis] = f
                    n_vis += 1
                    seen[f] = p
        if n_vis == 0:
            continue
        n_made = 0
        for a in range(n_vis):  # a new facet over every horizon ridge
            f = visible[a]
            for j in range(d):
                g = nbr[f, j]
                if seen[g] == p:
                    continue
                if n_free > 0:
                    n_free -= 1
                    h = free[n_free]
                else:
                    if top == cap:  # grow every per-facet array
                        cap *= 2
                        verts = np.concatenate((verts, np.empty_like(verts)))
                        nbr = np.concatenate((nbr, np.empty_like(nbr)))
                        normal = np.concatenate((normal, np.empty_like(normal)))
                        offset = np.concatenate((offset, np.empty_like(offset)))
                        alive = np.concatenate((alive, np.zeros_like(alive)))
                        seen = np.concatenate((seen, np.full_like(seen, -1)))
                        newf = np.concatenate((newf, np.empty_like(newf)))
                        free = np.concatenate((free, np.empty_like(free)))
                    h = top
                    top += 1
                for i in range(d):
                    verts[h, i] = verts[f, i]
                verts[h, j] = p
                nbr[h, j] = g
                back = _slot(nbr, g, f)
                if back < 0:
                    return np.nan
                nbr[g, back] = h
                newf[f, j] = h
                seen[h] = -1
                alive[h] = True
                offset[h] = _through(X, verts, h, f, g, p, size, inner, normal, offset)
                if math.isnan(offset[h]):
                    return np.nan
                if n_made == made.shape[0]:
                    made = np.concatenate((made, np.empty_like(made)))
                made[n_made, 0] = f
                made[n_made, 1] = j
                n_made += 1
        for a in range(n_made):  # link new facets by turning about each sub-ridge
            f, j = made[a, 0], made[a, 1]
            h = newf[f, j]
            for i in range(d):
                if i == j:
                    continue
                cur, out_v, keep = f, verts[f, i], verts[f, j]
                found = -1
                for _ in range(top + 1):
                    k = _slot(verts, cur, out_v)
                    nxt = nbr[cur, k]
                    if seen[nxt] != p:
                        found = newf[cur, k]
                        break
                    x = verts[nxt, _slot(nbr, nxt, cur)]
                    cur, out_v, keep = nxt, keep, x
                if found < 0:
                    return np.nan
                nbr[h, i] = found
        for a in range(n_vis):
            f = visible[a]
            alive[f] = False
            seen[f] = -1
            free[n_free] = f
            n_free += 1

    radius = np.inf
    for f in range(top):  # the independent check: a closed surface with every point inside
        if not alive[f]:
            continue
        for i in range(d):
            g = nbr[f, i]
            if not alive[g] or _slot(nbr, g, f) < 0:
                return np.nan
        for q in range(m):
            dist = -offset[f]
            for j in range(d):
                dist += normal[f, j] * X[q, j]
            if dist > CHECK * size:
                return np.nan
        radius = min(radius, offset[f])
    return radius

"""An exact, independent force-closure check with rational arithmetic.

Theorem 1 decided with ``fractions.Fraction`` and no linear programming:
vectors ``V`` positively span ``Q^d`` iff ``rank V = d`` and, for every
``i``, ``-v_i`` is a non-negative combination of ``V`` (then ``v_i`` has a
positive weight in some zero combination; summing those gives a strictly
positive one). Cone membership is decided by a phase-one simplex in
rationals with Bland's rule, which cannot cycle: exact, and fast enough for
the small sets of the tests. Ferrari–Canny's epsilon is checked the same
way, by the exact distance to the nearest facet of the wrench hull.
"""

from __future__ import annotations

from fractions import Fraction

Matrix = list[list[Fraction]]


def to_fractions(rows) -> Matrix:
    return [[Fraction(x) for x in row] for row in rows]


def _echelon(rows: Matrix) -> tuple[Matrix, list[int]]:
    m = [row[:] for row in rows]
    pivots, r = [], 0
    ncols = len(m[0]) if m else 0
    for c in range(ncols):
        pivot = next((i for i in range(r, len(m)) if m[i][c] != 0), None)
        if pivot is None:
            continue
        m[r], m[pivot] = m[pivot], m[r]
        inv = 1 / m[r][c]
        m[r] = [x * inv for x in m[r]]
        for i in range(len(m)):
            if i != r and m[i][c] != 0:
                f = m[i][c]
                m[i] = [a - f * b for a, b in zip(m[i], m[r], strict=True)]
        pivots.append(c)
        r += 1
    return m, pivots


def rank(columns: list[list[Fraction]]) -> int:
    """Rank of a set of column vectors."""
    if not columns:
        return 0
    return len(_echelon([list(col) for col in columns])[1])


def in_cone(columns: list[list[Fraction]], x: list[Fraction]) -> bool:
    """Whether ``x`` is a non-negative combination of ``columns`` (exactly).

    Phase one of the simplex method: minimise the sum of artificial
    variables ``a >= 0`` in ``V lam + a = x`` (rows signed so that
    ``x >= 0``), entering the lowest-index improving column and leaving the
    lowest-index basic variable among ratio ties (Bland's rule).
    """
    d, m = len(x), len(columns)
    rows = []
    for i in range(d):
        s = -1 if x[i] < 0 else 1
        rows.append([s * Fraction(columns[j][i]) for j in range(m)]
                    + [Fraction(int(i == r)) for r in range(d)] + [s * Fraction(x[i])])
    basis = [m + i for i in range(d)]

    def cost(j: int) -> int:
        return 1 if j >= m else 0

    while True:
        entering = next((j for j in range(m + d)
                         if cost(j) - sum(cost(basis[i]) * rows[i][j] for i in range(d)) < 0),
                        None)
        if entering is None:
            return sum(cost(basis[i]) * rows[i][-1] for i in range(d)) == 0
        ratios = [(rows[i][-1] / rows[i][entering], basis[i], i)
                  for i in range(d) if rows[i][entering] > 0]
        _, _, r = min(ratios)  # non-empty: phase one is bounded below by 0
        pivot = rows[r][entering]
        rows[r] = [v / pivot for v in rows[r]]
        for i in range(d):
            if i != r and rows[i][entering] != 0:
                f = rows[i][entering]
                rows[i] = [a - f * b for a, b in zip(rows[i], rows[r], strict=True)]
        basis[r] = entering


def positively_spans(columns: list[list[Fraction]]) -> bool:
    """Theorem 1, exactly: do the columns positively span their ambient space?"""
    d = len(columns[0])
    if rank(columns) < d:
        return False
    return all(in_cone(columns, [-v for v in col]) for col in columns)


def planar_hard_wrenches(points, normals, mu) -> list[list[Fraction]]:
    """Generating wrenches of planar hard fingers, built independently in rationals.

    Forces ``-n ± mu t`` with ``t = (-n_y, n_x)``, torques ``p x f`` about the
    origin. ``normals`` must be exactly unit (e.g. axis-aligned or (3, 4)/5).
    """
    cols = []
    for p, n, m in zip(points, normals, mu, strict=True):
        px, py = map(Fraction, p)
        nx, ny = map(Fraction, n)
        m = Fraction(m)
        for s in ((1, -1) if m != 0 else (1,)):
            fx, fy = -nx + s * m * -ny, -ny + s * m * nx
            cols.append([fx, fy, px * fy - py * fx])
    return cols


def spatial_pyramid4_wrenches(points, normals, mu) -> list[list[Fraction]]:
    """Spatial hard fingers on axis-aligned normals with a 4-edge inscribed pyramid.

    The pyramid's edges are ``-n ± mu e`` for the two coordinate axes ``e``
    orthogonal to ``n``: the same cone as forceclosure's ``Cone(4)`` for such
    normals, whatever tangent basis it picks.
    """
    cols = []
    for p, n, m in zip(points, normals, mu, strict=True):
        p = [Fraction(v) for v in p]
        n = [Fraction(v) for v in n]
        m = Fraction(m)
        axis = next(i for i in range(3) if n[i] != 0)
        dirs = [[0, 0, 0]]
        if m != 0:
            dirs = []
            for e in range(3):
                if e != axis:
                    for s in (1, -1):
                        v = [0, 0, 0]
                        v[e] = s
                        dirs.append(v)
        for t in dirs:
            f = [-n[i] + m * t[i] for i in range(3)]
            tau = [p[1] * f[2] - p[2] * f[1], p[2] * f[0] - p[0] * f[2],
                   p[0] * f[1] - p[1] * f[0]]
            cols.append(f + tau)
    return cols


def hull_distance_squared(points: list[list[Fraction]], metric: list[Fraction]) -> Fraction:
    """Squared distance from the origin to the nearest facet of the hull of ``points``, exactly.

    Every hyperplane through ``d`` affinely independent points that has all
    points on one side carries a facet; the distance to it is
    ``b / |a|`` for ``a . x = b``, measured with ``|a|^2 = sum metric_i a_i^2``
    (so that coordinates scaled by ``1 / sqrt(metric_i)`` are Euclidean).
    The origin must be inside the hull. Enumerates all ``d``-subsets: for
    small sets only.
    """
    from itertools import combinations

    d = len(points[0])
    best = None
    for subset in combinations(range(len(points)), d):
        x0 = points[subset[0]]
        rows = [[a - b for a, b in zip(points[i], x0, strict=True)] for i in subset[1:]]
        m, pivots = _echelon(rows)
        if len(pivots) != d - 1:
            continue
        free = next(c for c in range(d) if c not in pivots)
        a = [Fraction(0)] * d
        a[free] = Fraction(1)
        for r, c in enumerate(pivots):
            a[c] = -m[r][free]
        b = sum(ai * xi for ai, xi in zip(a, x0, strict=True))
        sides = [sum(ai * xi for ai, xi in zip(a, p, strict=True)) - b for p in points]
        if all(s <= 0 for s in sides):
            pass
        elif all(s >= 0 for s in sides):
            a, b = [-ai for ai in a], -b
        else:
            continue
        assert b > 0, "the origin is not inside the hull"
        dist2 = b * b / sum(w * ai * ai for w, ai in zip(metric, a, strict=True))
        best = dist2 if best is None else min(best, dist2)
    return best


def _rational_sqrt(x: Fraction) -> Fraction:
    from math import isqrt

    num, den = isqrt(x.numerator), isqrt(x.denominator)
    if num * num != x.numerator or den * den != x.denominator:
        raise ValueError(f"{x} is not the square of a rational")
    return Fraction(num, den)


def spatial_square_pyramid_wrenches(points, normals, mu, model="hard",
                                    circumscribed=False) -> list[list[Fraction]]:
    """Spatial contacts with a square pyramid inscribed in, or circumscribing, each cone.

    Each normal ``n`` needs a zero coordinate ``e`` and a rational length ``L`` (axes,
    3-4-5 directions); its tangents are ``t2 = L e`` and ``t1 = n x e``, both of length
    ``L``. The edges are ``-n + mu t`` for ``t`` in ``±t1, ±t2`` (inscribed: the square's
    corners on the circle) or ``±t1 ± t2`` (circumscribed: its sides touch the circle), so
    an inscribed pyramid that is closed proves closure of the circular cones and a
    circumscribed one that is not proves the opposite. ``mu = 0`` gives the single force
    ``-n``; ``model="soft"`` adds the pure torques ``(0, ±n)`` (the paper's soft finger).
    """
    cols = []
    for p, n, m in zip(points, normals, mu, strict=True):
        p = [Fraction(v) for v in p]
        n = [Fraction(v) for v in n]
        m = Fraction(m)
        zero = next(i for i in range(3) if n[i] == 0)
        length = _rational_sqrt(sum(v * v for v in n))
        e = [Fraction(int(i == zero)) for i in range(3)]
        t1 = [n[1] * e[2] - n[2] * e[1], n[2] * e[0] - n[0] * e[2], n[0] * e[1] - n[1] * e[0]]
        t2 = [length * v for v in e]
        if m == 0:
            dirs = [[Fraction(0)] * 3]
        elif circumscribed:
            dirs = [[a * x + b * y for x, y in zip(t1, t2, strict=True)]
                    for a in (1, -1) for b in (1, -1)]
        else:
            dirs = [[s * v for v in t] for t in (t1, t2) for s in (1, -1)]
        for t in dirs:
            f = [-n[i] + m * t[i] for i in range(3)]
            tau = [p[1] * f[2] - p[2] * f[1], p[2] * f[0] - p[0] * f[2],
                   p[0] * f[1] - p[1] * f[0]]
            cols.append(f + tau)
        if model == "soft":
            cols += [[Fraction(0)] * 3 + [s * v for v in n] for s in (1, -1)]
    return cols

"""An exact, independent force-closure check with rational arithmetic.

Theorem 1 decided with ``fractions.Fraction`` and no linear programming:
vectors ``V`` positively span ``Q^d`` iff ``rank V = d`` and, for every
``i``, ``-v_i`` is a non-negative combination of ``V`` (then ``v_i`` has a
positive weight in some zero combination; summing those gives a strictly
positive one). Cone membership is decided by Carathéodory's theorem: a
point of ``cone(V)`` is a non-negative combination of linearly independent
columns, so trying every independent subset is exact. Exponential, for the
small sets of the tests only.
"""

from __future__ import annotations

from fractions import Fraction
from itertools import combinations

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


def _solve(columns: list[list[Fraction]], x: list[Fraction]) -> list[Fraction] | None:
    """The unique solution of ``sum mu_j c_j = x`` for independent columns, or None."""
    d, k = len(x), len(columns)
    aug = [[columns[j][i] for j in range(k)] + [x[i]] for i in range(d)]
    m, pivots = _echelon(aug)
    if k in pivots:  # inconsistent: a pivot in the right-hand side
        return None
    mu = [Fraction(0)] * k
    for row, c in enumerate(pivots):
        mu[c] = m[row][k]
    return mu


def in_cone(columns: list[list[Fraction]], x: list[Fraction]) -> bool:
    """Whether ``x`` is a non-negative combination of ``columns`` (exactly)."""
    if all(v == 0 for v in x):
        return True
    d = len(x)
    for size in range(1, min(d, len(columns)) + 1):
        for subset in combinations(columns, size):
            if rank(list(subset)) < size:
                continue
            mu = _solve(list(subset), x)
            if mu is not None and all(v >= 0 for v in mu):
                return True
    return False


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

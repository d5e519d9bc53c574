"""A small dense two-phase simplex, compiled, for the LPs of Theorem 1.

``maximise c . x  subject to  A x = b,  x >= 0`` with ``A`` of a few rows
(``d + 1 <= 7``) and a few dozen columns: the shape of every LP the
force-closure test solves. One tableau, Dantzig's rule falling back to
Bland's rule after a run of degenerate pivots (so it cannot cycle), and the
duals read off the artificial columns. It allocates nothing per call: the
caller writes the LP into a tableau carved from its own buffer
(:func:`tableau`), so thousands of LPs run in a parallel loop.

Status codes: ``OPTIMAL``, ``INFEASIBLE``, ``UNBOUNDED`` and ``STALLED``
(the iteration limit; the caller then falls back to HiGHS).
"""

from __future__ import annotations

import numba as nb
import numpy as np

__all__ = ["INFEASIBLE", "OPTIMAL", "STALLED", "UNBOUNDED", "solve_tableau", "tableau"]

OPTIMAL, INFEASIBLE, UNBOUNDED, STALLED = 0, 1, 2, 3

_PIVOT = 1e-10  # smallest pivot element accepted
_COST = 1e-12  # reduced costs below -_COST improve the objective
_FEASIBLE = 1e-9  # Phase I residual accepted as feasible


@nb.njit(cache=True, nogil=True)
def tableau(buffer, rows, cols):  # pragma: no cover - compiled
    """A C-contiguous ``(rows + 1, cols + rows + 1)`` tableau in a flat buffer, zeroed.

    The caller writes ``A`` into ``T[:rows, :cols]`` and ``b`` into
    ``T[:rows, -1]``, then calls :func:`solve_tableau`.
    """
    size = (rows + 1) * (cols + rows + 1)
    T = buffer[:size].reshape(rows + 1, cols + rows + 1)
    T[:, :] = 0.0
    return T


@nb.njit(cache=True, nogil=True)
def _pivot(T, basis, r, c):  # pragma: no cover - compiled
    rows = T.shape[0]
    width = T.shape[1]
    inv = 1.0 / T[r, c]
    for j in range(width):
        T[r, j] *= inv
    T[r, c] = 1.0
    for i in range(rows):
        if i != r:
            f = T[i, c]
            if f != 0.0:
                for j in range(width):
                    T[i, j] -= f * T[r, j]
                T[i, c] = 0.0
    basis[r] = c


@nb.njit(cache=True, nogil=True)
def _iterate(T, basis, ncols, limit):  # pragma: no cover - compiled
    """Pivot until no column among the first ``ncols`` has a negative reduced cost."""
    m = basis.shape[0]
    rhs = T.shape[1] - 1
    degenerate = 0
    for _ in range(limit):
        bland = degenerate > 2 * (m + 1)
        enter = -1
        best = -_COST
        for j in range(ncols):
            dj = T[m, j]
            if dj < best:
                enter = j
                if bland:
                    break
                best = dj
        if enter < 0:
            return OPTIMAL
        leave = -1
        ratio = np.inf
        for i in range(m):
            a = T[i, enter]
            if a > _PIVOT:
                t = T[i, rhs] / a
                if t < ratio - 1e-15 or (t <= ratio + 1e-15 and leave >= 0
                                         and basis[i] < basis[leave]):
                    ratio = t
                    leave = i
        if leave < 0:
            return UNBOUNDED
        degenerate = degenerate + 1 if ratio <= 1e-15 else 0
        _pivot(T, basis, leave, enter)
    return STALLED


@nb.njit(cache=True, nogil=True)
def solve_tableau(T, m, n, c, basis, x, y):  # pragma: no cover - compiled
    """Solve ``max c.x, A x = b, x >= 0`` for the ``m x n`` ``A`` and ``b`` in ``T``; return status.

    Fills ``x`` and the duals ``y`` (``A^T y >= c`` with ``b . y = c . x`` at
    the optimum).
    """
    rhs = n + m
    for i in range(m):  # rows turned to b >= 0; y keeps each row's sign until the duals
        y[i] = 1.0
        if T[i, rhs] < 0.0:
            y[i] = -1.0
            for j in range(n):
                T[i, j] = -T[i, j]
            T[i, rhs] = -T[i, rhs]
        T[i, n + i] = 1.0
        basis[i] = n + i
    # Phase I: minimise the sum of the artificials.
    for j in range(n):
        s = 0.0
        for i in range(m):
            s += T[i, j]
        T[m, j] = -s
    s = 0.0
    for i in range(m):
        s += T[i, rhs]
    T[m, rhs] = -s
    limit = 50 * (n + m)
    status = _iterate(T, basis, n, limit)
    if status == STALLED:
        return STALLED
    if -T[m, rhs] > _FEASIBLE * (1.0 + abs(s)):
        return INFEASIBLE
    # Drive the artificials out of the basis where a real column can replace them.
    for i in range(m):
        if basis[i] >= n:
            best = _PIVOT
            col = -1
            for j in range(n):
                if abs(T[i, j]) > best:
                    best = abs(T[i, j])
                    col = j
            if col >= 0:
                _pivot(T, basis, i, col)
    # Phase II: reduced costs of -c (we minimise -c.x), artificials barred from entering.
    for j in range(n + m + 1):
        T[m, j] = 0.0
    for j in range(n):
        T[m, j] = -c[j]
    for i in range(m):
        k = basis[i]
        if k < n:
            f = T[m, k]
            if f != 0.0:
                for j in range(n + m + 1):
                    T[m, j] -= f * T[i, j]
    status = _iterate(T, basis, n, limit)
    if status != OPTIMAL:
        return status
    x[:] = 0.0
    for i in range(m):
        if basis[i] < n:
            x[basis[i]] = T[i, rhs]
    # Duals: y = c_B B^-1, and B^-1 sits (up to the row flips) in the artificial columns.
    for k in range(m):
        s = 0.0
        for i in range(m):
            if basis[i] < n:
                s += c[basis[i]] * T[i, n + k]
        y[k] *= s
    return OPTIMAL

"""A convex polygon cut by half-planes (Sutherland–Hodgman)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

__all__ = ["clip"]


def clip(ring: NDArray, a: NDArray, b: NDArray) -> NDArray[np.float64]:
    """The convex polygon ``ring`` cut by the half-planes ``a . y >= b`` (Sutherland–Hodgman,
    only with the half-planes that some vertex violates); ``(0, 2)`` when nothing is left.

    Parameters
    ----------
    ring : (k, 2) array
        The polygon's vertices in order.
    a : (h, 2) array, b : (h,) array
        The half-planes ``a[i] . y >= b[i]``.

    Examples
    --------
    >>> square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    >>> clip(square, np.array([[-1.0, 0.0]]), np.array([-1.0])).tolist()   # x <= 1
    [[0.0, 0.0], [1.0, 0.0], [1.0, 2.0], [0.0, 2.0]]
    >>> clip(square, np.array([[1.0, 0.0]]), np.array([3.0])).shape        # x >= 3: nothing
    (0, 2)
    """
    values = ring @ a.T - b  # (k, h)
    for h in np.flatnonzero((values < 0).any(axis=0)):
        if len(ring) == 0:
            break
        s = ring @ a[h] - b[h]
        out = []
        for i in range(len(ring)):
            j = (i + 1) % len(ring)
            if s[i] >= 0:
                out.append(ring[i])
            if (s[i] >= 0) != (s[j] >= 0):
                t = s[i] / (s[i] - s[j])
                out.append(ring[i] + t * (ring[j] - ring[i]))
        ring = np.array(out).reshape(-1, 2)
    return ring

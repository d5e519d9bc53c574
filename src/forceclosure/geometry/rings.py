"""Polygon rings in the plane: the one signed area.

A leaf module (NumPy only), so the objects, the constructions and the
pictures share one rule for a ring's area and orientation.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["signed_area"]


def signed_area(ring: ArrayLike) -> float:
    """The signed area of a closed ring of points (the shoelace formula).

    Positive for an anticlockwise ring, negative for a clockwise one; 0 for
    fewer than three points. The ring is taken about its first vertex, so that
    the products of far-away coordinates do not cancel.

    Parameters
    ----------
    ring : (n, 2) array
        The vertices in order, the last joined back to the first (not repeated).

    Returns
    -------
    float

    References
    ----------
    The surveyor's (shoelace) formula: the area of a simple polygon is
    ``1/2 sum_i (x_i y_{i+1} - x_{i+1} y_i)``.

    Examples
    --------
    >>> signed_area([[0, 0], [2, 0], [2, 1], [0, 1]])
    2.0
    >>> signed_area([[1e9, 1e9], [1e9, 1e9 + 1], [1e9 + 1, 1e9]])  # clockwise, far away
    -0.5
    >>> signed_area([[0, 0], [1, 1]])
    0.0
    """
    points = np.asarray(ring, dtype=float)
    if len(points) < 3:
        return 0.0
    x, y = (points - points[0]).T
    x1, y1 = np.concatenate((x[1:], x[:1])), np.concatenate((y[1:], y[:1]))  # np.roll(., -1)
    return 0.5 * float(np.sum(x * y1 - x1 * y))
